#pragma once
// Per cardiac cycle, per named face: systolic, diastolic and mean pressure, net flow volume
// and flow split, from the face samples of every time step; and the cycle-to-cycle change
// that decides when a run has become periodic.
//
// A cycle c covers [c T, (c + 1) T] and holds the N + 1 samples of its steps (both ends).
// Time averages and volumes use the trapezoidal rule over these samples (second order, as
// the time integrator). The change between cycles c - 1 and c is, over every outlet and
// both its pressure P and flow Q,
//   max_k |X_c(t_k) - X_{c-1}(t_k)| / max_k |X_c(t_k)|,
// the largest sample-by-sample difference relative to the cycle's peak magnitude. A run that
// is analysed by its cycle's numbers may stop on those instead (metrics_change): the largest
// of every inlet's (face with net inflow) systolic, diastolic and mean pressure's relative change
// and every outlet's flow split's change in points / 100.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tearflow::run {

struct FaceSeries {
  std::string face;
  bool outlet = false;          ///< counts in the flow split and the periodicity change
  std::vector<double> flow;     ///< outward flux per sample [m^3/s]
  std::vector<double> pressure; ///< mean pressure per sample [Pa]
  std::vector<double> reversed; ///< reversed (inward) part of the flux per sample [m^3/s]
};

struct CycleSamples {
  int cycle = 0; ///< 0-based
  std::vector<double> time;
  std::vector<FaceSeries> faces;
};

struct FaceCycleStats {
  std::string face;
  double systolic = 0.0, diastolic = 0.0, mean = 0.0; ///< pressure [Pa]
  double volume = 0.0;                                ///< net outward volume [m^3]
  double reversed_volume = 0.0;                       ///< inward volume through the face [m^3]
  std::optional<double> split_percent;                ///< share of the total outflow (outlets)
};

struct CycleStats {
  int cycle = 0;
  double t_begin = 0.0, t_end = 0.0;
  std::vector<FaceCycleStats> faces;
  std::optional<double> change; ///< relative change from the previous cycle (none for the first)
};

CycleStats summarize_cycle(const CycleSamples& samples);

/// The relative change between two cycles' outlet samples (definition above).
double cycle_change(const CycleSamples& previous, const CycleSamples& current);

/// The change of the cycle's numbers (definition above); 0 when nothing compares.
double metrics_change(const CycleStats& previous, const CycleStats& current);

/// {"period_s", "cycles": [{cycle, t_begin_s, t_end_s, change, faces: {name: {...}}}]},
/// every quantity with its unit in the key, pressures in Pa and mmHg.
nlohmann::json cycles_to_json(double period, const std::vector<CycleStats>& cycles);

} // namespace tearflow::run
