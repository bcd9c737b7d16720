#include "rom/lumped_network.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/error.hpp"

namespace tearflow::rom {

namespace {

double inverse(double a) {
  return a > 0.0 ? 1.0 / a : 0.0;
}

/// The convective coefficient for flow from area `in` to area `out` (file comment).
double convective(double in, double out, double density) {
  if (in <= 0.0 || out <= 0.0)
    return 0.0;
  const double bernoulli = inverse(out * out) - inverse(in * in);
  const double expansion = std::max(0.0, inverse(in) - inverse(out));
  return 0.5 * density * (bernoulli + expansion * expansion);
}

} // namespace

Convection convection(const NetworkEdge& e, double density) {
  return {convective(e.area_from, e.area_to, density) + e.loss,
          convective(e.area_to, e.area_from, density) + e.loss};
}

LumpedNetwork::LumpedNetwork(std::vector<NetworkNode> nodes, std::vector<NetworkEdge> edges,
                             std::vector<NetworkCoupling> couplings,
                             std::vector<NetworkOutlet> outlets, int inflow_node,
                             bc::Waveform inflow, double density)
    : nodes_(std::move(nodes)), edges_(std::move(edges)), couplings_(std::move(couplings)),
      outlets_(std::move(outlets)), inflow_node_(inflow_node), inflow_(std::move(inflow)),
      density_(density) {
  const int n = static_cast<int>(nodes_.size());
  auto check_node = [&](int i, const std::string& what) {
    if (i < 0 || i >= n)
      input_error("reduced-order network: {} names node {}, the network has {}", what, i, n);
  };
  for (const NetworkNode& node : nodes_)
    if (!(node.compliance >= 0.0))
      input_error("reduced-order network: node {} has compliance {} (expected >= 0)", node.name,
                  node.compliance);
  for (const NetworkEdge& e : edges_) {
    check_node(e.from, "edge " + e.name);
    check_node(e.to, "edge " + e.name);
    if (!(e.resistance >= 0.0 && e.inertance >= 0.0 && e.loss >= 0.0 && e.area_from >= 0.0 &&
          e.area_to >= 0.0))
      input_error("reduced-order network: edge {} has a negative or NaN parameter (R {}, L {}, "
                  "k {}, areas {} / {})",
                  e.name, e.resistance, e.inertance, e.loss, e.area_from, e.area_to);
    if (e.regain_edge >= static_cast<int>(edges_.size()) || !(e.regain >= 0.0))
      input_error("reduced-order network: edge {} has a junction regain {} from edge {}", e.name,
                  e.regain, e.regain_edge);
    if (e.resistance == 0.0 && e.inertance == 0.0 && e.loss == 0.0 &&
        (e.area_from == 0.0 || e.area_to == 0.0))
      input_error("reduced-order network: edge {} has neither resistance, inertance nor loss",
                  e.name);
  }
  for (const NetworkCoupling& c : couplings_) {
    check_node(c.a, "a coupling");
    check_node(c.b, "a coupling");
    if (!(c.compliance >= 0.0))
      input_error("reduced-order network: a coupling has compliance {}", c.compliance);
  }
  check_node(inflow_node_, "the inflow");
  if (inflow_.period() <= 0.0)
    input_error("reduced-order network: the inflow must be periodic");
  int next = n + static_cast<int>(edges_.size());
  for (const NetworkOutlet& o : outlets_) {
    check_node(o.node, "outlet " + o.name);
    const bc::WindkesselRCR& w = o.rcr;
    if (!(w.proximal_resistance >= 0.0 && w.capacitance >= 0.0 && w.distal_resistance >= 0.0))
      input_error("reduced-order network: outlet {} has a negative or NaN parameter", o.name);
    if (w.capacitance > 0.0 && w.distal_resistance <= 0.0)
      input_error("reduced-order network: outlet {} has a capacitor without distal resistance",
                  o.name);
    if (w.capacitance == 0.0 && w.proximal_resistance + w.distal_resistance <= 0.0)
      input_error("reduced-order network: outlet {} has no resistance", o.name);
    capacitor_.push_back(w.capacitance > 0.0 && w.proximal_resistance > 0.0 ? next++ : -1);
  }
  for (const NetworkEdge& e : edges_)
    convection_.push_back(convection(e, density_));
}

int LumpedNetwork::node(const std::string& name) const {
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].name == name)
      return static_cast<int>(i);
  return -1;
}

