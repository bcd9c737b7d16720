#include "tuning/outlet_tuning.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "fem/petsc.hpp"
#include "run/simulation.hpp"

namespace tearflow::tuning {

namespace {

const io::BoundaryCondition& single_inflow(const io::Case& c) {
  const io::BoundaryCondition* inflow = nullptr;
  for (const io::BoundaryCondition& b : c.boundary_conditions)
    if (b.type == io::BcType::Inflow) {
      if (inflow)
        input_error("tuning needs one inflow; the case has '{}' and '{}'", inflow->face, b.face);
      inflow = &b;
    }
  if (!inflow || inflow->flow.is_constant())
    input_error("tuning needs a periodic inflow waveform (one cardiac cycle)");
  return *inflow;
}

void check_outlets(const io::Case& c, const TuningTargets& t) {
  for (const OutletFraction& o : t.splits) {
    const auto it = std::find_if(c.boundary_conditions.begin(), c.boundary_conditions.end(),
                                 [&](const io::BoundaryCondition& b) { return b.face == o.face; });
    if (it == c.boundary_conditions.end() ||
        (it->type != io::BcType::Windkessel && it->type != io::BcType::Resistance))
      input_error("the targets' split for '{}' names no rcr or resistance outlet of the case",
                  o.face);
  }
  for (const io::BoundaryCondition& b : c.boundary_conditions)
    if ((b.type == io::BcType::Windkessel || b.type == io::BcType::Resistance) &&
        std::none_of(t.splits.begin(), t.splits.end(),
                     [&](const OutletFraction& o) { return o.face == b.face; }))
      input_error("outlet '{}' of the case has no target split", b.face);
}

std::vector<OutletFraction> fractions(const TuningTargets& t, const std::vector<double>& f) {
  std::vector<OutletFraction> out = t.splits;
  for (size_t i = 0; i < out.size(); ++i)
    out[i].fraction = f[i];
  return out;
}

void score(TuningStep& s, const TuningTargets& t) {
  const InletPressures& p = t.pressure;
  s.pressure_error = std::max({std::abs(s.achieved.systolic / p.systolic - 1.0),
                               std::abs(s.achieved.diastolic / p.diastolic - 1.0),
                               std::abs(s.achieved.mean / p.mean - 1.0)});
  s.split_error = 0.0;
  for (size_t i = 0; i < t.splits.size(); ++i)
    s.split_error =
        std::max(s.split_error, std::abs(s.split_percent[i] - 100.0 * t.splits[i].fraction));
}

/// Runs the case for t.cycles cycles and measures its last cycle.
void measure_3d(const io::Case& c, const std::string& inlet, const TuningTargets& t,
                TuningStep& s) {
  io::Case run_case = c;
  run_case.time.steps = t.cycles * c.time.steps_per_cycle;
  run_case.time.periodicity_tolerance = 0.0;
  run::Simulation sim(run_case);
  const run::RunSummary summary = sim.run({false, false, false});
  if (summary.cycles.empty())
    throw std::logic_error("the 3D run completed no cycle");
  const analysis::CycleStats& last = summary.cycles.back();
  s.split_percent.assign(t.splits.size(), 0.0);
  for (const analysis::FaceCycleStats& f : last.faces) {
    if (f.face == inlet)
      s.achieved = {f.systolic, f.diastolic, f.mean};
    for (size_t i = 0; i < t.splits.size(); ++i)
      if (f.face == t.splits[i].face)
        s.split_percent[i] = f.split_percent.value_or(0.0);
  }
}

void print_step(const TuningStep& s, const TuningTargets& t) {
  fmt::print("tune {} {}: R_T {:.4g} Pa s/m^3, C_T {:.4g} m^3/Pa, k_d {:.3f} -> {:.1f}/{:.1f} "
             "({:.1f}) mmHg, pressure error {:.2f} %, split error {:.2f} points\n",
             s.iteration == 0 ? "0D" : "3D", s.iteration, s.totals.resistance, s.totals.capacitance,
             s.totals.distal_share, s.achieved.systolic / units::mmHg,
             s.achieved.diastolic / units::mmHg, s.achieved.mean / units::mmHg,
             100.0 * s.pressure_error, s.split_error);
  (void)t;
  std::fflush(stdout);
}

} // namespace

io::Case with_outlets(io::Case c, const TuningTargets& t, const WindkesselTotals& totals,
                      const std::vector<double>& distribution) {
  const std::vector<bc::WindkesselBranch> rcr = distribute(totals, fractions(t, distribution));
  for (io::BoundaryCondition& b : c.boundary_conditions)
    for (const bc::WindkesselBranch& w : rcr)
      if (b.face == w.name) {
        b.type = io::BcType::Windkessel;
        b.rcr = w.rcr;
        b.rcr.reference_pressure = b.distal_pressure;
        b.initial_distal_pressure.reset();
      }
  return c;
}

TuningResult tune_outlets(const io::Case& c, const TuningTargets& t, bool progress) {
  const io::BoundaryCondition& inflow = single_inflow(c);
  check_outlets(c, t);
  if (t.max_iterations > 0 && c.time.steps_per_cycle == 0)
    input_error("the 3D stage runs whole cycles: the period {} s must be a multiple of "
                "time.step = {} s",
                c.time.period, c.time.step);
  const bool root = fem::mpi_rank() == 0;

  TuningResult result;
  std::vector<double> f;
  for (const OutletFraction& o : t.splits)
    f.push_back(o.fraction);
  InletPressures aim = t.pressure;
  for (int k = 0; k <= t.max_iterations; ++k) {
    const FitResult fit =
        fit_windkessel_totals(aim, inflow.flow, fractions(t, f), t.domain_resistance);
    TuningStep s;
    s.iteration = k;
    s.totals = fit.totals;
    s.distribution = f;
    result.tuned = with_outlets(c, t, fit.totals, f);
    if (k == 0) { // the 0D stage's own prediction
      s.achieved = fit.achieved;
      const bc::PeriodicState st =
          bc::WindkesselNetwork(distribute(fit.totals, fractions(t, f)), t.domain_resistance)
              .periodic(inflow.flow);
      double total = 0.0;
      for (size_t i = 0; i < f.size(); ++i)
        total += st.mean_branch_flow(i);
      for (size_t i = 0; i < f.size(); ++i)
        s.split_percent.push_back(100.0 * st.mean_branch_flow(i) / total);
    } else {
      measure_3d(result.tuned, inflow.face, t, s);
    }
    score(s, t);
    if (root && progress)
      print_step(s, t);
    result.steps.push_back(s);
    result.met = s.pressure_error <= t.pressure_tolerance && s.split_error <= t.split_tolerance;
    if (k == t.max_iterations || (k > 0 && result.met))
      break;
    if (k == 0)
      continue; // the first 3D run uses the 0D fit as it is
    // Fixed-point correction of the 0D stage's aims by what the 3D run achieved.
    aim.systolic *= t.pressure.systolic / s.achieved.systolic;
    aim.diastolic *= t.pressure.diastolic / s.achieved.diastolic;
    aim.mean *= t.pressure.mean / s.achieved.mean;
    double sum = 0.0;
    for (size_t i = 0; i < f.size(); ++i) {
      f[i] *= 100.0 * t.splits[i].fraction / std::max(s.split_percent[i], 1e-6);
      sum += f[i];
    }
    for (double& x : f)
      x /= sum;
  }
  return result;
}

} // namespace tearflow::tuning
