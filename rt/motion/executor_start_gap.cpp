// executor_start_gap.cpp — the block executor before a block that starts from rest a hair away
// from where the machine stands: the gap moved from rest to rest (motion/start_gap.hpp,
// docs/rt-executor.md "A block that starts a hair away").
#include "motion/executor.hpp"
#include "motion/path.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"

namespace pcnc {

bool Executor::start_gap_cycle(const Block& blk, const ExecInput& in) {
  if (!gap_.active()) {
    const PreparedBlock& b = prep_[0];
    // the linear axes alone: a rotary or TCP block's start is checked in joint space
    if (b.rotary || b.angular || b.tcp || b.kind == BlockKind::kRuled) return false;
    // where the block's own first cycles run from (a NURBS block: its curve's first point)
    const Vec3 start = b.kind == BlockKind::kNurbs ? nurbs_eval(view_of(blk.nurbs), view_of(blk.nurbs).u_min()).p
                                                   : evaluate(b, 0.0).p;
    if (!(norm(start - pos_) > kStartGapMm)) return false;
    if (in.hold) {  // held before it began: the gap move waits with the block
      hold_still();
      return true;
    }
    gap_.begin(pos_, start, cfg_, dt_);
  }
  // once begun it runs to its end, hold or not: a few cycles, from rest to rest
  const bool landed = gap_.step();
  pos_ = gap_.position();
  vel_ = gap_.velocity();
  acc_ = gap_.acceleration();
  v_ = gap_.speed();
  rot_vel_ = {0.0, 0.0, 0.0};
  rot_acc_ = {0.0, 0.0, 0.0};
  if (landed) rest_cycle_ = true;  // one cycle at rest, then the block from rest
  remember_cycle();
  return true;
}

}  // namespace pcnc
