#include "tuning/outlet_tuning.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "fem/petsc.hpp"
#include "run/simulation.hpp"

namespace tearflow::tuning {

namespace {

/// The outlets tuning sets: RCR and resistance ones (a resistance becomes an RCR).
bool tuned_law(const bc::BoundaryCondition& b) {
  const bc::Outlet* o = b.outlet();
  return o && (std::holds_alternative<bc::RcrOutlet>(o->law) ||
               std::holds_alternative<bc::ResistanceOutlet>(o->law));
}

const bc::BoundaryCondition& single_inflow(const io::Case& c) {
  const bc::BoundaryCondition* inflow = nullptr;
  for (const bc::BoundaryCondition& b : c.boundary_conditions)
    if (b.inflow()) {
      if (inflow)
        input_error("tuning needs one inflow; the case has '{}' and '{}'", inflow->face, b.face);
      inflow = &b;
    }
  if (!inflow || inflow->inflow()->flow.is_constant())
    input_error("tuning needs a periodic inflow waveform (one cardiac cycle)");
  return *inflow;
}

void check_outlets(const io::Case& c, const TuningTargets& t) {
  for (const OutletFraction& o : t.splits) {
    const auto it = std::find_if(c.boundary_conditions.begin(), c.boundary_conditions.end(),
                                 [&](const bc::BoundaryCondition& b) { return b.face == o.face; });
    if (it == c.boundary_conditions.end() || !tuned_law(*it))
      input_error("the targets' split for '{}' names no rcr or resistance outlet of the case",
                  o.face);
  }
  for (const bc::BoundaryCondition& b : c.boundary_conditions)
    if (tuned_law(b) && std::none_of(t.splits.begin(), t.splits.end(),
                                     [&](const OutletFraction& o) { return o.face == b.face; }))
      input_error("outlet '{}' of the case has no target split", b.face);
}

std::vector<OutletFraction> fractions(const TuningTargets& t, const std::vector<double>& f) {
  std::vector<OutletFraction> out = t.splits;
  for (size_t i = 0; i < out.size(); ++i)
    out[i].fraction = f[i];
  return out;
}

/// The step's worst pressure and split errors; NaN if any achieved value is (a run that
/// lost an outlet), so that it can never count as met.
void score(TuningStep& s, const TuningTargets& t) {
  const InletPressures& p = t.pressure;
  auto worst = [](double w, double x) {
    return std::isnan(w) || std::isnan(x) ? NAN : std::max(w, x);
  };
  s.pressure_error = 0.0;
  for (const auto& [achieved, target] :
       {std::pair{s.achieved.systolic, p.systolic}, std::pair{s.achieved.diastolic, p.diastolic},
        std::pair{s.achieved.mean, p.mean}})
    s.pressure_error = worst(s.pressure_error, std::abs(achieved / target - 1.0));
  s.split_error = s.split_percent.size() == t.splits.size() ? 0.0 : NAN;
  for (size_t i = 0; i < s.split_percent.size(); ++i)
    s.split_error =
        worst(s.split_error, std::abs(s.split_percent[i] - 100.0 * t.splits[i].fraction));
}

/// Runs the case for t.cycles cycles and measures its last cycle.
void measure_3d(const io::Case& c, const std::string& inlet, const TuningTargets& t,
                TuningStep& s) {
  io::Case run_case = c;
  run_case.time.steps = t.cycles * c.time.steps_per_cycle;
  run_case.time.periodicity_tolerance = 0.0;
  run::Simulation sim(run_case);
  const run::RunSummary summary = sim.run({false, {}, {}, false, false, {}});
  if (summary.cycles.empty())
    throw std::logic_error("the 3D run completed no cycle");
  measure_cycle(summary.cycles.back(), inlet, t, s);
}

/// The 3D domain's resistance seen in a run (its cycle means): shared, in series with all
/// outlets, or per outlet. A pressure recovery (a negative drop) counts as no resistance.
DomainResistance measured_domain(const TuningStep& s, bool per_outlet) {
  DomainResistance d;
  double q = 0.0, pq = 0.0;
  for (size_t i = 0; i < s.outlet_flow.size(); ++i) {
    q += s.outlet_flow[i];
    pq += s.outlet_flow[i] * s.outlet_pressure[i];
    if (per_outlet)
      d.branch.push_back(
          std::max(0.0, (s.achieved.mean - s.outlet_pressure[i]) / s.outlet_flow[i]));
  }
  if (!per_outlet)
    d.series = std::max(0.0, (s.achieved.mean - pq / q) / q);
  return d;
}

} // namespace

void print_step(const TuningStep& s) {
  std::string domain;
  if (!s.domain.branch.empty())
    domain = fmt::format(", 0D domain e_i {:.3g} Pa s/m^3", fmt::join(s.domain.branch, " "));
  else if (s.domain.series > 0.0)
    domain = fmt::format(", 0D domain R_s {:.3g} Pa s/m^3", s.domain.series);
  fmt::print("tune {} {}: R_T {:.4g} Pa s/m^3, C_T {:.4g} m^3/Pa, k_d {:.3f}{} -> {:.1f}/{:.1f} "
             "({:.1f}) mmHg, pressure error {:.2f} %, split error {:.2f} points\n",
             s.iteration == 0 ? "0D" : "3D", s.iteration, s.totals.resistance, s.totals.capacitance,
             s.totals.distal_share, domain, s.achieved.systolic / units::mmHg,
             s.achieved.diastolic / units::mmHg, s.achieved.mean / units::mmHg,
             100.0 * s.pressure_error, s.split_error);
  std::fflush(stdout);
}

io::Case with_outlets(io::Case c, const std::vector<bc::WindkesselBranch>& rcr) {
  for (bc::BoundaryCondition& b : c.boundary_conditions)
    for (const bc::WindkesselBranch& w : rcr)
      if (b.face == w.name && tuned_law(b)) { // a resistance outlet becomes an RCR
        bc::RcrOutlet tuned{w.rcr, std::nullopt};
        tuned.rcr.reference_pressure = bc::zero_d_branch(b.outlet()->law)->reference_pressure;
        b.outlet()->law = tuned;
      }
  return c;
}

io::Case with_outlets(io::Case c, const TuningTargets& t, const WindkesselTotals& totals,
                      const std::vector<double>& distribution) {
  return with_outlets(std::move(c), distribute(totals, fractions(t, distribution)));
}

OutletCorrection::OutletCorrection(const io::Case& c, TuningTargets targets)
    : targets_(std::move(targets)), inflow_(single_inflow(c).inflow()->flow),
      inlet_(single_inflow(c).face) {
  check_outlets(c, targets_);
  for (const OutletFraction& o : targets_.splits)
    f_.push_back(o.fraction);
  domain_ = {targets_.domain_resistance, {}};
  if (targets_.per_outlet)
    domain_.branch.assign(f_.size(), 0.0);
}

TuningStep OutletCorrection::plan(int iteration, const WindkesselTotals* previous) const {
  const InletPressures aim{targets_.pressure.systolic * defect_[0],
                           targets_.pressure.diastolic * defect_[1],
                           targets_.pressure.mean * defect_[2]};
  // From the last fit: the aims move little between iterations.
  const FitResult fit = fit_windkessel_totals(aim, inflow_, fractions(targets_, f_), domain_,
                                              previous ? *previous : WindkesselTotals{});
  TuningStep s;
  s.iteration = iteration;
  s.totals = fit.totals;
  s.distribution = f_;
  s.domain = domain_;
  s.outlets = distribute(fit.totals, fractions(targets_, f_), domain_);
  if (iteration == 0) { // the 0D stage's own prediction
    s.achieved = fit.achieved;
    const bc::PeriodicState st = zero_d_model(s.outlets, domain_).periodic(inflow_);
    double total = 0.0;
    for (size_t i = 0; i < f_.size(); ++i)
      total += st.mean_branch_flow(i);
    for (size_t i = 0; i < f_.size(); ++i)
      s.split_percent.push_back(100.0 * st.mean_branch_flow(i) / total);
  }
  return s;
}

bool OutletCorrection::score(TuningStep& s) const {
  tuning::score(s, targets_);
  return s.pressure_error <= targets_.pressure_tolerance &&
         s.split_error <= targets_.split_tolerance;
}

void OutletCorrection::learn(const TuningStep& s) {
  if (!(std::isfinite(s.pressure_error) && std::isfinite(s.split_error)))
    throw SolverError(fmt::format("tuning: the 3D run of iteration {} gave no finite inlet "
                                  "pressures or splits",
                                  s.iteration));
  // (a) The 0D model takes the domain's resistance as the run measured it.
  if (targets_.correct_domain)
    domain_ = measured_domain(s, targets_.per_outlet);
  // (b) What the corrected model of the outlets that ran still misses rescales the aims.
  const InletPressures p0 = inlet_pressures(zero_d_model(s.outlets, domain_).periodic(inflow_));
  defect_ = {p0.systolic / s.achieved.systolic, p0.diastolic / s.achieved.diastolic,
             p0.mean / s.achieved.mean};
  // (c) Shared parameters: the distribution follows the splits' misfit.
  f_ = s.distribution;
  if (targets_.per_outlet)
    return;
  double sum = 0.0;
  for (size_t i = 0; i < f_.size(); ++i) {
    f_[i] *= 100.0 * targets_.splits[i].fraction / std::max(s.split_percent[i], 1e-6);
    sum += f_[i];
  }
  for (double& x : f_)
    x /= sum;
}

void measure_cycle(const run::CycleStats& cycle, const std::string& inlet, const TuningTargets& t,
                   TuningStep& s) {
  const double period = cycle.t_end - cycle.t_begin;
  s.split_percent.assign(t.splits.size(), NAN);
  s.outlet_pressure.assign(t.splits.size(), NAN);
  s.outlet_flow.assign(t.splits.size(), NAN);
  for (const run::FaceCycleStats& f : cycle.faces) {
    if (f.face == inlet)
      s.achieved = {f.systolic, f.diastolic, f.mean};
    for (size_t i = 0; i < t.splits.size(); ++i)
      if (f.face == t.splits[i].face) {
        s.split_percent[i] = f.split_percent.value_or(NAN);
        s.outlet_pressure[i] = f.mean;
        s.outlet_flow[i] = f.volume / period;
      }
  }
}

TuningResult tune_outlets(const io::Case& c, const TuningTargets& t, bool progress,
                          const Measure& measure) {
  OutletCorrection correction(c, t);
  if (t.max_iterations > 0 && c.time.steps_per_cycle == 0)
    input_error("the 3D stage runs whole cycles: the period {} s must be a multiple of "
                "time.step = {} s",
                c.time.period, c.time.step);
  const bool root = progress && fem::mpi_rank() == 0; // (no MPI needed without progress)
  const Measure run_3d = measure ? measure : Measure(measure_3d);

  TuningResult result;
  for (int k = 0; k <= t.max_iterations; ++k) {
    TuningStep s = correction.plan(k, k == 0 ? nullptr : &result.steps.back().totals);
    result.tuned = with_outlets(c, s.outlets);
    if (k > 0)
      run_3d(result.tuned, correction.inlet(), t, s);
    result.met = correction.score(s);
    if (root)
      print_step(s);
    result.steps.push_back(s);
    if (k == t.max_iterations || (k > 0 && result.met))
      break;
    if (k > 0) // the first 3D run uses the 0D fit as it is
      correction.learn(s);
  }
  return result;
}

} // namespace tearflow::tuning
