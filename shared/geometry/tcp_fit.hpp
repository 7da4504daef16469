// tcp_fit.hpp — `--fit` for a tool-centre-point program on a 5-axis machine (issue 16, item 3):
// the largest uniform scale s <= 1 and the offset o of X, Y, Z (never the angles) such that,
// with every programmed tip p placed at s·p + o in workpiece coordinates and the tool axes
// unchanged, every joint stays within its travel after the inverse kinematics, at the
// programmed poses and at samples along every move (tip on the line, axis on the great circle,
// as tcp_path.hpp runs them). The tilt and rotary joints depend on the tool axis alone, so they
// are checked once and never scaled: a program whose axes leave their travel is refused, as is
// one with moves outside tool-centre-point control that turn a rotary joint (its joint values
// do not scale). With the angles fixed, each sample's x, y, z are an affine function of its tip,
// so for one s the offsets that fit form a convex polytope: whether it is empty is a linear
// program (minmax_lp.hpp), and s is found by bisection. The 3-axis fit is fit_to_travel in
// host/gcode/preflight.hpp; docs/kinematics.md ("--fit of a tool-centre-point program"). Pure.
#pragma once

#include <string>
#include <vector>

#include "geometry/kinematics.hpp"

namespace pcnc {

/// One programmed pose, in the order the program reaches them.
struct FitPose {
  ToolPose pose;        // tip in program coordinates (before the offset), unit tool axis
  bool tcp = true;      // false: reached with tool-centre-point control off (M429)
  double tilt = 0.0;    // with tcp off: the tilt and rotary words (rad); must be 0 to be fitted
  double rotary = 0.0;
  int line = 0;         // for messages
  // With tcp off, a move on which only the joints turn (the linear axes stand still: "turn C
  // first, with TCP off"): its linear joints are `joint_xyz` (program coordinates, scaled and
  // moved like a point), its angles `tilt` and `rotary` are kept, and `pose` is the tool pose
  // those joints give (the start of a TCP move that follows it). Not refused.
  bool turn_only = false;
  Vec3 joint_xyz{};
};

/// Where the joints may go: x, y, z in machine mm, and the rotary joints' travel.
struct JointTravel {
  Vec3 min{}, max{};
  RotaryTravel rotary{};
};

struct TcpFitResult {
  bool ok = false;
  std::string error;    // when !ok: why no scale fits, naming the line
  int error_line = 0;   // when !ok: that line (0: the whole program)
  double scale = 1.0;   // s
  Vec3 offset{};        // o: a program point p lands at s·p + o (workpiece coordinates)
  double margin_mm = 0.0;  // the smallest distance of a sampled joint x, y, z from its travel limits at (s, o)
  int samples = 0;      // poses checked (programmed poses and the dense points along the moves)
};

/// `start`: the joints before the first pose (the machine's home), for the choice among the
/// inverse's solutions. Each move is sampled `samples_per_move` (>= 2) times evenly for the
/// linear programs (a move into a turn-only pose: its end alone, the joints run linearly), and 8 times as densely (plus the sample nearest the pole, tcp_path.hpp) to
/// check the result: joints that leave the travel between the coarse samples (x, y, z are not
/// linear along a move that turns the table) add those samples and the fit is found again, so
/// the result holds at every dense sample. The first pose is sampled alone (the move to it from
/// the machine's position is not the program's). `tolerance`: s is found to within it.
TcpFitResult fit_tcp_program(const std::vector<FitPose>& poses, const Kinematics& kin, const JointTravel& travel,
                             const Joints& start, int samples_per_move = 16, double tolerance = 1e-9);

}  // namespace pcnc
