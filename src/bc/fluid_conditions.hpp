#pragma once
// The boundary conditions of a flow problem, resolved against the mesh: which faces are
// walls, which are inlets with their velocity profile, which are traction outlets.
#include <string>
#include <vector>

#include "bc/inflow_profile.hpp"
#include "bc/outlet.hpp"

namespace tearflow::bc {

/// Outlet traction h = -P n + beta rho (u.n)_- u, Q the outward flux, P from the outlet's law
/// (outlet.hpp); the default law is a zero pressure (traction-free).
struct TractionOutlet {
  std::string face;
  OutletLaw law;
  double backflow_beta = 0.2; ///< Esmaily-Moghadam et al. 2011
};

struct FluidConditions {
  std::vector<std::string> walls; ///< no-slip faces
  std::vector<InflowProfile> inflows;
  std::vector<TractionOutlet> outlets;
};

} // namespace tearflow::bc
