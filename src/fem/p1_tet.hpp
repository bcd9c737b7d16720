#pragma once
// Linear (P1) tetrahedron: shape-function gradients, volume, the element metric tensor and
// the exact P1 mass matrix. Pure functions of the four vertex positions.
#include <array>

#include "core/types.hpp"

namespace tearflow::fem {

struct TetGeometry {
  std::array<Vec3, 4> grad; ///< grad N_a, constant on the element [1/m]
  double volume = 0.0;      ///< signed volume [m^3]; > 0 for a valid element
};

/// Gradients from the inverse Jacobian of x(xi) = x0 + sum_k xi_k (x_k - x0).
inline TetGeometry tet_geometry(const std::array<Vec3, 4>& x) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  // Rows of J^{-1} are (e2 x e3, e3 x e1, e1 x e2) / det J.
  const Vec3 c1 = cross(e2, e3), c2 = cross(e3, e1), c3 = cross(e1, e2);
  const double det = dot(e1, c1);
  TetGeometry g;
  g.volume = det / 6.0;
  const double inv = 1.0 / det;
  g.grad[1] = inv * c1;
  g.grad[2] = inv * c2;
  g.grad[3] = inv * c3;
  g.grad[0] = -1.0 * (g.grad[1] + g.grad[2] + g.grad[3]);
  return g;
}

/// Exact P1 mass matrix entry: int N_a N_b dV = V/20 (1 + delta_ab).
inline double mass(double volume, int a, int b) {
  return volume / 20.0 * (a == b ? 2.0 : 1.0);
}

/// Element metric G_ij = sum_k dxi_k/dx_i dxi_k/dx_j (k = 1..3) used by the stabilization
/// parameters (Bazilevs et al. 2007, eq. 63), and g_i = sum_k dxi_k/dx_i = -grad N_0.
inline Mat3 metric_tensor(const TetGeometry& g) {
  Mat3 G{};
  for (int k = 1; k < 4; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        G[i][j] += g.grad[k][i] * g.grad[k][j];
  return G;
}

} // namespace tearflow::fem
