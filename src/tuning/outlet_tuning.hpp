#pragma once
// Two-stage tuning of a case's Windkessel outlets to measured inlet pressures and flow
// splits (tracker issue 6):
//  1. 0D: fit the totals (R_T, C_T, k_d) on the 0D model of the outlets (windkessel_fit.hpp),
//     distributing them by the target splits;
//  2. 3D: run the case for a few cycles with the fitted outlets, measure the last cycle's
//     inlet pressures and splits, and correct what the 0D model does not know about the 3D
//     domain (its resistance, inertance, compliance and the way it divides the flow) by a
//     fixed-point update of the 0D stage's aims:
//       aim_q <- aim_q * target_q / achieved_q   (q = systolic, diastolic, mean pressure),
//       f_i   <- f_i * target split_i / achieved split_i, normalised,
//     then refit and rerun, until every pressure is within its tolerance and every split
//     within its points, or the iterations run out. The update is exact for a 3D domain
//     that scales pressures and splits by fixed factors, and contracts quickly when the
//     domain's share of the pressure is small, as in arteries (a few percent).
#include <vector>

#include "io/case.hpp"
#include "tuning/targets.hpp"

namespace tearflow::tuning {

struct TuningStep {
  int iteration = 0; ///< 0: the 0D stage's own prediction; >= 1: a 3D run
  WindkesselTotals totals;
  std::vector<double> distribution; ///< the fractions the totals were distributed by
  InletPressures achieved;
  std::vector<double> split_percent; ///< achieved, per target outlet
  double pressure_error = 0.0;       ///< max relative error of the three pressures
  double split_error = 0.0;          ///< max |achieved - target| in percentage points
};

struct TuningResult {
  std::vector<TuningStep> steps;
  io::Case tuned; ///< the case with the final outlets
  bool met = false;
};

/// Checks the case against the targets (one periodic inflow; every RCR or resistance outlet
/// has a target split and every target names such an outlet) and tunes. With
/// targets.max_iterations == 0 only the 0D stage runs. `progress` prints one line per step.
TuningResult tune_outlets(const io::Case& c, const TuningTargets& targets, bool progress);

/// The case's outlets set to the totals distributed by `distribution` (RCR outlets).
io::Case with_outlets(io::Case c, const TuningTargets& targets, const WindkesselTotals& totals,
                      const std::vector<double>& distribution);

} // namespace tearflow::tuning
