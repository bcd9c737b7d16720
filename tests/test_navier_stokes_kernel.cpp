// The element Jacobian must be the exact derivative of the element residual: compare it
// with central finite differences on a random, skewed tet and a random state.
#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "mesh/structured_generator.hpp"
#include "physics/navier_stokes_kernel.hpp"

using namespace tearflow;
using namespace tearflow::physics;

namespace {

struct ElementCase {
  fem::TetGeometry geo;
  FluidElementState state;
  Stabilization stab;
  FluidProperties fluid{1060.0, 0.004};
};

/// A random state; `moving` adds a random mesh velocity w (ALE).
ElementCase random_setup(unsigned seed, bool moving = false) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  ElementCase s;
  const double h = 1e-3; // 1 mm element, velocities ~ 1 m/s: aortic scales
  std::array<Vec3, 4> x{Vec3{0, 0, 0}, Vec3{h, 0, 0}, Vec3{0.2 * h, 1.1 * h, 0},
                        Vec3{0.3 * h, 0.2 * h, 0.9 * h}};
  for (auto& p : x)
    for (double& c : p)
      c += 0.1 * h * U(gen);
  s.geo = fem::tet_geometry(x);
  for (int a = 0; a < 4; ++a) {
    for (int i = 0; i < 3; ++i) {
      s.state.u[a][i] = U(gen);
      s.state.udot[a][i] = 50.0 * U(gen);
      s.state.w[a][i] = moving ? 0.3 * U(gen) : 0.0;
    }
    s.state.p[a] = 1e4 + 500.0 * U(gen);
  }
  // div sigma_h, a fixed input of the kernel (lagged, navier_stokes_kernel.hpp): a few
  // hundred Pa/m, the size of mu Lap u in a 1 mm element at 1 m/s
  for (int i = 0; i < 3; ++i)
    s.state.viscous[i] = 500.0 * U(gen);
  s.stab = stabilization(s.geo, Vec3{0.3, -0.2, 0.5}, s.fluid, 1e-3);
  return s;
}

} // namespace

TEST(NavierStokesKernel, JacobianMatchesFiniteDifferences) {
  const double c_u = 2.0 / 3.0, c_a = 1.2e3; // alpha_f and alpha_m / (gamma dt), rho_inf = 0.5
  for (unsigned seed = 1; seed <= 10; ++seed) {
    ElementCase s = random_setup(seed, seed > 5); // seeds 6-10 on a moving mesh
    ElementMatrix K{};
    navier_stokes_jacobian(s.geo, s.state, s.stab, s.fluid, c_u, c_a, K);
    double scale = 0.0;
    for (auto& row : K)
      for (double v : row)
        scale = std::max(scale, std::abs(v));
    for (int d = 0; d < 4; ++d)
      for (int k = 0; k < 4; ++k) {
        // A change du of the unknown at t_{n+1} changes u_{n+af} by c_u du and the
        // acceleration by c_a du; a pressure change enters directly.
        const double h = (k < 3) ? 1e-6 : 1e-3;
        ElementVector Rp{}, Rm{};
        for (int sign : {1, -1}) {
          FluidElementState st = s.state;
          if (k < 3) {
            st.u[d][k] += sign * c_u * h;
            st.udot[d][k] += sign * c_a * h;
          } else {
            st.p[d] += sign * h;
          }
          navier_stokes_residual(s.geo, st, s.stab, s.fluid, sign > 0 ? Rp : Rm);
        }
        for (int r = 0; r < 16; ++r) {
          const double fd = (Rp[r] - Rm[r]) / (2 * h);
          // The residual is quadratic in u, so central differences are exact up to
          // round-off: ~1e-16 * |R| / h relative to the largest entry.
          EXPECT_NEAR(K[r][4 * d + k], fd, 1e-7 * scale) << "row " << r << " col " << 4 * d + k;
        }
      }
  }
}

TEST(NavierStokesKernel, RigidTranslationAndHydrostaticGiveNoResidual) {
  // Uniform velocity, zero acceleration, constant pressure: only the pressure term
  // -(div w, p) remains, and it sums to zero over the element's nodes (sum_a grad N_a = 0).
  // The mesh moves with a random, non-uniform velocity: a uniform flow must not see it
  // (geometric conservation of the convective ALE form).
  ElementCase s = random_setup(7, true);
  for (int a = 0; a < 4; ++a) {
    s.state.u[a] = {0.2, -0.1, 0.4};
    s.state.udot[a] = {0, 0, 0};
    s.state.p[a] = 1000.0;
  }
  s.state.viscous = {}; // a uniform flow's reconstructed viscous flux is zero
  ElementVector R{};
  navier_stokes_residual(s.geo, s.state, s.stab, s.fluid, R);
  for (int i = 0; i < 3; ++i) {
    double sum = 0.0;
    for (int a = 0; a < 4; ++a)
      sum += R[4 * a + i];
    EXPECT_NEAR(sum, 0.0, 1e-12);
  }
  for (int a = 0; a < 4; ++a)
    EXPECT_NEAR(R[4 * a + 3], 0.0, 1e-15);
}

