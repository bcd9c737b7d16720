#pragma once
// The boundary conditions of a solid problem, by face name, and the pure triangle kernels of
// its surface terms. Each adds -<w, t>_Gamma to the momentum residual R_u:
//   fixed face:       u_c = g_c(t) for the selected components c (Dirichlet rows);
//   follower load:    t = -P(t) n on the deformed surface:  +int_Gamma N_a P n da;
//   tissue support:   t = -k_s u - c_s du/dt - p_0 n (Robin; ../shared/reference/tbad-study.md):
//                     +int_Gamma0 N_a (k_s u + c_s v) dA + int_Gamma N_a p_0 n da.
// The spring-dashpot acts on the reference area (a support per unit undeformed area); p_0,
// like every pressure, follows the deformed surface. Triangles are oriented outward.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "core/types.hpp"

namespace tearflow::bc {

struct FixedFace {
  std::string face;
  std::uint8_t components = 0b111; ///< bit c set: u_c prescribed
  Vec3 displacement{};             ///< g reached at t = ramp [m]
  double ramp = 0.0;               ///< g(t) = min(t / ramp, 1) g; 0: g from the start [s]
  Vec3 at(double t) const {
    const double s = ramp > 0.0 ? std::min(t / ramp, 1.0) : 1.0;
    return s * displacement;
  }
};

struct PressureLoad {
  std::string face;
  Waveform pressure = Waveform::constant(0.0); ///< P(t) [Pa], > 0 pushes along -n
};

struct RobinSupport {
  std::string face;
  double stiffness = 0.0; ///< k_s [Pa/m]
  double damping = 0.0;   ///< c_s [Pa s/m]
  double pressure = 0.0;  ///< p_0 [Pa]
};

struct SolidConditions {
  std::vector<FixedFace> fixed;
  std::vector<PressureLoad> loads;
  std::vector<RobinSupport> supports;
};

using TriVector = std::array<double, 9>;
using TriMatrix = std::array<std::array<double, 9>, 9>;

/// Skew matrix [a]x with [a]x b = a x b.
inline Mat3 skew(const Vec3& a) {
  return {Vec3{0.0, -a[2], a[1]}, Vec3{a[2], 0.0, -a[0]}, Vec3{-a[1], a[0], 0.0}};
}

/// Follower pressure on the deformed triangle x: int N_a P n da = P/6 (x1 - x0) x (x2 - x0),
/// the same for the three nodes (n da is constant on a flat triangle). Adds to R.
inline void follower_pressure_residual(const std::array<Vec3, 3>& x, double P, TriVector& R) {
  const Vec3 c = cross(x[1] - x[0], x[2] - x[0]);
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i)
      R[3 * a + i] += P / 6.0 * c[i];
}

/// Its derivative times c_u (du/d unknown): d(e1 x e2) = -[e2]x de1 + [e1]x de2 with
/// e1 = x1 - x0, e2 = x2 - x0. Adds to K.
inline void follower_pressure_jacobian(const std::array<Vec3, 3>& x, double P, double c_u,
                                       TriMatrix& K) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0];
  const Mat3 S1 = skew(e1), S2 = skew(e2);
  std::array<Mat3, 3> dc; // dc / dx_b
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      dc[1][i][k] = -S2[i][k];
      dc[2][i][k] = S1[i][k];
      dc[0][i][k] = S2[i][k] - S1[i][k];
    }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
          K[3 * a + i][3 * b + k] += c_u * P / 6.0 * dc[b][i][k];
}

/// int_Gamma0 N_a (k u + c v) dA with the P1 triangle mass A0/12 (1 + delta_ab). Adds to R.
inline void robin_residual(double area0, const std::array<Vec3, 3>& u, const std::array<Vec3, 3>& v,
                           double k, double c, TriVector& R) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double m = area0 / 12.0 * (a == b ? 2.0 : 1.0);
      for (int i = 0; i < 3; ++i)
        R[3 * a + i] += m * (k * u[b][i] + c * v[b][i]);
    }
}

/// Its derivative: (k c_u + c c_v) M, c_u = du/d unknown, c_v = dv/d unknown. Adds to K.
inline void robin_jacobian(double area0, double k, double c, double c_u, double c_v, TriMatrix& K) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double m = area0 / 12.0 * (a == b ? 2.0 : 1.0);
      for (int i = 0; i < 3; ++i)
        K[3 * a + i][3 * b + i] += m * (k * c_u + c * c_v);
    }
}

} // namespace tearflow::bc
