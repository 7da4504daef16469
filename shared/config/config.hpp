// config.hpp — the machine configuration both processes read from one TOML file
// (configs/desktop-mill.toml by default). Every limit, gain and tolerance lives here, in SI-ish
// units named in the keys (mm, s, kg, N, A). Nothing physical is hard-coded elsewhere.
#pragma once

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/rotary_config.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/probe_contact.hpp"
#include "geometry/volumetric_error.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One linear axis: travel, motion limits, the simulated drive, the encoder and its servo.
struct AxisConfig {
  // travel and limits
  double travel_min_mm = 0.0;
  double travel_max_mm = 25.0;
  double max_velocity_mm_s = 50.0;
  double max_accel_mm_s2 = 1000.0;
  double following_error_limit_mm = 0.5;
  double home_mm = 0.0;  // where the axis stands when pcnc-rt starts (inside the travel)

  // simulated drive (plant)
  double moving_mass_kg = 1.0;
  double force_constant_n_per_a = 10.0;
  double current_limit_a = 5.0;
  double viscous_friction_n_s_per_m = 0.0;
  double coulomb_friction_n = 0.0;
  double gravity_load_n = 0.0;  // constant force along -axis (Z carries its own weight)
  double encoder_resolution_mm = 0.0001;

  // servo (PID on position error, output = amplifier current in A)
  double kp_a_per_mm = 0.0;
  double ki_a_per_mm_s = 0.0;
  double kd_a_s_per_mm = 0.0;
  double derivative_filter_hz = 500.0;
  double velocity_ff_a_s_per_mm = 0.0;
  double accel_ff_a_s2_per_mm = 0.0;
  double friction_ff_a = 0.0;       // Coulomb friction feed-forward: this current × sign(commanded velocity)
  double integrator_limit_a = 1.0;  // anti-windup clamp of the integral term
};

struct MotionConfig {
  double cycle_hz = 2000.0;             // servo and interpolation rate
  double contouring_angle_deg = 10.0;   // M21: junctions turning less than this do not stop
  bool contouring_default = false;      // contouring mode at program start (M21/M22 override)
  // Junction speed cap under contouring: the velocity vector may jump by at most this
  // fraction of the smallest axis acceleration times one cycle period.
  double junction_velocity_step_fraction = 1.0;
  // Path tolerance under M21 (0: off, the seed's rule alone; G64 P and --tolerance set it for a
  // program): the largest distance the commanded path may keep from the programmed points and
  // segments. The host merges collinear runs and smooths runs of short G1 moves within it
  // (host/gcode/smoothing.hpp), and every junction may also be passed at the junction-deviation
  // speed of a virtual arc that stays within it of the corner (grbl's and Klipper's rule;
  // rt/junction.hpp), corners sharper than the contouring angle included.
  double path_tolerance_mm = 0.0;
  // Smoothing: a junction of two G1 moves turning more than this is a real corner (kept).
  double smoothing_angle_deg = 30.0;
  // Not a TOML key: set with path_tolerance_mm by `--tolerance` (pcnc run, check, serve). The
  // operator's tolerance then holds for the whole program: G64 P does not change it.
  bool path_tolerance_fixed = false;
  double rapid_speed_mm_s = 0.0;        // 0: each axis's max velocity (projected on the move)
  double jog_accel_fraction = 1.0;      // jogs use this fraction of each axis's acceleration
  double subsample_steps = 8.0;         // plant integration sub-steps per cycle (if needed)
  // rt block check: how far a block's start may sit from the previous block's end (and its
  // stated length from its geometry) before the rt refuses it as corrupt.
  double block_tolerance_mm = 0.001;
};

/// `--tolerance MM`: the operator's path tolerance for every program (G64 P then ignored).
inline void set_operator_tolerance(MotionConfig& m, double mm) {
  m.path_tolerance_mm = mm;
  m.path_tolerance_fixed = true;
}

