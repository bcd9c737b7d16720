#pragma once
// Large-deformation elastodynamics of a hyperelastic solid on P1-P1 tetrahedra, total
// Lagrangian (reference configuration Omega_0, deformation gradient F = I + Grad u,
// J = det F), as a stabilized mixed displacement-pressure formulation:
//
//   rho_0 d^2u/dt^2 - Div P = 0,   P = P_dev(F) - p J F^{-T},   p = -U'(J) = -kappa (J - 1)
//
// The unknowns per node are (v, p): velocity and pressure, the same layout as the fluid's
// (u, p), so the FSI coupling can share the interface velocity; the displacement follows
// from the Newmark relations of generalized-alpha (solid_problem.hpp).
//
// Weak form, for all (w, q), the stationarity conditions of
//   Pi(u, p) = int W_dev(F) - p (J - 1) - p^2 / (2 kappa) - tau/2 |Grad p|^2  dV:
//   (w, rho_0 a) + (Grad w, P_dev(F)) - (Grad w, p J F^{-T}) - <w, t>_Gamma       = 0  [R_u]
//   s [ (q, J - 1) + (q, p / kappa) + sum_e tau_e (Grad q, Grad p)_e ]           = 0  [R_p]
// The pressure row is -s dPi/dp, with the sign flipped so that its diagonal block is positive
// (the Schur complement is then positive definite, as BoomerAMG wants) and scaled by a
// constant s [Pa/m] so that its residual is a force like the momentum rows' (otherwise
// ||R|| would not see it).
//
// Why mixed and why this stabilization. Displacement-only linear tets lock when nu -> 1/2:
// one J per element is about 5 volume constraints per node against 3 displacement dofs.
// A continuous P1 pressure has one constraint per node; P1-P1 violates inf-sup, which the
// Brezzi-Pitkaranta term tau (Grad q, Grad p) with tau = alpha h_e^2 / (2 mu) repairs
// (Brezzi & Pitkaranta 1984; for finite elasticity Klaas, Maniatty & Shephard, CMAME 1999;
// the P1-P1 + pressure-gradient stabilization of the reference study's solver, Liu & Marsden
// 2018, is the residual-based variant). It keeps the element stencil (no patch averaging
// like F-bar or the nodal-averaged tet of Bonet & Burton 1998, whose two-ring stencil would
// break the matrix preallocation and the one-layer ghosting), the same 4-dof node block as
// the fluid, and is locking-free up to kappa -> infinity. Its consistency error is
// O(alpha h^2 / mu |Lap p|), zero for a homogeneous pressure; `verify lame` measures it at
// nu = 0.49. Since Pi exists, the discrete system is Hamiltonian (`verify energy`).
//
// Materials (mu shear, kappa bulk modulus; for small strain both give Young's modulus E):
//   Neo-Hookean, isochoric + penalty:  W_dev = mu/2 (J^{-2/3} tr C - 3),  U = kappa/2 (J - 1)^2
//     P_dev = mu J^{-2/3} (F - tr C / 3 F^{-T});  the volumetric part through p (mixed).
//   St. Venant-Kirchhoff (for comparison; displacement-only, so it locks near nu = 1/2):
//     W = mu E:E + lambda/2 (tr E)^2,  E = (C - I)/2,  P = F (lambda tr E I + 2 mu E); p = 0.
//
// All element integrals are exact: F is constant on a P1 tet, and the products of shape
// functions are integrated with the P1 mass matrix V/20 (1 + delta_ab).
#include <array>
#include <cmath>

#include "core/error.hpp"
#include "fem/p1_tet.hpp"
#include "physics/solid_material.hpp"

namespace tearflow::physics {

// --- 3x3 tensor algebra ------------------------------------------------------------------

inline double det(const Mat3& A) {
  return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
         A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
         A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
}
/// A^{-T} = cof(A) / det A.
inline Mat3 inverse_transpose(const Mat3& A) {
  const double inv = 1.0 / det(A);
  Mat3 C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      C[i][j] = inv * (A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1]);
    }
  return C;
}
inline double contract(const Mat3& A, const Mat3& B) {
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    s += dot(A[i], B[i]);
  return s;
}
inline Vec3 apply(const Mat3& A, const Vec3& x) {
  return {dot(A[0], x), dot(A[1], x), dot(A[2], x)};
}

