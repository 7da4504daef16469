// rotary_joints.hpp — the rotary joints' values as the contract carries them: A, B, C by
// index 0, 1, 2 (rad inside, degrees only at the edges), and which of them a machine declares
// (a bit per joint). A plain array, trivially copyable, for blocks, status and the trace.
#pragma once

#include <array>
#include <cstdint>

namespace pcnc {

constexpr int kRotaryJoints = 3;  // A (about X), B (about Y), C (about Z)
using Rot3 = std::array<double, kRotaryJoints>;

/// Bit i set: the machine has rotary joint i ('A' + i).
using RotaryMask = std::uint8_t;
inline bool has_joint(RotaryMask mask, int i) { return ((mask >> i) & 1u) != 0; }
inline char joint_letter(int i) { return static_cast<char>('A' + i); }
inline char joint_lower(int i) { return static_cast<char>('a' + i); }

}  // namespace pcnc
