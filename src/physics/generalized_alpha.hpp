#pragma once
// Generalized-alpha for first-order systems (Jansen, Whiting, Hulbert, CMAME 2000):
//   alpha_m = (3 - rho_inf) / (2 (1 + rho_inf)),  alpha_f = 1 / (1 + rho_inf),
//   gamma = 1/2 + alpha_m - alpha_f   (second order, unconditionally stable),
//   u_{n+1} = u_n + dt ((1 - gamma) udot_n + gamma udot_{n+1}).
#include "core/error.hpp"

namespace tearflow::physics {

struct GeneralizedAlpha {
  double alpha_m = 1.0, alpha_f = 1.0, gamma = 1.0;

  static GeneralizedAlpha from_spectral_radius(double rho_inf) {
    if (!(rho_inf >= 0.0 && rho_inf <= 1.0))
      input_error("spectral radius {} is outside [0, 1]", rho_inf);
    GeneralizedAlpha g;
    g.alpha_m = (3.0 - rho_inf) / (2.0 * (1.0 + rho_inf));
    g.alpha_f = 1.0 / (1.0 + rho_inf);
    g.gamma = 0.5 + g.alpha_m - g.alpha_f;
    return g;
  }
  /// d u_{n+alpha_f} / d u_{n+1}
  double c_u() const { return alpha_f; }
  /// d udot_{n+alpha_m} / d u_{n+1}
  double c_a(double dt) const { return alpha_m / (gamma * dt); }
};

} // namespace tearflow::physics
