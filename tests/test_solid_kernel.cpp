// The solid element and surface kernels: Jacobians against central finite differences,
// stresses against the derivative of the energy, objectivity, and the material checks.
#include <random>

#include <gtest/gtest.h>

#include "bc/solid_conditions.hpp"
#include "physics/solid_kernel.hpp"

using namespace tearflow;
using namespace tearflow::physics;

namespace {

struct ElementCase {
  fem::TetGeometry geo;
  SolidElementState state;
  SolidMaterial material;
  PressureRow row;
};

/// A skewed 2 mm tet with displacements of ~20 % strain, pressures ~ mu / 10.
ElementCase random_setup(unsigned seed, SolidModel model) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  ElementCase s;
  const double h = 2e-3;
  std::array<Vec3, 4> x{Vec3{0, 0, 0}, Vec3{h, 0, 0}, Vec3{0.2 * h, 1.1 * h, 0},
                        Vec3{0.3 * h, 0.2 * h, 0.9 * h}};
  for (auto& p : x)
    for (double& c : p)
      c += 0.1 * h * U(gen);
  s.geo = fem::tet_geometry(x);
  s.material = SolidMaterial::from_young_poisson(model, 1.2e6, 0.45, 1450.0);
  for (int a = 0; a < 4; ++a) {
    for (int i = 0; i < 3; ++i) {
      s.state.u[a][i] = 0.2 * h * U(gen);
      s.state.a[a][i] = 10.0 * U(gen);
    }
    s.state.p[a] = 4e4 * U(gen);
  }
  s.row = {pressure_stabilization(s.material, s.geo.volume), s.material.mu / h};
  return s;
}

/// The largest entry of each (momentum | pressure row) x (displacement | pressure column)
/// block: their magnitudes differ by orders, so each block is checked on its own scale.
std::array<std::array<double, 2>, 2> block_scales(const ElementMatrix& K) {
  std::array<std::array<double, 2>, 2> m{};
  for (int r = 0; r < 16; ++r)
    for (int c = 0; c < 16; ++c) {
      double& s = m[r % 4 == 3][c % 4 == 3];
      s = std::max(s, std::abs(K[r][c]));
    }
  return m;
}

} // namespace

class SolidKernelJacobian : public ::testing::TestWithParam<SolidModel> {};

