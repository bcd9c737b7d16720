#pragma once
// The boundary conditions of a flow problem, resolved against the mesh: which faces are
// walls, which are inlets with their velocity profile, which are traction outlets.
#include <optional>
#include <string>
#include <vector>

#include "bc/inflow_profile.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

/// Outlet traction h = -P n + beta rho (u.n)_- u, Q the outward flux, and either
///   P = P_0(t) + R Q            (pressure outlet: R = 0; resistance outlet: P_0 = P_ref), or
///   P = P_d + R_p Q, C dP_d/dt = Q - (P_d - P_ref) / R_d   (RCR Windkessel, windkessel.hpp).
struct TractionOutlet {
  std::string face;
  Waveform pressure = Waveform::constant(0.0); ///< P_0(t) [Pa]
  double resistance = 0.0;                     ///< R [Pa s/m^3]; 0 for a pressure outlet
  double backflow_beta = 0.2;                  ///< Esmaily-Moghadam et al. 2011
  std::optional<WindkesselRCR> rcr;            ///< replaces P_0 and R when set
  double initial_distal_pressure = 0.0;        ///< P_d at the start [Pa]
};

struct FluidConditions {
  std::vector<std::string> walls; ///< no-slip faces
  std::vector<InflowProfile> inflows;
  std::vector<TractionOutlet> outlets;
};

} // namespace tearflow::bc
