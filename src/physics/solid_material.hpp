#pragma once
// A hyperelastic wall's material (solid_kernel.hpp has the laws): the parameters the case
// file's solid section is validated into.
#include <cmath>

#include "core/error.hpp"

namespace tearflow::physics {

enum class SolidModel { NeoHookean, StVenantKirchhoff };

struct SolidMaterial {
  SolidModel model = SolidModel::NeoHookean;
  double density = 1450.0; ///< rho_0 [kg/m^3]
  double mu = 4.03e5;      ///< shear modulus [Pa]
  double kappa = 2.0e7;    ///< bulk modulus [Pa]
  /// alpha of the pressure stabilization tau = alpha h_e^2 / (2 mu) [-]. On `verify lame`
  /// (nu = 0.49, 4 to 16 cells through the wall) any alpha in [0.01, 1] changed the
  /// displacement error by less than 10 % of itself: the mesh's O(h^2), not the
  /// stabilization, dominates. 0.1 sits in the middle of that range.
  double stabilization = 0.1;

  double lambda() const { return kappa - 2.0 / 3.0 * mu; }
  double youngs_modulus() const { return 9.0 * kappa * mu / (3.0 * kappa + mu); }
  double poisson_ratio() const { return (3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu)); }
  bool mixed() const { return model == SolidModel::NeoHookean; }

  /// mu = E / (2 (1 + nu)), kappa = E / (3 (1 - 2 nu)); InputError unless E > 0,
  /// -1 < nu < 0.5 and density > 0.
  static SolidMaterial from_young_poisson(SolidModel model, double E, double nu, double density) {
    if (!(E > 0.0) || !std::isfinite(E))
      input_error("solid material: Young's modulus must be > 0 Pa, got {} Pa", E);
    if (!(nu > -1.0 && nu < 0.5))
      input_error("solid material: Poisson's ratio must be in (-1, 0.5), got {}{}", nu,
                  nu >= 0.5 ? " (0.5 is the incompressible limit, where the bulk modulus is "
                              "infinite; use e.g. 0.49 or 0.499)"
                            : "");
    return from_shear_bulk(model, E / (2.0 * (1.0 + nu)), E / (3.0 * (1.0 - 2.0 * nu)), density);
  }
  /// InputError unless mu > 0, kappa > 0 and density > 0.
  static SolidMaterial from_shear_bulk(SolidModel model, double mu, double kappa, double density) {
    if (!(mu > 0.0) || !std::isfinite(mu))
      input_error("solid material: shear modulus must be > 0 Pa, got {} Pa", mu);
    if (!(kappa > 0.0) || !std::isfinite(kappa))
      input_error("solid material: bulk modulus must be > 0 Pa, got {} Pa", kappa);
    if (!(density > 0.0) || !std::isfinite(density))
      input_error("solid material: density must be > 0 kg/m^3, got {} kg/m^3", density);
    SolidMaterial m;
    m.model = model;
    m.mu = mu;
    m.kappa = kappa;
    m.density = density;
    return m;
  }
};

} // namespace tearflow::physics
