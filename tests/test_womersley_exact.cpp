// The analytic Womersley solution: complex Bessel functions against reference values, the
// solution against its defining equations (momentum, no-slip, flow rate) and known limits.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "bc/womersley_exact.hpp"

using namespace tearflow;
using namespace tearflow::bc;
using cplx = std::complex<double>;

namespace {

constexpr double kPi = std::numbers::pi;
const cplx kI32 = std::polar(1.0, 0.75 * kPi); // i^(3/2)

double rel(cplx a, cplx b) {
  return std::abs(a - b) / std::abs(b);
}

/// J0, J1 at z = i^(3/2) x (J0 = ber x + i bei x) from mpmath 1.3 at 40 digits.
struct RayValue {
  double x;
  cplx j0, j1;
};
const RayValue kRay[] = {
    {1, {0.98438178121308688, 0.24956604003665972}, {-0.39586826101971139, 0.30755663137553655}},
    {5, {-6.2300824786663577, 0.11603438155020038}, {0.3597766667766728, -5.7979079017926252}},
    {10, {138.84046594163265, 56.370458553906638}, {-59.477610426263329, 131.87863917568693}},
    {15, {-2967.2545346351292, -2952.7078873441173}, {2954.8652913524628, -2826.0936042573827}},
    {17, {9484.4544018693878, -13087.268169819325}, {12613.836305828673, 9565.4704591953635}},
    {20, {47489.37026506176, 114775.19736006622}, {-113602.51898665045, 44584.37470400382}},
    {30, {-46117602.577985, 109955713.1825061}, {-108110203.69317974, -46885734.672072366}},
    {40, {-112596696872.07407, 45628130285.641258}, {-44220722032.267616, -112008564758.73024}},
};

/// A flow with a few harmonics in a 1 cm radius pipe of blood; alpha = 12 at n = 1.
WomersleyFlow test_flow(double alpha) {
  WomersleyFlow f;
  f.radius = 0.01;
  f.density = 1060.0;
  f.viscosity = 0.004;
  f.omega = alpha * alpha * f.viscosity / (f.density * f.radius * f.radius);
  f.modes = {1e-5, std::polar(5e-6, 0.3), std::polar(2e-6, -1.1), cplx(0.0, 1e-6)};
  return f;
}

double flux_scale(const WomersleyFlow& f) {
  double s = 0.0;
  for (cplx q : f.modes)
    s += std::abs(q);
  return s;
}

} // namespace

TEST(Bessel, KelvinTableValues) {
  // Abramowitz & Stegun table 9.12 (ber 5 = -6.230082479, bei 5 = 0.116034382).
  const double table[][3] = {
      {1, 0.98438178, 0.24956604}, {5, -6.230082479, 0.116034382}, {10, 138.840466, 56.3704586}};
  for (const auto& [x, ber, bei] : table) {
    const cplx j = bessel_j0(kI32 * x);
    EXPECT_NEAR(j.real(), ber, 1e-8 * std::max(1.0, std::abs(ber))) << x;
    EXPECT_NEAR(j.imag(), bei, 1e-8 * std::max(1.0, std::abs(bei))) << x;
  }
}

TEST(Bessel, WomersleyRayAgainstHighPrecision) {
  double worst = 0.0;
  for (const RayValue& r : kRay) {
    const double e0 = rel(bessel_j0(kI32 * r.x), r.j0), e1 = rel(bessel_j1(kI32 * r.x), r.j1);
    EXPECT_LT(e0, 2e-14) << r.x;
    EXPECT_LT(e1, 2e-14) << r.x;
    worst = std::max({worst, e0, e1});
  }
  std::printf("J0, J1 on the ray i^(3/2) x, x = 1..40: worst relative error %.2e\n", worst);
}

TEST(Bessel, GeneralComplexArguments) {
  // mpmath references, and std::cyl_bessel_j on the real axis.
  const struct {
    cplx z, j0, j1;
  } ref[] = {
      {{3, 4},
       {-8.8121437936979055, -4.5984378997430351},
       {3.6541102814142644, -8.4031042565830872}},
      {{20, 5}, {11.57305816151333, -6.0480233138325912}, {6.2881238186496491, 11.363863418680365}},
      {{-7, 2},
       {1.1143094233060726, 0.063126244392085549},
       {-0.12786227854037559, 1.0526264484664747}}};
  for (const auto& r : ref) {
    EXPECT_LT(rel(bessel_j0(r.z), r.j0), 1e-13) << r.z;
    EXPECT_LT(rel(bessel_j1(r.z), r.j1), 1e-13) << r.z;
  }
  // Near the real axis the series loses digits to cancellation (terms ~e^|z| / |z|, J ~ 1).
  for (double x : {0.5, 3.0, 8.0, 12.0, 25.0, 60.0}) {
    EXPECT_NEAR(bessel_j0(x).real(), std::cyl_bessel_j(0.0, x), 1e-10) << x;
    EXPECT_NEAR(bessel_j1(x).real(), std::cyl_bessel_j(1.0, x), 1e-10) << x;
    EXPECT_NEAR(bessel_j0(-x).real(), std::cyl_bessel_j(0.0, x), 1e-10) << x;  // even
    EXPECT_NEAR(bessel_j1(-x).real(), -std::cyl_bessel_j(1.0, x), 1e-10) << x; // odd
  }
}

