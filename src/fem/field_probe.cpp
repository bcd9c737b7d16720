#include "fem/field_probe.hpp"

#include <cmath>

#include "fem/p1_tet.hpp"

namespace tearflow::fem {

std::optional<PointLocation> locate(const mesh::Mesh& mesh, const Vec3& p) {
  for (Index e = 0; e < mesh.num_tets(); ++e) {
    const Tet& t = mesh.tets[e];
    const TetGeometry g =
        tet_geometry({mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]});
    // N_a(p) = N_a(x_0) + grad N_a . (p - x_0), with N_a(x_0) = delta_a0.
    PointLocation loc{e, {}};
    bool inside = true;
    for (int a = 0; a < 4 && inside; ++a) {
      loc.barycentric[a] = (a == 0 ? 1.0 : 0.0) + dot(g.grad[a], p - mesh.points[t[0]]);
      inside = loc.barycentric[a] >= -1e-10;
    }
    if (inside)
      return loc;
  }
  return std::nullopt;
}

double interpolate(const mesh::Mesh& mesh, const PointLocation& at,
                   const std::vector<double>& field, int block, int component) {
  double v = 0.0;
  for (int a = 0; a < 4; ++a)
    v += at.barycentric[a] * field[static_cast<size_t>(block) * mesh.tets[at.tet][a] + component];
  return v;
}

std::pair<double, double> l2_error(const mesh::Mesh& mesh, const std::vector<double>& field,
                                   int block, int first, int count,
                                   const std::function<Vec3(const Vec3&)>& exact,
                                   const std::function<bool(const Vec3&)>& in_region) {
  // Degree-2 rule (Keast): four points with barycentric (a, b, b, b) and permutations.
  constexpr double a = 0.5854101966249685, b = 0.1381966011250105;
  double err2 = 0.0, norm2 = 0.0;
  for (const Tet& t : mesh.tets) {
    const std::array<Vec3, 4> x{mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]],
                                mesh.points[t[3]]};
    if (in_region && !in_region(0.25 * (x[0] + x[1] + x[2] + x[3])))
      continue;
    const double w = std::abs(tet_geometry(x).volume) / 4.0;
    for (int q = 0; q < 4; ++q) {
      Vec3 xq{}, uh{};
      for (int n = 0; n < 4; ++n) {
        const double N = (n == q) ? a : b;
        xq = xq + N * x[n];
        for (int c = 0; c < count; ++c)
          uh[c] += N * field[static_cast<size_t>(block) * t[n] + first + c];
      }
      const Vec3 u = exact(xq);
      const Vec3 d = uh - u;
      err2 += w * dot(d, d);
      norm2 += w * dot(u, u);
    }
  }
  return {std::sqrt(err2), std::sqrt(norm2)};
}

} // namespace tearflow::fem
