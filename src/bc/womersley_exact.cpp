#include "bc/womersley_exact.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tearflow::bc {

using cplx = std::complex<double>;

namespace detail {

cplx bessel_series(int nu, cplx z) {
  // DLMF 10.2.2: J_nu(z) = (z/2)^nu sum_{k>=0} (-z^2/4)^k / (k! (k + nu)!), nu = 0, 1.
  // Terms grow while k (k + nu) < |z|^2/4, then decrease; stop once negligible.
  const cplx x = -0.25 * z * z;
  cplx term = nu == 0 ? cplx(1.0) : 0.5 * z;
  cplx sum = term;
  const double peak = 0.5 * std::abs(z);
  for (int k = 1; k < 500; ++k) {
    term *= x / (double(k) * double(k + nu));
    sum += term;
    if (k > peak && std::abs(term) <= 1e-17 * std::abs(sum))
      break;
  }
  return sum;
}

cplx bessel_asymptotic(int nu, cplx z) {
  // J_nu(-z) = (-1)^nu J_nu(z): work in the right half plane, far from the Stokes line
  // arg z = pi where DLMF 10.17.3 stops holding.
  if (z.real() < 0.0)
    return (nu % 2 == 0 ? 1.0 : -1.0) * bessel_asymptotic(nu, -z);
  // DLMF 10.17.3: J_nu(z) ~ sqrt(2/(pi z)) [cos w sum_k (-1)^k a_2k / z^2k
  //                                         - sin w sum_k (-1)^k a_2k+1 / z^(2k+1)],
  // w = z - nu pi/2 - pi/4, a_k(nu) = prod_{j=1}^k (4 nu^2 - (2j - 1)^2) / (k! 8^k).
  // The series diverges: sum until the terms stop decreasing (k ~ 2|z|, error ~ e^{-2|z|}).
  const double mu = 4.0 * nu * nu;
  cplx b = 1.0, P = 1.0, Q = 0.0; // b_k = a_k(nu) / z^k
  double last = 1.0;
  for (int k = 1; k < 200; ++k) {
    b *= (mu - (2.0 * k - 1.0) * (2.0 * k - 1.0)) / (8.0 * k * z);
    const double size = std::abs(b);
    if (size >= last)
      break; // smallest term reached: optimal truncation
    last = size;
    const double sign = (k / 2) % 2 == 0 ? 1.0 : -1.0; // (-1)^floor(k/2)
    (k % 2 == 0 ? P : Q) += sign * b;
    if (size <= 1e-17 * std::abs(P))
      break;
  }
  const cplx w = z - (0.5 * nu + 0.25) * std::numbers::pi;
  return std::sqrt(2.0 / (std::numbers::pi * z)) * (P * std::cos(w) - Q * std::sin(w));
}

} // namespace detail

cplx bessel_j0(cplx z) {
  return std::abs(z) < kBesselAsymptoticFrom ? detail::bessel_series(0, z)
                                             : detail::bessel_asymptotic(0, z);
}

cplx bessel_j1(cplx z) {
  return std::abs(z) < kBesselAsymptoticFrom ? detail::bessel_series(1, z)
                                             : detail::bessel_asymptotic(1, z);
}

