#pragma once
// The pressure outlet: P = P_0(t), a given waveform. No memory; dP/dQ = 0.
#include <optional>
#include <string>

#include "bc/outlet_step.hpp"
#include "bc/waveform.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

struct PressureOutlet {
  Waveform pressure = Waveform::constant(0.0); ///< P_0(t) [Pa]

  bool coupled() const { return false; }
  StepLaw step_law(const StepClock& c) const { return {pressure(c.t_af()), 0.0}; }
  /// It sets the pressure itself: no 0D branch, and a network with it has nothing to start.
  std::optional<WindkesselRCR> zero_d() const { return std::nullopt; }
  std::string describe() const { return "pressure " + bc::describe(pressure) + " Pa"; }
};

} // namespace tearflow::bc
