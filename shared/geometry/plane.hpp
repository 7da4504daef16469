// plane.hpp — the working planes of RS274 (G17, G18, G19) as pure functions: which two axes
// span the plane, in angle order, for the axis normal to it. Arcs, offsets and the block
// check all measure angles this way: from plane_axes(n)[0] toward plane_axes(n)[1], so that
// the right-hand rule about the normal axis gives positive (G03) angles.
#pragma once

#include <array>

namespace pcnc {

/// G17 (normal Z): X->Y; G18 (normal Y): Z->X; G19 (normal X): Y->Z.
inline constexpr std::array<int, 2> plane_axes(int normal_axis) {
  return normal_axis == 2   ? std::array<int, 2>{0, 1}
         : normal_axis == 1 ? std::array<int, 2>{2, 0}
                            : std::array<int, 2>{1, 2};
}

/// "G17", "G18" or "G19" for the plane normal to `normal_axis`.
inline constexpr const char* plane_name(int normal_axis) {
  return normal_axis == 2 ? "G17" : normal_axis == 1 ? "G18" : "G19";
}

}  // namespace pcnc
