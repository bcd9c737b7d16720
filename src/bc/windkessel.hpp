#pragma once
// The three-element Windkessel (RCR) that closes an outlet:
//   P = P_d + R_p Q,    C dP_d/dt = Q - (P_d - P_ref) / R_d,                          (1)
// Q the outward flux, P the outlet pressure, P_d the distal (capacitor) pressure.
//
// In time, P_d advances by the trapezoidal rule (second order, A-stable, like the 3D
// generalized-alpha scheme) over each step t_n -> t_{n+1}:
//   C (P_d^{n+1} - P_d^n) / dt = (Q^n + Q^{n+1}) / 2 - ((P_d^n + P_d^{n+1}) / 2 - P_ref) / R_d,
// which is affine in Q^{n+1}: P_d^{n+1} = a + b Q^{n+1}.                                  (2)
// The 3D momentum balance is collocated at t_{n+alpha_f}, where the flux is
// Q_af = Q^n + alpha_f (Q^{n+1} - Q^n); eliminating Q^{n+1} with (2) gives the outlet's law
// within the step as an affine function of the flux the 3D problem sees:
//   P_af = P_d^n + alpha_f (P_d^{n+1} - P_d^n) + R_p Q_af = p0 + r Q_af,
//   r = R_p + b,   p0 = P_d^n + alpha_f (a + b Q^n - P_d^n) - b Q^n.                      (3)
// This is outlet_step.hpp's (1); outlet_rcr.hpp is the outlet law built on it.
#include "bc/outlet_step.hpp"

namespace tearflow::bc {

struct WindkesselRCR {
  double proximal_resistance = 0.0; ///< R_p [Pa s/m^3], >= 0
  double capacitance = 0.0;         ///< C [m^3/Pa], > 0
  double distal_resistance = 0.0;   ///< R_d [Pa s/m^3], > 0
  double reference_pressure = 0.0;  ///< P_ref, the pressure R_d drains to [Pa]
};

/// (2): the trapezoidal update P_d^{n+1} = a + b Q^{n+1}.
struct DistalUpdate {
  double a = 0.0, b = 0.0;
  double operator()(double q_next) const { return a + b * q_next; }
};

inline DistalUpdate distal_update(const WindkesselRCR& w, double pd_n, double q_n, double dt) {
  const double k = w.capacitance / dt, g = 1.0 / w.distal_resistance;
  const double denominator = k + 0.5 * g;
  return {((k - 0.5 * g) * pd_n + 0.5 * q_n + g * w.reference_pressure) / denominator,
          0.5 / denominator};
}

/// (3): the RCR outlet's law during the step from (P_d^n, Q^n).
inline StepLaw rcr_law(const WindkesselRCR& w, double pd_n, double q_n, double dt, double alpha_f) {
  const DistalUpdate d = distal_update(w, pd_n, q_n, dt);
  return {pd_n + alpha_f * (d(q_n) - pd_n) - d.b * q_n, w.proximal_resistance + d.b};
}

} // namespace tearflow::bc
