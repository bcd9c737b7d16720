#pragma once
// A short start-up: instead of from rest with the case's initial distal pressures, a run
// starts with every outlet capacitor's pressure (and the pressure field) taken from the
// periodic state of the 0D model of its outlets (bc/windkessel_network.hpp) at t = 0. The
// RCRs' memory (time constant R_d C, about a cardiac cycle in the aorta) would otherwise
// take several cycles to forget the initial guess; the 3D domain itself settles within
// about one cycle.
#include <optional>
#include <string>
#include <vector>

#include "bc/fluid_conditions.hpp"
#include "bc/windkessel_network.hpp"

namespace tearflow::run {

/// The outlets of `conditions` as a 0D network driven by the sum of the inflows, or nothing
/// when no outlet has a capacitor, there is no inflow, or an outlet sets the pressure.
struct OutletModel {
  bc::WindkesselNetwork network;
  bc::Waveform inflow;
  std::vector<size_t> outlet; ///< branch i models conditions.outlets[outlet[i]]
};
std::optional<OutletModel> outlet_model(const bc::FluidConditions& conditions);

/// The sum of the case's inflows (a sampled periodic waveform when there are several).
bc::Waveform total_inflow(const bc::FluidConditions& conditions);

} // namespace tearflow::run
