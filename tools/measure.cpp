// measure.cpp — `pcnc measure` (see measure.hpp): the command line, the three phases and the
// files. The mathematics is shared/geometry's (probe_calibration, volumetric_error,
// probe_grid_plan, probe_compensation, sphere_fit); this file runs programs and reads logs.
#include "measure.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "config/atomic_file.hpp"
#include "config/calibration_file.hpp"
#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/point_grid_csv.hpp"
#include "config/runtime_paths.hpp"
#include "config/surface_file.hpp"
#include "ctl.hpp"
#include "ctl_support.hpp"
#include "geometry/probe_compensation.hpp"
#include "geometry/probe_grid_plan.hpp"
#include "geometry/sphere_fit.hpp"
#include "measure_program.hpp"

namespace pcnc {
namespace {

using json = nlohmann::json;

struct MeasureOptions {
  std::string output;
  std::string config_path;
  std::string socket;
  std::string grid;         // X0,Y0,X1,Y1,NX,NY
  std::string points;       // a list of X,Y
  std::string estimate;     // a B-spline estimate of the workpiece
  std::optional<double> z;  // the plane estimate's height
  std::string calibration;  // read back instead of calibrating
  std::string save_calibration;
  std::string work_dir;
  double feed = 60.0;
  double clearance = 0.5;
  double distance = 1.0;
  std::optional<double> safe_z;
  bool no_volumetric = false;
  int per_ring = 12;
  double timeout_s = 3600.0;
};

// The reference objects' geometry is certified: their touches start 0.5 mm before the
// expected contact and may go 1 mm past it (--clearance and --distance are the workpiece's).
constexpr double kReferenceClearance = 0.5, kReferenceDistance = 1.0;

// An error that ends the command with `status`; the message goes to stderr.
struct Failure {
  int status;
  std::string message;
};

void say(const std::string& s) { std::fprintf(stderr, "pcnc measure: %s\n", s.c_str()); }

std::string fmt_row(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}

// Runs one generated program on the served machine and returns the probe log's points.
class Runner {
 public:
  Runner(CtlClient& c, const MeasureOptions& o, std::string dir) : c_(c), o_(o), dir_(std::move(dir)) {}

  std::vector<Vec3> run(const std::string& name, const std::vector<PlannedTouch>& touches, double safe_z) {
    const std::string program = dir_ + "/" + name + ".ngc", log = dir_ + "/" + name + ".log";
    std::error_code ec;
    std::filesystem::remove(log, ec);
    std::string error;
    if (!write_file_atomically(program, probing_program(touches, safe_z, o_.feed, log, name), &error))
      throw Failure{kExitBadInput, program + ": cannot be written: " + error};
    json ended;
    long long count0 = -1, shown = -1;
    auto last_shown = std::chrono::steady_clock::now();
    c_.on_notification = [&](const json& n) {
      const std::string method = n.value("method", "");
      const json p = n.value("params", json::object());
      if (method == "event" && p.value("event", "") == "program_end") ended = p;
      if (method == "status" && p.contains("probe")) {
        const long long count = p["probe"].value("count", 0ll);
        if (count0 < 0) count0 = count;
        const auto now = std::chrono::steady_clock::now();
        if (count != shown && now - last_shown > std::chrono::seconds(2)) {
          shown = count, last_shown = now;
          say(name + ": touch " + std::to_string(count - count0) + " of " + std::to_string(touches.size()));
        }
      }
    };
    const json st = c_.call("status", json::object(), 30.0);
    if (st.contains("result")) count0 = st["result"].value("probe", json::object()).value("count", 0ll);
    c_.call("subscribe", json{{"rate_hz", 2}}, 30.0);
    say(name + ": " + std::to_string(touches.size()) + " touches (" + program + ")");
    const json r = c_.call("run", json{{"file", program}, {"offset", json{{"x", 0.0}, {"y", 0.0}, {"z", 0.0}}}}, 60.0);
    if (r.contains("error")) {
      const json& e = r["error"];
      std::string msg = name + ": the machine refused the probing program: " + e.value("message", std::string("?"));
      for (const auto& x : e.value("data", json::object()).value("errors", json::array())) msg += "\n  " + x.get<std::string>();
      const int code = e.value("code", 0);
      throw Failure{code == 3 ? kExitBadInput : code == 2 ? kExitProcessDied : kExitFault, msg};
    }
    const auto t0 = std::chrono::steady_clock::now();
    while (ended.is_null()) {
      if (ctl::g_ctl_interrupt.load()) {
        c_.call("stop", json::object(), 30.0);
        throw Failure{kExitSignalBase + SIGINT, name + ": interrupted; the program was stopped"};
      }
      if (std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(o_.timeout_s))
        throw Failure{kExitFault, name + ": no end after " + std::to_string(o_.timeout_s) + " s (--timeout)"};
      std::string line;
      if (!c_.read_line(line, 0.2)) continue;
      const json n = json::parse(line, nullptr, false);
      if (!n.is_discarded() && !n.contains("id") && c_.on_notification) c_.on_notification(n);
    }
    c_.call("subscribe", json{{"rate_hz", 0}}, 30.0);
    c_.on_notification = nullptr;
    if (ended.value("end", "") != "completed") {
      const std::string message = ended.value("message", std::string());
      std::string hint;
      if (message.find("already triggered") != std::string::npos)
        hint = " (the object is nearer than planned: for the workpiece raise --z or --clearance)";
      else if (message.find("without the probe triggering") != std::string::npos)
        hint = " (the object is farther than planned: for the workpiece check --z or raise --distance)";
      throw Failure{kExitFault, name + ": the probing program ended '" + ended.value("end", std::string("?")) + "': " +
                                    message + hint};
    }
    std::vector<Vec3> latched = read_probe_log(log);
    if (latched.size() != touches.size())
      throw Failure{kExitFault, log + ": " + std::to_string(latched.size()) + " results for " +
                                    std::to_string(touches.size()) + " touches"};
    return latched;
  }