TEST(Bessel, BranchesAgreeAtCrossover) {
  // At |z| = kBesselAsymptoticFrom on the Womersley ray (and off the real axis generally) the
  // power series and the asymptotic expansion agree to rounding.
  double worst = 0.0;
  for (double arg : {0.75 * kPi, -0.25 * kPi, 0.25 * kPi, 0.5 * kPi, 0.6 * kPi}) {
    for (double dr : {-1e-9, 0.0, 1e-9}) {
      const cplx z = std::polar(kBesselAsymptoticFrom + dr, arg);
      for (int nu : {0, 1}) {
        const double d = rel(detail::bessel_series(nu, z), detail::bessel_asymptotic(nu, z));
        EXPECT_LT(d, 1e-10) << "nu " << nu << " arg " << arg;
        worst = std::max(worst, d);
      }
    }
  }
  std::printf("series vs asymptotic at |z| = %g: worst relative difference %.2e\n",
              kBesselAsymptoticFrom, worst);
}

TEST(Bessel, DerivativeIdentity) {
  // J0' = -J1 (DLMF 10.6.3), by complex central differences across the branch switch.
  for (double x : {2.0, 16.9, 17.1, 35.0}) {
    const cplx z = kI32 * x, h = kI32 * 1e-5;
    const cplx d = (bessel_j0(z + h) - bessel_j0(z - h)) / (2.0 * h);
    EXPECT_LT(rel(d, -bessel_j1(z)), 1e-9) << x;
  }
}

TEST(Womersley, SatisfiesMomentumEquation) {
  // rho du/dt = -dp/dz + mu (u'' + u'/r), derivatives by 4th-order central differences.
  const WomersleyFlow f = test_flow(12.0);
  const double R = f.radius, T = 2.0 * kPi / f.omega, dt = T * 1e-3, dr = R * 1e-3;
  auto d1 = [](auto g, double x, double h) {
    return (g(x - 2 * h) - 8 * g(x - h) + 8 * g(x + h) - g(x + 2 * h)) / (12 * h);
  };
  auto d2 = [](auto g, double x, double h) {
    return (-g(x - 2 * h) + 16 * g(x - h) - 30 * g(x) + 16 * g(x + h) - g(x + 2 * h)) /
           (12 * h * h);
  };
  double worst = 0.0;
  for (double r : {0.1 * R, 0.5 * R, 0.9 * R, 0.99 * R})
    for (double t : {0.0, 0.3 * T, 0.77 * T}) {
      auto in_t = [&](double s) { return f.axial_velocity(r, s); };
      auto in_r = [&](double s) { return f.axial_velocity(s, t); };
      const double inertia = f.density * d1(in_t, t, dt), G = f.pressure_gradient(t);
      const double viscous = f.viscosity * (d2(in_r, r, dr) + d1(in_r, r, dr) / r);
      const double scale = std::max({std::abs(inertia), std::abs(G), std::abs(viscous)});
      const double res = std::abs(inertia + G - viscous) / scale;
      EXPECT_LT(res, 1e-6) << "r " << r << " t " << t;
      worst = std::max(worst, res);
    }
  std::printf("momentum residual (relative): %.2e\n", worst);
}

TEST(Womersley, FlowRateAndNoSlip) {
  for (double alpha : {0.5, 4.0, 12.0, 25.0}) {
    const WomersleyFlow f = test_flow(alpha);
    const double R = f.radius, T = 2.0 * kPi / f.omega, U = flux_scale(f) / (kPi * R * R);
    EXPECT_NEAR(f.womersley_number(), alpha, 1e-12 * alpha);
    for (double t : {0.0, 0.21 * T, 0.5 * T, 0.9 * T}) {
      // Q = int_0^R 2 pi r u dr, composite Simpson on 4000 intervals (boundary layer ~R/alpha).
      const int n = 4000;
      double q = 0.0;
      for (int k = 0; k <= n; ++k) {
        const double r = R * k / n, w = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
        q += w * 2 * kPi * r * f.axial_velocity(r, t);
      }
      q *= R / n / 3.0;
      EXPECT_NEAR(q, f.flow(t), 1e-8 * flux_scale(f)) << "alpha " << alpha << " t " << t;
      EXPECT_NEAR(f.axial_velocity(R, t), 0.0, 1e-13 * U) << "alpha " << alpha;
    }
  }
}

