// The voxel grid: index <-> patient point, centred grids, rotations.
#include "core/image_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tearflow {

namespace {
Vec3 normalized(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return (1.0 / n) * v;
}
} // namespace

Vec3 ImageGrid::point(const Vec3& index) const {
  Vec3 p = origin;
  for (int a = 0; a < 3; ++a)
    p = p + (index[a] * spacing[a]) * direction[a];
  return p;
}

Vec3 ImageGrid::index(const Vec3& p) const {
  // The direction rows are orthonormal, so the inverse is the transpose.
  const Vec3 d = p - origin;
  return {dot(d, direction[0]) / spacing[0], dot(d, direction[1]) / spacing[1],
          dot(d, direction[2]) / spacing[2]};
}

bool ImageGrid::same_as(const ImageGrid& o) const {
  if (size != o.size)
    return false;
  const double h = std::min({spacing[0], spacing[1], spacing[2]});
  const double tol = 1e-4 * h;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(spacing[a] - o.spacing[a]) > tol)
      return false;
    for (int b = 0; b < 3; ++b)
      if (std::abs(direction[a][b] - o.direction[a][b]) > 1e-4)
        return false;
  }
  const Vec3 d = origin - o.origin;
  return std::sqrt(dot(d, d)) <= tol;
}

ImageGrid centred_grid(const Vec3& centre, const Mat3& direction, std::array<int, 3> size,
                       const Vec3& spacing) {
  ImageGrid g;
  g.size = size;
  g.spacing = spacing;
  // Gram-Schmidt, so that a direction read with rounding stays a rotation.
  g.direction[0] = normalized(direction[0]);
  g.direction[1] = normalized(direction[1] - dot(direction[1], g.direction[0]) * g.direction[0]);
  g.direction[2] = cross(g.direction[0], g.direction[1]);
  g.origin = centre;
  for (int a = 0; a < 3; ++a)
    g.origin = g.origin - (0.5 * (size[a] - 1) * spacing[a]) * g.direction[a];
  return g;
}

Mat3 rotation(const Vec3& axis, double degrees) {
  const Vec3 k = normalized(axis);
  const double t = degrees * std::numbers::pi / 180.0, c = std::cos(t), s = std::sin(t);
  Mat3 rows{};
  const Mat3 e{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int a = 0; a < 3; ++a) // v cos t + (k x v) sin t + k (k.v)(1 - cos t)
    rows[a] = c * e[a] + s * cross(k, e[a]) + (dot(k, e[a]) * (1 - c)) * k;
  return rows;
}

} // namespace tearflow