TEST_P(SolidKernelJacobian, MatchesFiniteDifferences) {
  // A velocity unknown with rho_inf = 0.5 and dt = 1 ms: u changes by c_u = alpha_f beta dt /
  // gamma, a by c_a = alpha_m / (gamma dt) per unit change of the unknown.
  const double c_u = 3.6e-4, c_a = 1.2e3;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const ElementCase s = random_setup(seed, GetParam());
    ElementMatrix K{};
    solid_jacobian(s.geo, s.state, s.material, s.row, c_u, c_a, K);
    const auto scale = block_scales(K);
    for (int d = 0; d < 4; ++d)
      for (int k = 0; k < 4; ++k) {
        const double h = (k < 3) ? 1e-5 : 1.0; // unknown: velocity [m/s] or pressure [Pa]
        ElementVector Rp{}, Rm{};
        for (int sign : {1, -1}) {
          SolidElementState st = s.state;
          if (k < 3) {
            st.u[d][k] += sign * c_u * h;
            st.a[d][k] += sign * c_a * h;
          } else {
            st.p[d] += sign * h;
          }
          solid_residual(s.geo, st, s.material, s.row, sign > 0 ? Rp : Rm);
        }
        for (int r = 0; r < 16; ++r) {
          const double fd = (Rp[r] - Rm[r]) / (2 * h);
          // Central differences: truncation O(h^2 |R'''|), here ~1e-9 relative; round-off
          // ~1e-16 |R| / (c_u h) ~ 1e-9. 1e-6 of the largest entry catches any wrong term.
          EXPECT_NEAR(K[r][4 * d + k], fd, 1e-6 * scale[r % 4 == 3][k == 3])
              << "seed " << seed << " row " << r << " col " << 4 * d + k;
        }
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Materials, SolidKernelJacobian,
                         ::testing::Values(SolidModel::NeoHookean, SolidModel::StVenantKirchhoff));

TEST(SolidKernel, StressIsTheDerivativeOfTheEnergy) {
  for (SolidModel model : {SolidModel::NeoHookean, SolidModel::StVenantKirchhoff}) {
    const ElementCase s = random_setup(11, model);
    const Mat3 F = deformation_gradient(s.geo, s.state.u);
    const Mat3 P = first_piola(s.material, F);
    for (int i = 0; i < 3; ++i)
      for (int J = 0; J < 3; ++J) {
        const double h = 1e-6;
        Mat3 Fp = F, Fm = F;
        Fp[i][J] += h;
        Fm[i][J] -= h;
        const double fd =
            (strain_energy(s.material, Fp) - strain_energy(s.material, Fm)) / (2.0 * h);
        EXPECT_NEAR(P[i][J], fd, 1e-6 * s.material.mu) << i << J;
      }
  }
}

TEST(SolidKernel, ResidualIsTheGradientOfTheStoredEnergy) {
  // R_u (without inertia) = dPi/du and R_p = -s dPi/dp: the discrete system is variational,
  // which the energy conservation of `verify energy` relies on.
  ElementCase s = random_setup(5, SolidModel::NeoHookean);
  s.state.a = {};
  ElementVector R{};
  solid_residual(s.geo, s.state, s.material, s.row, R);
  for (int d = 0; d < 4; ++d)
    for (int k = 0; k < 4; ++k) {
      const double h = k < 3 ? 1e-9 : 1.0;
      SolidElementState p = s.state, m = s.state;
      (k < 3 ? p.u[d][k] : p.p[d]) += h;
      (k < 3 ? m.u[d][k] : m.p[d]) -= h;
      const double fd = (solid_stored_energy(s.geo, p, s.material, s.row) -
                         solid_stored_energy(s.geo, m, s.material, s.row)) /
                        (2.0 * h);
      const double expected = k < 3 ? R[4 * d + k] : -R[4 * d + 3] / s.row.scale;
      EXPECT_NEAR(fd, expected, 1e-6 * std::abs(expected) + 1e-12) << d << k;
    }
}

TEST(SolidKernel, RigidRotationIsStressFree) {
  // Neo-Hookean and St. Venant-Kirchhoff are objective: a 40 degree rotation with zero
  // pressure and acceleration leaves no residual.
  for (SolidModel model : {SolidModel::NeoHookean, SolidModel::StVenantKirchhoff}) {
    ElementCase s = random_setup(3, model);
    const double c = std::cos(0.7), sn = std::sin(0.7);
    std::array<Vec3, 4> X{Vec3{0, 0, 0}, Vec3{1e-3, 0, 0}, Vec3{0, 1e-3, 0}, Vec3{0, 0, 1e-3}};
    s.geo = fem::tet_geometry(X);
    for (int a = 0; a < 4; ++a) {
      const Vec3 x{c * X[a][0] - sn * X[a][1], sn * X[a][0] + c * X[a][1], X[a][2]};
      s.state.u[a] = x - X[a];
      s.state.a[a] = {};
      s.state.p[a] = 0.0;
    }
    ElementVector R{};
    solid_residual(s.geo, s.state, s.material, s.row, R);
    for (double r : R)
      EXPECT_NEAR(r, 0.0, 1e-9 * s.material.mu * 1e-6);
  }
}

TEST(SolidKernel, FollowerPressureJacobianMatchesFiniteDifferences) {
  std::mt19937 gen(4);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::array<Vec3, 3> x{Vec3{0, 0, 0}, Vec3{1e-3, 0, 0}, Vec3{0.3e-3, 0.9e-3, 0}};
  for (auto& p : x)
    for (double& c : p)
      c += 2e-4 * U(gen);
  const double P = 1.3e4, c_u = 0.7;
  bc::TriMatrix K{};
  bc::follower_pressure_jacobian(x, P, c_u, K);
  for (int b = 0; b < 3; ++b)
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-7;
      bc::TriVector Rp{}, Rm{};
      auto xp = x, xm = x;
      xp[b][k] += c_u * h;
      xm[b][k] -= c_u * h;
      bc::follower_pressure_residual(xp, P, Rp);
      bc::follower_pressure_residual(xm, P, Rm);
      for (int r = 0; r < 9; ++r) // the residual is quadratic in x: exact up to round-off
        EXPECT_NEAR(K[r][3 * b + k], (Rp[r] - Rm[r]) / (2 * h), 1e-8 * P * 1e-3) << r << b << k;
    }
}

TEST(SolidMaterial, RejectsBadParameters) {
  EXPECT_THROW(SolidMaterial::from_young_poisson(SolidModel::NeoHookean, -1e6, 0.3, 1000.0),
               InputError);
  EXPECT_THROW(SolidMaterial::from_young_poisson(SolidModel::NeoHookean, 1e6, 0.5, 1000.0),
               InputError);
  EXPECT_THROW(SolidMaterial::from_young_poisson(SolidModel::NeoHookean, 1e6, -1.0, 1000.0),
               InputError);
  EXPECT_THROW(SolidMaterial::from_shear_bulk(SolidModel::NeoHookean, 1e5, 0.0, 1000.0),
               InputError);
  EXPECT_THROW(SolidMaterial::from_shear_bulk(SolidModel::NeoHookean, 1e5, 1e6, 0.0), InputError);
  try {
    SolidMaterial::from_young_poisson(SolidModel::NeoHookean, 1e6, 0.5, 1000.0);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Poisson's ratio must be in (-1, 0.5), got 0.5"),
              std::string::npos)
        << e.what();
  }
  const SolidMaterial m =
      SolidMaterial::from_young_poisson(SolidModel::NeoHookean, 1.2e6, 0.49, 1450.0);
  EXPECT_NEAR(m.youngs_modulus(), 1.2e6, 1e-6);
  EXPECT_NEAR(m.poisson_ratio(), 0.49, 1e-12);
}
