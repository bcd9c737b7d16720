// The element Jacobian must be the exact derivative of the element residual: compare it
// with central finite differences on a random, skewed tet and a random state.
#include <random>

#include <gtest/gtest.h>

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
  const ElementCase s = random_setup(3);
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
  const Stabilization at_T = stabilization(s.geo, u, s.fluid, 5e-3);
  s.fluid.stabilization_time_scale = 5e-3;
  for (double dt : {1e-3, 2.5e-3, 1e-2}) {
    const Stabilization fixed = stabilization(s.geo, u, s.fluid, dt);
    EXPECT_EQ(fixed.tau_m, at_T.tau_m);
    EXPECT_EQ(fixed.nu_c, at_T.nu_c);
  }
  s.fluid.stabilization_time_scale = 0.0;
  EXPECT_LT(stabilization(s.geo, u, s.fluid, 1e-3).tau_m, at_T.tau_m);
}
