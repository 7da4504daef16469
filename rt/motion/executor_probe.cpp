// executor_probe.cpp — the end of a probing block (G38.2-G38.5, docs/probe.md): the result
// handed to the state machine for the status, and the sync point after it. The speed law
// (executor.cpp) brakes a probing block at its acceleration from the cycle after the probe's
// input reached the state sought; the block ends where the machine then stands, which the next
// block must start from: the host sends it only after reading the result (a sync point), so a
// block already queued behind a probing move is refused.
#include "motion/executor.hpp"

namespace pcnc {

void Executor::finish_probe(MotionRing& ring, ExecResult& out, ProbeOutcome outcome) {
  out.probe_done = true;
  out.probe_outcome = outcome;
  out.probe_latched = outcome == ProbeOutcome::kContact ? probe_latched_ : pos_;
  out.probe_line = line_;
  out.probe_seq = seq_;
  probe_tripped_ = false;
  probe_arm_ = false;
  const Vec3 end = prep_[0].end;
  pop(ring, out);
  rest_cycle_ = true;
  ended_at_rest_ = true;
  after_motion_ = true;
  // Blocks already queued behind it were checked against its commanded end: harmless when the
  // machine stands there or none of them moves (an End block), refused otherwise.
  bool queued_motion = false;
  for (std::size_t i = 0; i < prepared_; ++i) queued_motion = queued_motion || prep_[i].motion;
  if (queued_motion && norm(pos_ - end) > cfg_.motion.block_tolerance_mm) {
    out.fault = FaultCode::kBadBlock;
    out.reason = "a block was queued behind a probing move (the host must wait for the probe's result)";
    out.fault_line = ring.peek(0).line;
    return;
  }
  if (!queued_motion) tail_ = pos_;  // the next block starts where the probing move stopped
  probe_sync_ = prepared_ == 0;
}

}  // namespace pcnc