 private:
  CtlClient& c_;
  const MeasureOptions& o_;
  std::string dir_;
};

// The nine approach directions that locate a ball's centre: straight down and eight at 50°
// from the vertical.
std::vector<Vec3> ball_approaches() {
  std::vector<Vec3> d{{0.0, 0.0, -1.0}};
  for (int k = 0; k < 8; ++k) d.push_back(approach_direction(50.0 * std::numbers::pi / 180.0, k * std::numbers::pi / 4.0));
  return d;
}

// The pitch tables' layout from the artefact's balls: per axis the distinct levels of their
// centres (within 0.5 mm), nodes evenly from the lowest to the highest level; one level: no
// pitch table on that axis.
VolumetricError artefact_layout(const TableScene& t) {
  VolumetricError layout;
  for (int i = 0; i < kAxes; ++i) {
    std::vector<double> levels;
    for (int b = 0; b < t.artefact_balls; ++b) levels.push_back(t.artefact_centres[static_cast<std::size_t>(b)][i]);
    std::sort(levels.begin(), levels.end());
    std::vector<double> distinct;
    for (double v : levels)
      if (distinct.empty() || v - distinct.back() > 0.5) distinct.push_back(v);
    PitchTable& p = layout.pitch[static_cast<std::size_t>(i)];
    if (distinct.size() < 2) continue;
    p.count = std::min<int>(static_cast<int>(distinct.size()), kMaxPitchNodes);
    p.start_mm = distinct.front();
    p.step_mm = (distinct.back() - distinct.front()) / (p.count - 1);
  }
  return layout;
}

void calibrate_volumetric_phase(Runner& runner, const MachineConfig& cfg, const MeasureOptions& o, double safe_z,
                                MeasureCalibration& cal) {
  const TableScene& t = cfg.table;
  if (o.no_volumetric) {
    say("volumetric: skipped (--no-volumetric): no volumetric error assumed");
    return;
  }
  if (t.artefact_balls < 2)
    throw Failure{kExitBadInput, cfg.source_path + ": [workpiece] has no reference artefact (artefact_balls_mm, "
                                 "artefact_ball_radius_mm): the volumetric calibration needs one (or --no-volumetric)"};
  const std::vector<Vec3> dirs = ball_approaches();
  std::vector<PlannedTouch> touches;
  for (int b = 0; b < t.artefact_balls; ++b) {
    const auto one = sphere_touches(t.artefact_centres[static_cast<std::size_t>(b)], t.artefact_ball_radius_mm,
                                    cfg.probe.model.ball_radius_mm, dirs, kReferenceClearance, kReferenceDistance);
    touches.insert(touches.end(), one.begin(), one.end());
  }
  const std::vector<Vec3> latched = runner.run("artefact", touches, safe_z);
  std::vector<Vec3> centres;
  for (int b = 0; b < t.artefact_balls; ++b) {
    const std::vector<Vec3> pts(latched.begin() + b * static_cast<long>(dirs.size()),
                                latched.begin() + (b + 1) * static_cast<long>(dirs.size()));
    const SphereFit f = fit_sphere(pts);
    if (!f.ok()) throw Failure{kExitFault, "artefact ball " + std::to_string(b + 1) + ": " + f.error};
    centres.push_back(f.centre);
  }
  std::vector<LengthMeasurement> lengths;
  for (int i = 0; i < t.artefact_balls; ++i)
    for (int j = i + 1; j < t.artefact_balls; ++j)
      lengths.push_back({centres[static_cast<std::size_t>(i)], centres[static_cast<std::size_t>(j)],
                         norm(t.artefact_centres[static_cast<std::size_t>(j)] - t.artefact_centres[static_cast<std::size_t>(i)])});
  const VolumetricCalibration v = calibrate_volumetric(lengths, artefact_layout(t));
  if (!v.ok()) throw Failure{kExitFault, "volumetric calibration on the artefact: " + v.error};
  cal.volumetric = v.model;
  cal.artefact_lengths = static_cast<int>(lengths.size());
  cal.artefact_rms_before_mm = v.rms_before, cal.artefact_rms_after_mm = v.rms_after;
  cal.artefact_max_before_mm = v.max_before, cal.artefact_max_after_mm = v.max_after;
  say(fmt_row("volumetric: %.0f lengths between the artefact's balls, error RMS %.3f -> %.3f um, max %.3f -> ", lengths.size(),
          v.rms_before * 1e3, v.rms_after * 1e3, v.max_before * 1e3) +
      fmt_row("%.3f um; squareness XY %.1f YZ %.1f ZX %.1f urad", v.max_after * 1e3, v.model.squareness_xy_urad,
          v.model.squareness_yz_urad, v.model.squareness_zx_urad));
}

void calibrate_probe_phase(Runner& runner, const MachineConfig& cfg, const MeasureOptions& o, double safe_z,
                           MeasureCalibration& cal) {
  const TableScene& t = cfg.table;
  if (!(t.sphere_radius_mm > 0.0))
    throw Failure{kExitBadInput, cfg.source_path + ": [workpiece] has no reference sphere (sphere_center_mm, "
                                 "sphere_radius_mm): the probe calibration needs one"};
  const CalibrationLayout layout;  // 7 polar nodes (15°) x order 4
  const std::vector<Vec3> dirs = calibration_directions(layout, o.per_ring);
  const auto touches = sphere_touches(t.sphere_center, t.sphere_radius_mm, cfg.probe.model.ball_radius_mm, dirs,
                                      kReferenceClearance, kReferenceDistance);
  const std::vector<Vec3> latched = runner.run("sphere", touches, safe_z);
  std::vector<ProbeTouch> pt;
  for (std::size_t i = 0; i < latched.size(); ++i) pt.push_back({actual_position(cal.volumetric, latched[i]), touches[i].approach});
  // The sphere's centre is known (the artefact's certificate): r_eff then absorbs what a
  // constant offset of the probe or of the calibrated machine coordinates would add.
  const ProbeCalibrationResult r = calibrate_probe(pt, t.sphere_radius_mm, layout, &t.sphere_center);
  if (!r.ok()) throw Failure{kExitFault, "probe calibration on the reference sphere: " + r.error};
  cal.probe = r.cal;
  cal.probe_touches = static_cast<int>(pt.size());
  cal.probe_rms_mm = r.rms, cal.probe_max_mm = r.max_abs;
  cal.sphere_centre_mm = t.sphere_center;
  cal.sphere_radius_mm = t.sphere_radius_mm;
  const double R = cfg.probe.model.ball_radius_mm;
  say(fmt_row("probe: %.0f touches on the sphere, residuals RMS %.3f max %.3f um; pre-travel ", static_cast<double>(pt.size()),
          r.rms * 1e3, r.max_abs * 1e3) +
      fmt_row("down %.2f um, sideways +X %.2f +Y %.2f -X %.2f um", (R - effective_radius(r.cal, {0, 0, -1})) * 1e3,
          (R - effective_radius(r.cal, {1, 0, 0})) * 1e3, (R - effective_radius(r.cal, {0, 1, 0})) * 1e3,
          (R - effective_radius(r.cal, {-1, 0, 0})) * 1e3));
}

// "a,b,c,..." → numbers; empty when malformed.
std::vector<double> parse_numbers(const std::string& s) {
  std::vector<double> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !std::isfinite(v)) return {};
    out.push_back(v);
  }
  return out;
}

