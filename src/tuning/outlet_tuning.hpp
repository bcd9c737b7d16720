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
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "io/case.hpp"
#include "run/cycle_summary.hpp"
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

/// The state of the 3D correction between runs (steps a-c of the file comment): what the
/// runs so far taught the 0D model. plan() fits the outlets of an iteration; learn() takes a
/// measured 3D step of the outlets that ran. Shared by the separate correction runs of
/// tune_outlets and the corrections at the cycle ends of one run (corrected_run.hpp).
class OutletCorrection {
public:
  /// Checks the case against the targets (one periodic inflow; every RCR or resistance
  /// outlet has a target split and every target names such an outlet).
  OutletCorrection(const io::Case& c, TuningTargets targets);
  /// The outlets of iteration k fitted to the current aims, from the previous totals when
  /// given; iteration 0 carries the 0D model's own prediction as achieved.
  TuningStep plan(int iteration, const WindkesselTotals* previous = nullptr) const;
  /// Fills the step's errors; true when every pressure and split is within its tolerance.
  bool score(TuningStep& step) const;
  /// Corrects the 0D model with a measured step (finite pressures and splits, or SolverError).
  void learn(const TuningStep& measured);
  const std::string& inlet() const { return inlet_; }
  const TuningTargets& targets() const { return targets_; }
  const bc::Waveform& inflow() const { return inflow_; }

private:
  TuningTargets targets_;
  bc::Waveform inflow_;
  std::string inlet_;
  std::vector<double> f_; ///< the distribution of the totals over the outlets
  DomainResistance domain_;
  std::array<double, 3> defect_ = {1.0, 1.0, 1.0}; ///< P0D / P3D per pressure, last run
};

/// A run's cycle as a measured step: inlet pressures, splits, outlet mean pressures and flows.
void measure_cycle(const run::CycleStats& cycle, const std::string& inlet_face,
                   const TuningTargets& targets, TuningStep& step);
/// One progress line of a step (stdout).
void print_step(const TuningStep& step);

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
