// bench_ideal_planner.cpp — figures, not a test: the machine time issue 14's ideal planner
// (report/ideal_planner.hpp: LinuxCNC/grbl-class, unlimited look-ahead, every junction at its
// junction-deviation speed for the path tolerance) needs for a program, on the same machine and
// with the same --fit transform as `pcnc run FILE --fit`. tools/bench_surfacing.sh prints it
// beside pcnc's machine time; docs/smoothing.md, "The ideal planner".
//
// Usage: bench_ideal_planner PROGRAM [--config F] [--fit] [--contouring on|off]
//                            [--tolerance MM] [--chord MM] [--arcs whole|chords] [--lines OUT.csv]
//                            [--keep-bend-limits]
// Prints one line: "ideal <time> s  segments <n>  stops <n>  length <mm>  bends ..." (what the
// ideal's speeds ask of the programmed curve at its bends, ideal_planner.hpp).
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "gcode/program.hpp"
#include "run_job_options.hpp"
#include "report/ideal_planner.hpp"

using namespace pcnc;

int main(int argc, char** argv) {
  pcnc::BenchCli app{"the ideal junction-deviation planner's machine time for a program (issue 14's yardstick)"};
  std::string program, config_path = default_config_path(), contouring = "on";
  bool fit = false;
  double tolerance = -1.0;
  IdealPlannerOptions ideal;
  app.add_option("PROGRAM", program, "G-code program")->required();
  app.add_option("--config", config_path, "machine config (default: the desktop mill)");
  app.add_option("--contouring", contouring, "on or off: the program's start state, as for pcnc run");
  app.add_flag("--fit", fit, "scale and centre the program into the travel, as pcnc run --fit");
  app.add_option("--tolerance", tolerance, "junction deviation (mm); default: the config's path tolerance");
  app.add_option("--chord", ideal.chord_tolerance_mm, "curves (and arcs as chords) as chords of at most this sagitta (mm)");
  std::string arcs = "whole";
  app.add_option("--arcs", arcs,
                 "whole: an arc is one segment at most at sqrt(A*r) (LinuxCNC; the issue's figures); chords: grbl's "
                 "chords, each junction at the junction-deviation speed")
      ->one_of({"whole", "chords"});
  app.add_flag("--keep-bend-limits", ideal.keep_bend_limits,
               "not the ideal's rule: also hold every bend (turn < 10°) to sqrt(a·rho), the axes' acceleration on the "
               "curve the points draw (a floor for a planner that keeps the limits)");
  std::string lines_csv;
  app.add_option("--lines", lines_csv, "write the ideal's time per source line to this CSV (line,time_s)");
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  ideal.arcs_as_chords = arcs == "chords";
  MachineConfig c = load_config(config_path);
  ideal.tolerance_mm = tolerance >= 0.0 ? tolerance : c.motion.path_tolerance_mm;
  set_operator_tolerance(c.motion, 0.0);  // the moves as programmed, no smoothing
  const JobOptions o = run_job_options(c, fit, contouring == "on");
  const CheckResult r = check_program(program, c, o);
  if (!r.ok) {
    std::fprintf(stderr, "bench_ideal_planner: %s does not check\n", program.c_str());
    return 2;
  }
  std::vector<Move> moves;
  const MoveListing l = list_moves(program, c, o, r.transform, [&](const Move& m) { moves.push_back(m); });
  if (!l.ok) {
    std::fprintf(stderr, "bench_ideal_planner: %s: the moves do not list\n", program.c_str());
    return 2;
  }
  const IdealPlan p = ideal_planner_time(moves, c, ideal);
  std::printf("ideal %.2f s  segments %llu  stops %llu  length %.1f mm", p.time_s,
              static_cast<unsigned long long>(p.segments), static_cast<unsigned long long>(p.stops), p.length_mm);
  std::printf("  bends %llu, over the axes' limit %llu, asking median %.2f max %.1f x the limit",
              static_cast<unsigned long long>(p.bends), static_cast<unsigned long long>(p.bends_over_limit),
              p.bend_accel_median, p.bend_accel_max);
  if (p.unmodelled_moves > 0) std::printf("  unmodelled moves %llu", static_cast<unsigned long long>(p.unmodelled_moves));
  std::printf("\n");
  if (!lines_csv.empty()) {
    std::FILE* f = std::fopen(lines_csv.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "bench_ideal_planner: cannot write %s\n", lines_csv.c_str());
      return 2;
    }
    std::fprintf(f, "line,time_s\n");
    for (const IdealLineTime& t : p.line_times) std::fprintf(f, "%d,%.6f\n", t.line, t.time_s);
    std::fclose(f);
  }
  return 0;
}