int LumpedNetwork::edge(const std::string& name) const {
  for (size_t i = 0; i < edges_.size(); ++i)
    if (edges_[i].name == name)
      return static_cast<int>(i);
  return -1;
}

int LumpedNetwork::num_unknowns() const {
  int n = static_cast<int>(nodes_.size() + edges_.size());
  for (int c : capacitor_)
    n += c >= 0 ? 1 : 0;
  return n;
}

namespace {

/// The outlet's flow Q_o and its derivatives by the node pressure and by P_d (file comment;
/// an outlet with R_p = 0 and a capacitor puts the capacitor on its node, see mass()).
struct OutletFlow {
  double q = 0.0, by_node = 0.0, by_distal = 0.0;
};

OutletFlow outlet_flow(const bc::WindkesselRCR& w, bool capacitor, double p, double pd) {
  if (capacitor)
    return {(p - pd) / w.proximal_resistance, 1.0 / w.proximal_resistance,
            -1.0 / w.proximal_resistance};
  if (w.capacitance > 0.0) // R_p = 0: the node itself is the capacitor's pressure
    return {(p - w.reference_pressure) / w.distal_resistance, 1.0 / w.distal_resistance, 0.0};
  const double r = w.proximal_resistance + w.distal_resistance;
  return {(p - w.reference_pressure) / r, 1.0 / r, 0.0};
}

} // namespace

struct LumpedNetwork::Work {
  Eigen::MatrixXd mass, jacobian;
  Eigen::VectorXd x, x_prev, rhs, rate, dx, tmp;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  explicit Work(int n)
      : mass(Eigen::MatrixXd::Zero(n, n)), jacobian(n, n), x(n), x_prev(n), rhs(n), rate(n), dx(n),
        tmp(n), lu(n) {}
};

