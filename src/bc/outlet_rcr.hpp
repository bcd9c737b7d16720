#pragma once
// The three-element Windkessel outlet (windkessel.hpp (1)-(3)): its state is the distal
// (capacitor) pressure P_d, advanced by the trapezoidal rule.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "bc/outlet_step.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

struct RcrOutlet {
  WindkesselRCR rcr;
  /// P_d at the start [Pa]; without it 0, or the 0D periodic state's (time.start).
  std::optional<double> initial_distal_pressure;

  struct State {
    double distal_pressure = 0.0; ///< P_d at t_n [Pa]
  };
  static constexpr std::size_t record_size = 1;

  bool coupled() const { return true; }
  State initial() const { return {initial_distal_pressure.value_or(0.0)}; }
  StepLaw step_law(const State& s, double q_n, const StepClock& c) const {
    return rcr_law(rcr, s.distal_pressure, q_n, c.dt, c.alpha_f);
  }
  State commit(const State& s, double q_n, double q_next, double dt) const {
    return {distal_update(rcr, s.distal_pressure, q_n, dt)(q_next)};
  }
  std::optional<WindkesselRCR> zero_d() const { return rcr; }
  /// The state at the start of a run from the 0D model's P_d there; none when the case gave it.
  std::optional<State> start(double distal_pressure) const {
    if (initial_distal_pressure)
      return std::nullopt;
    return State{distal_pressure};
  }
  double distal_pressure(const State& s) const { return s.distal_pressure; }
  std::array<double, record_size> record(const State& s) const { return {s.distal_pressure}; }
  State restore(const std::array<double, record_size>& r) const { return {r[0]}; }
  std::string describe() const {
    return fmt::format("rcr R_p {}, C {}, R_d {}, P_ref {}", rcr.proximal_resistance,
                       rcr.capacitance, rcr.distal_resistance, rcr.reference_pressure);
  }
};

} // namespace tearflow::bc
