#include "bc/windkessel_network.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tearflow::bc {

double PeriodicState::eval(const Series& c, double t) const {
  double v = c.empty() ? 0.0 : c[0].real();
  if (period_ <= 0.0)
    return v;
  const double w = 2.0 * std::numbers::pi / period_;
  for (size_t n = 1; n < c.size(); ++n)
    v += 2.0 * (c[n] * std::polar(1.0, w * static_cast<double>(n) * t)).real();
  return v;
}

WindkesselNetwork::WindkesselNetwork(std::vector<WindkesselBranch> branches,
                                     double series_resistance)
    : branches_(std::move(branches)), series_resistance_(series_resistance) {
  if (branches_.empty())
    input_error("a Windkessel network needs at least one outlet branch");
  if (series_resistance < 0.0)
    input_error("series resistance {} Pa s/m^3 is negative", series_resistance);
  for (const WindkesselBranch& b : branches_) {
    const WindkesselRCR& w = b.rcr;
    if (w.proximal_resistance < 0.0 || w.capacitance < 0.0 || w.distal_resistance < 0.0)
      input_error("outlet '{}': resistances and capacitance must not be negative", b.name);
    if (w.capacitance > 0.0 && w.distal_resistance <= 0.0)
      input_error("outlet '{}': a capacitance needs a distal resistance > 0", b.name);
    if (w.proximal_resistance + w.distal_resistance <= 0.0)
      input_error("outlet '{}': zero total resistance", b.name);
  }
}

std::complex<double> WindkesselNetwork::impedance(size_t i, double omega) const {
  const WindkesselRCR& w = branches_[i].rcr;
  using namespace std::complex_literals;
  return w.proximal_resistance +
         w.distal_resistance / (1.0 + 1i * omega * w.distal_resistance * w.capacitance);
}

std::vector<double> PeriodicState::sample_inlet_pressure(int samples) const {
  // e^{i n w t_k} by repeated multiplication: one sine and cosine per sample, not per mode.
  std::vector<double> v(samples, inlet_.empty() ? 0.0 : inlet_[0].real());
  for (int k = 0; k < samples; ++k) {
    const std::complex<double> z = std::polar(1.0, 2.0 * std::numbers::pi * k / samples);
    std::complex<double> zn = 1.0;
    for (size_t n = 1; n < inlet_.size(); ++n) {
      zn *= z;
      v[k] += 2.0 * (inlet_[n] * zn).real();
    }
  }
  return v;
}

PeriodicState WindkesselNetwork::periodic(const Waveform& inflow, int modes) const {
  return periodic(inflow.fourier(inflow.is_constant() ? 1 : modes), inflow.period());
}

PeriodicState WindkesselNetwork::periodic(const std::vector<std::complex<double>>& q,
                                          double period) const {
  using C = std::complex<double>;
  using namespace std::complex_literals;
  PeriodicState s;
  s.period_ = period;
  const size_t nb = branches_.size();
  s.inlet_.resize(q.size());
  s.node_.resize(q.size());
  s.flow_.assign(nb, PeriodicState::Series(q.size()));
  s.distal_.assign(nb, PeriodicState::Series(q.size()));
  const double w = s.period_ > 0.0 ? 2.0 * std::numbers::pi / s.period_ : 0.0;
  for (size_t n = 0; n < q.size(); ++n) {
    const double omega = w * static_cast<double>(n);
    C admittance = 0.0, source = q[n];
    for (size_t i = 0; i < nb; ++i) {
      admittance += 1.0 / impedance(i, omega);
      if (n == 0)
        source += branches_[i].rcr.reference_pressure / impedance(i, 0.0);
    }
    const C p = source / admittance;
    s.node_[n] = p;
    s.inlet_[n] = p + series_resistance_ * q[n];
    for (size_t i = 0; i < nb; ++i) {
      const WindkesselRCR& r = branches_[i].rcr;
      const C ref = n == 0 ? C(r.reference_pressure) : C(0.0);
      s.flow_[i][n] = (p - ref) / impedance(i, omega);
      s.distal_[i][n] = ref + s.flow_[i][n] * r.distal_resistance /
                                  (1.0 + 1i * omega * r.distal_resistance * r.capacitance);
    }
  }
  return s;
}

NetworkHistory WindkesselNetwork::integrate(const Waveform& inflow, double t0, double dt, int steps,
                                            std::vector<double> pd) const {
  const size_t nb = branches_.size();
  if (pd.size() != nb)
    input_error("{} initial distal pressures for {} outlet branches", pd.size(), nb);
  NetworkHistory h;
  h.branch_flow.assign(nb, {});
  h.distal_pressure.assign(nb, {});
  std::vector<double> q(nb, 0.0);
  // P at the node from sum_i Q_i = Q_in with Q_i = (P - a_i) / r_i, each branch affine.
  auto solve_node = [&](double q_in, const std::vector<DistalUpdate>& d) {
    double num = q_in, den = 0.0;
    for (size_t i = 0; i < nb; ++i) {
      const WindkesselRCR& w = branches_[i].rcr;
      const double r = w.proximal_resistance + d[i].b, a = d[i].a;
      num += a / r;
      den += 1.0 / r;
    }
    return num / den;
  };
  auto record = [&](double t, double p, double q_in) {
    h.time.push_back(t);
    h.inlet_pressure.push_back(p + series_resistance_ * q_in);
    for (size_t i = 0; i < nb; ++i) {
      h.branch_flow[i].push_back(q[i]);
      h.distal_pressure[i].push_back(pd[i]);
    }
  };
  // A capacitor-free branch is a resistance: P_d = P_ref (b = 0), Q = (P - P_ref) / R_p.
  auto updates = [&](bool initial) {
    std::vector<DistalUpdate> d(nb);
    for (size_t i = 0; i < nb; ++i) {
      const WindkesselRCR& w = branches_[i].rcr;
      if (!branches_[i].has_capacitor())
        d[i] = {w.reference_pressure, w.distal_resistance};
      else
        d[i] = initial ? DistalUpdate{pd[i], 0.0} : distal_update(w, pd[i], q[i], dt);
    }
    return d;
  };
  // The initial flows follow from the initial distal pressures and Q_in(t0).
  std::vector<DistalUpdate> d = updates(true);
  double p = solve_node(inflow(t0), d);
  for (size_t i = 0; i < nb; ++i)
    q[i] = (p - d[i].a) / (branches_[i].rcr.proximal_resistance + d[i].b);
  record(t0, p, inflow(t0));
  for (int k = 1; k <= steps; ++k) {
    const double t = t0 + k * dt, q_in = inflow(t);
    d = updates(false);
    p = solve_node(q_in, d);
    for (size_t i = 0; i < nb; ++i) {
      q[i] = (p - d[i].a) / (branches_[i].rcr.proximal_resistance + d[i].b);
      pd[i] = d[i](q[i]);
    }
    record(t, p, q_in);
  }
  return h;
}

} // namespace tearflow::bc
