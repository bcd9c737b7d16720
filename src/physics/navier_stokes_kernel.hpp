#pragma once
// Incompressible Navier-Stokes, Newtonian, on P1-P1 tetrahedra with residual-based
// stabilization (SUPG / PSPG / LSIC; Tezduyar 1992, Bazilevs et al. 2007):
//
//   rho (du/dt + u . grad u) - div(2 mu eps(u)) + grad p = 0,   div u = 0   in Omega
//
// Weak form, for all (w, q):
//   (w, rho (du/dt + u . grad u)) + (eps(w), 2 mu eps(u)) - (div w, p) - <w, h>_GammaN
//   + sum_e (tau_M u . grad w, r_M)_e + (div w, rho nu_C div u)              [SUPG, LSIC]
//   + (q, div u) + sum_e (tau_M / rho grad q, r_M)_e = 0                      [PSPG]
// with the strong momentum residual r_M = rho (du/dt + u . grad u) + grad p (the viscous
// term vanishes on P1) and
//   tau_M = (4/dt^2 + u.G u + C_I nu^2 G:G)^(-1/2)      (Bazilevs et al. 2007, eq. 63;
//   tau_C = (u.G u + C_I nu^2 G:G)^(-1/2),                C_I = 36 for linear tets)
//   nu_C  = 1 / (tau_C g.g)
// Bazilevs et al. (eq. 65) take nu_C = 1 / (tau_M g.g), which grows like h^2 / dt as
// dt -> 0 (tau_M -> dt/2). In slow transient flow on fine steps that is a bulk viscosity
// rho nu_C far above mu (about 100 Pa s, 4e4 mu, in the pulse tube at h 1.5 mm, dt 25 us):
// the grad-div penalty then drives the element-wise div u of the P1 velocity to zero and
// locks (Olshanskii & Reusken, Math. Comp. 2004; Jenkins, John, Linke & Rebholz, Adv.
// Comput. Math. 2014: the grad-div parameter must stay O(1), a large one locks
// non-divergence-conforming pairs). Measured on `verify pulse`: the wave speed rose from 4.70
// to 5.49 m/s as dt fell from 35 to 17.5 us and the pulse lost 10-21 % of int p dt; with
// tau_C both are dt-independent (4.49 m/s at both steps, under 1 % lost). tau_C is tau_M
// without its time term, so nu_C keeps the steady limits of Tezduyar's LSIC parameter,
// O(|u| h) in advection and O(nu) in viscous flow (Tezduyar & Osawa, CMAME 2000; Tezduyar,
// IJNMF 2003), and does not depend on the time step (Hsu, Bazilevs, Calo, Tezduyar & Hughes,
// CMAME 2010, on stabilized methods at small time steps). tau_M keeps its time term: SUPG
// and PSPG with tau_M ~ dt/2 are consistent (r_M includes du/dt), and the pulse speed does
// not move with dt once nu_C is fixed.
//
// Where 4/dt^2 is not small against u.G u (coarse meshes: h 4.5 mm, |u| 1 m/s gives
// 2e5 s^-2, 4/dt^2 is 1.6e5 at dt 5 ms), the step sets the stabilization, so results move
// with dt for a reason other than time accuracy: the 4.5 mm dissection's peak-systolic
// TL-FL pressure difference rose by 14-16 % per halving of dt (20 -> 2.5 ms) while with the
// time term's T held at 5 ms it moved by under 0.3 % from 10 to 2.5 ms (docs/study.md).
// FluidProperties::stabilization_time_scale sets T; 0 (the default) takes dt.
//
// On a moving mesh (ALE, fsi_problem.hpp) the same form holds on the configuration at
// t_{n+alpha_f} with du/dt the time derivative at fixed mesh node and the convective velocity
// c = u - w, w the mesh velocity (Bazilevs, Calo, Hughes & Zhang 2008, eq. 12): every
// u . grad below becomes c . grad. w does not depend on the element's unknowns here (the
// mesh follows the wall through a separate solve), so the Jacobian keeps its form with c.
// A uniform u then gives zero residual whatever the mesh does: the geometric conservation
// the uniform-flow test checks.
//
// Generalized-alpha (Jansen, Whiting, Hulbert 2000): velocity at t_{n+alpha_f}, acceleration
// at t_{n+alpha_m}, pressure at t_{n+1}; the unknowns are (u, p) at t_{n+1}, so
// d u_{n+af} / d u_{n+1} = alpha_f = c_u and d udot_{n+am} / d u_{n+1} = alpha_m/(gamma dt) = c_a.
//
// tau_M and nu_C are computed from the velocity of the previous step (lagged): they are
// then constant over the Newton iterations of a step, so the Jacobian below is the exact
// derivative of the residual (checked by finite differences in the tests). r_M is the full
// strong residual except for -mu Lap u, which P1 cannot represent (zero inside each
// element): an O(tau_M) = O(h^2) inconsistency, the usual one of P1 stabilized methods;
// the Poiseuille refinement study (mu Lap u = grad p there) still converges at rate ~1.9.
//
// All integrals are exact: every integrand is a polynomial of degree <= 2 on the element,
// integrated with the P1 mass matrix M_ab = V/20 (1 + delta_ab).
#include <array>
#include <cmath>

