// vec3.hpp — the 3-vector every stage uses for points and directions (mm, unit vectors).
// A plain std::array so that blocks holding it stay trivially copyable for shared memory.
#pragma once

#include <array>
#include <cmath>

namespace pcnc {

constexpr int kAxes = 3;  // X, Y, Z
using Vec3 = std::array<double, kAxes>;

inline constexpr Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline constexpr Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline constexpr Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline constexpr Vec3 operator*(const Vec3& a, double s) { return s * a; }
inline constexpr double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
/// Unit vector along a; the zero vector stays zero.
inline Vec3 normalized(const Vec3& a) {
  const double n = norm(a);
  return n > 0.0 ? (1.0 / n) * a : Vec3{0.0, 0.0, 0.0};
}

inline constexpr char axis_name(int axis) { return "XYZ"[axis]; }

}  // namespace pcnc
