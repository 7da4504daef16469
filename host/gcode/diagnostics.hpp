// diagnostics.hpp — errors and warnings of the G-code front end ("file:line:col: error: ...").
//
// Every pipeline stage (lexer, parser, interpreter, preflight, preprocessor, block check)
// reports through a DiagnosticSink. The sink keeps memory bounded on programs of any length:
// errors are kept up to a cap (the rest are counted), and a warning that repeats (same key,
// e.g. "spindle words ignored") is kept once with the line of its first occurrence and a
// repeat count.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace pcnc {

struct Diagnostic {
  enum class Severity { kWarning, kError } severity = Severity::kError;
  std::string file;
  int line = 0;
  int column = 0;
  std::string message;
};

/// Where a line of a program the front end made from another file form came from in that
/// file (a JSON ruled-surface program run as its G-code form): the line and column of the value
/// and its key path ("pieces[2].points[5]").
struct SourcePlace {
  int line = 0;
  int column = 0;
  std::string path;
};
/// One place per line of the made program, from its line 1.
using SourcePlaces = std::vector<SourcePlace>;

/// "file:line:col: error: message" (column omitted when 0, line omitted when 0).
std::string format_diagnostic(const Diagnostic& d);

class DiagnosticSink {
 public:
  static constexpr std::size_t kMaxErrors = 50;

  explicit DiagnosticSink(std::string file = {}) : file_(std::move(file)) {}

  void error(int line, int column, std::string message);
  /// A warning; `key` groups repeats (empty key: never grouped, but still capped).
  void warning(int line, int column, std::string_view key, std::string message);

  /// Counts one more occurrence of the warning kept under `key`; false if there is none yet
  /// (then the caller reports it with warning()).
  bool repeat(std::string_view key);

  std::uint64_t error_count() const { return error_count_; }
  std::uint64_t warning_count() const { return warning_count_; }
  bool has_errors() const { return error_count_ > 0; }

  /// The kept diagnostics in the order they were first reported; repeated warnings get a
  /// "(repeated N more times)" suffix, and a final note counts errors beyond the cap.
  std::vector<Diagnostic> take();

  const std::string& file() const { return file_; }
  /// The file later diagnostics name (the control flow switches it inside a subroutine file).
  void set_file(std::string file) { file_ = std::move(file); }
  /// A made program's lines (LineReader::Generated): diagnostics at its line L are reported at
  /// places[L - 1] (line, column) with the place's path before the message.
  void set_source_places(std::shared_ptr<const SourcePlaces> places) { places_ = std::move(places); }
  /// A made program's line L as the file's line (L itself without places).
  int file_line(int line) const;

 private:
  struct Kept {
    Diagnostic d;
    std::string key;
    std::uint64_t repeats = 0;
  };
  void place(int& line, int& column, std::string& message) const;
  std::string file_;
  std::shared_ptr<const SourcePlaces> places_;
  std::vector<Kept> kept_;
  std::uint64_t error_count_ = 0;
  std::uint64_t warning_count_ = 0;
  std::uint64_t dropped_warnings_ = 0;
};

}  // namespace pcnc
