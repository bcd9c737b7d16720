#pragma once
// Shared set-up of the solid verification cases: a case with a `solid:` section.
#include <string>

#include "io/case.hpp"

namespace tearflow::verify {

/// A solid-only case: time step dt, `steps` steps, generalized-alpha rho_inf, tight Newton
/// for loads of about `force` newtons.
inline io::Case solid_case(std::string name, io::SolidSpec solid, double dt, int steps,
                           double rho_inf, double force) {
  io::Case c;
  c.name = std::move(name);
  c.solid = std::move(solid);
  c.time.step = dt;
  c.time.steps = steps;
  c.time.spectral_radius = rho_inf;
  // Newton's error must sit far below every tolerance checked (1e-2, and the 1e-4
  // nonlinearity of the small-load cases): a residual of 1e-10 of the load, or 1e-9 of the
  // step's initial one. Not tighter: round-off stalls the stiffest case (displacement-only,
  // nu = 0.49) at ~1e-10 relative, and near a steady state the initial residual is itself
  // small, so the absolute bound must be the one that stops.
  c.newton = {20, 1e-9, 1e-10 * force};
  return c;
}

} // namespace tearflow::verify
