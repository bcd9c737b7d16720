#include "tuning/windkessel_fit.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::tuning {

std::vector<bc::WindkesselBranch> distribute(const WindkesselTotals& t,
                                             const std::vector<OutletFraction>& outlets,
                                             const DomainResistance& domain) {
  std::vector<bc::WindkesselBranch> branches;
  for (size_t i = 0; i < outlets.size(); ++i) {
    const OutletFraction& o = outlets[i];
    const double r = t.resistance / o.fraction - domain.of_branch(i);
    branches.push_back(
        {o.face,
         {(1.0 - t.distal_share) * r, t.capacitance * o.fraction, t.distal_share * r, 0.0}});
  }
  return branches;
}

bc::WindkesselNetwork zero_d_model(const std::vector<bc::WindkesselBranch>& outlets,
                                   const DomainResistance& domain) {
  std::vector<bc::WindkesselBranch> branches = outlets;
  for (size_t i = 0; i < branches.size(); ++i) // e_i in series: part of the proximal side
    branches[i].rcr.proximal_resistance += domain.of_branch(i);
  return bc::WindkesselNetwork(branches, domain.series);
}

InletPressures inlet_pressures(const bc::PeriodicState& state) {
  // 2000 samples per period find the extremes to (pi/2000)^2/2 ~ 1e-6 of the pulse; the
  // rectangle rule gives the mean of a trigonometric polynomial exactly.
  const std::vector<double> v = state.sample_inlet_pressure(2000);
  InletPressures p{*std::max_element(v.begin(), v.end()), *std::min_element(v.begin(), v.end()),
                   0.0};
  for (double x : v)
    p.mean += x / static_cast<double>(v.size());
  return p;
}

InletPressures inlet_pressures(const bc::WindkesselNetwork& network, const bc::Waveform& inflow) {
  return inlet_pressures(network.periodic(inflow));
}

namespace {

/// Parameters in unconstrained variables: x = (ln (R_T - R_min), ln C_T, logit k_d).
WindkesselTotals from_x(const Eigen::VectorXd& x, double r_min) {
  return {r_min + std::exp(x[0]), std::exp(x[1]), 1.0 / (1.0 + std::exp(-x[2]))};
}
Eigen::VectorXd to_x(const WindkesselTotals& t, double r_min) {
  Eigen::VectorXd x(3);
  x << std::log(t.resistance - r_min), std::log(t.capacitance),
      std::log(t.distal_share / (1.0 - t.distal_share));
  return x;
}

/// The relative misfit of the three pressures, for Eigen's Levenberg-Marquardt.
struct Misfit {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const InletPressures* targets;
  const std::vector<std::complex<double>>* inflow_modes;
  double period;
  const std::vector<OutletFraction>* outlets;
  const DomainResistance* domain;
  double r_min;
  int* evaluations;

  int inputs() const { return 3; }
  int values() const { return 3; }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    ++*evaluations;
    const bc::WindkesselNetwork net =
        zero_d_model(distribute(from_x(x, r_min), *outlets, *domain), *domain);
    const InletPressures p = inlet_pressures(net.periodic(*inflow_modes, period));
    f.resize(3);
    f << p.systolic / targets->systolic - 1.0, p.diastolic / targets->diastolic - 1.0,
        p.mean / targets->mean - 1.0;
    return 0;
  }
};

} // namespace

FitResult fit_windkessel_totals(const InletPressures& targets, const bc::Waveform& inflow,
                                const std::vector<OutletFraction>& outlets,
                                const DomainResistance& domain, WindkesselTotals start) {
  if (!(targets.diastolic > 0.0 && targets.diastolic < targets.mean &&
        targets.mean < targets.systolic))
    input_error("no Windkessel can meet P_sys = {:.1f}, P_dias = {:.1f}, MAP = {:.1f} mmHg: "
                "expected 0 < P_dias < MAP < P_sys",
                targets.systolic / units::mmHg, targets.diastolic / units::mmHg,
                targets.mean / units::mmHg);
  const double q_mean = inflow.mean();
  if (!(q_mean > 0.0))
    input_error("the inflow's mean {:.3g} m^3/s is not positive: no resistance gives MAP", q_mean);
  if (!domain.branch.empty() && domain.branch.size() != outlets.size())
    throw std::logic_error("one domain branch resistance per outlet expected");
  // Every outlet's own resistance R_T / f_i - e_i must stay positive.
  double r_min = 0.0;
  for (size_t i = 0; i < outlets.size(); ++i)
    r_min = std::max(r_min, domain.of_branch(i) * outlets[i].fraction);
  if (targets.mean / q_mean <= domain.series + r_min)
    input_error("MAP {:.1f} mmHg is below the 3D domain's own pressure drop: no outlet "
                "resistance can meet it",
                targets.mean / units::mmHg);
  if (start.resistance <= r_min) {
    start.resistance = targets.mean / q_mean - domain.series;
    start.capacitance = inflow.period() / start.resistance; // R_T C_T = one cardiac period
    start.distal_share = 0.85;
  }

  // Levenberg-Marquardt from the given start and from a grid of time constants and distal
  // shares; the best fit wins. A single start can stall where k_d saturates (the logit's
  // flat tails), and the fit must not depend on the user's guess.
  const std::vector<std::complex<double>> modes = inflow.fourier(128);
  FitResult best;
  best.max_relative_error = 1e300;
  std::vector<WindkesselTotals> starts = {start};
  for (double tau : {0.3, 1.0, 3.0}) // time constants in cardiac periods
    for (double kd : {0.6, 0.8, 0.95})
      starts.push_back({start.resistance, tau * inflow.period() / start.resistance, kd});
  int evaluations = 0;
  for (const WindkesselTotals& s0 : starts) {
    Misfit misfit{&targets, &modes, inflow.period(), &outlets, &domain, r_min, &evaluations};
    Eigen::NumericalDiff<Misfit> functor(misfit);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Misfit>> lm(functor);
    lm.parameters.xtol = 1e-12;
    lm.parameters.ftol = 1e-12;
    lm.parameters.maxfev = 500;
    Eigen::VectorXd x = to_x(s0, r_min);
    lm.minimize(x);
    FitResult r;
    r.totals = from_x(x, r_min);
    r.achieved = inlet_pressures(zero_d_model(distribute(r.totals, outlets, domain), domain)
                                     .periodic(modes, inflow.period()));
    r.max_relative_error = std::max({std::abs(r.achieved.systolic / targets.systolic - 1.0),
                                     std::abs(r.achieved.diastolic / targets.diastolic - 1.0),
                                     std::abs(r.achieved.mean / targets.mean - 1.0)});
    if (r.max_relative_error < best.max_relative_error)
      best = r;
    if (best.max_relative_error < 1e-8)
      break; // solved to round-off: the other starts would find the same point
  }
  best.evaluations = evaluations;
  return best;
}

} // namespace tearflow::tuning
