// executor_ruled.cpp — a ruled-surface block in execution (five-axis, docs/ruled-surface.md): the rt's
// follower (ruled_follower.hpp) steps along the piece's schedule, and the executor puts its
// joints into the machine's setpoint; a piece flows into the next ruled piece that continues it
// (same tool point, direction and axis) at the speed both allow, else it ends at rest. The speed
// law of lines, arcs and curves (executor.cpp) does not apply: the piece carries its own.
#include <algorithm>
#include <cmath>

#include "config/joint_map.hpp"
#include "motion/executor.hpp"

namespace pcnc {

double Executor::ruled_exit_speed(const MotionRing& ring, const ExecInput& in) const {
  const RuledGeometry& g = ring.peek(0).ruled;
  if (in.hold || prepared_ < 2 || !(g.end_speed > 0.0)) return 0.0;
  const Block& next = ring.peek(1);
  if (next.kind != BlockKind::kRuled || !(next.ruled.start_speed > 0.0)) return 0.0;
  // continuity: the next piece starts with the tool where and as this one ends
  const PreparedBlock& p = prep_[0];
  const PreparedBlock& q = prep_[1];
  if (norm(q.start - p.end) > cfg_.motion.block_tolerance_mm || dot(p.dir_end, q.dir_start) < 0.9999 ||
      norm(next.rotary.axis_start - ring.peek(0).rotary.axis_end) > 1e-6) {
    return 0.0;
  }
  const double scale = std::clamp(in.feed_override, 0.0, 1.0);
  // the next piece may have to stop within its own length (what follows it is not known)
  const double stop = std::sqrt(2.0 * next.ruled.accel * next.ruled.length);
  return std::min({g.end_speed, next.ruled.start_speed, scale * next.ruled.schedule_speed[0], stop});
}

void Executor::put_ruled(const RuledSample& s) {
  from_joints(cfg_, s.q, pos_, rot_);
  Rot3 rv{}, ra{};
  from_joints(cfg_, s.dq, vel_, rv);
  from_joints(cfg_, s.ddq, acc_, ra);
  rot_vel_ = rv;
  rot_acc_ = ra;
  v_ = s.feed;
  s_ = ruled_.travelled();
}

void Executor::ruled_step(MotionRing& ring, const ExecInput& in, ExecResult& out) {
  const Block& blk = ring.peek(0);
  const double scale = in.hold ? 0.0 : std::clamp(in.feed_override, 0.0, 1.0);
  const RuledSample& s = ruled_.step(blk.ruled, dt_, ruled_exit_speed(ring, in), scale);
  put_ruled(s);
  if (!ruled_.done()) return;
  if (!(s.feed > 0.0) || prepared_ < 2 || ring.peek(1).kind != BlockKind::kRuled) {
    // the end at rest: land exactly on the host's end joints, rest one cycle, then the next block
    pos_ = prep_[0].land;
    rot_ = prep_[0].rot_end;
    hold_still();
    pop(ring, out);
    rest_cycle_ = true;
    ended_at_rest_ = true;
    after_motion_ = true;
    return;
  }
  // a flowing join: the next part of the piece starts at the speed this one ended with, the
  // cycle's leftover length already travelled along it
  ruled_carry_ = ruled_.leftover();
  ruled_speed_ = s.feed;
  flow_into_next(ring, out);
  put_ruled(ruled_.sample());
}

}  // namespace pcnc
