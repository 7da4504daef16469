// check_progress.hpp — how far a check of a program has got (the front end's progress).
//
// Checking a large CAM file is long work: every line runs through the whole pipeline before
// anything moves (a 1.3 MB surfacing program takes about a second, a 50 MB one most of a
// minute). check_program reports its progress to JobOptions::on_check_progress while it reads,
// at most ten times a second, and only once a check has run for a tenth of a second: `pcnc
// check` and `pcnc run` draw it, the service puts it in the job's status. The handler may end
// the check early by throwing CheckInterrupted (Ctrl-C, a stop): the check then fails with one
// error at the line reached, and nothing moves.
//
// May include: the C++ library only.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

namespace pcnc {

/// Which pass over the program: --fit's measuring pass (the part's extents, before the
/// transform is known), then the check itself.
enum class CheckPass : std::uint8_t { kFit, kCheck };

struct CheckProgress {
  CheckPass pass = CheckPass::kCheck;
  std::uint64_t line = 0;         // the program's line reached (its own file's number)
  std::uint64_t bytes_read = 0;   // of the program's text, up to the line reached
  std::uint64_t total_bytes = 0;  // the program's size (0: not known)
  std::uint64_t blocks = 0;       // blocks made and accepted so far (the check pass)

  /// The part of the program's text read, 0..1 (0 when its size is not known). A loop or a
  /// subroutine call reads lines again: the fraction follows the line being read.
  double fraction() const {
    if (total_bytes == 0) return 0.0;
    const double f = static_cast<double>(bytes_read) / static_cast<double>(total_bytes);
    return f < 0.0 ? 0.0 : (f > 1.0 ? 1.0 : f);
  }
};

using CheckProgressHandler = std::function<void(const CheckProgress&)>;

/// Thrown by a CheckProgressHandler to end the check: it fails with `what()` as its error,
/// at the line reached.
class CheckInterrupted : public std::runtime_error {
 public:
  explicit CheckInterrupted(const std::string& why) : std::runtime_error(why) {}
};

}  // namespace pcnc
