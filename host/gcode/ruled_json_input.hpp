// ruled_json_input.hpp — the JSON file form of a ruled-surface program (`pcnc ruled --json`,
// docs/ruled-surface.md "The file form") as an input of the one front-end pipeline: the head
// of gcode/pipeline.hpp's chain for a `.json` program. The file is read and checked
// (read_ruled_program_json), then written as the G-code form `pcnc ruled` writes
// (ruled_program_lines) with the preamble built from the machine's config: the joints turned to
// the first tool vector with TCP off, M428, the rapids to the first set point, the G5.4 groups,
// M429 and the joints turned back. The lexer, interpreter, preflight and block check then run
// that text as they run any program, so `pcnc check`, `pcnc run` and a job over the control
// socket take the file form as they take the G-code form, and the two give the same blocks
// (their line numbers aside: a made line's diagnostics and blocks name the place in the JSON
// file it came from, LineReader::Generated).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "config/config.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/ruled_program.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// A program file the front end reads as the JSON file form: its name ends in ".json" (any case).
bool is_ruled_json_program(const std::string& path);

/// The largest JSON program file read (it is parsed whole, unlike the G-code form's stream).
inline constexpr std::size_t kMaxRuledJsonBytes = std::size_t{64} << 20;

/// The rotary joints' words that put the tool axis at `axis` with the tip at `tip` (machine
/// coordinates): the inverse kinematics nearest the joints' homes, "A4.500000 C-90.000000" (B
/// on a B-tilt machine, six decimals of degrees), and the words that turn them back ("A0 C0").
/// Both empty on a machine without 5-axis kinematics. `pcnc ruled` writes these into its
/// program; the JSON input builds its preamble with them.
struct RuledTurnWords {
  std::string turn;
  std::string back;
};
RuledTurnWords ruled_turn_words(const MachineConfig& config, const Vec3& tip, const Vec3& axis);

/// The G-code form of a JSON ruled-surface program on this machine, or why it is refused.
/// `offset` and `scale` place program coordinates in the machine (machine = scale * program +
/// offset: the job's frame), for the turn words. The preamble: G21 G90 G17 G94, [G0 <turn>],
/// M428, G0 Z<zc>, G0 X Y of the first set point, G0 Z of the first set point (a null move
/// when it is zc), with zc the higher of the first and the last set point's Z; after the
/// pieces G0 Z<zc>, M429, [G0 <back>], M2. For `pcnc ruled`'s pieces (approach from the
/// clearance, retract to it) that is the program it writes, header comments aside.
struct RuledJsonInput {
  std::string text;                            // the G-code form, one line per '\n'
  std::shared_ptr<const SourcePlaces> places;  // each line's place in the JSON file
  std::string refusal_text;                    // format_diagnostic of the refusal; empty when made
  Diagnostic refusal;
};
RuledJsonInput ruled_json_input(const std::string& json_text, const std::string& origin, const MachineConfig& config,
                                const Vec3& offset, double scale);

/// A program the front end refuses before any of it runs (a bad JSON program file): the
/// refusal with its file, line and column.
struct ProgramRefused : std::runtime_error {
  explicit ProgramRefused(Diagnostic d) : std::runtime_error(format_diagnostic(d)), diagnostic(std::move(d)) {}
  Diagnostic diagnostic;
};

/// Opens `path` as the JSON file form: read (a regular file of at most kMaxRuledJsonBytes),
/// made into its G-code form, a LineReader over that. Throws ProgramRefused when the file is
/// refused, std::runtime_error when it cannot be read.
std::unique_ptr<LineReader> open_ruled_json_program(const std::string& path, const MachineConfig& config,
                                                    const Vec3& offset, double scale);

}  // namespace pcnc