// The X/Y list of --points: "x,y" per line; a header line and # comments are skipped.
std::vector<std::pair<double, double>> read_xy_list(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure{kExitBadInput, path + ": cannot be read"};
  std::vector<std::pair<double, double>> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#' || (n == 1 && line.find_first_of("0123456789") == std::string::npos)) continue;
    const std::vector<double> v = parse_numbers(line);
    if (v.size() != 2) throw Failure{kExitBadInput, path + ":" + std::to_string(n) + ": expected X,Y in mm"};
    out.emplace_back(v[0], v[1]);
  }
  if (out.size() < 3) throw Failure{kExitBadInput, path + ": at least 3 points are needed"};
  return out;
}

std::string points_csv(const std::vector<Vec3>& pts) {
  std::string s = "x,y,z\n";
  char buf[128];
  for (const Vec3& p : pts) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g\n", p[0], p[1], p[2]);
    s += buf;
  }
  return s;
}

int measure(const MeasureOptions& o) {
  MachineConfig cfg;
  try {
    cfg = load_config(o.config_path);
    check_output_paths({{o.output, "-o"}, {o.save_calibration, "--save-calibration"}});
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) say(p);
    return kExitBadInput;
  } catch (const std::exception& e) {
    say(e.what());
    return kExitBadInput;
  }
  try {
    if (!cfg.probe.present) throw Failure{kExitBadInput, cfg.source_path + ": the machine has no [probe]"};
    if (o.grid.empty() == o.points.empty()) throw Failure{kExitBadInput, "give --grid or --points (one of them)"};
    if (!(o.feed > 0.0) || !(o.clearance > 0.0) || !(o.distance > 0.0))
      throw Failure{kExitBadInput, "--feed, --clearance and --distance must be > 0"};
    // what to probe, before anything moves
    ProbeGridSpec spec;
    spec.ball_radius_mm = cfg.probe.model.ball_radius_mm;
    spec.clearance_mm = o.clearance;
    spec.probe_distance_mm = o.distance;
    std::vector<std::pair<double, double>> xy;
    if (!o.grid.empty()) {
      const std::vector<double> g = parse_numbers(o.grid);
      if (g.size() != 6 || g[4] != std::floor(g[4]) || g[5] != std::floor(g[5]) || g[4] < 2 || g[5] < 2 || g[4] > 200 ||
          g[5] > 200 || !(g[2] > g[0]) || !(g[3] > g[1]))
        throw Failure{kExitBadInput, "--grid '" + o.grid + "': expected X0,Y0,X1,Y1,NX,NY (mm; X1 > X0, Y1 > Y0, 2..200 points a side)"};
      spec.x0_mm = g[0], spec.y0_mm = g[1], spec.x1_mm = g[2], spec.y1_mm = g[3];
      spec.nx = static_cast<int>(g[4]), spec.ny = static_cast<int>(g[5]);
    } else {
      xy = read_xy_list(o.points);
    }
    std::optional<BSplineSurface> estimate_surface;
    SurfaceEstimate estimate;
    if (!o.estimate.empty()) {
      try {
        estimate_surface = load_surface_file(o.estimate);
      } catch (const std::exception& e) {
        throw Failure{kExitBadInput, e.what()};
      }
      estimate.surface = &*estimate_surface;
    } else if (o.z) {
      estimate.z0_mm = *o.z;
    } else if (cfg.table.has_surface && !cfg.table.bspline) {
      estimate.z0_mm = cfg.table.z_mm;
    } else {
      throw Failure{kExitBadInput, "where is the workpiece? give --z (its height, mm) or --estimate S.json"};
    }
    const double safe_z = o.safe_z ? *o.safe_z : cfg.axes[2].travel_max_mm - 1.0;
    MeasureCalibration cal;
    bool calibrated_now = false;
    if (!o.calibration.empty()) {
      try {
        cal = load_calibration_file(o.calibration);
      } catch (const std::exception& e) {
        throw Failure{kExitBadInput, e.what()};
      }
      say("calibration read from " + o.calibration + fmt_row(" (probe: %.0f touches, RMS %.3f um; artefact: %.0f lengths)",
                                                         cal.probe_touches, cal.probe_rms_mm * 1e3, cal.artefact_lengths));
    }
    std::string dir = o.work_dir;
    bool remove_dir = false;
    if (dir.empty()) {
      std::string tmpl = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : std::string("/tmp")) + "/pcnc-measure-XXXXXX";
      if (mkdtemp(tmpl.data()) == nullptr) throw Failure{kExitFault, "cannot create a temporary directory " + tmpl};
      dir = tmpl;
      remove_dir = true;
    } else {
      std::error_code ec;
      std::filesystem::create_directories(dir, ec);
      dir = std::filesystem::absolute(dir).lexically_normal().string();
    }
    struct Cleanup {
      std::string d;
      bool on;
      ~Cleanup() {
        std::error_code ec;
        if (on) std::filesystem::remove_all(d, ec);
      }
    } cleanup{dir, remove_dir};

    CtlOptions co;
    co.socket = o.socket;
    co.config_path = o.config_path;
    std::string socket = o.socket;
    if (socket.empty()) socket = find_control_socket(cfg);
    ctl::install_interrupt();
    std::vector<Vec3> result;
    int status = kExitOk;
    {
      CtlClient client = [&]() -> CtlClient {
        try {
          return CtlClient(socket);
        } catch (const std::exception& e) {
          throw Failure{kExitProcessDied, std::string(e.what()) + " (start the machine with `pcnc serve`)"};
        }
      }();
      Runner runner(client, o, dir);
      if (o.calibration.empty()) {
        calibrate_volumetric_phase(runner, cfg, o, safe_z, cal);
        calibrate_probe_phase(runner, cfg, o, safe_z, cal);
        calibrated_now = true;
        const std::string path = o.save_calibration.empty()
                                     ? (std::filesystem::path(o.output).parent_path() / "measure-calibration.json").string()
                                     : o.save_calibration;
        try {
          save_calibration_file(path, cal);
        } catch (const std::exception& e) {
          throw Failure{kExitBadInput, e.what()};
        }
        say("calibration written to " + path + " (reuse it with --calibration)");
      }
      // the workpiece
      std::vector<ProbePoint> plan;
      if (!o.grid.empty()) {
        const ProbeGridPlan p = plan_probe_grid(spec, estimate);
        if (!p.ok()) throw Failure{kExitBadInput, "--grid: " + p.error};
        plan = p.points;
      } else {
        for (std::size_t i = 0; i < xy.size(); ++i) {
          ProbePoint pp = plan_probe_point(xy[i].first, xy[i].second, spec, estimate);
          pp.col = static_cast<int>(i);
          plan.push_back(pp);
        }
      }
      std::vector<PlannedTouch> touches;
      std::vector<Vec3> approaches;
      for (const ProbePoint& p : plan) {
        touches.push_back({p.start, p.end, p.approach});
        approaches.push_back(p.approach);
      }
      const std::vector<Vec3> latched = runner.run("workpiece", touches, safe_z);
      std::vector<Vec3> centres;
      for (const Vec3& p : latched) centres.push_back(actual_position(cal.volumetric, p));
      if (!o.grid.empty()) {
        PointGrid g;
        g.cols = spec.nx, g.rows = spec.ny, g.points = centres;
        const GridCompensation comp = compensate_grid(g, approaches, cal.probe);
        if (!comp.ok()) throw Failure{kExitFault, "compensation of the grid: " + comp.error};
        result = comp.contacts.points;
      } else {
        const PointsCompensation comp = compensate_points(centres, approaches, cal.probe);
        if (!comp.ok()) throw Failure{kExitFault, "compensation of the points: " + comp.error};
        result = comp.contacts;
      }
    }
    (void)calibrated_now;
    std::string error;
    if (!write_file_atomically(o.output, points_csv(result), &error)) throw Failure{kExitBadInput, o.output + ": cannot be written: " + error};
    say("wrote " + std::to_string(result.size()) + " compensated points to " + o.output +
        (o.grid.empty() ? std::string() : " (" + std::to_string(spec.nx) + " x " + std::to_string(spec.ny) + " grid; `pcnc surface fit` reads it)"));
    return status;
  } catch (const Failure& f) {
    say(f.message);
    return f.status;
  } catch (const std::exception& e) {  // the socket lost, a log unreadable
    say(e.what());
    return kExitProcessDied;
  }
}

}  // namespace

