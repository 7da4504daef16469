// make_blocks.hpp — test helper: builds ring Blocks from simple geometry the way the host's
// preprocessor does (speeds and accelerations projected so that no axis exceeds its limits),
// so rt tests do not depend on the host. Not used by production code.
#pragma once

#include <cstdint>
#include <vector>

#include "ipc/block.hpp"
#include "config/config.hpp"

namespace pcnc::test {

class ProgramBuilder {
 public:
  ProgramBuilder(const MachineConfig& config, const Vec3& start);

  ProgramBuilder& contouring(bool on);
  ProgramBuilder& line(const Vec3& end, double feed_mm_s);
  ProgramBuilder& rapid(const Vec3& end);
  /// Arc about `center` (its normal-axis coordinate is ignored) to `end`; cw = G02.
  /// `turns` extra full circles. The normal-axis difference end − start makes it a helix.
  ProgramBuilder& arc(const Vec3& end, const Vec3& center, int normal_axis, bool cw, double feed_mm_s,
                      int turns = 0);
  ProgramBuilder& dwell(double seconds);
  ProgramBuilder& pause(bool optional = false);
  ProgramBuilder& end();

  const std::vector<Block>& blocks() const { return blocks_; }
  std::vector<Block>& blocks() { return blocks_; }
  const Vec3& position() const { return pos_; }

 private:
  Block next(BlockKind kind);
  const MachineConfig& cfg_;
  Vec3 pos_;
  bool contouring_ = false;
  std::uint64_t seq_ = 0;
  std::uint32_t line_ = 0;
  std::vector<Block> blocks_;
};

/// Where the machine stands at start-up (the axes' home_mm).
Vec3 home(const MachineConfig& config);

/// From home: a rapid to `corner`, then a closed square of side `side` in the XY plane at
/// `feed`, then End.
std::vector<Block> square_program(const MachineConfig& config, const Vec3& corner, double side, double feed,
                                  bool contouring);
/// From home: a rapid to (center + radius·X), then a circle of radius `radius` about
/// `center` (XY) cut into `segments` straight lines, then End.
std::vector<Block> polygon_circle_program(const MachineConfig& config, const Vec3& center, double radius,
                                          int segments, double feed, bool contouring);

}  // namespace pcnc::test
