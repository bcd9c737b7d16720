#pragma once
// The resistance outlet: P = P_ref + R Q. No memory; dP/dQ = R.
#include <optional>
#include <string>

#include <fmt/format.h>

#include "bc/outlet_step.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

struct ResistanceOutlet {
  double resistance = 0.0;         ///< R [Pa s/m^3], > 0
  double reference_pressure = 0.0; ///< P_ref [Pa]

  bool coupled() const { return resistance != 0.0; }
  StepLaw step_law(const StepClock&) const { return {reference_pressure, resistance}; }
  /// In a 0D network: an RCR without capacitor.
  std::optional<WindkesselRCR> zero_d() const {
    return WindkesselRCR{resistance, 0.0, 0.0, reference_pressure};
  }
  std::string describe() const {
    return fmt::format("resistance {} Pa s/m^3 to {} Pa", resistance, reference_pressure);
  }
};

} // namespace tearflow::bc
