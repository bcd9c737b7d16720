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
// with the strong momentum residual
//   r_M = rho (du/dt + u . grad u) + grad p - div sigma_h,
// sigma_h the viscous flux 2 mu eps(u) reconstructed at the nodes (below).
//
// The viscous term of r_M. On P1, div(2 mu eps(u)) is zero inside each element, so without a
// reconstruction r_M = grad p in Poiseuille flow, where the exact residual is zero, and
// SUPG/PSPG act on it: an O(tau_M) inconsistency. Jansen, Collis, Whiting & Shakib ("A
// better consistency for low-order stabilized finite element methods", CMAME 174, 1999;
// svSolver's and PHASTA's default for linear elements, "Include Viscous Correction in
// Stabilization") rebuild the flux at the nodes by the lumped L2 projection
//   sigma_a = sum_{e ni a} V_e sigma(u)_e / sum_{e ni a} V_e
// and take div sigma_h from its P1 interpolant, a constant per element (viscous_flux,
// flux_divergence below; FluidProblem assembles the projection). Like tau_M it is lagged:
// computed once per step from the predictor u_n + alpha_f dt udot_n of u_{n+af}, on the mesh
// at t_n, and its divergence taken on the element as it is. The projection couples each
// element to its neighbours' neighbours, which the matrix's pattern does not hold; lagged, the
// Jacobian below stays the exact derivative and Newton quadratic (from the current iterate
// with the term held fixed in the Jacobian, Newton contracted linearly, by about 4e-3 per
// iteration on the thin-lumen pipe; docs/performance.md). The predictor's O(dt^2) error
// enters multiplied by tau_M.
// FluidProperties::stabilization.viscous_correction false drops it, as svMultiPhysics does.
//
// The parameters, from the element metric G (below) and the lagged advection velocity u:
//   tau_M = (4/T^2 + u.G u + C_I nu^2 G:G)^(-1/2)       (Bazilevs et al. 2007, eq. 63)
//   tau_C = (u.G u + C_I nu^2 G:G)^(-1/2),                C_I = 36 for linear tets
//   nu_C  = c_div / (tau_C tr G)                          (svSolver: c_div = 1/8)
// G. The reference tet's metric sum_{k=1..3} grad xi_k grad xi_k^T leaves node 0 out, so it
// changes with the mesher's numbering (tau_M by 15 % over the renumberings of a skewed tet;
// docs/performance.md). PHASTA's and svSolver's `e3gijd` ("an invariance problem with tets")
// take dxi/dx^T M dxi/dx with M = c1 (I + 1 1^T) / 2, c1 = 2^(1/3); since grad N_0 =
// -sum_k grad xi_k that is (c1 / 2) sum_{a=0..3} grad N_a grad N_a^T: every node alike, and
// det M = 1, so the metric's determinant is the reference tet's. Metric::reference_tet keeps
// the old form (svMultiPhysics').
// nu_C. Bazilevs et al. (eq. 65) take nu_C = 1 / (tau_M g.g), which grows like h^2 / dt as
// dt -> 0 (tau_M -> dt/2) and locks the P1 velocity's element-wise div u (Olshanskii &
// Reusken, Math. Comp. 2004; Jenkins, John, Linke & Rebholz, Adv. Comput. Math. 2014):
// measured on `verify pulse`, the wave speed rose 4.70 -> 5.49 m/s as dt fell 35 -> 17.5 us.
// With tau_C (tau_M without its time term) nu_C keeps the steady limits of Tezduyar's LSIC
// parameter, O(|u| h) in advection and O(nu) in viscous flow (Tezduyar & Osawa, CMAME 2000),
// and does not depend on the step (Hsu, Bazilevs, Calo, Tezduyar & Hughes, CMAME 2010). The
// scale c_div = 1/8 tr G is svSolver's (rho / (8 tau_M tr G)); the earlier 1 / g.g, g.g =
// |grad N_0|^2 (about 3 / tr G), put 40 % of the thin true lumen's loss into grad-div
// (docs/performance.md, "The P1 scheme's loss in a narrow lumen"). The momentum equation's
// grad-div term carries the continuity error into the momentum rows, so Newton's test bounds
// continuity in its own units (fluid_solver.cpp), whatever c_div.
// T. With T = dt the stabilization, and with it the pressure differences of a coarse mesh,
// change with the step for a reason other than time accuracy (the 4.5 mm dissection's TL-FL
// difference by 14-16 % per halving of dt; docs/study.md). T is therefore a time scale of the
// flow, 5 ms (the cardiac cycle's, about period / 200), whatever the step; but at most four
// steps: with tau_M much above dt the PSPG term's tau_M rho du/dt outweighs the continuity
// equation's div u, and the FSI solvers failed (`verify pulse` at dt 50 us: Newton made no
// progress from the first step with T = 1 ms, and converged with T = 0.2 ms;
// docs/performance.md). So every step of 1.25 ms or more, the studies' 5-20 ms among them,
// takes T = 5 ms, and the fine steps of wave verification T = 4 dt.
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
// at t_{n+alpha_m}, pressure taken as it is; the unknowns are (u, p) of step n+1. The pressure
// is the multiplier of the balance at t_{n+alpha_f}, so it approximates p(t_{n+alpha_f}) (the
// outlets' verification shows it, verify/rcr.cpp); runs report it extrapolated to t_{n+1}
// beside the velocity (run/flow_model.cpp). So
// d u_{n+af} / d u_{n+1} = alpha_f = c_u and d udot_{n+am} / d u_{n+1} = alpha_m/(gamma dt) = c_a.
//
// tau_M and nu_C are computed from the velocity of the previous step (lagged): they are
// then constant over the Newton iterations of a step, so the Jacobian below is the exact
// derivative of the residual for a given sigma_h (checked by finite differences in the tests).
//
// All integrals are exact: every integrand is a polynomial of degree <= 2 on the element,
// integrated with the P1 mass matrix M_ab = V/20 (1 + delta_ab).
#include <algorithm>
#include <array>
#include <cmath>

