// block_check_util.hpp — the two helpers every part of the block check uses (block_check.cpp,
// block_check_rotary.cpp, block_check_ruled.cpp): a bad-block verdict naming its reason, axis
// and value, and "every coordinate is a finite number". Internal to shared/ipc.
#pragma once

#include <cmath>
#include <cstdint>

#include "ipc/block_check.hpp"

namespace pcnc {

inline BlockVerdict refuse_block(const char* reason, int axis = 0, double value = 0.0) {
  return {FaultCode::kBadBlock, reason, static_cast<std::uint8_t>(axis), value};
}

inline bool all_finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace pcnc