TEST(NavierStokesKernel, GradDivParameterDoesNotDependOnTheTimeStep) {
  // tau_M -> dt/2 as dt -> 0, but nu_C = 1 / (tau_C g.g) uses tau_M without its time term:
  // a step 1000x smaller must leave it unchanged (with nu_C = 1 / (tau_M g.g) it would grow
  // ~1000x), and tau_M must approach dt/2 (4/dt^2 dominates the other terms by ~1e8 at
  // dt = 1e-7 s, so to a relative 1e-6 after the square root).
  ElementCase s = random_setup(3);
  s.fluid.stabilization.time_scale = 0.0; // tau_M's time term from the step
  const Vec3 u{0.3, -0.2, 0.5};
  const Stabilization coarse = stabilization(s.geo, u, s.fluid, 1e-4);
  const Stabilization fine = stabilization(s.geo, u, s.fluid, 1e-7);
  EXPECT_DOUBLE_EQ(fine.nu_c, coarse.nu_c);
  EXPECT_NEAR(fine.tau_m, 0.5e-7, 1e-6 * 0.5e-7);
  EXPECT_LT(coarse.tau_m, 0.5e-4);
}

TEST(NavierStokesKernel, StabilizationTimeScaleReplacesTheStep) {
  // With T set, tau_M no longer depends on dt and equals the value at dt = T exactly (the
  // same expression); nu_C never depends on either.
  ElementCase s = random_setup(4);
  const Vec3 u{0.3, -0.2, 0.5};
  s.fluid.stabilization.time_scale = 0.0;
  const Stabilization at_T = stabilization(s.geo, u, s.fluid, 5e-3);
  s.fluid.stabilization.time_scale = 5e-3;
  for (double dt : {1e-3, 2.5e-3, 1e-2}) {
    const Stabilization fixed = stabilization(s.geo, u, s.fluid, dt);
    EXPECT_EQ(fixed.tau_m, at_T.tau_m);
    EXPECT_EQ(fixed.nu_c, at_T.nu_c);
  }
  s.fluid.stabilization.time_scale = 0.0;
  EXPECT_LT(stabilization(s.geo, u, s.fluid, 1e-3).tau_m, at_T.tau_m);
  // The default: 5 ms whatever the step, at most four steps (the file comment says why).
  const StabilizationSpec automatic;
  EXPECT_EQ(automatic.effective_time_scale(1e-2), 5e-3);
  EXPECT_EQ(automatic.effective_time_scale(1.25e-3), 5e-3);
  EXPECT_EQ(automatic.effective_time_scale(1e-4), 4e-4);
}

TEST(NavierStokesKernel, StabilizationDoesNotDependOnNodeOrder) {
  // The 12 orderings of a skewed tet's nodes that keep it positively oriented are the same
  // element: tau_M and nu_C must agree to round-off (1e-12 relative; the metric is a sum over
  // the four corners). The reference tet's metric leaves node 0 out and does not (it spread
  // tau_M by 15 % and nu_C ninefold: docs/performance.md); the test shows that too, so that
  // it keeps measuring something.
  const std::array<Vec3, 4> x{Vec3{0, 0, 0}, Vec3{3e-3, 0, 0}, Vec3{0.4e-3, 0.6e-3, 0},
                              Vec3{2.5e-3, 0.3e-3, 0.5e-3}}; // a flat, skewed tet
  const Vec3 u{0.4, -0.3, 0.8};
  FluidProperties fluid;
  for (auto metric :
       {StabilizationSpec::Metric::symmetric, StabilizationSpec::Metric::reference_tet}) {
    fluid.stabilization.metric = metric;
    double tau_lo = 1e300, tau_hi = 0, nu_lo = 1e300, nu_hi = 0;
    std::array<int, 4> order{0, 1, 2, 3};
    int orderings = 0;
    do {
      std::array<Vec3, 4> y;
      for (int a = 0; a < 4; ++a)
        y[a] = x[order[a]];
      const fem::TetGeometry geo = fem::tet_geometry(y);
      if (geo.volume <= 0)
        continue;
      ++orderings;
      const Stabilization st = stabilization(geo, u, fluid, 1e-2);
      tau_lo = std::min(tau_lo, st.tau_m), tau_hi = std::max(tau_hi, st.tau_m);
      nu_lo = std::min(nu_lo, st.nu_c), nu_hi = std::max(nu_hi, st.nu_c);
    } while (std::next_permutation(order.begin(), order.end()));
    EXPECT_EQ(orderings, 12);
    if (metric == StabilizationSpec::Metric::symmetric) {
      EXPECT_NEAR(tau_hi / tau_lo, 1.0, 1e-12);
      EXPECT_NEAR(nu_hi / nu_lo, 1.0, 1e-12);
    } else {
      EXPECT_GT(tau_hi / tau_lo, 1.05);
    }
  }
}