#include "fem/p1_tet.hpp"

namespace tearflow::physics {

/// How the residual-based stabilization is formed (file comment; docs/case-file.md, fluid).
struct StabilizationSpec {
  /// T in tau_M's transient term 4 / T^2 [s]; 0: the time step dt; < 0 (the default): the
  /// flow's time scale, automatic_time_scale, at most automatic_steps steps.
  double time_scale = -1.0;
  static constexpr double automatic_time_scale = 5e-3; ///< [s]
  static constexpr double automatic_steps = 4.0;
  /// T at step dt [s].
  double effective_time_scale(double dt) const {
    return time_scale > 0.0   ? time_scale
           : time_scale == 0. ? dt
                              : std::min(automatic_time_scale, automatic_steps * dt);
  }
  enum class Metric {
    symmetric,    ///< (c1/2) sum over the four corners: node-order free (PHASTA, svSolver)
    reference_tet ///< the unit tet's, node 0 left out (svMultiPhysics)
  } metric = Metric::symmetric;
  double grad_div = 0.125;        ///< c_div in nu_C = c_div / (tau_C tr G)
  bool viscous_correction = true; ///< sigma_h's divergence in r_M
};

struct FluidProperties {
  double density = 1060.0;  ///< rho [kg/m^3]
  double viscosity = 0.004; ///< mu [Pa s]
  StabilizationSpec stabilization{};
};

/// Nodal values on one element. Node-major dofs: 4 a + i (i < 3 velocity, i = 3 pressure).
struct FluidElementState {
  std::array<Vec3, 4> u;    ///< velocity at t_{n+alpha_f} [m/s]
  std::array<Vec3, 4> udot; ///< acceleration at t_{n+alpha_m} [m/s^2]
  std::array<double, 4> p;  ///< pressure at t_{n+1} [Pa]
  std::array<Vec3, 4> w{};  ///< mesh velocity [m/s] (zero on a fixed mesh)
  Vec3 viscous{};           ///< div sigma_h on the element [Pa/m] (zero: no correction)
};

struct Stabilization {
  double tau_m = 0.0;     ///< [s]
  double nu_c = 0.0;      ///< [m^2/s]
  double advection = 0.0; ///< sqrt(u.G u) of the lagged velocity [1/s]
};

using ElementVector = std::array<double, 16>;
using ElementMatrix = std::array<std::array<double, 16>, 16>;

/// The element metric G of the stabilization (file comment).
inline Mat3 stabilization_metric(const fem::TetGeometry& geo, StabilizationSpec::Metric metric) {
  if (metric == StabilizationSpec::Metric::reference_tet)
    return fem::metric_tensor(geo);
  const double c = 0.5 * std::cbrt(2.0); // c1 / 2, c1 = 2^(1/3): det M = 1
  Mat3 G{};
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        G[i][j] += c * geo.grad[a][i] * geo.grad[a][j];
  return G;
}

/// tau_M and nu_C from the element metric and an advection velocity (the lagged one); nu_C
/// does not depend on dt (see the file comment).
inline Stabilization stabilization(const fem::TetGeometry& geo, const Vec3& velocity,
                                   const FluidProperties& fluid, double dt) {
  constexpr double C_I = 36.0;
  const StabilizationSpec& spec = fluid.stabilization;
  const Mat3 G = stabilization_metric(geo, spec.metric);
  const double nu = fluid.viscosity / fluid.density;
  double uGu = 0.0, GG = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      uGu += velocity[i] * G[i][j] * velocity[j];
      GG += G[i][j] * G[i][j];
    }
  const double steady = uGu + C_I * nu * nu * GG; // tau_C^-2
  const double T = spec.effective_time_scale(dt);
  Stabilization s;
  s.tau_m = 1.0 / std::sqrt(4.0 / (T * T) + steady);
  s.nu_c = spec.grad_div * std::sqrt(steady) / (G[0][0] + G[1][1] + G[2][2]);
  s.advection = std::sqrt(uGu);
  return s;
}