/// dP_iJ / dF_kL, stored as A[i][J][k][L].
using Tangent = std::array<std::array<Mat3, 3>, 3>;

// --- materials: energy, first Piola-Kirchhoff stress, tangent ------------------------------

/// F = I + sum_b u_b (x) Grad N_b.
inline Mat3 deformation_gradient(const fem::TetGeometry& geo, const std::array<Vec3, 4>& u) {
  Mat3 F{};
  for (int i = 0; i < 3; ++i) {
    F[i][i] = 1.0;
    for (int b = 0; b < 4; ++b)
      for (int J = 0; J < 3; ++J)
        F[i][J] += u[b][i] * geo.grad[b][J];
  }
  return F;
}

/// Green-Lagrange strain E = (F^T F - I) / 2.
inline Mat3 green_strain(const Mat3& F) {
  Mat3 E{};
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J) {
      for (int k = 0; k < 3; ++k)
        E[I][J] += 0.5 * F[k][I] * F[k][J];
      if (I == J)
        E[I][J] -= 0.5;
    }
  return E;
}

/// W_dev (Neo-Hookean, isochoric) or W (St. Venant-Kirchhoff) [J/m^3].
inline double strain_energy(const SolidMaterial& m, const Mat3& F) {
  if (m.model == SolidModel::NeoHookean)
    return 0.5 * m.mu * (std::pow(det(F), -2.0 / 3.0) * contract(F, F) - 3.0);
  const Mat3 E = green_strain(F);
  const double trE = E[0][0] + E[1][1] + E[2][2];
  return m.mu * contract(E, E) + 0.5 * m.lambda() * trE * trE;
}

/// P_dev (Neo-Hookean) or P (St. Venant-Kirchhoff) [Pa].
inline Mat3 first_piola(const SolidMaterial& m, const Mat3& F) {
  Mat3 P{};
  if (m.model == SolidModel::NeoHookean) {
    const Mat3 A = inverse_transpose(F);
    const double c = m.mu * std::pow(det(F), -2.0 / 3.0), I1 = contract(F, F);
    for (int i = 0; i < 3; ++i)
      for (int J = 0; J < 3; ++J)
        P[i][J] = c * (F[i][J] - I1 / 3.0 * A[i][J]);
    return P;
  }
  const Mat3 E = green_strain(F);
  const double trE = E[0][0] + E[1][1] + E[2][2];
  Mat3 S{}; // S = lambda tr E I + 2 mu E
  for (int I = 0; I < 3; ++I)
    for (int J = 0; J < 3; ++J)
      S[I][J] = 2.0 * m.mu * E[I][J] + (I == J ? m.lambda() * trE : 0.0);
  for (int i = 0; i < 3; ++i)
    for (int J = 0; J < 3; ++J)
      for (int K = 0; K < 3; ++K)
        P[i][J] += F[i][K] * S[K][J];
  return P;
}

