#pragma once
// The pressure pulse of `verify pulse` (fsi_pulse.cpp) on the linear continuum of the tube,
// without a mesh: what an exact solver would measure, feature by feature, if the tube were
// the classical one-dimensional model. The inlet pressure's spectrum is carried down an
// infinite tube (no reflection) with the wavenumber
//   k(w) = k_d(w) / sqrt(1 - F10(alpha)),
// where k_d solves the inviscid dispersion relation of a fluid column in an elastic tube with
// the radial inertia of the fluid and the inertia of the wall,
//   w^2 = c0^2 k^2 / ((ka/2) I0(ka) / I1(ka) + rho_s h a k^2 / (2 rho)),
// (increasing in k towards c0^2 / beta, beta = rho_s h a / (2 rho): one root below the
// cut-off w = c0 / sqrt(beta), ~480 Hz here; the spectrum above it is dropped and its share
// of the pulse's energy reported), and Womersley's factor F10 = 2 J1(L) / (L J0(L)),
// L = i^(3/2) alpha, alpha = a sqrt(w rho / mu), adds the viscous wall layer (Womersley 1957;
// the frequency-domain model of e.g. Reymond et al. 2009). c0 is the long-wave speed
// 1 / sqrt(rho D) of the wall's distensibility D.
//
// What the model leaves out is what the 3D tube adds: the wall's axial motion and its own
// axial waves, its shear across the thickness, the clamped ends and the reflections.
#include <complex>
#include <functional>
#include <vector>

namespace tearflow::verify {

struct ContinuumTube {
  double radius = 0.0;          ///< a [m]
  double wall_thickness = 0.0;  ///< h [m]
  double fluid_density = 0.0;   ///< rho [kg/m^3]
  double viscosity = 0.0;       ///< mu [Pa s]
  double wall_density = 0.0;    ///< rho_s [kg/m^3]
  double long_wave_speed = 0.0; ///< c0 [m/s]
};

/// Phase speed [m/s] of the inviscid wave of wavenumber k > 0 [1/m] in the tube, the
/// dispersion relation above: c0 / sqrt((ka/2) I0(ka) / I1(ka) + rho_s h a k^2 / (2 rho)).
double dispersive_speed(const ContinuumTube& tube, double k);

class PulseContinuum {
public:
  /// `inlet`: the inlet pressure p(0, t) [Pa], zero after its pulse; `duration`: the time
  /// span to be evaluated [s] (the run's).
  PulseContinuum(const ContinuumTube& tube, const std::function<double(double)>& inlet,
                 double duration);

  /// p(z, t) [Pa] at the times t [s].
  std::vector<double> pressure(double z, const std::vector<double>& t) const;
  /// Share of the inlet pulse's energy above the cut-off (dropped).
  double energy_above_cutoff() const { return dropped_; }

private:
  double period_ = 0.0; ///< the transform's window: long enough that nothing wraps around
  std::vector<double> omega_;
  std::vector<std::complex<double>> spectrum_, wavenumber_;
  double dropped_ = 0.0;
};

} // namespace tearflow::verify