TEST(Womersley, LowFrequencyTendsToPoiseuille) {
  // Quasi-steady: u -> 2 Q(t)/(pi R^2) (1 - r^2/R^2), dp/dz -> -8 mu Q(t)/(pi R^4); the
  // departure is O(alpha^2).
  double previous = 0.0;
  for (double alpha : {0.2, 0.1, 0.05, 1e-4}) {
    const WomersleyFlow f = test_flow(alpha);
    const double R = f.radius, T = 2.0 * kPi / f.omega, U = flux_scale(f) / (kPi * R * R);
    double err = 0.0, gerr = 0.0;
    for (double t : {0.0, 0.4 * T, 0.8 * T}) {
      const double Q = f.flow(t);
      for (double r : {0.0, 0.3 * R, 0.8 * R})
        err = std::max(
            err,
            std::abs(f.axial_velocity(r, t) - 2 * Q / (kPi * R * R) * (1 - r * r / (R * R))) / U);
      const double G0 = 8 * f.viscosity * flux_scale(f) / (kPi * R * R * R * R);
      gerr = std::max(
          gerr,
          std::abs(f.pressure_gradient(t) + 8 * f.viscosity * Q / (kPi * R * R * R * R)) / G0);
    }
    EXPECT_LT(err, alpha * alpha) << alpha;
    EXPECT_LT(gerr, alpha * alpha) << alpha;
    if (previous > 0 && alpha > 0.01) {
      EXPECT_NEAR(previous / err, 4.0, 0.4) << alpha;
    }
    previous = err;
    std::printf("alpha %-6g: |u - Poiseuille| / U = %.3e\n", alpha, err);
  }
}

TEST(Womersley, CentrelineLagsFlowAtHighAlpha) {
  // Single harmonic Q = cos(w t): the centreline velocity's phase from a DFT of samples.
  WomersleyFlow f = test_flow(12.0);
  f.modes = {0.0, 1e-5};
  const double T = 2.0 * kPi / f.omega, U = 1e-5 / (kPi * f.radius * f.radius);
  const int M = 256;
  cplx u1 = 0.0;
  for (int k = 0; k < M; ++k)
    u1 += f.axial_velocity(0.0, k * T / M) * std::polar(1.0, -2 * kPi * k / M);
  u1 *= 2.0 / M;
  const double lag = -std::arg(u1); // Q's phase is 0
  // Large-alpha estimate: J1/J0 -> i, so u(0)/U -> 1 / (1 - sqrt(2)(1 - i)/alpha).
  const cplx est = 1.0 / (1.0 - std::sqrt(2.0) * cplx(1.0, -1.0) / 12.0);
  std::printf("alpha 12: centreline amplitude %.4f U (Poiseuille 2 U), lags the flow by "
              "%.2f deg = %.4f T (estimate %.2f deg)\n",
              std::abs(u1) / U, lag * 180 / kPi, lag / (2 * kPi), -std::arg(est) * 180 / kPi);
  EXPECT_GT(lag, 0.0);
  EXPECT_NEAR(lag, -std::arg(est), 0.02);
  EXPECT_NEAR(std::abs(u1) / U, std::abs(est), 0.02);
}

TEST(Womersley, FromWaveform) {
  // Q(t) = 5 + 2 cos(w t) - sin(2 w t) [ml/s] sampled at 64 points; T = 0.8 s.
  const double T = 0.8, w = 2 * kPi / T;
  auto Q = [&](double t) { return 1e-6 * (5 + 2 * std::cos(w * t) - std::sin(2 * w * t)); };
  std::vector<double> ts, vs;
  for (int i = 0; i < 64; ++i) {
    ts.push_back(i * T / 64);
    vs.push_back(Q(ts.back()));
  }
  const auto wave = bc::Waveform::periodic(ts, vs, T, "test");
  const WomersleyFlow f = womersley_from_waveform(wave, 8, 0.012, 1060.0, 0.0035);
  EXPECT_NEAR(f.omega, w, 1e-12);
  EXPECT_NEAR(f.womersley_number(), 0.012 * std::sqrt(w * 1060.0 / 0.0035), 1e-12);
  ASSERT_EQ(f.modes.size(), 8u);
  EXPECT_EQ(f.modes[0].imag(), 0.0);
  EXPECT_NEAR(std::abs(f.modes[1] - 2e-6), 0.0, 1e-11);
  EXPECT_NEAR(std::abs(f.modes[2] - cplx(0.0, 1e-6)), 0.0, 1e-11); // -sin = Re(i e^{i2wt})
  for (double t : {0.0, 0.1, 0.37, -0.5})
    EXPECT_NEAR(f.flow(t), Q(t), 1e-11) << t;
  // A constant waveform gives steady Poiseuille flow.
  const WomersleyFlow s = womersley_from_waveform(bc::Waveform::constant(1e-6), 4, 0.01, 1e3, 1e-3);
  EXPECT_EQ(s.omega, 0.0);
  EXPECT_NEAR(s.axial_velocity(0.0, 3.0), 2e-6 / (kPi * 1e-4), 1e-15);
  EXPECT_NEAR(s.pressure_gradient(1.0), -8e-3 * 1e-6 / (kPi * 1e-8), 1e-12);
}
