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
                                             const std::vector<OutletFraction>& outlets) {
  std::vector<bc::WindkesselBranch> branches;
  for (const OutletFraction& o : outlets) {
    const double r = t.resistance / o.fraction;
    branches.push_back(
        {o.face,
         {(1.0 - t.distal_share) * r, t.capacitance * o.fraction, t.distal_share * r, 0.0}});
  }
  return branches;
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

/// Parameters in unconstrained variables: x = (ln R_T, ln C_T, logit k_d).
WindkesselTotals from_x(const Eigen::VectorXd& x) {
  return {std::exp(x[0]), std::exp(x[1]), 1.0 / (1.0 + std::exp(-x[2]))};
}
Eigen::VectorXd to_x(const WindkesselTotals& t) {
  Eigen::VectorXd x(3);
  x << std::log(t.resistance), std::log(t.capacitance),
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
  double series_resistance;
  int* evaluations;

  int inputs() const { return 3; }
  int values() const { return 3; }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    ++*evaluations;
    const bc::WindkesselNetwork net(distribute(from_x(x), *outlets), series_resistance);
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
                                double series_resistance, WindkesselTotals start) {
  if (!(targets.diastolic > 0.0 && targets.diastolic < targets.mean &&
        targets.mean < targets.systolic))
    input_error("no Windkessel can meet P_sys = {:.1f}, P_dias = {:.1f}, MAP = {:.1f} mmHg: "
                "expected 0 < P_dias < MAP < P_sys",
                targets.systolic / units::mmHg, targets.diastolic / units::mmHg,
                targets.mean / units::mmHg);
  const double q_mean = inflow.mean();
  if (!(q_mean > 0.0))
    input_error("the inflow's mean {:.3g} m^3/s is not positive: no resistance gives MAP", q_mean);
  const double r_min = series_resistance;
  if (targets.mean / q_mean <= r_min)
    input_error("MAP {:.1f} mmHg is below the 3D domain's own pressure drop: no outlet "
                "resistance can meet it",
                targets.mean / units::mmHg);
  if (start.resistance <= 0.0) {
    start.resistance = targets.mean / q_mean - r_min;
    start.capacitance = 1.0 / start.resistance; // R_T C_T = 1 s, a cardiac period
    start.distal_share = 0.85;
  }

  // Levenberg-Marquardt from the given start and from a grid of time constants and distal
  // shares; the best fit wins. A single start can stall where k_d saturates (the logit's
  // flat tails), and the fit must not depend on the user's guess.
  const std::vector<std::complex<double>> modes = inflow.fourier(128);
  FitResult best;
  best.max_relative_error = 1e300;
  std::vector<WindkesselTotals> starts = {start};
  for (double tau : {0.3, 1.0, 3.0})
    for (double kd : {0.6, 0.8, 0.95})
      starts.push_back({start.resistance, tau / start.resistance, kd});
  int evaluations = 0;
  for (const WindkesselTotals& s0 : starts) {
    Misfit misfit{&targets, &modes, inflow.period(), &outlets, series_resistance, &evaluations};
    Eigen::NumericalDiff<Misfit> functor(misfit);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Misfit>> lm(functor);
    lm.parameters.xtol = 1e-12;
    lm.parameters.ftol = 1e-12;
    lm.parameters.maxfev = 500;
    Eigen::VectorXd x = to_x(s0);
    lm.minimize(x);
    FitResult r;
    r.totals = from_x(x);
    r.achieved =
        inlet_pressures(bc::WindkesselNetwork(distribute(r.totals, outlets), series_resistance)
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
