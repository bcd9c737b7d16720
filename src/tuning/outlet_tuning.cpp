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
  const run::RunSummary summary = sim.run({false, false, false});
  if (summary.cycles.empty())
    throw std::logic_error("the 3D run completed no cycle");
  const analysis::CycleStats& last = summary.cycles.back();
  const double period = last.t_end - last.t_begin;
  s.split_percent.assign(t.splits.size(), NAN);
  s.outlet_pressure.assign(t.splits.size(), NAN);
  s.outlet_flow.assign(t.splits.size(), NAN);
  for (const analysis::FaceCycleStats& f : last.faces) {
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

} // namespace

io::Case with_outlets(io::Case c, const std::vector<bc::WindkesselBranch>& rcr) {
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

io::Case with_outlets(io::Case c, const TuningTargets& t, const WindkesselTotals& totals,
                      const std::vector<double>& distribution) {
  return with_outlets(std::move(c), distribute(totals, fractions(t, distribution)));
}

TuningResult tune_outlets(const io::Case& c, const TuningTargets& t, bool progress,
                          const Measure& measure) {
  const io::BoundaryCondition& inflow = single_inflow(c);
  check_outlets(c, t);
  if (t.max_iterations > 0 && c.time.steps_per_cycle == 0)
    input_error("the 3D stage runs whole cycles: the period {} s must be a multiple of "
                "time.step = {} s",
                c.time.period, c.time.step);
  const bool root = progress && fem::mpi_rank() == 0; // (no MPI needed without progress)
  const Measure run_3d = measure ? measure : Measure(measure_3d);

  TuningResult result;
  std::vector<double> f; // the distribution of the totals over the outlets
  for (const OutletFraction& o : t.splits)
    f.push_back(o.fraction);
  DomainResistance domain{t.domain_resistance, {}};
  if (t.per_outlet)
    domain.branch.assign(f.size(), 0.0);
  std::array<double, 3> defect = {1.0, 1.0, 1.0}; // P0D / P3D per pressure, from the last run
  for (int k = 0; k <= t.max_iterations; ++k) {
    const InletPressures aim{t.pressure.systolic * defect[0], t.pressure.diastolic * defect[1],
                             t.pressure.mean * defect[2]};
    // From the last fit: the aims move little between iterations.
    const FitResult fit =
        fit_windkessel_totals(aim, inflow.flow, fractions(t, f), domain,
                              k == 0 ? WindkesselTotals{} : result.steps.back().totals);
    TuningStep s;
    s.iteration = k;
    s.totals = fit.totals;
    s.distribution = f;
    s.domain = domain;
    s.outlets = distribute(fit.totals, fractions(t, f), domain);
    result.tuned = with_outlets(c, s.outlets);
    if (k == 0) { // the 0D stage's own prediction
      s.achieved = fit.achieved;
      const bc::PeriodicState st = zero_d_model(s.outlets, domain).periodic(inflow.flow);
      double total = 0.0;
      for (size_t i = 0; i < f.size(); ++i)
        total += st.mean_branch_flow(i);
      for (size_t i = 0; i < f.size(); ++i)
        s.split_percent.push_back(100.0 * st.mean_branch_flow(i) / total);
    } else {
      run_3d(result.tuned, inflow.face, t, s);
    }
    score(s, t);
    if (root && progress)
      print_step(s);
    result.steps.push_back(s);
    result.met = s.pressure_error <= t.pressure_tolerance && s.split_error <= t.split_tolerance;
    if (k == t.max_iterations || (k > 0 && result.met))
      break;
    if (k == 0)
      continue; // the first 3D run uses the 0D fit as it is
    if (!(std::isfinite(s.pressure_error) && std::isfinite(s.split_error)))
      throw SolverError(fmt::format("tuning: the 3D run of iteration {} gave no finite inlet "
                                    "pressures or splits",
                                    k));
    // (a) The 0D model takes the domain's resistance as the run measured it.
    if (t.correct_domain)
      domain = measured_domain(s, t.per_outlet);
    // (b) What the corrected model of the outlets that ran still misses rescales the aims.
    const InletPressures p0 =
        inlet_pressures(zero_d_model(s.outlets, domain).periodic(inflow.flow));
    defect = {p0.systolic / s.achieved.systolic, p0.diastolic / s.achieved.diastolic,
              p0.mean / s.achieved.mean};
    // (c) Shared parameters: the distribution follows the splits' misfit.
    if (t.per_outlet)
      continue;
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