TEST(NavierStokesKernel, SymmetricMetricKeepsTheReferenceTetsDeterminant) {
  // det of c1/2 sum_a grad N_a grad N_a^T equals the reference tet's det (c1 = 2^(1/3) makes
  // det M = 1; PHASTA's e3gijd): the two metrics measure the same volume.
  ElementCase s = random_setup(5);
  const auto det = [](const Mat3& m) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double sym = det(stabilization_metric(s.geo, StabilizationSpec::Metric::symmetric));
  const double ref = det(stabilization_metric(s.geo, StabilizationSpec::Metric::reference_tet));
  EXPECT_NEAR(sym / ref, 1.0, 1e-12);
}

TEST(NavierStokesKernel, ReconstructedViscousFluxIsExactForQuadraticFlow) {
  // The viscous correction's consistency: for a quadratic velocity, the lumped projection of
  // the elements' 2 mu eps(u) (viscous_flux) is the exact, linear flux at every interior node
  // of a uniform Kuhn mesh (the average of a P1 gradient over a point-symmetric patch is exact
  // for quadratics), so on elements away from the boundary flux_divergence gives
  // div(2 mu eps(u)) = mu (Lap u + grad div u) exactly, where a P1 residual without it has
  // zero. Tolerance: round-off, 1e-9 of the term.
  const double mu = 0.004, h = 1e-3;
  const mesh::Mesh m = mesh::make_box({8 * h, 8 * h, 8 * h}, {8, 8, 8});
  const auto u = [](const Vec3& x) { // a quadratic field with div u != 0
    return Vec3{x[0] * x[1] + 3 * x[2] * x[2], x[1] * x[1] - x[0] * x[2],
                2 * x[0] * x[0] + x[1] * x[2]};
  };
  // mu (Lap u + grad div u): Lap u = (6, 2, 4); div u = y + 2y + y = 4y, grad div u = (0, 4, 0)
  const Vec3 exact{mu * 6, mu * (2 + 4), mu * 4};
  std::vector<SymTensor> sum(m.points.size(), SymTensor{});
  std::vector<double> volume(m.points.size(), 0.0);
  for (const Tet& t : m.tets) {
    const fem::TetGeometry geo =
        fem::tet_geometry({m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]});
    const SymTensor sigma = viscous_flux(
        geo, {u(m.points[t[0]]), u(m.points[t[1]]), u(m.points[t[2]]), u(m.points[t[3]])}, mu);
    for (Index a : t) {
      for (int k = 0; k < 6; ++k)
        sum[a][k] += 0.25 * geo.volume * sigma[k];
      volume[a] += 0.25 * geo.volume;
    }
  }
  const auto interior = [&](const Vec3& x) {
    for (double c : x)
      if (c < 0.5 * h || c > 7.5 * h) // the nodes off the boundary
        return false;
    return true;
  };
  int checked = 0;
  for (const Tet& t : m.tets) {
    if (!interior(m.points[t[0]]) || !interior(m.points[t[1]]) || !interior(m.points[t[2]]) ||
        !interior(m.points[t[3]]))
      continue;
    std::array<SymTensor, 4> nodal;
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 6; ++k)
        nodal[a][k] = sum[t[a]][k] / volume[t[a]];
    const Vec3 div = flux_divergence(
        fem::tet_geometry({m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]}), nodal);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(div[i], exact[i], 1e-9 * mu * 6);
    ++checked;
  }
  EXPECT_EQ(checked, 6 * 6 * 6 * 6); // the Kuhn split's six tets per inner cube
}