struct GcodeConfig {
  double arc_radius_tolerance_mm = 0.002;   // |r_end - r_start| allowed (absolute part)
  double arc_radius_tolerance_rel = 0.001;  // ... plus this fraction of the radius
  bool clamp_excess_feed = true;            // F above the machine maximum: clamp (warn) or reject
  double max_feed_mm_min = 0.0;             // 0: from the axis limits
  // G54..G59, mm, program zero in machine coordinates: the defaults of the work-coordinate
  // state (config/work_state.hpp) until its file exists; the file then wins.
  std::array<Vec3, 6> work_offsets{};
  int nurbs_knots = 0;                      // 0: open uniform (LinuxCNC); 1: chord length (seed)
  double nurbs_chord_tolerance_mm = 0.001;  // δ of the NURBS feed schedule
  // --surface: how far a move corrected by the measured surface may leave the corrected path
  // between its split points while the path tolerance (motion.path_tolerance_mm) is 0;
  // a path tolerance > 0 is used instead (host/gcode/surface_correction.hpp).
  double surface_tolerance_mm = 0.001;
  // Lines a program may execute (loops and subroutine calls count each time they run): a loop
  // that never ends is an error at this count, not a hang. Key: max_executed_lines.
  double max_executed_lines = 50e6;
  // LinuxCNC-format tool table (host/gcode/tool_table.hpp); empty: none. A relative path in
  // the file is made relative to the config file's directory when the config is parsed.
  std::string tool_table;
  // A measured surface file (config/surface_file.hpp) every program is corrected by
  // (host/gcode/surface_correction.hpp); empty: none. Relative to the config file, as
  // tool_table. `--surface S.json` on run, check, serve and pcnc-host sets it.
  std::string surface;
  bool pause_on_tool_change = false;        // M6 pauses the program for the operator (false: it does not)
};

// [cutter_comp], every key optional: cutter radius compensation (host/gcode/cutter_comp.hpp).
struct CutterCompConfig {
  // The exact gouge test over the look-ahead window (true), or LinuxCNC's local tests alone.
  bool gouge_check = true;
  // Biarc fitting under G41/G42: a run of >= 8 G1 moves each shorter than this is one smooth curve.
  double fit_segment_max_mm = 0.5;
  double fit_tolerance_mm = 0.001;  // the biarcs' maximum deviation from the curve
};

struct ProcessConfig {
  std::string shm_name = "/pcnc-desktop-mill";
  // Empty: the default in the machine's runtime directory (config/runtime_paths.hpp); a path
  // set here is honoured after its directory is checked.
  std::string socket_path;
  int socket_mode = 0600;
  std::string socket_group;        // group (name or number) of the socket and its runtime directory; empty: ours
  std::string state_dir;           // journal; empty: the default private state directory (runtime_paths.hpp)
  double host_timeout_s = 0.1;     // rt: host heartbeat older than this while running -> HOST_LOST
  double rt_timeout_s = 0.1;       // host: rt heartbeat older than this -> rt lost
  double jog_deadman_s = 0.5;      // continuous jog stops without a keep-alive this long
  double client_idle_timeout_s = 60.0;  // service: a connection without requests this long is closed (0: never)
  int rt_priority = 80;            // SCHED_FIFO priority asked for
  // Real clock: the rt sleeps until this long before each deadline and spins the rest, so
  // that the wake-up does not pay the idle CPU's exit latency (a virtual machine's idle vCPU
  // can take milliseconds to wake). Costs this fraction of a core: spin / period. 0: sleep.
  double rt_spin_us = 0.0;
  // When the rt's trace file cannot be written (disk full, I/O error): true ("stop"): a running
  // program stops along the path and no program starts until the rt is restarted; false
  // ("continue"): programs run on without a trace. Either way the failure is logged and
  // published (Status::trace_failed) and `pcnc run` exits non-zero. Key: on_trace_failure.
  bool trace_failure_stops = true;
};

// [probe], optional: a touch-trigger probe in the spindle whose ball centre is the controlled
// point (docs/probe.md). Absent: the machine has no probe and G38.x is refused.
struct ProbeConfig {
  bool present = false;
  ProbeModel model{};
};

