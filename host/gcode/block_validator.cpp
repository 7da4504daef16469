// block_validator.cpp — the rt's block check as the pipeline's last stage (see block_validator.hpp).
#include "gcode/block_validator.hpp"

#include <cstdio>

namespace pcnc {

BlockVerdict BlockValidator::check(Block& b) {
  b.seq = next_seq_;
  // After a probing move the next block starts where the probe stopped, which the rt knows and
  // checks exactly (docs/probe.md); here it continues from wherever the interpreter put it.
  const bool moving = b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kArc ||
                      b.kind == BlockKind::kNurbs || b.kind == BlockKind::kRuled;
  if (after_probe_ && moving) tail_ = b.start;
  BlockVerdict verdict = check_block(b, expected_block_start(b, tail_, rot_tail_, config_), next_seq_, config_);
  if (verdict.fault == FaultCode::kNone) verdict = check_rotary(b, rot_tail_, config_);
  if (verdict.fault != FaultCode::kNone) return verdict;
  if (moving && b.length > 0.0) block_tail(b, tail_, rot_tail_);  // as the rt's prepare_block sets PreparedBlock::motion
  if (moving) after_probe_ = b.probe_rule != 0;
  ++next_seq_;
  return verdict;
}

std::string describe_refusal(const Block& b, const BlockVerdict& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, " (axis %c, value %.4f)",
                v.axis < kAxes ? axis_name(v.axis) : v.axis < kAxes + kRotaryJoints ? joint_letter(v.axis - kAxes) : '?',
                v.value);
  return "block " + std::to_string(b.seq) + " (" + to_string(b.kind) + ") is refused by the rt's block check: " +
         v.reason + buf + "; the machine would fault here";
}

}  // namespace pcnc
