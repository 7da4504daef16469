// run_report.cpp — formatting the terminal run report.
#include "report/run_report.hpp"

#include <cstdio>
#include <string>

#include "report/run_summary.hpp"

namespace pcnc {

Vec3 to_program_coordinates(const Vec3& machine, const Transform& t) {
  return (1.0 / t.scale) * (machine - t.offset);
}

std::string format_run_report(const RunReport& r) {
  const Status& s = r.job.final_status;
  const Transform& t = r.check.transform;
  const Vec3 prog = to_program_coordinates(s.actual, t);
  const Vec3 rms = rms_following_error(s);
  std::string corner, smoothing;
  if (r.path_tolerance_mm > 0.0) {
    char c[128];
    std::snprintf(c, sizeof c, " (path tolerance %.1f um: corners at the junction-deviation speed)",
                  r.path_tolerance_mm * 1000.0);
    corner = c;
  }
  {
    // the tolerance the curves were fitted to: the run's, or what the program's G64 P set
    const double lo = r.check.smoothed_curves > 0 ? r.check.smoothing_min_tolerance_mm : r.path_tolerance_mm;
    const double hi = r.check.smoothed_curves > 0 ? r.check.smoothing_max_tolerance_mm : r.path_tolerance_mm;
    char tol[64];
    if (hi > lo) {
      std::snprintf(tol, sizeof tol, "%.1f-%.1f um (G64 P)", lo * 1000.0, hi * 1000.0);
    } else {
      std::snprintf(tol, sizeof tol, "%.1f um%s", hi * 1000.0, hi != r.path_tolerance_mm ? " (G64 P)" : "");
    }
    char c[320];
    std::snprintf(c, sizeof c,
                  "  smoothing         tolerance %s: %llu G1 moves smoothed into %llu blocks (%llu curves), path "
                  "max %.2f um from the programmed moves\n",
                  tol, static_cast<unsigned long long>(r.check.smoothed_moves),
                  static_cast<unsigned long long>(r.check.smoothed_blocks),
                  static_cast<unsigned long long>(r.check.smoothed_curves), r.check.max_path_deviation_mm * 1000.0);
    smoothing = c;
    if (r.check.packed_arcs > 0) {
      std::snprintf(c, sizeof c,
                    "  arc packing       %llu arcs packed into %llu blocks (%llu curve%s, exact: max %.3f um from "
                    "the arcs)\n",
                    static_cast<unsigned long long>(r.check.packed_arcs),
                    static_cast<unsigned long long>(r.check.packed_blocks),
                    static_cast<unsigned long long>(r.check.packed_curves), r.check.packed_curves == 1 ? "" : "s",
                    r.check.packed_max_deviation_mm * 1000.0);
      smoothing += c;
    }
  }
  std::string pauses;
  if (r.job.pauses > 0) {
    pauses = "  pauses            " + std::to_string(r.job.pauses) + " (M0/M1 on line" + (r.job.pauses > 1 ? "s " : " ");
    for (std::size_t i = 0; i < r.job.pause_lines.size(); ++i) pauses += (i ? ", " : "") + std::to_string(r.job.pause_lines[i]);
    if (r.job.pauses > r.job.pause_lines.size()) pauses += ", ...";
    pauses += r.job.pauses_mode == "ask" ? "): the machine waited at rest for the operator (--pauses ask)\n"
                                         : "): the machine came to rest there and went on (--pauses continue)\n";
  }
  char buf[4096];
  int n = std::snprintf(
      buf, sizeof buf,
      "run report: %s\n"
      "  result            %s%s%s\n"
      "  program time      %.3f s machine time (%.3f s wall, %s clock)\n"
      "  feed time L/F     %.3f s (pure path length over programmed feed)\n"
      "  lines / blocks    %llu lines read, %llu blocks sent, %llu blocks done\n"
      "  junctions         %llu passed without stopping, %llu stops%s\n"
      "  transform         machine = %.6g * program + (%.4f, %.4f, %.4f) mm\n"
      "  final position    machine X%.4f Y%.4f Z%.4f mm; program X%.4f Y%.4f Z%.4f\n"
      "  commanded         X%.4f Y%.4f Z%.4f mm\n"
      "  max follow. error X %.2f um  Y %.2f um  Z %.2f um\n"
      "  RMS follow. error X %.2f um  Y %.2f um  Z %.2f um\n"
      "  contour error     max %.2f um, RMS %.2f um (measured position to the programmed path)\n"
      "  ring underruns    %llu (host slot refill p99 %.1f us)\n"
      "  rt cycle          compute p99 %.2f us max %.2f us; wake-up p99 %.1f us max %.1f us; %llu overruns\n",
      r.program.c_str(), to_string(r.job.end), r.job.message.empty() ? "" : ": ", r.job.message.c_str(),
      s.program_time_s, r.job.wall_time_s, s.clock_virtual ? "virtual" : "real", r.check.feed_length_time_s,
      static_cast<unsigned long long>(r.job.lines_read), static_cast<unsigned long long>(r.job.blocks_sent),
      static_cast<unsigned long long>(s.blocks_done), static_cast<unsigned long long>(s.junction_flows),
      static_cast<unsigned long long>(s.junction_stops), corner.c_str(), t.scale, t.offset[0], t.offset[1], t.offset[2], s.actual[0],
      s.actual[1], s.actual[2], prog[0], prog[1], prog[2], s.commanded[0], s.commanded[1], s.commanded[2], s.max_following_error[0] * 1000.0,
      s.max_following_error[1] * 1000.0, s.max_following_error[2] * 1000.0, rms[0] * 1000.0, rms[1] * 1000.0,
      rms[2] * 1000.0, s.max_contour_error * 1000.0, rms_contour_error(s) * 1000.0,
      static_cast<unsigned long long>(s.underruns), r.job.refill_latency.quantile(0.99), s.timing.compute_p99_us, s.timing.compute_max_us,
      s.timing.wake_p99_us, s.timing.wake_max_us, static_cast<unsigned long long>(s.timing.overruns));
  return std::string(buf, static_cast<std::size_t>(n > 0 ? n : 0)) + pauses + smoothing;
}

}  // namespace pcnc
