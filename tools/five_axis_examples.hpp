// five_axis_examples.hpp — the project's own 5-axis test programs (examples/5axis/, issue 16):
// an impeller-like blade cut by flank passes along its twisted ruled surface, a helix on a
// tilted axis with the tool leaning out of it (in G93 inverse time), and passes over a dome
// that go through and beside the XYZAC singularity (A = 0, where C is undetermined). Each is
// a list of tool poses (tip and tool axis in program coordinates) built from a small geometry
// whose functions are exposed here so that tests can check the programmed points against it;
// five_axis_program_lines writes the poses in the dialect of LinuxCNC's XYZAC demos
// (M428 ... M429, `G1 X Y Z A C F`), the angles from pcnc's inverse kinematics. Pure.
#pragma once

#include <string>
#include <vector>

#include "geometry/kinematics.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One programmed pose: the tool tip (program coordinates, mm) and the unit tool axis (tip to
/// spindle, workpiece frame). `rapid`: reached by G0, else by G1 at the program's feed.
struct ProgramPose {
  Vec3 tip{};
  Vec3 axis{0.0, 0.0, 1.0};
  bool rapid = false;
};

struct FiveAxisExample {
  std::string file;                 // "impeller-blade.ngc"
  std::vector<std::string> header;  // comment lines (without parentheses)
  std::vector<ProgramPose> poses;   // from the first G0 to the last move
  double feed_mm_min = 240.0;       // of the tool tip
  bool inverse_time = false;        // G93: F on every G1 = feed / tip length (per minute)
};

// ---- the geometries (program coordinates of desktop-5axis.toml: program zero, its G54, lies on
// the C axis 25 mm above the table face, so the table face is Z-25) ----

/// A blade standing on a hub: the ruled surface between the hub curve (at hub_z) and the
/// shroud curve (at shroud_z), both at the radius r0 + (r1 − r0)·u from the C axis, the shroud
/// turned by a twist that grows along the blade: a twisted, non-developable ruled surface.
struct Blade {
  double hub_z = -22.0, shroud_z = -16.0;         // mm
  double r0 = 2.0, r1 = 6.0;                      // mm from the C axis, u = 0 .. 1
  double start_deg = -20.0, sweep_deg = 40.0;     // angle of the hub point: start + sweep·u
  double twist0_deg = 15.0, twist1_deg = 35.0;    // the shroud point leads by twist0 + (twist1 − twist0)·u
  double half_thickness = 0.3;                    // the faces lie this far either side of the ruled surface
  double tool_radius = 1.0;                       // flat end mill
  double stock = 0.2;                             // left by the first pass on each face
};
Vec3 blade_hub(const Blade& b, double u);
Vec3 blade_shroud(const Blade& b, double u);
/// The unit ruling (hub to shroud) at u.
Vec3 blade_ruling(const Blade& b, double u);
/// The unit normal of the ruled surface along the hub edge at u (perpendicular to the ruling
/// and to the hub curve's tangent), pointing to the blade's leading side.
Vec3 blade_normal(const Blade& b, double u);

/// A helix about an axis tilted `tilt_deg` from +Z towards the azimuth `toward_deg`, starting
/// at `base`; the tool axis leans `lean_deg` out of the helix's axis, towards the tip's radial
/// direction, so that A and C both move all the way round.
struct TiltedHelix {
  Vec3 base{0.0, 0.0, -22.0};
  double tilt_deg = 20.0, toward_deg = -90.0;
  double radius = 4.0, pitch = 1.5, turns = 3.0;
  double lean_deg = 25.0;
  double step_deg = 6.0;  // angle between programmed points
};
/// The helix's axis w and the two unit vectors e1, e2 across it (e1 × e2 = w).
void helix_frame(const TiltedHelix& h, Vec3& w, Vec3& e1, Vec3& e2);
/// The tip point and the tool axis at the helix angle theta (rad, 0 at the start).
ProgramPose helix_pose(const TiltedHelix& h, double theta);

/// A dome (sphere) the tool stays normal to: the tool axis is the outward normal at the tip.
struct Dome {
  Vec3 centre{2.0, -1.5, -22.0};
  double radius = 5.0;
  double beside_deg = 2.0;   // the second pass's great circle misses the pole by this much
  double reach_deg = 40.0;   // each pass runs to this tilt from the pole
  double step_deg = 4.0;
};

// ---- the programs ----

FiveAxisExample impeller_blade_example(const Blade& b = {});
FiveAxisExample tilted_helix_example(const TiltedHelix& h = {});
FiveAxisExample singularity_example(const Dome& d = {});
std::vector<FiveAxisExample> five_axis_examples();

/// The program text, one string per line: the header, G21 G90 G17 G54 and G94 or G93, M428,
/// one `G0|G1 X Y Z A C [F]` line per pose (X Y Z 4 decimals; A C in degrees, 4 decimals),
/// M429, M2. A and C are the inverse kinematics of each pose (tip = pose tip + `work_offset`,
/// the G54 point) nearest the joints before it (within `travel`), starting from `start`:
/// the joints the machine takes, so that a C through the singularity keeps its value and a
/// continuous C is written unwrapped. Where a move leaves the pole (A = 0, C undetermined)
/// towards another C than the joints stand at, C is turned first with TCP off: before M428
/// (`G0 C`) at the start, or on the pole where the tool arrived (the pose written with the C it
/// arrived with, M429, `G0 C`, M428, the pose again with the new C); the poses on the pole carry
/// the C the tool leaves it with, as the planner requires (host/gcode/tcp_move.cpp).
std::vector<std::string> five_axis_program_lines(const FiveAxisExample& e, const Kinematics& kin,
                                                 const RotaryTravel& travel, const Vec3& work_offset,
                                                 const Joints& start);

}  // namespace pcnc
