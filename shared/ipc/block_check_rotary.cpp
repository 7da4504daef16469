// block_check_rotary.cpp — the rotary joints' part of the block check (block_check.hpp):
// continuity of the joints, their travel, and a tool-centre-point block's ends against the
// forward kinematics. Pure, allocation-free: the rt runs it on every block it takes.
#include <cmath>

#include "config/joint_map.hpp"
#include "geometry/axis_slerp.hpp"
#include "ipc/block_check.hpp"
#include "ipc/block_check_util.hpp"

namespace pcnc {
namespace {

constexpr double kRadTol = 1e-6;  // rad: joints agree

}  // namespace

int outside_rotary_travel(const Rot3& r, const MachineConfig& cfg, double tol_rad) {
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto& j = cfg.rotary[static_cast<std::size_t>(i)];
    if (!j || j->continuous) continue;
    const double v = r[static_cast<std::size_t>(i)];
    if (!(v >= j->travel_min_rad - tol_rad && v <= j->travel_max_rad + tol_rad)) return i;
  }
  return -1;
}

Vec3 expected_block_start(const Block& b, const Vec3& xyz, const Rot3& rot, const MachineConfig& cfg) {
  const bool straight = b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kRuled;
  if (!straight || b.rotary.tcp == 0 || !std::isfinite(b.rotary.tool_length)) return xyz;
  return forward(kinematics_with_tool(cfg, b.rotary.tool_length), to_joints(cfg, xyz, rot)).tip;
}

void block_tail(const Block& b, Vec3& xyz, Rot3& rot) {
  switch (b.kind) {
    case BlockKind::kLine:
    case BlockKind::kRapid:
    case BlockKind::kRuled:
      xyz = b.rotary.tcp ? b.rotary.joint_end : b.end;
      rot = b.rotary.end;
      return;
    case BlockKind::kArc:
    case BlockKind::kNurbs:
      xyz = b.end;
      return;
    default:
      return;
  }
}

BlockVerdict check_rotary(const Block& b, const Rot3& tail_rot, const MachineConfig& cfg) {
  const RotaryMotion& r = b.rotary;
  // a ruled block is checked as a straight TCP block (check_ruled holds it to tcp 1, angular 0)
  const bool straight = b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kRuled;
  const RotaryMask mask = cfg.rotary_mask();
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!std::isfinite(r.start[k]) || !std::isfinite(r.end[k])) return refuse_block("rotary: non-finite joint value", 3 + i);
    if (!has_joint(mask, i) && (r.start[k] != 0.0 || r.end[k] != 0.0)) {
      return refuse_block("rotary: a joint the machine does not have moves", 3 + i, r.end[k]);
    }
  }
  if (r.tcp > 1 || r.angular > 1) return refuse_block("rotary: tcp or angular flag is not 0 or 1");
  auto near = [](const Rot3& a, const Rot3& b) {
    for (int i = 0; i < kRotaryJoints; ++i) {
      if (std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) > kRadTol) return false;
    }
    return true;
  };
  if (!straight) {  // arcs, NURBS, dwells ... keep the joints where they are (or carry none: all 0)
    if (r.tcp || r.angular || (mask != 0 && !(near(r.start, tail_rot) && near(r.end, tail_rot)) &&
                               !(r.start == Rot3{} && r.end == Rot3{}))) {
      return refuse_block("rotary: only straight moves may turn a joint or run under TCP");
    }
    return {};
  }
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (std::abs(r.start[k] - tail_rot[k]) > kRadTol) {
      return refuse_block("rotary: start does not continue from the previous end", 3 + i, r.start[k] - tail_rot[k]);
    }
  }
  if (int j = outside_rotary_travel(r.end, cfg, kRadTol); j >= 0) {
    return refuse_block("rotary: end outside the joint's travel", 3 + j, r.end[static_cast<std::size_t>(j)]);
  }
  const double tol = cfg.motion.block_tolerance_mm;
  if (r.tcp) {
    if (cfg.kinematics.kind == KinematicsKind::kTrivial) return refuse_block("rotary: TCP on a machine without kinematics");
    if (!all_finite(r.axis_start) || !all_finite(r.axis_end) || !all_finite(r.joint_end) || !std::isfinite(r.tool_length) ||
        r.tool_length < 0.0) {
      return refuse_block("rotary: TCP block with a non-finite or negative value");
    }
    if (std::abs(norm(r.axis_start) - 1.0) > 1e-6 || std::abs(norm(r.axis_end) - 1.0) > 1e-6) {
      return refuse_block("rotary: TCP tool axes are not unit vectors");
    }
    if (int ax = outside_travel(r.joint_end, cfg, tol); ax >= 0) {
      return refuse_block("rotary: TCP block ends outside the travel", ax, r.joint_end[static_cast<std::size_t>(ax)]);
    }
    const Kinematics kin = kinematics_with_tool(cfg, r.tool_length);
    // the axis depends on the rotary joints alone (the start tip is check_block's, via expected_block_start)
    const ToolPose p0 = forward(kin, to_joints(cfg, r.joint_end, r.start));
    if (norm(p0.axis - r.axis_start) > 1e-6) return refuse_block("rotary: TCP start joints do not give the start tool axis");
    const ToolPose pe = forward(kin, to_joints(cfg, r.joint_end, r.end));
    if (norm(pe.tip - b.end) > tol) return refuse_block("rotary: TCP end joints do not put the tool tip at the end", 0, norm(pe.tip - b.end));
    if (norm(pe.axis - r.axis_end) > 1e-6) return refuse_block("rotary: TCP end joints do not give the end tool axis");
  }
  if (r.angular) {
    double want = 0.0;
    if (r.tcp) {
      want = make_axis_slerp(r.axis_start, r.axis_end).angle;
    } else {
      double sq = 0.0;
      for (int i = 0; i < kRotaryJoints; ++i) {
        const double d = r.end[static_cast<std::size_t>(i)] - r.start[static_cast<std::size_t>(i)];
        sq += d * d;
      }
      want = std::sqrt(sq);
    }
    if (norm(b.end - b.start) > tol) return refuse_block("rotary: an angular block moves the tool tip or the linear axes");
    if (!(want > 0.0) || std::abs(b.length - want) > 1e-9 * (1.0 + want)) {
      return refuse_block("rotary: angular block's length is not its turn", 0, b.length - want);
    }
  }
  return {};
}

}  // namespace pcnc
