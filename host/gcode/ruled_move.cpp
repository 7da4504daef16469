// ruled_move.cpp — a ruled move's joint walk, feed cap and blocks (see ruled_move.hpp).
#include "gcode/ruled_move.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "config/joint_map.hpp"
#include "geometry/kinematics_rates.hpp"
#include "geometry/ruled_motion.hpp"
#include "ipc/block_ruled.hpp"

namespace pcnc {
namespace {

// The joints' limits in kinematics order (x y z tilt rotary); +inf where the joint is absent.
void joint_limits(const MachineConfig& cfg, Joints& vmax, Joints& amax) {
  for (int i = 0; i < 3; ++i) {
    vmax[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_velocity_mm_s;
    amax[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_accel_mm_s2;
  }
  const double inf = std::numeric_limits<double>::infinity();
  vmax[kTilt] = vmax[kRotary] = amax[kTilt] = amax[kRotary] = inf;
  const int idx[2] = {tilt_index(cfg), rotary_index(cfg)};
  for (int k = 0; k < 2; ++k) {
    if (idx[k] < 0 || !cfg.rotary[static_cast<std::size_t>(idx[k])]) continue;
    vmax[static_cast<std::size_t>(kTilt + k)] = cfg.rotary[static_cast<std::size_t>(idx[k])]->max_velocity_rad_s;
    amax[static_cast<std::size_t>(kTilt + k)] = cfg.rotary[static_cast<std::size_t>(idx[k])]->max_accel_rad_s2;
  }
}

}  // namespace

Joints ruled_start_joints(const Move& m, const MachineConfig& cfg) {
  const Kinematics kin = kinematics_with_tool(cfg, m.tool_length);
  const Joints seed = to_joints(cfg, Vec3{}, m.rot_start);
  // the tool axis the joints give now, with the start tip: the linear axes where they stand
  const ToolPose now = forward(kin, seed);
  return inverse(kin, ToolPose{m.start, now.axis}, seed, cfg.rotary_travel());
}

RuledJointWalk walk_ruled_piece(const RuledModel& model, const MachineConfig& cfg, double tool_length, const Joints& q0) {
  RuledJointWalk w;
  const Kinematics kin = kinematics_with_tool(cfg, tool_length);
  const RotaryTravel travel = cfg.rotary_travel();
  const RuledCurves c = model.curves();
  const int n = static_cast<int>(model.directrix.size());
  Joints q = q0;
  w.q_min = w.q_max = q0;
  for (int s = 0; s <= n * kRuledSamplesPerSegment; ++s) {
    const double u = static_cast<double>(s) / kRuledSamplesPerSegment;
    const RuledJet j = ruled_jet(c, u);
    const Joints q_prev = q;
    q = inverse(kin, ToolPose{j.c.p, j.e.p}, q, travel);
    // the rotary joints move continuously between samples: a jump is the tool axis leaving the
    // pole of the rotary joint toward another angle than the one it stands at
    if (s > 0 && (std::abs(q[kRotary] - q_prev[kRotary]) > kRuledJointJump || std::abs(q[kTilt] - q_prev[kTilt]) > kRuledJointJump)) {
      w.error = "the ruled piece turns the rotary joint by " + std::to_string((q[kRotary] - q_prev[kRotary]) * 180.0 / 3.14159265358979) +
                " deg between two samples at u = " + std::to_string(u) +
                " (the tool axis leaves the pole toward another angle than the joint stands at); expected the joint "
                "turned toward the piece's tilt before the G5.4";
      return w;
    }
    for (std::size_t i = 0; i < q.size(); ++i) {
      if (!std::isfinite(q[i])) {
        w.error = "the tool pose at u = " + std::to_string(u) + " of the ruled piece has no joint solution";
        return w;
      }
      w.q_min[i] = std::min(w.q_min[i], q[i]);
      w.q_max[i] = std::max(w.q_max[i], q[i]);
    }
    // joint rates at a tip speed of 1 mm/s (constant): q' = dq/ds and q'' = d²q/ds²
    const ToolMotion tm = tool_motion(j, u, 1.0, 0.0);
    const Joints dq = joint_rates(kin, q, PoseRate{tm.velocity, tm.axis_velocity});
    const Joints ddq = joint_accels(kin, q, dq, PoseRate{tm.acceleration, tm.axis_acceleration});
    Joints r{}, b{};
    for (std::size_t i = 0; i < q.size(); ++i) r[i] = std::abs(dq[i]), b[i] = std::abs(ddq[i]);
    w.rate.push_back(r);
    w.bend.push_back(b);
  }
  w.q_end = q;
  return w;
}

double ruled_tangential_accel(const RuledJointWalk& w, const MachineConfig& cfg) {
  Joints vmax{}, amax{};
  joint_limits(cfg, vmax, amax);
  double accel = std::numeric_limits<double>::infinity();
  for (const AxisConfig& a : cfg.axes) accel = std::min(accel, a.max_accel_mm_s2);
  accel *= kRuledLimitShare;
  for (const Joints& r : w.rate)
    for (std::size_t i = 0; i < r.size(); ++i)
      if (r[i] > 0.0) accel = std::min(accel, kRuledTangentialShare * kRuledLimitShare * amax[i] / r[i]);
  return accel;
}

void cap_ruled_feed(RuledJointWalk& w, const MachineConfig& cfg, double accel) {
  Joints vmax{}, amax{};
  joint_limits(cfg, vmax, amax);
  double cap = std::numeric_limits<double>::infinity();
  w.speed_joint = -1;
  w.sample_caps.clear();
  for (std::size_t s = 0; s < w.rate.size(); ++s) {
    double here = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < static_cast<std::size_t>(kJoints); ++i) {
      const double r = w.rate[s][i], b = w.bend[s][i];
      const double fv = r > 0.0 ? kRuledLimitShare * vmax[i] / r : here;
      // what the tangential acceleration leaves of the joint's budget for the path's term
      const double left = std::max(0.0, kRuledLimitShare * amax[i] - r * accel);
      const double fa = b > 0.0 ? std::sqrt(left / b) : here;
      here = std::min({here, fv, fa});
      if (std::min(fv, fa) < cap) {
        cap = std::min(fv, fa);
        w.speed_joint = static_cast<int>(i);
      }
    }
    w.sample_caps.push_back(here);
  }
  w.feed_cap = cap;
}

std::vector<double> ruled_feed_schedule(const RuledModel& part, const std::vector<double>& sample_caps, double feed,
                                        double accel) {
  const int n = static_cast<int>(part.directrix.size());
  const int per = kRuledSamplesPerSegment;
  std::vector<double> v(static_cast<std::size_t>(n) + 1, feed);
  // point i caps the speed on [i - 1, i + 1]: the line to either neighbour stays under every
  // sample's cap of the segment between them
  for (int i = 0; i <= n; ++i) {
    const int lo = std::max(0, (i - 1) * per), hi = std::min(n * per, (i + 1) * per);
    for (int s = lo; s <= hi && s < static_cast<int>(sample_caps.size()); ++s) {
      v[static_cast<std::size_t>(i)] = std::min(v[static_cast<std::size_t>(i)], sample_caps[static_cast<std::size_t>(s)]);
    }
  }
  // the backward pass: every drop reachable at half the tangential acceleration (the rt reads
  // the schedule one cycle ahead only, and a line in u between two points asks up to twice the
  // acceleration of the squares' difference)
  for (int i = n - 1; i >= 0; --i) {
    const double ds = hermite_arc_length(HermiteView{part.directrix.data() + i, 1});
    const auto k = static_cast<std::size_t>(i);
    v[k] = std::min(v[k], std::sqrt(v[k + 1] * v[k + 1] + accel * ds));
  }
  return v;
}

void set_ruled_block_fields(Block& b) {
  const RuledCurves c = curves_of(b.ruled);
  const RuledJet j0 = ruled_jet(c, 0.0), j1 = ruled_jet(c, b.ruled.segment_count);
  b.kind = BlockKind::kRuled;
  b.start = j0.c.p;
  b.end = j1.c.p;
  b.length = b.ruled.length;
  b.speed = 0.0;
  for (int i = 0; i < b.ruled.schedule_count; ++i) b.speed = std::max(b.speed, b.ruled.schedule_speed[i]);
  b.dir_start = normalized(j0.c.d1);
  b.dir_end = normalized(j1.c.d1);
  const RuledExtent e = ruled_extent(b.ruled);
  b.motion_class = e.moving <= 1 ? MotionClass::kSingleAxis : static_cast<MotionClass>(e.moving);
  b.driving_axis = static_cast<std::uint8_t>(e.widest);
  b.driving_dir = b.end[e.widest] >= b.start[e.widest] ? 1 : -1;
  b.rotary.tcp = 1;
  b.rotary.axis_start = j0.e.p;
  b.rotary.axis_end = j1.e.p;
}

RuledMoveBlocks plan_ruled_move(const Move& m, const MachineConfig& cfg) {
  RuledMoveBlocks out;
  if (!m.ruled || m.ruled->directrix.empty()) {
    out.error = "a ruled move without its piece";
    return out;
  }
  const Joints q0 = ruled_start_joints(m, cfg);
  RuledJointWalk whole = walk_ruled_piece(*m.ruled, cfg, m.tool_length, q0);
  if (!whole.error.empty()) {
    out.error = whole.error;
    return out;
  }
  // the tip's tangential acceleration, one for the whole piece (its parts flow into each other;
  // kept for braking and holds too): what the slowest linear axis allows, and what leaves every
  // joint half its budget for the path's term
  const double accel = ruled_tangential_accel(whole, cfg);
  cap_ruled_feed(whole, cfg, accel);
  out.speed_joint = whole.feed_cap < m.feed_mm_s ? whole.speed_joint : -1;
  const std::vector<RuledModel> parts = split_for_blocks(*m.ruled);
  Joints q = q0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const RuledModel& part = parts[k];
    RuledJointWalk w = walk_ruled_piece(part, cfg, m.tool_length, q);
    if (!w.error.empty()) {
      out.error = w.error;
      return out;
    }
    cap_ruled_feed(w, cfg, accel);
    Block b{};
    b.kind = BlockKind::kRuled;
    b.line = static_cast<std::uint32_t>(m.line > 0 ? m.line : 0);
    const std::vector<double> sched = ruled_feed_schedule(part, w.sample_caps, m.feed_mm_s, accel);
    if (std::string e = to_geometry(part, m.feed_mm_s, accel, 0.0, 0.0, b.ruled); !e.empty()) {
      out.error = e;
      return out;
    }
    double top = 0.0;
    for (std::size_t i = 0; i < sched.size(); ++i) {
      b.ruled.schedule_speed[i] = sched[i];
      top = std::max(top, sched[i]);
    }
    // the parts of one piece flow at the slower of the two schedules at their join
    if (k > 0) b.ruled.start_speed = std::min(out.blocks.back().ruled.schedule_speed[out.blocks.back().ruled.schedule_count - 1], sched.front());
    if (k > 0) out.blocks.back().ruled.end_speed = b.ruled.start_speed;
    out.feed = std::max(out.feed, top);
    set_ruled_block_fields(b);
    b.accel = accel;
    RotaryMotion& r = b.rotary;
    r.tool_length = m.tool_length;
    Vec3 xyz{};
    r.start = r.end = m.rot_start;
    from_joints(cfg, q, xyz, r.start);
    from_joints(cfg, w.q_end, r.joint_end, r.end);
    out.blocks.push_back(b);
    q = w.q_end;
  }
  return out;
}

}  // namespace pcnc
