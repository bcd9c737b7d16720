#pragma once
// A lumped (0D) network of compliant vessel segments, orifices and Windkessel outlets, driven
// by an inflow, integrated to its periodic state: the reduced-order model of a dissected aorta
// (rom/dissection_network.hpp builds one from a model directory).
//
// Unknowns: the pressure p_i of every node, the flow q_e of every edge (from -> to) and the
// distal pressure P_d,o of every outlet with a capacitor. The equations (a DAE):
//   node i:   Q_in delta_i,in + sum_{e into i} q_e - sum_{e out of i} q_e - sum_{o at i} Q_o
//               - C_i dp_i/dt - sum_{couplings (i,j)} C_ij d(p_i - p_j)/dt = 0,
//   edge e:   p_from - p_to = R_e q_e + L_e dq_e/dt + B_e(q_e) [- h_e (q_c^2 - q_e^2)],
//   outlet o: C_o dP_d,o/dt = Q_o - (P_d,o - P_ref,o) / R_d,o,  Q_o = (p_i - P_d,o) / R_p,o,
// with the convective term of an edge (Bernoulli between its end areas, a Borda-Carnot loss
// on expansion, and a loss coefficient k_e):
//   B_e(q) = c_e^+ q^2 (q >= 0),  -c_e^- q^2 (q < 0),  c^+ = rho/2 (1/A_to^2 - 1/A_from^2)
//            + rho/2 max(0, 1/A_from - 1/A_to)^2 + k_e, and c^- the same with from <-> to;
// the bracketed term couples an edge to another's flow q_c at a junction: the head of the
// flow arriving there carried onward (h_e), NetworkEdge.
// A coupling is a compliant membrane between two nodes (the flap between the lumina): volume
// that one node gains the other loses. An outlet without a capacitor is a resistance
// R_p + R_d to P_ref.
//
// Time: BDF2 (the first step backward Euler) with Newton on the dense Jacobian; the network
// is small (tens of unknowns), and the factorization is kept over iterations and steps while
// the iteration contracts by 10 per iteration (a chord method). BDF2 also handles rigid networks
// (no node compliance), where the node pressures are algebraic. Cycles repeat until the state at
// the cycle's start changes by less than the tolerances.
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::rom {

struct NetworkNode {
  std::string name;
  double compliance = 0.0; ///< C_i to the outside [m^3/Pa]
};

struct NetworkEdge {
  std::string name;
  int from = 0, to = 0;
  double resistance = 0.0; ///< R [Pa s/m^3]
  double inertance = 0.0;  ///< L [Pa s^2/m^3]
  double loss = 0.0;       ///< k, added to both directions' coefficient [Pa s^2/m^6]
  /// End areas for the Bernoulli and expansion terms [m^2]; 0: no convective term.
  double area_from = 0.0, area_to = 0.0;
  /// A junction's carried head: the kinetic head rho/2 (q_c / A_j)^2 of the flow q_c that
  /// arrives at the junction on edge `regain_edge` is what this edge's flow q starts from, not
  /// its own head in the junction's channel: adds -h (q_c^2 - q^2), h = rho / (2 A_j^2), with
  /// `area_from` = A_j, so that the edge's Bernoulli term runs from the arriving velocity to
  /// its own exit velocity. At a dividing junction (q < q_c) the static pressure rises as the
  /// flow slows (a regain); at a combining one (q > q_c) the combined flow's acceleration
  /// draws on the arriving flow's head only.
  /// Even in both flows, as Bernoulli's term is: a backflow that leaves the junction on the
  /// approach edge finds the same static pressure there. None when `regain_edge` < 0.
  /// [Pa s^2/m^6]
  int regain_edge = -1;
  double regain = 0.0;
};

struct NetworkCoupling {
  int a = 0, b = 0;
  double compliance = 0.0; ///< C_ab [m^3/Pa]
};

struct NetworkOutlet {
  std::string name;
  int node = 0;
  bc::WindkesselRCR rcr;
};

/// The convective coefficients (c^+, c^-) of an edge for density rho (file comment).
struct Convection {
  double forward = 0.0, backward = 0.0;
};
Convection convection(const NetworkEdge& edge, double density);

/// The periodic state, sampled: per sample time the node pressures, edge flows and outlet
/// flows of the last cycle.
struct NetworkSolution {
  std::vector<double> time;                                 ///< [s], the last cycle
  std::vector<std::vector<double>> pressure, flow, outflow; ///< [sample][node|edge|outlet]
  int cycles = 0;                                           ///< cycles integrated
  double last_change = 0.0;  ///< largest pressure change between the last two cycle starts [Pa]
  int newton_iterations = 0; ///< in all
  int factorizations = 0;    ///< of the Jacobian, in all (it is kept while it contracts)
};

struct IntegrationOptions {
  int steps_per_cycle = 400;
  int samples_per_cycle = 100; ///< must divide steps_per_cycle
  int max_cycles = 30;
  double pressure_tolerance = 1.0; ///< [Pa] change of any pressure between cycle starts
  double newton_tolerance = 1e-9;  ///< relative to the equations' scales
};

class LumpedNetwork {
public:
  /// Checks indices, non-negative parameters, an outlet capacitor with a distal resistance,
  /// a positive inflow period; InputError otherwise.
  LumpedNetwork(std::vector<NetworkNode> nodes, std::vector<NetworkEdge> edges,
                std::vector<NetworkCoupling> couplings, std::vector<NetworkOutlet> outlets,
                int inflow_node, bc::Waveform inflow, double density);

  const std::vector<NetworkNode>& nodes() const { return nodes_; }
  const std::vector<NetworkEdge>& edges() const { return edges_; }
  const std::vector<NetworkOutlet>& outlets() const { return outlets_; }
  int node(const std::string& name) const; ///< -1 if none
  int edge(const std::string& name) const; ///< -1 if none
  double period() const { return inflow_.period(); }

  /// Integrates from every node at `start_pressure` and the outlets' capacitors at
  /// `start_distal` (one per outlet; the 0D periodic state of the outlets is a good start)
  /// until periodic. SolverError when Newton fails or the cycles run out.
  NetworkSolution periodic(double start_pressure, const std::vector<double>& start_distal,
                           const IntegrationOptions& options = {}) const;

private:
  struct Work;
  int num_unknowns() const;
  std::vector<NetworkNode> nodes_;
  std::vector<NetworkEdge> edges_;
  std::vector<NetworkCoupling> couplings_;
  std::vector<NetworkOutlet> outlets_;
  std::vector<int> capacitor_; ///< per outlet, its P_d's unknown, -1 without a capacitor
  std::vector<Convection> convection_;
  int inflow_node_ = 0;
  bc::Waveform inflow_;
  double density_ = 0.0;
};

} // namespace tearflow::rom
