#pragma once
// What every outlet law gives the 3D problem for one step t_n -> t_{n+1}: the outlet pressure
// at the momentum balance's time t_{n+alpha_f} as an affine function of the outward flux
// there,
//   P_af = p0 + r Q_af,                                                                   (1)
// with dP/dQ = r in Newton's tangent (windkessel.hpp derives it for the RCR). A law with
// memory (a capacitor, an inertance) folds its time discretisation into p0 and r; the 3D
// problem sees (1) only, whatever the law.
namespace tearflow::bc {

/// (1) during one step.
struct StepLaw {
  double p0 = 0.0;         ///< [Pa]
  double resistance = 0.0; ///< r = dP_af/dQ_af [Pa s/m^3]
};

/// The step a law is linearized over: t_n, dt and generalized-alpha's alpha_f.
struct StepClock {
  double t_n = 0.0, dt = 1.0, alpha_f = 1.0;
  double t_af() const { return t_n + alpha_f * dt; }
};

} // namespace tearflow::bc