/// A symmetric tensor's six components: xx, yy, zz, xy, yz, xz.
using SymTensor = std::array<double, 6>;

/// The element's viscous flux 2 mu eps(u) (constant on a P1 element) [Pa].
inline SymTensor viscous_flux(const fem::TetGeometry& geo, const std::array<Vec3, 4>& u,
                              double mu) {
  Mat3 L{}; // L_ij = du_i / dx_j
  for (int b = 0; b < 4; ++b)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        L[i][j] += u[b][i] * geo.grad[b][j];
  return {2 * mu * L[0][0],         2 * mu * L[1][1],         2 * mu * L[2][2],
          mu * (L[0][1] + L[1][0]), mu * (L[1][2] + L[2][1]), mu * (L[0][2] + L[2][0])};
}

/// div sigma_h of the P1 interpolant of nodal fluxes sigma_a (constant on the element) [Pa/m].
inline Vec3 flux_divergence(const fem::TetGeometry& geo, const std::array<SymTensor, 4>& sigma) {
  Vec3 d{};
  for (int a = 0; a < 4; ++a) {
    const SymTensor& S = sigma[a];
    const Vec3& g = geo.grad[a];
    d[0] += S[0] * g[0] + S[3] * g[1] + S[5] * g[2];
    d[1] += S[3] * g[0] + S[1] * g[1] + S[4] * g[2];
    d[2] += S[5] * g[0] + S[4] * g[1] + S[2] * g[2];
  }
  return d;
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
      f.r[c][i] = fluid.density * (s.udot[c][i] + dot(f.L[i], f.c[c])) + f.grad_p[i] - s.viscous[i];
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
        // (w, rho (udot + u.grad u)): r_M without grad p and div sigma_h
        v += fem::mass(V, a, c) * (f.r[c][i] - f.grad_p[i] + s.viscous[i]);
        v += tau * f.W[a][c] * f.r[c][i]; // SUPG
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