#include "fem/p1_tet.hpp"

namespace tearflow::physics {

struct FluidProperties {
  double density = 1060.0;  ///< rho [kg/m^3]
  double viscosity = 0.004; ///< mu [Pa s]
  /// T in tau_M's transient term 4 / T^2 [s]; 0: the time step dt.
  double stabilization_time_scale = 0.0;
};

/// Nodal values on one element. Node-major dofs: 4 a + i (i < 3 velocity, i = 3 pressure).
struct FluidElementState {
  std::array<Vec3, 4> u;    ///< velocity at t_{n+alpha_f} [m/s]
  std::array<Vec3, 4> udot; ///< acceleration at t_{n+alpha_m} [m/s^2]
  std::array<double, 4> p;  ///< pressure at t_{n+1} [Pa]
  std::array<Vec3, 4> w{};  ///< mesh velocity [m/s] (zero on a fixed mesh)
};

struct Stabilization {
  double tau_m = 0.0; ///< [s]
  double nu_c = 0.0;  ///< [m^2/s]
};

using ElementVector = std::array<double, 16>;
using ElementMatrix = std::array<std::array<double, 16>, 16>;

/// tau_M and nu_C from the element metric and an advection velocity (the lagged one); nu_C
/// does not depend on dt (see the file comment).
inline Stabilization stabilization(const fem::TetGeometry& geo, const Vec3& velocity,
                                   const FluidProperties& fluid, double dt) {
  constexpr double C_I = 36.0;
  const Mat3 G = fem::metric_tensor(geo);
  const double nu = fluid.viscosity / fluid.density;
  double uGu = 0.0, GG = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      uGu += velocity[i] * G[i][j] * velocity[j];
      GG += G[i][j] * G[i][j];
    }
  const double steady = uGu + C_I * nu * nu * GG; // tau_C^-2
  Stabilization s;
  const double T = fluid.stabilization_time_scale > 0.0 ? fluid.stabilization_time_scale : dt;
  s.tau_m = 1.0 / std::sqrt(4.0 / (T * T) + steady);
  const Vec3& g = geo.grad[0]; // g = -grad N_0; only g.g enters
  s.nu_c = std::sqrt(steady) / dot(g, g);
  return s;
}

/// Quantities shared by the residual and the Jacobian of one element.
struct FluidElementFields {
  Mat3 L{};                                  ///< velocity gradient L_ij = du_i/dx_j
  double div = 0.0;                          ///< div u
  Vec3 grad_p{};                             ///< grad p
  std::array<Vec3, 4> c{};                   ///< convective velocity u - w at the nodes
  std::array<Vec3, 4> r{};                   ///< nodal values of the strong residual r_M
  std::array<std::array<double, 4>, 4> cg{}; ///< cg_cd = c_c . grad N_d
  std::array<std::array<double, 4>, 4> W{};  ///< W_ac = int (c . grad N_a) N_c
};

