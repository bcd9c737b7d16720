// Two-stage outlet tuning on a three-outlet junction (tuning/outlet_tuning.hpp): targets
// are made by a 3D run with a known set of Windkessel totals and splits; tuning starts from
// nothing but those targets and must reproduce them with a bounded number of 3D runs.
#include <cmath>

#include <fmt/format.h>

#include "core/units.hpp"
#include "mesh/junction_generator.hpp"
#include "run/simulation.hpp"
#include "tuning/outlet_tuning.hpp"
#include "verify/cases.hpp"
#include "verify/pulsatile_inflow.hpp"

namespace tearflow::verify {

namespace {

constexpr double T = 1.0, dt = 0.01, Q_mean = 1e-5;
// The bounded number of 3D runs: the junction takes ~1 % of the pressure, which the first
// run measures and the 0D model then holds (outlet_tuning.hpp), so one correction run
// should meet the aims; 3 leaves one spare.
constexpr int kMaxRuns = 3;
const tuning::WindkesselTotals kTruth{1.2e8, 8e-9, 0.8};
const std::vector<tuning::OutletFraction> kTruthSplit = {
    {"outlet_1", 0.55}, {"outlet_2", 0.25}, {"outlet_3", 0.20}};

io::Case junction_case(double element_size) {
  io::Case c;
  c.name = "verify-tuning";
  mesh::JunctionSpec spec;
  spec.element_size = element_size;
  c.mesh.generator = [spec](const io::Case&) { return mesh::make_junction(spec); };
  c.time.step = dt;
  c.time.period = T;
  c.time.steps_per_cycle = static_cast<int>(std::round(T / dt));
  c.time.steps = 2 * c.time.steps_per_cycle;
  c.boundary_conditions = {{"wall", bc::NoSlip{}},
                           {"inlet", bc::Inflow{pulsatile_inflow(Q_mean, T)}}};
  for (const tuning::OutletFraction& o : kTruthSplit) // RCRs the tuning sets
    c.boundary_conditions.push_back({o.face, bc::Outlet{bc::RcrOutlet{}}});
  c.newton = {10, 1e-6, 1e-14};
  return c;
}

} // namespace

VerificationResult verify_tuning(const VerifyOptions& options) {
  const double h = 0.0012 * options.coarsening;
  const io::Case base = junction_case(h);

  // The "measurement": the last of two cycles with the true outlets.
  tuning::TuningTargets truth_setup;
  truth_setup.splits = kTruthSplit;
  std::vector<double> truth_fractions;
  for (const auto& o : kTruthSplit)
    truth_fractions.push_back(o.fraction);
  run::Simulation truth(tuning::with_outlets(base, truth_setup, kTruth, truth_fractions));
  const run::RunSummary measured = truth.run({false, {}, {}, options.progress, false, {}});
  tuning::TuningTargets targets;
  targets.pressure_tolerance = 0.01; // aim at 1 % and 0.5 points; accept 3 % and 2 points
  targets.split_tolerance = 0.5;
  // The cap lies above the bound checked below (kMaxRuns), so that a tuning needing more
  // runs than the bound shows it in runs_3d instead of being cut off at the bound.
  targets.max_iterations = kMaxRuns + 3;
  targets.cycles = 2;
  for (const run::FaceCycleStats& f : measured.cycles.back().faces) {
    if (f.face == "inlet")
      targets.pressure = {f.systolic, f.diastolic, f.mean};
    if (f.split_percent)
      targets.splits.push_back({f.face, *f.split_percent / 100.0});
  }

  const tuning::TuningResult r = tuning::tune_outlets(base, targets, options.progress);
  const tuning::TuningStep& last = r.steps.back();

  VerificationResult res;
  res.name = "tuning";
  res.metrics.push_back({"pressure_error", last.pressure_error, 0.03,
                         "max over P_sys, P_dias, MAP at the inlet of |achieved / target - 1| "
                         "after tuning; 3 % (the issue's bound)"});
  res.metrics.push_back({"split_error_points", last.split_error, 2.0,
                         "max over outlets of |achieved - target split| in % points; 2"});
  res.metrics.push_back({"runs_3d", static_cast<double>(last.iteration), kMaxRuns,
                         "3D runs taken (two cycles each) until the 1 % / 0.5 point aims were "
                         "met, or the cap (6) when never; at most 3"});
  nlohmann::json steps = nlohmann::json::array();
  for (const tuning::TuningStep& s : r.steps)
    steps.push_back({{"iteration", s.iteration},
                     {"R_T", s.totals.resistance},
                     {"C_T", s.totals.capacitance},
                     {"k_d", s.totals.distal_share},
                     {"domain_series_resistance_Pa_s_per_m3", s.domain.series},
                     {"pressure_error", s.pressure_error},
                     {"split_error_points", s.split_error}});
  res.details = {
      {"element_size_m", h},
      {"truth",
       {{"R_T", kTruth.resistance}, {"C_T", kTruth.capacitance}, {"k_d", kTruth.distal_share}}},
      {"targets_mmHg",
       {targets.pressure.systolic / units::mmHg, targets.pressure.diastolic / units::mmHg,
        targets.pressure.mean / units::mmHg}},
      {"steps", steps}};
  return res;
}

} // namespace tearflow::verify
