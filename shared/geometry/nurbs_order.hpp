// nurbs_order.hpp — the NURBS degrees evaluation supports. Evaluation works on fixed arrays
// sized by kMaxNurbsDegree (no allocation, real-time safe); the block that carries a curve
// over the ring (ipc/block.hpp) sizes its knot array by it too.
#pragma once

namespace pcnc {

constexpr int kMinNurbsDegree = 1;
constexpr int kMaxNurbsDegree = 5;
constexpr int kMinNurbsOrder = kMinNurbsDegree + 1;  // 2
constexpr int kMaxNurbsOrder = kMaxNurbsDegree + 1;  // 6

}  // namespace pcnc