inline FluidElementFields element_fields(const fem::TetGeometry& geo, const FluidElementState& s,
                                         const FluidProperties& fluid) {
  FluidElementFields f;
  for (int b = 0; b < 4; ++b)
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        f.L[i][j] += s.u[b][i] * geo.grad[b][j];
      f.grad_p[i] += s.p[b] * geo.grad[b][i];
    }
  f.div = f.L[0][0] + f.L[1][1] + f.L[2][2];
  for (int c = 0; c < 4; ++c)
    f.c[c] = s.u[c] - s.w[c];
  for (int c = 0; c < 4; ++c)
    for (int i = 0; i < 3; ++i)
      f.r[c][i] = fluid.density * (s.udot[c][i] + dot(f.L[i], f.c[c])) + f.grad_p[i];
  for (int c = 0; c < 4; ++c)
    for (int d = 0; d < 4; ++d)
      f.cg[c][d] = dot(f.c[c], geo.grad[d]);
  // W_ac = sum_b cg_ba M_bc = V/20 (sum_b cg_ba + cg_ca): the P1 mass matrix is V/20 (1 + I).
  const double m = geo.volume / 20.0;
  for (int a = 0; a < 4; ++a) {
    const double col = f.cg[0][a] + f.cg[1][a] + f.cg[2][a] + f.cg[3][a];
    for (int c = 0; c < 4; ++c)
      f.W[a][c] = m * (col + f.cg[c][a]);
  }
  return f;
}

/// Element residual (interior terms; boundary tractions are added by the BCs).
inline void navier_stokes_residual(const fem::TetGeometry& geo, const FluidElementState& s,
                                   const Stabilization& stab, const FluidProperties& fluid,
                                   ElementVector& R) {
  const FluidElementFields f = element_fields(geo, s, fluid);
  const double V = geo.volume, rho = fluid.density, mu = fluid.viscosity, tau = stab.tau_m;
  const double p_mean = 0.25 * (s.p[0] + s.p[1] + s.p[2] + s.p[3]);
  Vec3 r_sum{};
  for (int c = 0; c < 4; ++c)
    r_sum = r_sum + f.r[c];
  for (int a = 0; a < 4; ++a) {
    const Vec3& gN = geo.grad[a];
    for (int i = 0; i < 3; ++i) {
      double v = 0.0;
      for (int c = 0; c < 4; ++c) {
        v += fem::mass(V, a, c) * (f.r[c][i] - f.grad_p[i]); // (w, rho (udot + u.grad u))
        v += tau * f.W[a][c] * f.r[c][i];                    // SUPG
      }
      for (int j = 0; j < 3; ++j)
        v += V * mu * (f.L[i][j] + f.L[j][i]) * gN[j]; // viscous
      v -= V * p_mean * gN[i];                         // -(div w, p)
      v += V * rho * stab.nu_c * f.div * gN[i];        // LSIC
      R[4 * a + i] = v;
    }
    R[4 * a + 3] = 0.25 * V * f.div                         // (q, div u)
                   + tau / rho * 0.25 * V * dot(gN, r_sum); // PSPG
  }
}

