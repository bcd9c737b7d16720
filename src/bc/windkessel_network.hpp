#pragma once
// The 3D-free model of an arterial tree's outlets: an inflow Q_in(t) through an optional
// series resistance R_s (the 3D domain's own resistance, when known) into one node whose
// pressure P(t) drives parallel outlet branches, each an RCR Windkessel (windkessel.hpp) or
// a plain resistance (an RCR without capacitor). Used to start 3D runs near their periodic
// state, to verify the 3D outlets, and by the tuning of outlet parameters.
//
// The periodic state is solved exactly in the frequency domain: with
// Q_in(t) = Re(sum_n q_n e^{i n w t}), each branch has the impedance
//   Z_i(w) = R_p,i + R_d,i / (1 + i w R_d,i C_i),
// the node pressure is P_n = Q_n / sum_i Z_i^{-1} for n >= 1 and, at n = 0,
//   P_0 = (Q_0 + sum_i P_ref,i / Z_i(0)) / sum_i Z_i(0)^{-1};
// branch flows are Q_i,n = (P_n - P_ref,i delta_n0) / Z_i, distal pressures
// P_d,i,n = P_ref,i delta_n0 + Q_i,n R_d,i / (1 + i n w R_d,i C_i), inlet P + R_s Q_in.
#include <complex>
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

struct WindkesselBranch {
  std::string name;
  /// A resistance outlet R has proximal_resistance R, capacitance 0, distal_resistance 0.
  WindkesselRCR rcr;
  bool has_capacitor() const { return rcr.capacitance > 0.0; }
};

/// A periodic solution as Fourier series; evaluates any quantity at any time.
class PeriodicState {
public:
  double period() const { return period_; }
  double inlet_pressure(double t) const { return eval(inlet_, t); }
  double node_pressure(double t) const { return eval(node_, t); }
  double branch_flow(size_t i, double t) const { return eval(flow_[i], t); }
  double distal_pressure(size_t i, double t) const { return eval(distal_[i], t); }
  double mean_branch_flow(size_t i) const { return flow_[i][0].real(); }
  /// The inlet pressure at `samples` equally spaced times over one period (from t = 0).
  std::vector<double> sample_inlet_pressure(int samples) const;
  size_t num_branches() const { return flow_.size(); }

private:
  friend class WindkesselNetwork;
  using Series = std::vector<std::complex<double>>; // c_0, c_1, ... as in Waveform::fourier
  double eval(const Series& c, double t) const;
  double period_ = 0.0;
  Series inlet_, node_;
  std::vector<Series> flow_, distal_;
};

/// States of a time integration (trapezoidal rule, as the 3D outlets): per time sample.
struct NetworkHistory {
  std::vector<double> time, inlet_pressure;
  std::vector<std::vector<double>> branch_flow, distal_pressure; ///< [branch][sample]
};

class WindkesselNetwork {
public:
  /// Throws InputError on a branch with negative values, a capacitor without a distal
  /// resistance, or a zero total impedance.
  explicit WindkesselNetwork(std::vector<WindkesselBranch> branches,
                             double series_resistance = 0.0);

  const std::vector<WindkesselBranch>& branches() const { return branches_; }

  /// The periodic response to a periodic inflow (exact up to the `modes` harmonics kept;
  /// a constant inflow gives the steady state).
  PeriodicState periodic(const Waveform& inflow, int modes = 128) const;
  /// The same from the inflow's Fourier coefficients (Waveform::fourier) and period, for
  /// callers that evaluate many networks for one inflow.
  PeriodicState periodic(const std::vector<std::complex<double>>& inflow_modes,
                         double period) const;

  /// Integrates from t0 with the distal pressures `pd0` by the trapezoidal rule (the scheme
  /// of the 3D outlets, windkessel.hpp) for `steps` steps of dt.
  NetworkHistory integrate(const Waveform& inflow, double t0, double dt, int steps,
                           std::vector<double> pd0) const;

private:
  std::complex<double> impedance(size_t i, double omega) const;
  std::vector<WindkesselBranch> branches_;
  double series_resistance_ = 0.0;
};

} // namespace tearflow::bc
