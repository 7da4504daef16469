// check.cpp — the `pcnc check` subcommand over check_program / BlockStream.
#include "check.hpp"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdio>
#include <iostream>
#include <memory>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "gcode/program.hpp"
#include "progress.hpp"

namespace pcnc {
namespace {

std::string f4(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  std::string s(buf);
  if (s == "-0.0000") s = "0.0000";
  return s;
}

}  // namespace

std::optional<std::array<double, 3>> parse_xyz(const std::string& text) {
  std::array<double, 3> v{};
  const char* p = text.data();
  const char* e = text.data() + text.size();
  for (int i = 0; i < 3; ++i) {
    while (p < e && *p == ' ') ++p;
    if (p < e && *p == '+') ++p;
    const auto r = std::from_chars(p, e, v[static_cast<std::size_t>(i)]);
    if (r.ec != std::errc()) return std::nullopt;
    p = r.ptr;
    while (p < e && *p == ' ') ++p;
    if (i < 2) {
      if (p == e || *p != ',') return std::nullopt;
      ++p;
    }
  }
  if (p != e) return std::nullopt;
  return v;
}

int run_check_command(const CheckCommandOptions& o, std::ostream& out, std::ostream& err, std::FILE* progress) {
  MachineConfig config;
  try {
    config = load_config(o.config_path.empty() ? default_config_path() : o.config_path);
    if (o.tolerance >= 0.0) set_operator_tolerance(config.motion, o.tolerance);
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) err << "pcnc check: " << p << "\n";
    return kExitBadInput;
  }
  JobOptions job;
  job.fit = o.fit;
  if (!o.offset.empty()) {
    const auto v = parse_xyz(o.offset);
    if (!v) {
      err << "pcnc check: --offset '" << o.offset << "': expected X,Y,Z in mm, e.g. 12.5,12.5,25\n";
      return 2;
    }
    job.offset = *v;
  }
  if (o.contouring == "on")
    job.contouring = true;
  else if (o.contouring == "off")
    job.contouring = false;
  else if (!o.contouring.empty()) {
    err << "pcnc check: --contouring '" << o.contouring << "': expected on or off\n";
    return 2;
  }

