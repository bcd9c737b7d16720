#pragma once
// The analytic Womersley solution (Womersley 1955): fully developed pulsatile flow in a rigid
// straight circular pipe, for verifying the solver and as an inflow profile. Includes the
// complex Bessel functions J0, J1 it needs (std::cyl_bessel_j is real only).
#include <complex>
#include <vector>

#include "bc/waveform.hpp"

namespace tearflow::bc {

/// Bessel functions of the first kind of complex argument. Built for the Womersley ray
/// z = i^(3/2) x (where J0 = ber x + i bei x): relative error < 1e-14 there for x up to 150
/// (measured against mpmath). Power series for |z| < kBesselAsymptoticFrom, Hankel's
/// asymptotic expansion beyond. Off the ray: also ~1e-14, except near the real axis, where the
/// series loses digits to cancellation (~1e-10 relative just below the switch).
std::complex<double> bessel_j0(std::complex<double> z);
std::complex<double> bessel_j1(std::complex<double> z);

/// |z| at which bessel_j0/j1 switch from the power series to the asymptotic expansion.
inline constexpr double kBesselAsymptoticFrom = 17.0;

namespace detail {
/// The two branches, exposed for testing: power series DLMF 10.2.2,
/// J_nu(z) = (z/2)^nu sum_k (-z^2/4)^k / (k! Gamma(nu + k + 1)), and Hankel's expansion
/// DLMF 10.17.3, J_nu(z) ~ sqrt(2/(pi z)) (P cos w - Q sin w), w = z - nu pi/2 - pi/4.
std::complex<double> bessel_series(int nu, std::complex<double> z);
std::complex<double> bessel_asymptotic(int nu, std::complex<double> z);
} // namespace detail

/// Fully developed pulsatile flow in a rigid straight pipe of radius R, driven by the flow
///   Q(t) = Re( sum_{n=0}^{N-1} q_n e^{i n w t} ),  q_0 real (the mean flow).
/// Per mode n >= 1, with nu = mu / rho and beta_n = i^(3/2) R sqrt(n w / nu):
///   u_n(r) = Q_n / (pi R^2) [J0(beta_n) - J0(beta_n r/R)] / [J0(beta_n) - (2/beta_n) J1(beta_n)]
///   G_n    = -(i n w rho Q_n / (pi R^2)) J0(beta_n) / [J0(beta_n) - (2/beta_n) J1(beta_n)]
/// (G = dp/dz), which solve rho du/dt = -dp/dz + mu (u'' + u'/r) with u(R) = 0 and
/// int 2 pi r u dr = Q; mode 0 is Poiseuille, u_0 = 2 Q_0/(pi R^2) (1 - r^2/R^2),
/// G_0 = -8 mu Q_0 / (pi R^4).
struct WomersleyFlow {
  double radius = 0.0, density = 0.0, viscosity = 0.0; ///< R [m], rho [kg/m^3], mu [Pa s]
  double omega = 0.0;                                  ///< 2 pi / period [1/s]; 0: steady
  std::vector<std::complex<double>> modes; ///< Q(t) = Re(sum_n modes[n] exp(i n omega t)) [m^3/s]
  double flow(double t) const;             ///< Q(t) [m^3/s]
  double axial_velocity(double r, double t) const; ///< u_z(r, t) [m/s]
  double pressure_gradient(double t) const;        ///< dp/dz(t) [Pa/m] (negative drives flow in +z)
  double womersley_number() const;                 ///< alpha = R sqrt(omega / nu) at n = 1
};

/// Builds the modes from a Waveform's Fourier coefficients: with c_n from Waveform::fourier,
/// v(t) = Re(c_0 + 2 sum c_n e^{i n w t}), so modes[0] = c_0, modes[n] = 2 c_n. A constant
/// waveform gives steady Poiseuille flow (omega = 0). `viscosity` is dynamic [Pa s].
WomersleyFlow womersley_from_waveform(const bc::Waveform& q, int modes, double radius,
                                      double density, double viscosity);

} // namespace tearflow::bc
