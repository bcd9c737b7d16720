#pragma once
// The two-element Windkessel outlet: a resistance R and a capacitance C in parallel,
//   C dP/dt = Q - (P - P_ref) / R,
// its state the outlet (capacitor) pressure P. It is the RCR of windkessel.hpp without the
// proximal resistance, so one step is that law's trapezoidal rule with R_p = 0 and R_d = R:
//   P^{n+1} = a + b Q^{n+1},  P_af = p0 + b Q_af.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "bc/outlet_step.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

struct RcOutlet {
  double resistance = 0.0;         ///< R [Pa s/m^3], > 0
  double capacitance = 0.0;        ///< C [m^3/Pa], > 0
  double reference_pressure = 0.0; ///< P_ref, the pressure R drains to [Pa]
  /// P at the start [Pa]; without it 0, or the 0D periodic state's (time.start).
  std::optional<double> initial_pressure;

  struct State {
    double pressure = 0.0; ///< P at t_n [Pa]
  };
  static constexpr std::size_t record_size = 1;

  WindkesselRCR as_rcr() const { return {0.0, capacitance, resistance, reference_pressure}; }
  bool coupled() const { return true; }
  State initial() const { return {initial_pressure.value_or(0.0)}; }
  StepLaw step_law(const State& s, double q_n, const StepClock& c) const {
    return rcr_law(as_rcr(), s.pressure, q_n, c.dt, c.alpha_f);
  }
  State commit(const State& s, double q_n, double q_next, double dt) const {
    return {distal_update(as_rcr(), s.pressure, q_n, dt)(q_next)};
  }
  std::optional<WindkesselRCR> zero_d() const { return as_rcr(); }
  std::optional<State> start(double distal_pressure) const {
    if (initial_pressure)
      return std::nullopt;
    return State{distal_pressure};
  }
  /// The capacitor's pressure, reported as the distal pressure.
  double distal_pressure(const State& s) const { return s.pressure; }
  std::array<double, record_size> record(const State& s) const { return {s.pressure}; }
  State restore(const std::array<double, record_size>& r) const { return {r[0]}; }
  std::string describe() const {
    return fmt::format("rc R {}, C {}, P_ref {}", resistance, capacitance, reference_pressure);
  }
};

} // namespace tearflow::bc