/// dP/dF of first_piola.
inline Tangent first_piola_tangent(const SolidMaterial& m, const Mat3& F) {
  Tangent T{};
  auto delta = [](int a, int b) { return a == b ? 1.0 : 0.0; };
  if (m.model == SolidModel::NeoHookean) {
    // P = mu J^{-2/3} (F - I1/3 A), A = F^{-T}, dJ/dF = J A, dA_iJ/dF_kL = -A_kJ A_iL.
    const Mat3 A = inverse_transpose(F);
    const double c = m.mu * std::pow(det(F), -2.0 / 3.0), I1 = contract(F, F);
    for (int i = 0; i < 3; ++i)
      for (int J = 0; J < 3; ++J)
        for (int k = 0; k < 3; ++k)
          for (int L = 0; L < 3; ++L)
            T[i][J][k][L] = c * (delta(i, k) * delta(J, L) - 2.0 / 3.0 * A[k][L] * F[i][J] -
                                 2.0 / 3.0 * F[k][L] * A[i][J] +
                                 2.0 / 9.0 * I1 * A[k][L] * A[i][J] + I1 / 3.0 * A[k][J] * A[i][L]);
    return T;
  }
  // P = F S: dP_iJ/dF_kL = delta_ik S_LJ + lambda F_iJ F_kL + mu (F_iL F_kJ + (F F^T)_ik delta_JL).
  const Mat3 E = green_strain(F);
  const double trE = E[0][0] + E[1][1] + E[2][2], lambda = m.lambda();
  for (int i = 0; i < 3; ++i)
    for (int J = 0; J < 3; ++J)
      for (int k = 0; k < 3; ++k)
        for (int L = 0; L < 3; ++L) {
          const double S_LJ = 2.0 * m.mu * E[L][J] + delta(L, J) * lambda * trE;
          const double FFt_ik = dot(F[i], F[k]);
          T[i][J][k][L] = delta(i, k) * S_LJ + lambda * F[i][J] * F[k][L] +
                          m.mu * (F[i][L] * F[k][J] + FFt_ik * delta(J, L));
        }
  return T;
}

// --- element kernels -----------------------------------------------------------------------

/// Nodal values on one element. Node-major dofs: 4 a + i (i < 3 momentum, i = 3 pressure).
struct SolidElementState {
  std::array<Vec3, 4> u;   ///< displacement at t_{n+alpha_f} [m]
  std::array<Vec3, 4> a;   ///< acceleration at t_{n+alpha_m} [m/s^2]
  std::array<double, 4> p; ///< pressure at the stage [Pa]
};

/// The pressure row's constants: tau_e [m^2/Pa] and the row scale s [Pa/m].
struct PressureRow {
  double tau = 0.0;
  double scale = 1.0;
};

/// tau_e = alpha h_e^2 / (2 mu), h_e the edge of the regular tet of the element's volume.
inline double pressure_stabilization(const SolidMaterial& m, double volume) {
  const double h = std::cbrt(6.0 * std::sqrt(2.0) * volume);
  return m.stabilization * h * h / (2.0 * m.mu);
}

using ElementVector = std::array<double, 16>;
using ElementMatrix = std::array<std::array<double, 16>, 16>;

/// Element residual: inertia, stress and pressure terms of R_u; R_p.
inline void solid_residual(const fem::TetGeometry& geo, const SolidElementState& s,
                           const SolidMaterial& m, const PressureRow& row, ElementVector& R) {
  const double V = geo.volume;
  const Mat3 F = deformation_gradient(geo, s.u);
  const Mat3 P = first_piola(m, F);
  const double J = det(F), p_mean = 0.25 * (s.p[0] + s.p[1] + s.p[2] + s.p[3]);
  const Mat3 A = inverse_transpose(F);
  Vec3 grad_p{};
  for (int b = 0; b < 4; ++b)
    grad_p = grad_p + s.p[b] * geo.grad[b];
  for (int a = 0; a < 4; ++a) {
    const Vec3& gN = geo.grad[a];
    const Vec3 PgN = apply(P, gN), ga = apply(A, gN); // P Grad N_a;  grad N_a = F^{-T} Grad N_a
    for (int i = 0; i < 3; ++i) {
      double v = V * PgN[i]; // (Grad w, P_dev)
      for (int c = 0; c < 4; ++c)
        v += m.density * fem::mass(V, a, c) * s.a[c][i]; // (w, rho_0 a)
      if (m.mixed())
        v -= V * p_mean * J * ga[i]; // -(Grad w, p J F^{-T})
      R[4 * a + i] = v;
    }
    double q = V * row.tau * dot(gN, grad_p); // tau (Grad q, Grad p)
    for (int c = 0; c < 4; ++c)
      q += fem::mass(V, a, c) * s.p[c] / m.kappa; // (q, p / kappa)
    if (m.mixed())
      q += 0.25 * V * (J - 1.0); // (q, J - 1)
    R[4 * a + 3] = row.scale * q;
  }
}

