// The linear continuum of the pulse tube (verify/pulse_continuum.hpp), the reference
// `verify pulse` compares its measured speeds with.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "verify/pulse_continuum.hpp"

namespace tearflow::verify {
namespace {

double smoothstep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

// A pulse 40 ms long in the tube of `verify pulse`, with a vanishing viscosity: its
// wavelength (~0.2 m) is 40 radii, so it must travel undistorted at the long-wave speed.
// Expected deviations: dispersion raises 1/c by (ka)^2 / 16 ~ 2e-3 at the pulse's 25 Hz
// (ka = 0.16), a time shift of 0.1 ms at z = 0.2 m against edges that rise by P0 over 20
// ms: ~1 % of P0; Womersley's F10 ~ 2 / alpha ~ 1e-3 at mu = 1e-9 Pa s. Tolerance 2 % of P0.
TEST(PulseContinuum, LongPulseTravelsUndistortedAtTheLongWaveSpeed) {
  const double P0 = 1000.0, c0 = 5.0, z = 0.2;
  auto inlet = [&](double t) {
    return P0 * smoothstep(t / 0.02) * (1.0 - smoothstep((t - 0.02) / 0.02));
  };
  const PulseContinuum tube({0.005, 0.001, 1000.0, 1e-9, 1200.0, c0}, inlet, 0.1);
  std::vector<double> t;
  for (int i = 0; i <= 200; ++i)
    t.push_back(0.1 * i / 200);
  const std::vector<double> p = tube.pressure(z, t);
  double worst = 0.0;
  for (size_t i = 0; i < t.size(); ++i)
    worst = std::max(worst, std::abs(p[i] - inlet(t[i] - z / c0)));
  EXPECT_LT(worst, 0.02 * P0);
  EXPECT_LT(tube.energy_above_cutoff(), 1e-6); // a 25 Hz pulse has nothing near 480 Hz
}

// The same tube with blood's viscosity and the reference's 3 ms pulse: the wall layer and
// the dispersion both slow and smear the pulse, so its peak at 2.5 cm arrives after the
// long-wave time z / c0 and lower than the inlet's (the 3D run's peak falls by 40 % between
// 1.5 and 3.5 cm). Here only the direction is checked; the size is what `verify pulse`
// reports beside the measured speed.
TEST(PulseContinuum, ShortPulseArrivesLateAndLower) {
  const double P0 = 1333.2, c0 = 5.25, z = 0.025;
  auto inlet = [&](double t) {
    return P0 * smoothstep(t / 1.25e-3) * (1.0 - smoothstep((t - 3e-3) / 1.25e-3));
  };
  const PulseContinuum tube({0.005, 0.001, 1000.0, 0.003, 1200.0, c0}, inlet, 0.015);
  std::vector<double> t;
  for (int i = 0; i <= 1500; ++i)
    t.push_back(0.015 * i / 1500);
  const std::vector<double> p = tube.pressure(z, t);
  const auto peak = std::max_element(p.begin(), p.end());
  const double t_peak = t[static_cast<size_t>(peak - p.begin())];
  // The inlet peaks on its plateau, between 1.25 and 3 ms: centre 2.125 ms.
  EXPECT_GT(t_peak, 2.125e-3 + z / c0);
  EXPECT_LT(*peak, 0.95 * P0);
  EXPECT_GT(*peak, 0.5 * P0);
}

} // namespace
} // namespace tearflow::verify
