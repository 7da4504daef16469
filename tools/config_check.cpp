// config_check.cpp — `pcnc config check [FILE]`: loads a machine config the way both
// processes do and prints the machine as it was understood (axes, travel, limits, drive,
// gains, cycle rate, contouring, timing), or every problem found (exit 2).
#include "config_check.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <cmath>
#include <memory>
#include <sstream>

#include "config/config.hpp"
#include "config/exit_status.hpp"

namespace pcnc {
namespace {

std::string plain_num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string pad(const std::string& s, std::size_t width) { return s.size() >= width ? s + " " : s + std::string(width - s.size(), ' '); }

// The rotary joints and the kinematics (degrees at this edge; the config holds radians).
void print_rotary(const MachineConfig& c, std::ostream& out) {
  const Kinematics& k = c.kinematics;
  auto point = [](const Vec3& p) { return "(" + plain_num(p[0]) + ", " + plain_num(p[1]) + ", " + plain_num(p[2]) + ") mm"; };
  if (k.kind == KinematicsKind::kTrivial) {
    out << "  kinematics   trivial (X Y Z, no rotary joints)\n";
    return;
  }
  out << "  kinematics   " << (k.kind == KinematicsKind::kTableTable ? "xyzac-trt (A tilts the table, C turns it)"
                                                                     : "xyzbc-head-table (B tilts the head, C turns the table)")
      << "; tilt pivot " << point(k.tilt_pivot) << ", rotary pivot " << point(k.rotary_pivot)
      << "; tool length from the tool table\n";
  auto deg = [](double rad) { return plain_num(rad * kDegPerRad); };
  out << "  joint travel deg            home deg  v_max deg/s  a_max deg/s^2  f.err limit deg  encoder deg\n";
  for (const auto& r : c.rotary) {
    if (!r) continue;
    const std::string travel =
        r->continuous ? std::string("continuous")
                      : deg(r->travel_min_rad) + " .. " + deg(r->travel_max_rad) + " (" +
                            deg(r->travel_max_rad - r->travel_min_rad) + ")";
    out << "  " << pad(std::string(1, r->letter), 6) << pad(travel, 22) << pad(deg(r->home_rad), 10)
        << pad(deg(r->max_velocity_rad_s), 13) << pad(deg(r->max_accel_rad_s2), 15)
        << pad(deg(r->following_error_limit_rad), 17) << deg(r->encoder_resolution_rad) << "\n";
  }
  out << "  joint J kg m^2  Kt N m/A  I_max A  T_max N m  viscous N m s/rad  Coulomb N m  drive a_max deg/s^2\n";
  for (const auto& r : c.rotary) {
    if (!r) continue;
    const double torque = r->torque_constant_nm_per_a * r->current_limit_a;
    out << "  " << pad(std::string(1, r->letter), 6) << pad(plain_num(r->inertia_kg_m2), 10)
        << pad(plain_num(r->torque_constant_nm_per_a), 10) << pad(plain_num(r->current_limit_a), 9) << pad(plain_num(torque), 11)
        << pad(plain_num(r->viscous_friction_nm_s_per_rad), 19) << pad(plain_num(r->coulomb_friction_nm), 13)
        << deg(torque / r->inertia_kg_m2) << "\n";
  }
  out << "  joint Kp A/deg  Ki A/(deg s)  Kd A s/deg  D filter Hz  Vff A s/deg  Aff A s^2/deg  Fff A  I limit A\n";
  for (const auto& r : c.rotary) {
    if (!r) continue;
    const double per_deg = kRadPerDeg;  // gains per rad inside, per deg in the file
    out << "  " << pad(std::string(1, r->letter), 6) << pad(plain_num(r->kp_a_per_rad * per_deg), 10)
        << pad(plain_num(r->ki_a_per_rad_s * per_deg), 14) << pad(plain_num(r->kd_a_s_per_rad * per_deg), 12)
        << pad(plain_num(r->derivative_filter_hz), 13) << pad(plain_num(r->velocity_ff_a_s_per_rad * per_deg), 13)
        << pad(plain_num(r->accel_ff_a_s2_per_rad * per_deg), 15) << pad(plain_num(r->friction_ff_a), 7)
        << plain_num(r->integrator_limit_a) << "\n";
  }
}

// The machine as understood, one block per subject.
void print_machine(const MachineConfig& c, std::ostream& out) {
  const char* axis_names = "XYZ";
  out << c.source_path << ": OK: machine '" << c.name << "'\n";
  out << "  cycle        " << plain_num(c.motion.cycle_hz) << " Hz (period " << plain_num(c.cycle_period_s() * 1e6)
      << " us); plant sub-steps " << plain_num(c.motion.subsample_steps) << "; shared memory " << c.process.shm_name << "\n";
  out << "  contouring   angle " << plain_num(c.motion.contouring_angle_deg) << " deg, at program start "
      << (c.motion.contouring_default ? "on (M21)" : "off (M22)") << ", junction velocity step "
      << plain_num(c.motion.junction_velocity_step_fraction) << " x a_max x period, path tolerance "
      << plain_num(c.motion.path_tolerance_mm) << " mm"
      << (c.motion.path_tolerance_mm > 0.0
              ? " (G1 runs smoothed, real corners over " + plain_num(c.motion.smoothing_angle_deg) +
                    " deg passed at the junction-deviation speed)"
              : std::string(" (off: corners sharper than the angle stop)"))
      << "\n";
  out << "  speeds       rapids "
      << (c.motion.rapid_speed_mm_s > 0.0 ? plain_num(c.motion.rapid_speed_mm_s) + " mm/s" : std::string("each axis's max velocity"))
      << "; max feed "
      << (c.gcode.max_feed_mm_min > 0.0 ? plain_num(c.gcode.max_feed_mm_min) + " mm/min" : std::string("from the axis limits"))
      << ", F above it " << (c.gcode.clamp_excess_feed ? "clamped with a warning" : "refused") << "; jogs at "
      << plain_num(c.motion.jog_accel_fraction) << " of each axis's acceleration\n";
  out << "  axis  travel mm           home mm   v_max mm/s  a_max mm/s^2  f.err limit mm  encoder mm\n";
  for (int i = 0; i < kAxes; ++i) {
    const AxisConfig& a = c.axes[static_cast<std::size_t>(i)];
    out << "  " << pad(std::string(1, axis_names[i]), 6)
        << pad(plain_num(a.travel_min_mm) + " .. " + plain_num(a.travel_max_mm) + " (" + plain_num(a.travel_max_mm - a.travel_min_mm) + ")", 20)
        << pad(plain_num(a.home_mm), 10) << pad(plain_num(a.max_velocity_mm_s), 12) << pad(plain_num(a.max_accel_mm_s2), 14)
        << pad(plain_num(a.following_error_limit_mm), 16) << plain_num(a.encoder_resolution_mm) << "\n";
  }
  out << "  axis  mass kg  Kf N/A  I_max A  F_max N  gravity N  viscous N s/m  Coulomb N  drive a_max mm/s^2\n";
  for (int i = 0; i < kAxes; ++i) {
    const AxisConfig& a = c.axes[static_cast<std::size_t>(i)];
    const double force = a.force_constant_n_per_a * a.current_limit_a;
    // what the drive can give against gravity, before friction: the planner's a_max must stay below it
    const double drive_accel = (force - std::abs(a.gravity_load_n)) / a.moving_mass_kg * 1000.0;
    out << "  " << pad(std::string(1, axis_names[i]), 6) << pad(plain_num(a.moving_mass_kg), 9)
        << pad(plain_num(a.force_constant_n_per_a), 8) << pad(plain_num(a.current_limit_a), 9) << pad(plain_num(force), 9)
        << pad(plain_num(a.gravity_load_n), 11) << pad(plain_num(a.viscous_friction_n_s_per_m), 15) << pad(plain_num(a.coulomb_friction_n), 11)
        << plain_num(drive_accel) << "\n";
  }
  out << "  axis  Kp A/mm  Ki A/(mm s)  Kd A s/mm  D filter Hz  Vff A s/mm  Aff A s^2/mm  Fff A  I limit A\n";
  for (int i = 0; i < kAxes; ++i) {
    const AxisConfig& a = c.axes[static_cast<std::size_t>(i)];
    out << "  " << pad(std::string(1, axis_names[i]), 6) << pad(plain_num(a.kp_a_per_mm), 9) << pad(plain_num(a.ki_a_per_mm_s), 13)
        << pad(plain_num(a.kd_a_s_per_mm), 11) << pad(plain_num(a.derivative_filter_hz), 13) << pad(plain_num(a.velocity_ff_a_s_per_mm), 12)
        << pad(plain_num(a.accel_ff_a_s2_per_mm), 14) << pad(plain_num(a.friction_ff_a), 7) << plain_num(a.integrator_limit_a) << "\n";
  }
  print_rotary(c, out);
  out << "  timing       host lost after " << plain_num(c.process.host_timeout_s) << " s, rt lost after "
      << plain_num(c.process.rt_timeout_s) << " s, jog dead-man " << plain_num(c.process.jog_deadman_s) << " s, idle client closed after "
      << (c.process.client_idle_timeout_s > 0.0 ? plain_num(c.process.client_idle_timeout_s) + " s" : std::string("never"))
      << "; rt SCHED_FIFO priority " << c.process.rt_priority << ", spin " << plain_num(c.process.rt_spin_us) << " us\n";
  out << "  g-code       arc radius tolerance " << plain_num(c.gcode.arc_radius_tolerance_mm) << " mm + "
      << plain_num(c.gcode.arc_radius_tolerance_rel) << " x r; NURBS knots "
      << (c.gcode.nurbs_knots == 0 ? "open uniform" : "chord length") << ", chord tolerance "
      << plain_num(c.gcode.nurbs_chord_tolerance_mm) << " mm\n";
  for (int i = 0; i < 6; ++i) {
    const Vec3& o = c.gcode.work_offsets[static_cast<std::size_t>(i)];
    out << (i == 0 ? "  offsets      " : "               ") << "G" << 54 + i << " (" << plain_num(o[0]) << ", " << plain_num(o[1])
        << ", " << plain_num(o[2]) << ") mm\n";
  }
  out << "  files        socket " << (c.process.socket_path.empty() ? std::string("(default runtime directory)") : c.process.socket_path)
      << ", journal " << (c.process.state_dir.empty() ? std::string("(default state directory)") : c.process.state_dir)
      << "; trace failure: " << (c.process.trace_failure_stops ? "stop" : "continue") << "\n";
  if (c.probe.present) {  // docs/probe.md
    const ProbeModel& p = c.probe.model;
    out << "  probe        ball R " << plain_num(p.ball_radius_mm) << " mm, pre-travel axial " << plain_num(p.pretravel_axial_mm)
        << " mm, lateral " << plain_num(p.pretravel_lateral_mm) << " + " << plain_num(p.pretravel_lobe_mm)
        << " x cos 3az mm, repeatability " << plain_num(p.repeatability_mm) << " mm (seed " << p.seed << "), overtravel "
        << plain_num(p.overtravel_mm) << " mm\n";
  } else {
    out << "  probe        none (G38.x refused)\n";
  }
  const TableScene& t = c.table;
  out << "  table        ";
  if (t.has_surface) {
    out << "workpiece top z = " << plain_num(t.z_mm) << " + " << plain_num(t.slope_x) << " x + " << plain_num(t.slope_y) << " y mm";
    if (t.bump_height_mm != 0.0) {
      out << " + bump " << plain_num(t.bump_height_mm) << " mm (sigma " << plain_num(t.bump_sigma_mm) << " mm) at (" << plain_num(t.bump_x_mm)
          << ", " << plain_num(t.bump_y_mm) << ")";
    }
  } else {
    out << "no workpiece";
  }
  if (t.sphere_radius_mm > 0.0) {
    out << "; sphere R " << plain_num(t.sphere_radius_mm) << " mm at (" << plain_num(t.sphere_center[0]) << ", " << plain_num(t.sphere_center[1])
        << ", " << plain_num(t.sphere_center[2]) << ")";
  }
  if (t.has_gauge) {
    out << "; gauge block (" << plain_num(t.gauge_min[0]) << ", " << plain_num(t.gauge_min[1]) << ", " << plain_num(t.gauge_min[2]) << ") .. ("
        << plain_num(t.gauge_max[0]) << ", " << plain_num(t.gauge_max[1]) << ", " << plain_num(t.gauge_max[2]) << ")";
  }
  out << "\n";
}

// Plausibility notes that do not refuse the config (stderr).
void print_notes(const MachineConfig& c, std::ostream& err) {
  for (const auto& r : c.rotary) {
    if (!r) continue;
    const double drive = r->torque_constant_nm_per_a * r->current_limit_a / r->inertia_kg_m2;  // rad/s^2
    if (drive < r->max_accel_rad_s2) {
      err << c.source_path << ": warning: [axis." << static_cast<char>(r->letter + 32) << "] max_accel_deg_s2 "
          << plain_num(r->max_accel_rad_s2 * kDegPerRad) << " deg/s^2 is more than the drive can give ("
          << plain_num(drive * kDegPerRad) << " deg/s^2 = torque_constant x current_limit / inertia): expect following-error faults\n";
    }
  }
  const char* axis_names = "XYZ";
  for (int i = 0; i < kAxes; ++i) {
    const AxisConfig& a = c.axes[static_cast<std::size_t>(i)];
    const double drive_accel = (a.force_constant_n_per_a * a.current_limit_a - std::abs(a.gravity_load_n)) / a.moving_mass_kg * 1000.0;
    if (drive_accel < a.max_accel_mm_s2) {
      err << c.source_path << ": warning: [axis." << static_cast<char>(axis_names[i] + 32) << "] max_accel_mm_s2 "
          << plain_num(a.max_accel_mm_s2) << " mm/s^2 is more than the drive can give (" << plain_num(drive_accel)
          << " mm/s^2 = (force_constant x current_limit - |gravity|) / mass): expect following-error faults\n";
    }
  }
}

}  // namespace

int run_config_check(const std::string& path, bool quiet, std::ostream& out, std::ostream& err) {
  MachineConfig config;
  try {
    config = load_config(path);
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) err << "pcnc config check: " << p << "\n";
    err << "pcnc config check: " << path << ": " << e.problems.size() << " problem" << (e.problems.size() == 1 ? "" : "s")
        << "; the config is refused\n";
    return kExitBadInput;
  }
  if (quiet) {
    out << path << ": OK\n";
  } else {
    print_machine(config, out);
    print_notes(config, err);
  }
  return kExitOk;
}

void add_config_subcommand(CLI::App& app, int& exit_code) {
  auto* config = app.add_subcommand("config", "machine configuration files");
  config->require_subcommand(1);
  auto* check = config->add_subcommand(
      "check", "load a machine config (TOML) as pcnc-rt and pcnc-host do; print the machine as understood, or every "
               "problem (exit 2)");
  auto path = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  check->add_option("FILE", *path, "the config; default: $PCNC_CONFIG or configs/desktop-mill.toml");
  check->add_flag("-q,--quiet", *quiet, "print only the verdict (problems still go to stderr)");
  check->callback([path, quiet, &exit_code] {
    exit_code = run_config_check(path->empty() ? default_config_path() : *path, *quiet, std::cout, std::cerr);
  });
}

}  // namespace pcnc
