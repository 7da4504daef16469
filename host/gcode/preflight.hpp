// preflight.hpp — pipeline stage after the interpreter (and the geometry stages to come;
// gcode/pipeline.hpp): checks every move of a program before anything moves.
//
// Soft limits (every end point, every arc's extreme points and every NURBS curve's extreme
// points against the configured travel, in machine coordinates after work offset and --fit
// scale), and the program's figures: extents,
// move count, last point, feed time. Also the --fit transform computed from the extents.
// O(1) memory: only the first violation per axis and side is reported, then counted.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "config/config.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/move.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/tcp_fit.hpp"

namespace pcnc {

/// Axis-aligned box; empty until the first point.
struct Box {
  Vec3 min{1e300, 1e300, 1e300};
  Vec3 max{-1e300, -1e300, -1e300};
  void add(const Vec3& p, std::uint8_t axes = 7) {
    for (int i = 0; i < kAxes; ++i) {
      if (!((axes >> i) & 1u)) continue;
      const auto k = static_cast<std::size_t>(i);
      if (p[k] < min[k]) min[k] = p[k];
      if (p[k] > max[k]) max[k] = p[k];
    }
  }
  bool has(int axis) const { return min[static_cast<std::size_t>(axis)] <= max[static_cast<std::size_t>(axis)]; }
};

/// Calls f(point) for the end point and every extreme point of an arc (where an in-plane
/// coordinate peaks), in machine coordinates. An arc whose end radius differs from its start
/// radius (within the arc tolerance) is taken at the larger of the two, as the rt's block
/// check takes its bulge (ipc/block_check.cpp), so that what the preflight and --fit let
/// through the rt accepts too.
template <class F>
void for_each_extreme(const Move& m, F&& f);

class Preflight {
 public:
  Preflight(const MachineConfig& config, DiagnosticSink& sink, bool check_limits);

  void add(const Move& m);
  /// --fit on a machine with rotary joints: also hand every move's end pose (tip in the frame's
  /// machine coordinates, tool axis, TCP on or off, the joints' values) to `out`, in order, and
  /// the tool length of the TCP moves to `tool_length` (geometry/tcp_fit.hpp). Only the --fit
  /// measuring pass collects; a normal run keeps O(1) memory.
  void collect_fit_poses(std::vector<FitPose>* out, double* tool_length) {
    fit_poses_ = out;
    fit_tool_length_ = tool_length;
  }
  /// Reports the soft-limit counts per axis (call once at the end).
  void finish();

  std::uint64_t moves() const { return moves_; }
  const Box& extents() const { return all_; }      // every point, machine coordinates
  const Box& fit_extents() const { return fit_; }  // program-frame points the program set itself
  const Vec3& last_point() const { return last_; }
  double feed_time_s() const { return feed_time_s_; }

 private:
  void check_point(const Move& m, const Vec3& p);
  void add_nurbs(const Move& m);
  bool within_seen(const Move& m) const;  // a NURBS move that cannot change the extents nor leave the travel
  const MachineConfig& config_;
  DiagnosticSink& sink_;
  bool check_limits_;
  std::uint64_t moves_ = 0;
  Box all_;
  Box fit_;
  Vec3 last_{};
  double feed_time_s_ = 0.0;
  std::array<std::uint64_t, 6> violations_{};  // per axis: [2*i] below min, [2*i+1] above max
  std::array<std::uint64_t, 6> rot_violations_{};  // per rotary joint A B C, as violations_
  // Rotary joints (preflight_rotary.cpp): a move that turns one (its end within the joint's
  // travel) or runs under TCP (the joints sampled along it, linear ones included)
  void add_rotary(const Move& m);
  void add_ruled(const Move& m);  // G5.4 ... G5.5: the joints along the piece (preflight_rotary.cpp)
  void check_joint(const Move& m, int joint, double value_rad, const char* where);
  void check_linear_joint(const Move& m, int axis, double value_mm);
  // every joint's extremes along a TCP move or a ruled piece (linear ones included)
  void check_joint_extremes(const Move& m, const Joints& q_min, const Joints& q_max, const char* where);
  std::vector<Vec3> points_;                     // scratch: a NURBS curve's extreme points
  void add_fit_pose(const Move& m);
  std::vector<FitPose>* fit_poses_ = nullptr;
  double* fit_tool_length_ = nullptr;
};

/// The --fit transform for program points spanning `box` (machine coordinates under the frame
/// `offset`, scale 1): the largest uniform scale <= 1 that fits the travel, then centred on the
/// travel. Axes the box does not cover keep `offset`.
struct FitResult {
  Vec3 offset{};
  double scale = 1.0;
};
/// `tool_radius_mm` > 0: the box was measured on a cutter-compensated path at scale 1, which
/// lies that far beside the contour; the scale leaves it unscaled (--fit scales the path, never
/// the tool): s = (travel - 2r) / (extent - 2r).
FitResult fit_to_travel(const Box& box, const Vec3& offset, const MachineConfig& config, double tool_radius_mm = 0.0);

/// Path length of a move (line: distance; arc: helix length; NURBS: arc length).
double move_length(const Move& m);

// ---- template implementation ----
template <class F>
void for_each_extreme(const Move& m, F&& f) {
  f(m.end);
  if (m.kind != MoveKind::kArc) return;
  const auto pa = plane_axes(m.normal_axis);
  const auto a0 = static_cast<std::size_t>(pa[0]);
  const auto a1 = static_cast<std::size_t>(pa[1]);
  const auto nk = static_cast<std::size_t>(m.normal_axis);
  constexpr double kHalfPi = 1.57079632679489661923;
  const double t0 = std::atan2(m.start[a1] - m.center[a1], m.start[a0] - m.center[a0]);
  const double lo = std::min(t0, t0 + m.sweep);
  const double hi = std::max(t0, t0 + m.sweep);
  const double helix = m.end[nk] - m.start[nk];
  const double r_end = std::hypot(m.end[a0] - m.center[a0], m.end[a1] - m.center[a1]);
  const double r_start = std::hypot(m.start[a0] - m.center[a0], m.start[a1] - m.center[a1]);
  const double r = std::max({m.radius, r_start, r_end});  // the rt's spiral reaches the larger
  for (double k = std::ceil(lo / kHalfPi); k * kHalfPi <= hi; k += 1.0) {
    const double t = k * kHalfPi;
    Vec3 p = m.center;
    p[a0] = m.center[a0] + r * std::cos(t);
    p[a1] = m.center[a1] + r * std::sin(t);
    p[nk] = m.start[nk] + (m.sweep != 0.0 ? helix * (t - t0) / m.sweep : 0.0);
    f(p);
  }
}

}  // namespace pcnc
