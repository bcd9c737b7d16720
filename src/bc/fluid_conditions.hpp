#pragma once
// The boundary conditions of a flow problem, resolved against the mesh: which faces are
// walls, which are inlets with their velocity profile, which are traction outlets.
#include <string>
#include <vector>

#include "bc/inflow_profile.hpp"

namespace tearflow::bc {

/// Outlet traction h = -P n + beta rho (u.n)_- u with P = P_0(t) + R Q, Q the outward flux.
struct TractionOutlet {
  std::string face;
  Waveform pressure = Waveform::constant(0.0); ///< P_0(t) [Pa]
  double resistance = 0.0;                     ///< R [Pa s/m^3]; 0 for a pressure outlet
  double backflow_beta = 0.2;                  ///< Esmaily-Moghadam et al. 2011
};

struct FluidConditions {
  std::vector<std::string> walls; ///< no-slip faces
  std::vector<InflowProfile> inflows;
  std::vector<TractionOutlet> outlets;
};

} // namespace tearflow::bc