/// Exact derivative of solid_residual with respect to the nodal unknowns, where a change of
/// the unknown changes u by c_u and a by c_a times as much, and p enters directly.
inline void solid_jacobian(const fem::TetGeometry& geo, const SolidElementState& s,
                           const SolidMaterial& m, const PressureRow& row, double c_u, double c_a,
                           ElementMatrix& K) {
  const double V = geo.volume;
  const Mat3 F = deformation_gradient(geo, s.u);
  const Tangent T = first_piola_tangent(m, F);
  const double J = det(F), p_mean = 0.25 * (s.p[0] + s.p[1] + s.p[2] + s.p[3]);
  const Mat3 A = inverse_transpose(F);
  std::array<Vec3, 4> g; // spatial gradients F^{-T} Grad N_a
  for (int a = 0; a < 4; ++a)
    g[a] = apply(A, geo.grad[a]);
  for (int a = 0; a < 4; ++a) {
    const Vec3& gNa = geo.grad[a];
    for (int d = 0; d < 4; ++d) {
      const Vec3& gNd = geo.grad[d];
      const double M_ad = fem::mass(V, a, d);
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
          double stiff = 0.0; // Grad N_a . (dP/dF) . Grad N_d
          for (int Jx = 0; Jx < 3; ++Jx)
            stiff += gNa[Jx] * dot(T[i][Jx][k], gNd);
          double v = m.density * c_a * (i == k ? M_ad : 0.0) + c_u * V * stiff;
          if (m.mixed()) // d(J F^{-T})_iJ/dF_kL = J (A_kL A_iJ - A_kJ A_iL)
            v -= c_u * V * p_mean * J * (g[a][i] * g[d][k] - g[a][k] * g[d][i]);
          K[4 * a + i][4 * d + k] = v;
        }
        K[4 * a + i][4 * d + 3] = m.mixed() ? -0.25 * V * J * g[a][i] : 0.0;
        K[4 * a + 3][4 * d + i] = m.mixed() ? row.scale * c_u * 0.25 * V * J * g[d][i] : 0.0;
      }
      K[4 * a + 3][4 * d + 3] = row.scale * (M_ad / m.kappa + V * row.tau * dot(gNa, gNd));
    }
  }
}

/// The element's share of Pi(u, p) (stored energy, mixed form) [J]; at the pressure that
/// satisfies R_p = 0 it is the condensed strain energy.
inline double solid_stored_energy(const fem::TetGeometry& geo, const SolidElementState& s,
                                  const SolidMaterial& m, const PressureRow& row) {
  const double V = geo.volume;
  const Mat3 F = deformation_gradient(geo, s.u);
  double e = V * strain_energy(m, F);
  Vec3 grad_p{};
  double pMp = 0.0, p_sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    grad_p = grad_p + s.p[a] * geo.grad[a];
    p_sum += s.p[a];
    for (int b = 0; b < 4; ++b)
      pMp += s.p[a] * fem::mass(V, a, b) * s.p[b];
  }
  if (m.mixed())
    e -= 0.25 * V * p_sum * (det(F) - 1.0);
  return e - 0.5 * pMp / m.kappa - 0.5 * V * row.tau * dot(grad_p, grad_p);
}

/// Element Cauchy stress sigma = J^{-1} P F^T with P = P_dev - p J F^{-T} (mean pressure).
inline Mat3 cauchy_stress(const SolidMaterial& m, const Mat3& F, double p) {
  const Mat3 P = first_piola(m, F);
  const double J = det(F);
  Mat3 sigma{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      for (int K = 0; K < 3; ++K)
        sigma[i][j] += P[i][K] * F[j][K] / J;
      if (i == j && m.mixed())
        sigma[i][j] -= p;
    }
  return sigma;
}

/// sqrt(3/2 dev sigma : dev sigma) [Pa].
inline double von_mises(const Mat3& sigma) {
  const double tr = (sigma[0][0] + sigma[1][1] + sigma[2][2]) / 3.0;
  double s2 = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double d = sigma[i][j] - (i == j ? tr : 0.0);
      s2 += d * d;
    }
  return std::sqrt(1.5 * s2);
}

} // namespace tearflow::physics