  if (!o.surface.empty()) config.gcode.surface = o.surface;
  if (const std::string why = load_job_state(config, o.tool_table, job); !why.empty()) {
    err << "pcnc check: " << why << "\n";
    return 2;
  }
  if (o.print_moves) {
    const MoveListing r = list_moves(
        o.file, config, job,
        [&](const Move& m) {
          const std::string s = format_move(m);
          if (!s.empty()) out << s << "\n";
        },
        [&](const ProgramMessage& m) {
          if (m.kind == MessageKind::kPrint) {
            err << m.text << "\n";
          } else {
            out << "MSG " << m.text << "\n";
          }
        });
    for (const Diagnostic& d : r.diagnostics) {
      if (d.severity == Diagnostic::Severity::kError || !o.quiet) err << format_diagnostic(d) << "\n";
    }
    return r.ok ? 0 : kExitBadInput;
  }
  job.on_message = [&](const ProgramMessage& m) {
    if (!o.quiet) err << o.file << ":" << m.line << ": " << (m.kind == MessageKind::kPrint ? "print" : "message") << ": " << m.text << "\n";
  };
  // progress on stderr while a long program is checked (a bar on a terminal, else a line every
  // 5 s), cleared before the verdict; none with --quiet
  std::optional<ProgressDisplay> display;
  if (!o.quiet && progress != nullptr) {
    display.emplace(progress, ProgressDisplay::is_terminal(progress));
    job.on_check_progress = [&display](const CheckProgress& c) { display->checking(c); };
  }
  const CheckResult r = check_program(o.file, config, job);
  if (display) display->finish();
  std::size_t errors = 0, warnings = 0;
  for (const Diagnostic& d : r.diagnostics) {
    const bool is_error = d.severity == Diagnostic::Severity::kError;
    (is_error ? errors : warnings)++;
    if (is_error || !o.quiet) err << format_diagnostic(d) << "\n";
  }
  errors = static_cast<std::size_t>(r.error_count);  // with those beyond the shown ones
  if (!r.ok) {
    out << o.file << ": FAILED: " << r.lines << " lines, " << errors << " error" << (errors == 1 ? "" : "s")
        << "; nothing would move\n";
    return kExitBadInput;
  }
  if (!o.quiet) {
    const Transform& t = r.transform;
    out << o.file << ": OK: " << r.lines << " lines, " << r.moves << " moves, " << warnings << " warning"
        << (warnings == 1 ? "" : "s") << "\n";
    out << "  transform: machine = " << f4(t.scale) << " * program + (" << f4(t.offset[0]) << ", " << f4(t.offset[1])
        << ", " << f4(t.offset[2]) << ") mm" << (o.fit ? "  (--fit)" : "") << "\n";
    out << "  extents (machine): X " << f4(r.min_point[0]) << " .. " << f4(r.max_point[0]) << ", Y "
        << f4(r.min_point[1]) << " .. " << f4(r.max_point[1]) << ", Z " << f4(r.min_point[2]) << " .. "
        << f4(r.max_point[2]) << " mm\n";
    out << "  feed time (length/F, no acceleration): " << f4(r.feed_length_time_s) << " s\n";
    if (!r.assumed_probe_lines.empty()) {
      // docs/probe.md: each probing move is a sync point; a run interprets the rest again with its result
      out << "  probing: " << r.assumed_probe_lines.size() << " probing move" << (r.assumed_probe_lines.size() == 1 ? "" : "s")
          << " (first at line " << r.assumed_probe_lines.front()
          << "): the rest checked assuming contact at each move's commanded end; a run checks it again with the real result\n";
    }
    if (r.comp.sessions > 0) {
      const CompFigures& c = r.comp;
      out << "  cutter compensation: " << c.sessions << " entr" << (c.sessions == 1 ? "y" : "ies") << ", tool diameter up to "
          << f4(2.0 * c.max_radius_mm) << " mm: " << c.moves_in << " moves offset (biarcs counted) -> " << c.moves_out
          << " tool moves (" << c.corner_arcs << " convex corner arcs, " << c.concave_corners
          << " concave corners cut back)\n";
      if (c.fitted_nurbs + c.fitted_runs > 0) {
        out << "  biarc fit: " << c.biarcs << " biarcs (" << c.fit_arcs << " arcs) replaced " << c.moves_replaced
            << " programmed moves (" << c.fitted_nurbs << " NURBS curves, " << c.fitted_runs
            << " runs of short G1 moves); max deviation " << f4(c.max_fit_deviation_mm * 1000.0) << " um\n";
      }
    }
  } else {
    out << o.file << ": OK\n";
  }
  if (o.print_blocks) {
    try {
      BlockStream stream(o.file, config, job, r.transform);
      Block b;
      std::uint64_t seq = 0;
      while (stream.next(b)) {
        ++seq;
        out << seq << " " << format_block(b) << "\n";
      }
    } catch (const std::exception& e) {
      err << "pcnc check: " << e.what() << "\n";
      return kExitBadInput;
    }
  }
  return 0;
}

void add_check_subcommand(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<CheckCommandOptions>();
  CLI::App* sub =
      app.add_subcommand("check", "check a G-code program without a machine: syntax, words, arcs, soft limits, feeds");
  sub->add_option("FILE", opts->file, "G-code program, or a ruled-surface program in the JSON file form (a .json file: pcnc ruled --json, docs/ruled-surface.md), run as the G-code form the host makes of it")->required();
  sub->add_option("--config", opts->config_path,
                  "machine configuration (TOML); default: $PCNC_CONFIG or configs/desktop-mill.toml");
  sub->add_flag("--fit", opts->fit, "scale the program down uniformly (never up) and centre it so it fits the travel");
  sub->add_option("--offset", opts->offset, "program zero in machine coordinates X,Y,Z mm (default: the config's G54)");
  sub->add_option("--contouring", opts->contouring, "contouring at program start: on|off (default: the config's)");
  sub->add_option("--tolerance", opts->tolerance,
                  "path tolerance in mm for the whole program (smoothing, merging, corner speed); default: the "
                  "config's motion.path_tolerance_mm, changed by G64 P")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_flag("--print-blocks", opts->print_blocks, "print the preprocessed ring blocks, one per line");
  sub->add_flag("--print-moves", opts->print_moves,
                "print the moves as they leave the interpreter (L<line> <kind> (x,y,z)->(x,y,z), machine mm) and "
                "the MSG/DEBUG messages, in program order; checks the program as G-code only (not the travel)");
  sub->add_option("--tool-table", opts->tool_table, "tool table (LinuxCNC format, mm); default: the config's gcode.tool_table");
  sub->add_option("--surface", opts->surface,
                  "correct Z of every move by this measured surface (`pcnc surface fit`'s file; docs/surface.md)");
  sub->add_flag("-q,--quiet", opts->quiet, "print only errors and the verdict");
  sub->callback([opts, &exit_code] { exit_code = run_check_command(*opts, std::cout, std::cerr, stderr); });
}

}  // namespace pcnc