struct MachineConfig {
  std::string name = "desktop-mill";
  std::string source_path;  // the file it came from
  std::array<AxisConfig, kAxes> axes{};
  MotionConfig motion{};
  GcodeConfig gcode{};
  CutterCompConfig cutter_comp{};
  ProcessConfig process{};
  // Rotary joints [axis.a], [axis.b], [axis.c] (index 0, 1, 2; absent: none) and [kinematics]
  // (default: trivial, the 3-axis mill). The tool length is the tool table's, not the config's.
  std::array<std::optional<RotaryAxisConfig>, kRotaryAxes> rotary{};
  Kinematics kinematics{};
  ProbeConfig probe{};
  TableScene table{};  // [workpiece], optional: what the probe can touch (docs/probe.md)
  // [machine_error], optional: where the machine really is when its encoders read p is
  // actual_position(machine_error, p); only the simulated probe sees it (docs/measurement.md).
  bool has_machine_error = false;
  VolumetricError machine_error{};

  double cycle_period_s() const { return 1.0 / motion.cycle_hz; }
  /// The kinematics' tilt joint (A of table-table, B of head-table) and its rotary joint (C);
  /// nullptr on the trivial machine.
  const RotaryAxisConfig* tilt_joint() const {
    if (kinematics.kind == KinematicsKind::kTableTable && rotary[0]) return &*rotary[0];
    if (kinematics.kind == KinematicsKind::kHeadTable && rotary[1]) return &*rotary[1];
    return nullptr;
  }
  const RotaryAxisConfig* rotary_joint() const {
    return kinematics.kind != KinematicsKind::kTrivial && rotary[2] ? &*rotary[2] : nullptr;
  }
  /// The joints' travel for the inverse kinematics' choice of solution (geometry/kinematics.hpp):
  /// unbounded for a continuous joint or on the trivial machine.
  RotaryTravel rotary_travel() const {
    RotaryTravel t;
    if (const RotaryAxisConfig* a = tilt_joint(); a && !a->continuous) {
      t.tilt_min = a->travel_min_rad;
      t.tilt_max = a->travel_max_rad;
    }
    if (const RotaryAxisConfig* c = rotary_joint(); c && !c->continuous) {
      t.rotary_min = c->travel_min_rad;
      t.rotary_max = c->travel_max_rad;
    }
    return t;
  }
  /// The declared rotary joints, a bit per joint (A 1, B 2, C 4).
  std::uint8_t rotary_mask() const {
    std::uint8_t m = 0;
    for (int i = 0; i < kRotaryAxes; ++i) {
      if (rotary[static_cast<std::size_t>(i)]) m = static_cast<std::uint8_t>(m | (1u << i));
    }
    return m;
  }
  Vec3 travel_min() const { return {axes[0].travel_min_mm, axes[1].travel_min_mm, axes[2].travel_min_mm}; }
  Vec3 travel_max() const { return {axes[0].travel_max_mm, axes[1].travel_max_mm, axes[2].travel_max_mm}; }
};

/// Reads a TOML machine configuration. Every section and key that defines the machine is
/// required (a missing [axis.z] must not fall back to built-in values); unknown keys and
/// out-of-range values are errors (a typo in a gain must not pass silently). The few optional
/// keys and their defaults are listed in docs/configuration.md. Throws ConfigError listing
/// every problem found, each naming the file (with line:column where the text has one), the
/// section, the key and why, with the key's unit.
MachineConfig load_config(const std::string& path);
/// Same, from TOML text (for tests); `origin` names it in messages.
MachineConfig parse_config(const std::string& toml_text, const std::string& origin);

/// Where the default config lives: $PCNC_CONFIG, else configs/desktop-mill.toml found
/// relative to the executable's directory (build tree or install), else the working directory.
std::string default_config_path();

/// A config that cannot be used. what() is all problems, one per line; `problems` holds them apart.
struct ConfigError : std::runtime_error {
  explicit ConfigError(const std::string& what) : std::runtime_error(what), problems{what} {}
  explicit ConfigError(std::vector<std::string> all);
  std::vector<std::string> problems;
};

}  // namespace pcnc
