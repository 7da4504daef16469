// interpreter_probe.cpp — G38.2-G38.5, straight probing as LinuxCNC defines it (docs/probe.md):
// a straight move at the feed toward the programmed point that the rt stops when the probe's
// input changes (toward: it triggers; away: it releases). The words are checked as LinuxCNC
// checks them; the move is a kLine Move with its probe rule. Where the move ends and what
// #5061-#5070 hold come from the probe's result (ProbeResults): known from an earlier pass of a
// run, or, for `pcnc check`, assumed to be contact at the commanded end. With
// ProbeResults::stop_at_unknown the first unknown one is a sync point: the source stops there.
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "ipc/block.hpp"

namespace pcnc {

using namespace interp;

Vec3 Interpreter::to_program(const Vec3& machine) const {
  const double u = inches_ ? kInch : 1.0;
  return (1.0 / u) * (to_job(machine) - origin_);
}

bool Interpreter::probe(const ParsedLine& l, int motion, MoveList& out) {
  const int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  const std::string name = g_name(motion);
  if (!config_.probe.present) {
    return fail(l, column, name + ": the machine has no probe; expected a [probe] section in the machine config");
  }
  if (comp_.side != 0) {
    return fail(l, column, "cannot probe (" + name + ") with cutter radius compensation on; expected G40 first");
  }
  if (frame_.surface) {
    return fail(l, column, "cannot probe (" + name + ") while moves are corrected by a measured surface (--surface)");
  }
  Vec3 q = q_;
  std::uint8_t known = known_;
  int first_col = 0;
  q = axis_target(l, q_, known, first_col);
  const int at = column > 0 ? column : first_col;
  Move m = base_move(MoveKind::kLine, l, at);
  if (!feed_for_move(l, at, m.feed_mm_s)) return false;
  m.end = to_machine(q);
  m.known = known;
  m.contouring = false;  // a probing move starts and ends at rest
  m.probe_rule = static_cast<std::uint8_t>(motion - 381);  // 382 -> kProbeTowardError ... 385 -> kProbeAway
  const bool errors = m.probe_rule == kProbeTowardError || m.probe_rule == kProbeAwayError;
  if (errors && m.end == m.start) {  // LinuxCNC: NCE_START_POINT_TOO_CLOSE_TO_PROBE_POINT
    return fail(l, first_col > 0 ? first_col : at, name + " to the point the probe stands on; expected a point to move toward");
  }

  // The result: known, or the sync point, or assumed (check).
  const int index = probes_++;
  ProbeResult r;
  r.outcome = ProbeOutcome::kContact;
  r.latched = r.stop = m.end;
  const ProbeResults* known_results = frame_.probe.get();
  if (known_results && index < static_cast<int>(known_results->known.size())) {
    r = known_results->known[static_cast<std::size_t>(index)];
  } else if (known_results && known_results->refuse_unknown) {
    return fail(l, at, name + " is not supported in a streamed program: lines sent one by one cannot wait for the probe's result; "
                              "expected the program run as a file (pcnc run, pcnc ctl run) or pcnc ctl probe");
  } else if (known_results && known_results->stop_at_unknown) {
    probe_sync_ = true;
  } else {
    assumed_probe_lines_.push_back(l.line);
  }
  if (r.outcome == ProbeOutcome::kAlreadyTriggered) {
    return fail(l, at, std::string("the probe was ") + (probe_toward(m.probe_rule) ? "already triggered" : "not triggered") +
                           " at the start of " + name + "; expected it " +
                           (probe_toward(m.probe_rule) ? "clear of the workpiece" : "touching"));
  }
  if (r.outcome == ProbeOutcome::kNoContact && errors) {
    return fail(l, at, name + " reached its end without the probe " +
                           (probe_toward(m.probe_rule) ? std::string("triggering") : std::string("releasing")) +
                           "; expected a point beyond the surface (or G38.3/G38.5, which do not fail)");
  }
  out.push(m);
  // The machine stands where the probe stopped; #5061-#5063 the latched point (the programmed
  // point after no contact), in the work coordinates and units now; #5070 whether it touched.
  q_ = to_job(r.stop);
  known_ = known;
  const bool contact = r.outcome == ProbeOutcome::kContact;
  const Vec3 p = to_program(contact ? r.latched : m.end);
  for (int i = 0; i < 9; ++i) params_.at(5061 + i) = i < 3 ? p[static_cast<std::size_t>(i)] : 0.0;
  params_.at(5070) = contact ? 1.0 : 0.0;
  return true;
}

}  // namespace pcnc
