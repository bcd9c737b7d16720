#pragma once
// Two-stage tuning of a case's Windkessel outlets to measured inlet pressures and flow
// splits (tracker issue 6):
//  1. 0D: fit the totals (R_T, C_T, k_d) on the 0D model of the outlets (windkessel_fit.hpp),
//     distributing them by the target splits, with the 3D domain's resistances in the model;
//  2. 3D: run the case for a few cycles with the fitted outlets, measure the last cycle's
//     inlet pressures and splits, and correct the 0D model with what the run shows of the
//     3D domain, then refit and rerun, until every pressure is within its tolerance and
//     every split within its points, or the iterations run out. The correction
//     (docs/tuning.md):
//       a. the domain's own resistance from the run's mean pressures and flows,
//            shared:     R_s = (P_in - sum_i Q_i P_i / Q) / Q        (in series),
//            per outlet: e_i = (P_in - P_i) / Q_i                     (in series with outlet i),
//          goes into the 0D model (correct_domain; the domain is rigid, so its compliance is
//          not estimated);
//       b. what the corrected 0D model still misses (inertance, convective losses) rescales
//          the fit's aims: aim_q = target_q * P0D_q / P3D_q, with P0D the corrected model of
//          the outlets that ran (q = systolic, diastolic, mean pressure);
//       c. shared parameters: f_i <- f_i * target split_i / achieved split_i, normalised.
//          Per-outlet parameters need no such step: with e_i in the model, R_i = R_T/f_i - e_i
//          splits the mean flow as the targets.
//     Without (a), (b) is the plain fixed-point update of the aims, exact for a domain that
//     scales pressures by fixed factors.
#include <functional>
#include <string>
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
  DomainResistance domain;           ///< the 0D model's domain when this step was fitted
  /// Per target outlet: its RCR, and the cycle's mean pressure [Pa] and flow [m^3/s] there.
  std::vector<bc::WindkesselBranch> outlets;
  std::vector<double> outlet_pressure, outlet_flow;
};

/// Runs a case with the step's outlets and fills the step's achieved inlet pressures, splits
/// and outlet mean pressures and flows: by default a 3D run of targets.cycles cycles (its
/// last cycle measured); tests pass a model of a domain.
using Measure = std::function<void(const io::Case& tuned, const std::string& inlet_face,
                                   const TuningTargets& targets, TuningStep& step)>;

struct TuningResult {
  std::vector<TuningStep> steps;
  io::Case tuned; ///< the case with the final outlets
  bool met = false;
};

/// Checks the case against the targets (one periodic inflow; every RCR or resistance outlet
/// has a target split and every target names such an outlet) and tunes. With
/// targets.max_iterations == 0 only the 0D stage runs. `progress` prints one line per step.
TuningResult tune_outlets(const io::Case& c, const TuningTargets& targets, bool progress,
                          const Measure& measure = {});

/// The case's outlets set to the given RCRs (by face name).
io::Case with_outlets(io::Case c, const std::vector<bc::WindkesselBranch>& outlets);
/// The case's outlets set to the totals distributed by `distribution` (RCR outlets).
io::Case with_outlets(io::Case c, const TuningTargets& targets, const WindkesselTotals& totals,
                      const std::vector<double>& distribution);

} // namespace tearflow::tuning