NetworkSolution LumpedNetwork::periodic(double start_pressure,
                                        const std::vector<double>& start_distal,
                                        const IntegrationOptions& opt) const {
  if (start_distal.size() != outlets_.size())
    input_error("reduced-order network: {} start pressures for {} outlets", start_distal.size(),
                outlets_.size());
  if (opt.steps_per_cycle <= 0 || opt.samples_per_cycle <= 0 ||
      opt.steps_per_cycle % opt.samples_per_cycle != 0)
    input_error("reduced-order network: {} samples do not divide {} steps per cycle",
                opt.samples_per_cycle, opt.steps_per_cycle);
  const int n_nodes = static_cast<int>(nodes_.size());
  const int n_edges = static_cast<int>(edges_.size());
  const int n = num_unknowns();
  Work w(n);

  // The mass matrix M of M dx/dt + G(x, t) = 0 (constant).
  for (int i = 0; i < n_nodes; ++i)
    w.mass(i, i) += nodes_[i].compliance;
  for (const NetworkCoupling& c : couplings_) {
    w.mass(c.a, c.a) += c.compliance, w.mass(c.b, c.b) += c.compliance;
    w.mass(c.a, c.b) -= c.compliance, w.mass(c.b, c.a) -= c.compliance;
  }
  for (int e = 0; e < n_edges; ++e)
    w.mass(n_nodes + e, n_nodes + e) = edges_[e].inertance;
  for (size_t o = 0; o < outlets_.size(); ++o) {
    if (capacitor_[o] >= 0)
      w.mass(capacitor_[o], capacitor_[o]) = outlets_[o].rcr.capacitance;
    else if (outlets_[o].rcr.capacitance > 0.0)
      w.mass(outlets_[o].node, outlets_[o].node) += outlets_[o].rcr.capacitance;
  }

  // G(x, t) and its Jacobian K, added to `rhs` and `jacobian`.
  // The mass matrix's entries, for M x without its zeros.
  struct Entry {
    int row, col;
    double value;
  };
  std::vector<Entry> mass;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (w.mass(i, j) != 0.0)
        mass.push_back({i, j, w.mass(i, j)});

  // G(x, t), added to `rhs`.
  auto add_g = [&](const Eigen::VectorXd& x, double t) {
    w.rhs(inflow_node_) -= inflow_(t);
    for (int e = 0; e < n_edges; ++e) {
      const NetworkEdge& edge = edges_[e];
      const int row = n_nodes + e;
      const double q = x(row);
      const double c = q >= 0.0 ? convection_[e].forward : -convection_[e].backward;
      w.rhs(edge.from) += q, w.rhs(edge.to) -= q;
      w.rhs(row) += edge.resistance * q + c * q * q - x(edge.from) + x(edge.to);
      if (edge.regain_edge >= 0) {
        const double qc = x(n_nodes + edge.regain_edge);
        w.rhs(row) -= edge.regain * (qc * qc - q * q);
      }
    }
    for (size_t o = 0; o < outlets_.size(); ++o) {
      const bc::WindkesselRCR& rcr = outlets_[o].rcr;
      const int i = outlets_[o].node, d = capacitor_[o];
      const OutletFlow f = outlet_flow(rcr, d >= 0, x(i), d >= 0 ? x(d) : 0.0);
      w.rhs(i) += f.q;
      if (d >= 0)
        w.rhs(d) += -f.q + (x(d) - rcr.reference_pressure) / rcr.distal_resistance;
    }
  };
  // Its Jacobian K = dG/dx, added to `jacobian`.
  auto add_k = [&](const Eigen::VectorXd& x) {
    for (int e = 0; e < n_edges; ++e) {
      const NetworkEdge& edge = edges_[e];
      const int row = n_nodes + e;
      const double q = x(row);
      const double c = q >= 0.0 ? convection_[e].forward : -convection_[e].backward;
      w.jacobian(edge.from, row) += 1.0, w.jacobian(edge.to, row) -= 1.0;
      w.jacobian(row, row) += edge.resistance + 2.0 * c * q;
      w.jacobian(row, edge.from) -= 1.0, w.jacobian(row, edge.to) += 1.0;
      if (edge.regain_edge >= 0) {
        const int col = n_nodes + edge.regain_edge;
        w.jacobian(row, col) -= 2.0 * edge.regain * x(col);
        w.jacobian(row, row) += 2.0 * edge.regain * q;
      }
    }
    for (size_t o = 0; o < outlets_.size(); ++o) {
      const bc::WindkesselRCR& rcr = outlets_[o].rcr;
      const int i = outlets_[o].node, d = capacitor_[o];
      const OutletFlow f = outlet_flow(rcr, d >= 0, x(i), d >= 0 ? x(d) : 0.0);
      w.jacobian(i, i) += f.by_node;
      if (d < 0)
        continue;
      w.jacobian(i, d) += f.by_distal;
      w.jacobian(d, i) -= f.by_node;
      w.jacobian(d, d) += -f.by_distal + 1.0 / rcr.distal_resistance;
    }
  };

  const double period = inflow_.period();
  const double dt = period / opt.steps_per_cycle;
  double flow_scale = 0.0;
  for (int k = 0; k < 64; ++k)
    flow_scale = std::max(flow_scale, std::abs(inflow_(period * k / 64.0)));
  flow_scale = std::max(flow_scale, 1e-12);
  const double p_scale = 1e4; // ~ 75 mmHg: what the updates are measured against

  w.x.setZero();
  w.x.head(n_nodes).setConstant(start_pressure);
  for (size_t o = 0; o < outlets_.size(); ++o)
    if (capacitor_[o] >= 0)
      w.x(capacitor_[o]) = start_distal[o];

  NetworkSolution s;
  const int every = opt.steps_per_cycle / opt.samples_per_cycle;
  Eigen::VectorXd cycle_start = w.x, last_delta = Eigen::VectorXd::Zero(n);
  bool extrapolated = false;
  double last_rho = 0.0;
  bool first_step = true, refactor = true;
  double factored_for = 0.0; // the BDF coefficient of the factorized Jacobian
  for (int cycle = 0; cycle < opt.max_cycles; ++cycle) {
    s.time.clear(), s.pressure.clear(), s.flow.clear(), s.outflow.clear();
    for (int step = 0; step < opt.steps_per_cycle; ++step) {
      if (step % every == 0) { // sample the state at the step's start
        const double t = (cycle * opt.steps_per_cycle + step) * dt;
        s.time.push_back(t);
        s.pressure.emplace_back(w.x.data(), w.x.data() + n_nodes);
        s.flow.emplace_back(w.x.data() + n_nodes, w.x.data() + n_nodes + n_edges);
        std::vector<double> out(outlets_.size());
        for (size_t o = 0; o < outlets_.size(); ++o) {
          const int d = capacitor_[o];
          out[o] =
              outlet_flow(outlets_[o].rcr, d >= 0, w.x(outlets_[o].node), d >= 0 ? w.x(d) : 0.0).q;
        }
        s.outflow.push_back(std::move(out));
      }
      const double t = (cycle * opt.steps_per_cycle + step + 1) * dt;
      // BDF2: dx/dt = (a x + history) / dt; the first step backward Euler.
      const double a = first_step ? 1.0 : 1.5;
      if (first_step)
        w.rate = -w.x;
      else
        w.rate = -2.0 * w.x + 0.5 * w.x_prev;
      w.x_prev = w.x;
      // Newton with the factorization kept while it contracts fast (a chord method): the
      // Jacobian changes only through the convective terms, slowly over a step.
      if (a != factored_for)
        refactor = true, factored_for = a;
      bool converged = false;
      double previous = 0.0;
      for (int it = 0; it < 40 && !converged; ++it) {
        w.tmp = (a * w.x + w.rate) / dt;
        w.rhs.setZero();
        for (const Entry& m : mass)
          w.rhs(m.row) += m.value * w.tmp(m.col);
        add_g(w.x, t);
        if (refactor) {
          w.jacobian = (a / dt) * w.mass;
          add_k(w.x);
          w.lu.compute(w.jacobian);
          refactor = false;
          ++s.factorizations;
        }
        w.dx = w.lu.solve(w.rhs);
        w.x -= w.dx;
        ++s.newton_iterations;
        double size = w.dx.head(n_nodes).cwiseAbs().maxCoeff() / (opt.newton_tolerance * p_scale);
        if (n_edges > 0)
          size = std::max(size, w.dx.segment(n_nodes, n_edges).cwiseAbs().maxCoeff() /
                                    (opt.newton_tolerance * flow_scale));
        converged = size <= 1.0;
        if (!w.x.allFinite())
          break;
        if (!converged && it > 0 && size > 0.1 * previous)
          refactor = true; // contracting slowly: the factorization is stale
        previous = size;
      }
      if (!converged || !w.x.allFinite())
        throw SolverError(fmt::format("reduced-order network: Newton did not converge at "
                                      "t = {:.4f} s (cycle {})",
                                      t, cycle + 1));
      first_step = false;
    }
    s.cycles = cycle + 1;
    double change = 0.0;
    for (int i = 0; i < n; ++i)
      if (i < n_nodes || i >= n_nodes + n_edges)
        change = std::max(change, std::abs(w.x(i) - cycle_start(i)));
    s.last_change = change;
    if (cycle > 0 && change <= opt.pressure_tolerance)
      return s;
    // The slowest mode (the capacitors draining through the outlets) decays by a factor rho
    // per cycle: with the cycle's change d_k = rho d_{k-1}, the state it tends to is
    // x + rho / (1 - rho) d_k (Aitken's extrapolation of the geometric series). Applied when
    // two successive ratios agree within 10 % (the faster modes have died out); the next
    // step restarts BDF2 by backward Euler.
    w.tmp = w.x - cycle_start;
    const double rho = cycle > 0 ? w.tmp.dot(last_delta) / last_delta.squaredNorm() : 0.0;
    if (!extrapolated && rho > 0.05 && rho < 0.95 && std::abs(rho - last_rho) < 0.1 * rho) {
      w.x += (rho / (1.0 - rho)) * w.tmp;
      first_step = true, extrapolated = true;
    } else
      extrapolated = false;
    last_rho = rho;
    last_delta = w.tmp;
    cycle_start = w.x;
  }
  throw SolverError(fmt::format("reduced-order network: not periodic after {} cycles (the "
                                "pressures still change by {:.3g} Pa per cycle)",
                                opt.max_cycles, s.last_change));
}

} // namespace tearflow::rom
