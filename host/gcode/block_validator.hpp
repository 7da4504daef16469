// block_validator.hpp — the last stage of the front-end pipeline (gcode/pipeline.hpp): every
// block the preprocessor makes goes through the rt's own block check (ipc/block_check.hpp)
// exactly as the rt will call it, so that what `pcnc check` accepts is what the rt executes.
//
// The rt's call (rt/motion/executor.cpp, Executor::prepare_visible) is reproduced here:
//   * seq: the ring feeder numbers a program's blocks 1, 2, 3, ... (service/ring_feeder.hpp)
//     and the rt expects exactly that; the validator gives each block its number;
//   * expected start: where the machine stands at program start (the job frame's start
//     position), then the end of the last motion block (a line, rapid, arc or NURBS block of
//     non-zero length: the rt's PreparedBlock::motion); dwell, pause and end blocks leave it.
#pragma once

#include <cstdint>
#include <string>

#include <optional>

#include "config/config.hpp"
#include "ipc/block.hpp"
#include "ipc/block_check.hpp"

namespace pcnc {

class BlockValidator {
 public:
  /// `start`: the machine position before the program's first block.
  /// `rot_start`: the rotary joints then (rad; unset: their homes).
  BlockValidator(const MachineConfig& config, const Vec3& start, const std::optional<Rot3>& rot_start = std::nullopt)
      : config_(config), tail_(start) {
    for (int i = 0; i < kRotaryJoints; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (config.rotary[k]) rot_tail_[k] = rot_start ? (*rot_start)[k] : config.rotary[k]->home_rad;
    }
  }

  /// Numbers `block` (seq) and checks it as the rt will. On acceptance the next block is
  /// expected to continue from it.
  BlockVerdict check(Block& block);

  /// Blocks checked so far (the last one's seq).
  std::uint64_t count() const { return next_seq_ - 1; }

 private:
  const MachineConfig& config_;
  Vec3 tail_;
  Rot3 rot_tail_{};
  std::uint64_t next_seq_ = 1;
  bool after_probe_ = false;  // the last motion block was a probing move
};

/// The error text for a refused block: its number, kind, the rt's reason, axis and value.
std::string describe_refusal(const Block& block, const BlockVerdict& verdict);

}  // namespace pcnc