void add_measure_subcommand(CLI::App& app, int& exit_code) {
  static MeasureOptions o;
  o.config_path = default_config_path();
  auto* m = app.add_subcommand(
      "measure",
      "measure the workpiece on a served machine (`pcnc serve`) with its touch probe: calibrate the volumetric error on "
      "the reference artefact and the probe on the reference sphere (the config's [workpiece]), probe a grid or a list of "
      "points along the surface normal, write the compensated points as CSV (x,y,z; docs/measurement.md)");
  m->add_option("-o,--output", o.output, "the compensated points (CSV: x,y,z, machine mm; a grid in rows of constant y)")->required();
  m->add_option("--grid", o.grid, "probe a grid: X0,Y0,X1,Y1,NX,NY (machine mm; NX points a row, NY rows)");
  m->add_option("--points", o.points, "probe a list of points instead: a file of X,Y lines (machine mm)")->check(CLI::ExistingFile);
  m->add_option("--z", o.z, "the workpiece's expected height (mm; a plane): touches straight down (default: the config's "
                            "[workpiece] z_mm)");
  m->add_option("--estimate", o.estimate, "a B-spline surface file (a design or an earlier measurement): touches along its normals")
      ->check(CLI::ExistingFile);
  m->add_option("--calibration", o.calibration, "read the calibrations from this file instead of calibrating")->check(CLI::ExistingFile);
  m->add_option("--save-calibration", o.save_calibration,
                "where to write the calibrations (default: measure-calibration.json beside -o)");
  m->add_option("--config", o.config_path, "machine configuration (TOML): the reference sphere and artefact, the probe, the socket")
      ->capture_default_str();
  m->add_option("--socket", o.socket, "the control socket (default: the one `pcnc serve` of --config listens on)");
  m->add_option("--feed", o.feed, "probing feed, mm/min (capped by the machine so the stop fits the overtravel)")->capture_default_str();
  m->add_option("--clearance", o.clearance, "each probing move on the workpiece starts this far (mm) before the expected contact (the reference objects': 0.5)")->capture_default_str();
  m->add_option("--distance", o.distance, "and may go this far (mm) past it before it is an error (the reference objects': 1)")->capture_default_str();
  m->add_option("--safe-z", o.safe_z, "the height to cross at between touches (default: 1 mm below the Z travel's top)");
  m->add_option("--per-ring", o.per_ring, "touches per polar ring on the reference sphere (>= 9)")->check(CLI::Range(9, 72))->capture_default_str();
  m->add_flag("--no-volumetric", o.no_volumetric, "skip the artefact: assume no volumetric error");
  m->add_option("--work-dir", o.work_dir, "keep the generated programs and probe logs here (default: a temporary directory, removed)");
  m->add_option("--timeout", o.timeout_s, "seconds each probing program may take")->capture_default_str();
  m->callback([&exit_code] { exit_code = measure(o); });
}

}  // namespace pcnc