namespace {

constexpr double kPi = std::numbers::pi;
const cplx kI32 = std::polar(1.0, 0.75 * kPi); // i^(3/2) = e^{3 pi i / 4}

/// For small |beta| the differences J0(b) - J0(b rho) and D = J0(b) - (2/b) J1(b) cancel
/// (both are O(b^2)); sum their series directly:
///   J0(b) - J0(b rho) = sum_{k>=1} (-b^2/4)^k (1 - rho^2k) / (k!)^2,
///   D                 = sum_{k>=1} (-b^2/4)^k k / ((k!)^2 (k + 1)).
constexpr double kSmallBeta = 1.0;

cplx j0_difference(cplx beta, double rho) {
  if (std::abs(beta) >= kSmallBeta)
    return bessel_j0(beta) - bessel_j0(beta * rho);
  const cplx x = -0.25 * beta * beta;
  cplx term = 1.0, sum = 0.0;
  double rho2k = 1.0;
  for (int k = 1; k < 30; ++k) {
    term *= x / (double(k) * k);
    rho2k *= rho * rho;
    sum += term * (1.0 - rho2k);
  }
  return sum;
}

cplx womersley_denominator(cplx beta) {
  if (std::abs(beta) >= kSmallBeta)
    return bessel_j0(beta) - 2.0 / beta * bessel_j1(beta);
  const cplx x = -0.25 * beta * beta;
  cplx term = 1.0, sum = 0.0;
  for (int k = 1; k < 30; ++k) {
    term *= x / (double(k) * k);
    sum += term * (double(k) / (k + 1));
  }
  return sum;
}

/// beta_n = i^(3/2) R sqrt(n omega / nu), nu = mu / rho.
cplx beta_n(const WomersleyFlow& f, int n) {
  return kI32 * f.radius * std::sqrt(n * f.omega * f.density / f.viscosity);
}

/// Number of modes to sum: only the mean when steady.
size_t active_modes(const WomersleyFlow& f) {
  return f.omega > 0.0 ? f.modes.size() : std::min<size_t>(f.modes.size(), 1);
}

} // namespace

double WomersleyFlow::flow(double t) const {
  double q = 0.0;
  for (size_t n = 0; n < active_modes(*this); ++n)
    q += (modes[n] * std::polar(1.0, double(n) * omega * t)).real();
  return q;
}

double WomersleyFlow::axial_velocity(double r, double t) const {
  if (modes.empty())
    return 0.0;
  const double area = kPi * radius * radius, rho = r / radius;
  // Mode 0, Poiseuille: u_0 = 2 Q_0 / (pi R^2) (1 - r^2/R^2).
  double u = 2.0 * modes[0].real() / area * (1.0 - rho * rho);
  // Modes n >= 1: u_n = Q_n/(pi R^2) [J0(b) - J0(b r/R)] / [J0(b) - (2/b) J1(b)].
  for (size_t n = 1; n < active_modes(*this); ++n) {
    const cplx b = beta_n(*this, int(n));
    const cplx un = modes[n] / area * j0_difference(b, rho) / womersley_denominator(b);
    u += (un * std::polar(1.0, double(n) * omega * t)).real();
  }
  return u;
}

double WomersleyFlow::pressure_gradient(double t) const {
  if (modes.empty())
    return 0.0;
  const double area = kPi * radius * radius;
  // Mode 0: G_0 = -8 mu Q_0 / (pi R^4).
  double g = -8.0 * viscosity * modes[0].real() / (area * radius * radius);
  // Modes n >= 1: G_n = -(i n w rho Q_n / (pi R^2)) J0(b) / [J0(b) - (2/b) J1(b)].
  for (size_t n = 1; n < active_modes(*this); ++n) {
    const cplx b = beta_n(*this, int(n));
    const cplx gn = -cplx(0.0, double(n) * omega * density) * modes[n] / area * bessel_j0(b) /
                    womersley_denominator(b);
    g += (gn * std::polar(1.0, double(n) * omega * t)).real();
  }
  return g;
}

double WomersleyFlow::womersley_number() const {
  return radius * std::sqrt(omega * density / viscosity);
}

WomersleyFlow womersley_from_waveform(const bc::Waveform& q, int modes, double radius,
                                      double density, double viscosity) {
  if (!(radius > 0.0) || !(density > 0.0) || !(viscosity > 0.0))
    input_error("Womersley flow: radius {}, density {} and viscosity {} must be positive", radius,
                density, viscosity);
  if (modes < 1)
    input_error("Womersley flow: {} modes; at least 1 (the mean) is needed", modes);
  WomersleyFlow f;
  f.radius = radius;
  f.density = density;
  f.viscosity = viscosity;
  if (q.is_constant()) {
    f.modes = {cplx(q.mean())};
    return f;
  }
  f.omega = 2.0 * kPi / q.period();
  f.modes = q.fourier(modes);
  for (size_t n = 1; n < f.modes.size(); ++n)
    f.modes[n] *= 2.0;
  f.modes[0] = f.modes[0].real();
  return f;
}

} // namespace tearflow::bc
