#include "verify/pulse_continuum.hpp"

#include <cmath>
#include <numbers>
#include <optional>

#include "bc/womersley_exact.hpp"

namespace tearflow::verify {

namespace {

using cplx = std::complex<double>;

/// Womersley's F10(alpha) = 2 J1(L) / (L J0(L)), L = i^(3/2) alpha.
cplx womersley_f10(double alpha) {
  const cplx L = std::pow(cplx(0.0, 1.0), 1.5) * alpha;
  if (alpha > 30.0) // J1/J0 -> i (1 + i/(2L)) for Im L -> infinity: skips overflowing J's
    return 2.0 / L * (cplx(0.0, 1.0) + 1.0 / (2.0 * L));
  return 2.0 * bc::bessel_j1(L) / (L * bc::bessel_j0(L));
}

/// I0(x) / I1(x), x > 0.
double bessel_i_ratio(double x) {
  if (x > 500.0) // asymptotic (DLMF 10.40.1); cyl_bessel_i overflows near 700
    return 1.0 + 1.0 / (2.0 * x) + 3.0 / (8.0 * x * x);
  return std::cyl_bessel_i(0.0, x) / std::cyl_bessel_i(1.0, x);
}

/// k(w) [1/m] (see the header); nullopt above the dispersion's cut-off.
std::optional<cplx> wavenumber(const ContinuumTube& tube, double w) {
  if (w == 0.0)
    return cplx(0.0);
  auto omega2 = [&](double k) { return std::pow(k * dispersive_speed(tube, k), 2); };
  // omega2 grows with k; k a = 100 is far past the cut-off.
  double lo = w / tube.long_wave_speed, hi = 2e4;
  if (omega2(hi) <= w * w)
    return std::nullopt;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (omega2(mid) < w * w ? lo : hi) = mid;
  }
  const double alpha = tube.radius * std::sqrt(w * tube.fluid_density / tube.viscosity);
  return 0.5 * (lo + hi) / std::sqrt(1.0 - womersley_f10(alpha));
}

} // namespace

double dispersive_speed(const ContinuumTube& tube, double k) {
  const double ka = k * tube.radius;
  const double fluid = 0.5 * ka * bessel_i_ratio(ka);
  const double wall =
      tube.wall_density * tube.wall_thickness * tube.radius * k * k / (2.0 * tube.fluid_density);
  return tube.long_wave_speed / std::sqrt(fluid + wall);
}

PulseContinuum::PulseContinuum(const ContinuumTube& tube,
                               const std::function<double(double)>& inlet, double duration) {
  // The transform's window: 8x the evaluated duration, so the pulse's periodic copies lie far
  // outside it; 4096 samples (34 kHz for the 15 ms of `verify pulse`); frequencies up to
  // 4 kHz, where the smoothed 3 ms pulse's spectrum is ~1e-6 of its peak.
  period_ = 8.0 * duration;
  const int samples = 4096;
  const double dts = period_ / samples, f_max = 4000.0;
  std::vector<std::pair<double, double>> pulse; // (t, p) where p != 0
  for (int i = 0; i < samples; ++i)
    if (const double p = inlet(i * dts); p != 0.0)
      pulse.emplace_back(i * dts, p);
  double energy = 0.0, energy_dropped = 0.0;
  for (int n = 0; n <= static_cast<int>(f_max * period_); ++n) {
    const double w = 2.0 * std::numbers::pi * n / period_;
    cplx s = 0.0;
    for (auto [t, p] : pulse)
      s += p * std::exp(cplx(0.0, -w * t)) * dts;
    const std::optional<cplx> k = wavenumber(tube, w);
    energy += std::norm(s);
    if (!k) {
      energy_dropped += std::norm(s);
      continue;
    }
    omega_.push_back(w);
    spectrum_.push_back(s);
    wavenumber_.push_back(*k);
  }
  dropped_ = energy_dropped / energy;
}

std::vector<double> PulseContinuum::pressure(double z, const std::vector<double>& t) const {
  // p(z, t) = (1/T) Re(S_0 + 2 sum_{n>=1} S_n exp(i (w_n t - k_n z))).
  std::vector<cplx> at_z(omega_.size());
  for (size_t n = 0; n < omega_.size(); ++n)
    at_z[n] = spectrum_[n] * std::exp(cplx(0.0, -1.0) * wavenumber_[n] * z);
  std::vector<double> p(t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    double v = 0.0;
    for (size_t n = 0; n < omega_.size(); ++n)
      v +=
          (omega_[n] == 0.0 ? 1.0 : 2.0) * (at_z[n] * std::exp(cplx(0.0, omega_[n] * t[i]))).real();
    p[i] = v / period_;
  }
  return p;
}

} // namespace tearflow::verify