/// Exact derivative of navier_stokes_residual with respect to the nodal (u, p) at t_{n+1}.
///
/// Each 3x3 velocity block (a, d) is built as s_ad I + m_ad L + X_d (x) grad N_a
/// + grad N_a (x) Y_d, from per-element and per-node quantities computed once:
///   s_ad = rho c_a M_ad + rho c_u A_ad + mu V c_u grad N_a . grad N_d
///          + tau rho (c_a W_ad + c_u B_ad)          [inertia, convection, viscous, SUPG dr_M/du]
///   m_ad = rho c_u (M_ad + tau W_ad)                  [d(u . grad u)/du in Galerkin and SUPG]
///   X_d  = mu V c_u grad N_d + tau c_u (M r)_d          [viscous transpose, SUPG d(u.grad w)/du]
///   Y_d  = rho nu_C V c_u grad N_d                      [LSIC]
/// with A_ad = sum_c M_ac cg_cd, B_ad = sum_c W_ac cg_cd and (M r)_d = sum_c M_dc r_c.
inline void navier_stokes_jacobian(const fem::TetGeometry& geo, const FluidElementState& s,
                                   const Stabilization& stab, const FluidProperties& fluid,
                                   double c_u, double c_a, ElementMatrix& K) {
  const FluidElementFields f = element_fields(geo, s, fluid);
  const double V = geo.volume, rho = fluid.density, mu = fluid.viscosity, tau = stab.tau_m;
  const double m = V / 20.0; // off-diagonal entry of the P1 mass matrix
  const auto& g = geo.grad;

  // Per node: column sums of cg (= c_sum . grad N_d), X_d, Y_d; per test node a: the rows
  // of W summed and L^T grad N_a.
  Vec3 r_sum{};
  for (int c = 0; c < 4; ++c)
    r_sum = r_sum + f.r[c];
  std::array<double, 4> cg_col{}, W_row{};
  std::array<Vec3, 4> X{}, Y{}, LtgN{};
  for (int d = 0; d < 4; ++d) {
    cg_col[d] = f.cg[0][d] + f.cg[1][d] + f.cg[2][d] + f.cg[3][d];
    const Vec3 Mr = m * (r_sum + f.r[d]);
    X[d] = (mu * V * c_u) * g[d] + (tau * c_u) * Mr;
    Y[d] = (rho * stab.nu_c * V * c_u) * g[d];
    W_row[d] = f.W[d][0] + f.W[d][1] + f.W[d][2] + f.W[d][3];
    for (int k = 0; k < 3; ++k)
      LtgN[d][k] = g[d][0] * f.L[0][k] + g[d][1] * f.L[1][k] + g[d][2] * f.L[2][k];
  }

  for (int a = 0; a < 4; ++a) {
    const Vec3& gNa = g[a];
    for (int d = 0; d < 4; ++d) {
      const Vec3& gNd = g[d];
      const double M_ad = (a == d) ? 2.0 * m : m;
      const double A_ad = m * (cg_col[d] + f.cg[a][d]);
      const double B_ad = f.W[a][0] * f.cg[0][d] + f.W[a][1] * f.cg[1][d] + f.W[a][2] * f.cg[2][d] +
                          f.W[a][3] * f.cg[3][d];
      const double grad_grad = dot(gNa, gNd);
      const double s_ad = rho * c_a * M_ad + rho * c_u * A_ad + mu * V * c_u * grad_grad +
                          tau * rho * (c_a * f.W[a][d] + c_u * B_ad);
      const double m_ad = rho * c_u * (M_ad + tau * f.W[a][d]);
      for (int i = 0; i < 3; ++i) {
        double* row = &K[4 * a + i][4 * d];
        for (int k = 0; k < 3; ++k)
          row[k] = m_ad * f.L[i][k] + X[d][i] * gNa[k] + gNa[i] * Y[d][k];
        row[i] += s_ad;
        row[3] = -0.25 * V * gNa[i] + tau * W_row[a] * gNd[i]; // pressure, SUPG
      }
      // Continuity row: (q, div u) and PSPG.
      double* row = &K[4 * a + 3][4 * d];
      for (int k = 0; k < 3; ++k)
        row[k] = 0.25 * V * c_u * gNd[k] +
                 tau * 0.25 * V * (c_a * gNa[k] + c_u * (gNa[k] * cg_col[d] + LtgN[a][k]));
      row[3] = tau * V / rho * grad_grad;
    }
  }
}

} // namespace tearflow::physics
