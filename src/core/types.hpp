#pragma once
// Fixed-size types for linear tetrahedra. Indices are PETSc's (32-bit in Debian's build).
#include <array>
#include <cstdint>

namespace tearflow {

using Index = std::int32_t;
using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;
using Tet = std::array<Index, 4>;
using Tri = std::array<Index, 3>;

/// The face of `t` opposite its node `skip`, its nodes in t's order.
inline Tri face_opposite(const Tet& t, int skip) {
  Tri f{};
  for (int i = 0, j = 0; i < 4; ++i)
    if (i != skip)
      f[j++] = t[i];
  return f;
}

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator*(double s, const Vec3& a) {
  return {s * a[0], s * a[1], s * a[2]};
}
inline double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

} // namespace tearflow
