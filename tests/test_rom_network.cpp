// The lumped network of the reduced-order model (rom/lumped_network.hpp) against exact
// answers: the steady state of resistances, orifices and Bernoulli terms; the periodic state of
// a linear network against the outlets' exact frequency-domain solution
// (bc/windkessel_network.hpp), with BDF2's second-order rate; an inertance's pressure; the
// flap coupling's volume exchange.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "bc/windkessel_network.hpp"
#include "core/error.hpp"
#include "rom/lumped_network.hpp"

using namespace tearflow;
using namespace tearflow::rom;

namespace {

const double kRho = 1100.0;

bc::Waveform pulsatile(double mean, double amplitude) {
  std::vector<double> t, q;
  for (int k = 0; k < 200; ++k) {
    const double s = 2.0 * std::numbers::pi * k / 200.0;
    t.push_back(k / 200.0);
    q.push_back(mean + amplitude * std::sin(s) + 0.3 * amplitude * std::cos(2 * s));
  }
  return bc::Waveform::periodic(t, q, 1.0, "test");
}

/// A constant inflow as a (trivially) periodic waveform.
bc::Waveform steady(double q) {
  return bc::Waveform::periodic({0.0, 0.25, 0.5, 0.75}, {q, q, q, q}, 1.0, "test");
}

} // namespace

TEST(RomNetwork, SteadyOrificeAndBernoulliAreExact) {
  // Inflow Q through an edge with R, loss k and areas A1 -> A2 (an expansion) into a
  // resistance outlet R_o: p_in = R_o Q + R Q + (rho/2 (1/A2^2 - 1/A1^2)
  // + rho/2 (1/A1 - 1/A2)^2 + k) Q^2. Steady, so exact up to Newton's tolerance.
  const double q = 1e-4, r = 1e6, k = 3e9, a1 = 1e-4, a2 = 4e-4, ro = 1e8;
  NetworkEdge e{"e", 0, 1, r, 1e4, k, a1, a2};
  const LumpedNetwork net({{"in", 0.0}, {"out", 0.0}}, {e}, {}, {{"o", 1, {ro, 0.0, 0.0, 0.0}}}, 0,
                          steady(q), kRho);
  const NetworkSolution s = net.periodic(0.0, {0.0}, {40, 4, 30, 1e-6, 1e-12});
  const double c =
      0.5 * kRho * (1 / (a2 * a2) - 1 / (a1 * a1)) + 0.5 * kRho * std::pow(1 / a1 - 1 / a2, 2) + k;
  const double expected = ro * q + r * q + c * q * q;
  EXPECT_NEAR(s.pressure.back()[0], expected, 1e-9 * expected);
  EXPECT_NEAR(s.flow.back()[0], q, 1e-12 * q);
  // Reversed flow (outflow at the inlet) takes the other direction's coefficient.
  const LumpedNetwork back({{"in", 0.0}, {"out", 0.0}}, {e}, {}, {{"o", 1, {ro, 0.0, 0.0, 0.0}}}, 0,
                           steady(-q), kRho);
  const NetworkSolution b = back.periodic(0.0, {0.0}, {40, 4, 30, 1e-6, 1e-12});
  const double c_back = 0.5 * kRho * (1 / (a1 * a1) - 1 / (a2 * a2)) + k; // a contraction
  const double expected_back = -(ro * q + r * q + c_back * q * q);
  EXPECT_NEAR(b.pressure.back()[0], expected_back, 1e-9 * std::abs(expected_back));
}

TEST(RomNetwork, JunctionRegainCarriesTotalPressureOnward) {
  // The through-flow Q arrives on edge 0 (areas A_0 -> A_j) at a junction (node 1) and
  // divides into a side branch (edge 1, an orifice) and a lumen onward (edge 2, resistance r,
  // areas A_j -> A_2, the junction's regain of Q's head). Steady, inviscid apart from r: the
  // total pressure p + rho/2 v^2 carried from the junction (v = Q / A_j) to the lumen's end
  // (v = q / A_2) falls by r q only, to Newton's tolerance; backward, the lumen's flow expands
  // from A_2 into A_j and loses Borda-Carnot's rho/2 (1/A_2 - 1/A_j)^2 q^2 besides; without the
  // regain the lumen's own Bernoulli term would take its own flow's head at A_j instead,
  // off by rho/2 (Q^2 - q^2) / A_j^2 (tens of % of the drop here).
  const double q = 2e-4, r = 4e6, a0 = 4e-4, aj = 2.5e-4, a2 = 2e-4;
  NetworkEdge through{"through", 0, 1, 1e5, 0.0, 0.0, a0, aj},
      branch{"branch", 1, 2, 0.0, 0.0, 2e9}, lumen{"lumen", 1, 3, r, 0.0, 0.0, aj, a2};
  lumen.regain_edge = 0, lumen.regain = 0.5 * kRho / (aj * aj);
  for (const double sign : {1.0, -1.0}) {
    const LumpedNetwork net({{"in", 0.0}, {"j", 0.0}, {"b", 0.0}, {"l", 0.0}},
                            {through, branch, lumen}, {},
                            {{"ob", 2, {3e7, 0.0, 0.0, 0.0}}, {"ol", 3, {3e7, 0.0, 0.0, 0.0}}}, 0,
                            steady(sign * q), kRho);
    const NetworkSolution s = net.periodic(0.0, {0.0, 0.0}, {40, 4, 30, 1e-6, 1e-12});
    const std::vector<double>&p = s.pressure.back(), &f = s.flow.back();
    const double total_j = p[1] + 0.5 * kRho * f[0] * f[0] / (aj * aj);
    const double total_2 = p[3] + 0.5 * kRho * f[2] * f[2] / (a2 * a2);
    const double borda = f[2] < 0.0 ? 0.5 * kRho * std::pow(1 / a2 - 1 / aj, 2) * f[2] * f[2] : 0.0;
    EXPECT_NEAR(total_j - total_2, r * f[2] - borda, 1e-9 * std::abs(p[1])) << "direction " << sign;
    EXPECT_NEAR(f[1] + f[2], f[0], 1e-12 * q);
    EXPECT_GT(std::abs(f[2]), 0.2 * q); // the lumen carries a real share ...
    EXPECT_GT(std::abs(f[1]), 0.2 * q); // ... and so does the branch
  }
}

TEST(RomNetwork, LinearNetworkConvergesToTheExactPeriodicStateAtSecondOrder) {
  // A series resistance into two RCR outlets: the exact periodic state is the frequency-
  // domain solution of bc::WindkesselNetwork. BDF2's error is O(dt^2): halving dt divides it
  // by about 4 (3 to 5 allowed: the error constant also shifts with dt at these step counts).
  const bc::WindkesselRCR a{2e7, 1.5e-9, 2e8, 0.0}, b{1e7, 3e-9, 1e8, 500.0};
  const double rs = 3e6;
  const bc::Waveform q = pulsatile(8e-5, 6e-5);
  const bc::PeriodicState exact = bc::WindkesselNetwork({{"a", a}, {"b", b}}, rs).periodic(q, 128);
  std::vector<double> errors;
  for (int steps : {100, 200, 400}) {
    const LumpedNetwork net({{"in", 0.0}, {"node", 0.0}}, {{"s", 0, 1, rs}}, {},
                            {{"a", 1, a}, {"b", 1, b}}, 0, q, kRho);
    IntegrationOptions opt;
    opt.steps_per_cycle = steps, opt.samples_per_cycle = 100, opt.pressure_tolerance = 1e-3;
    const NetworkSolution s =
        net.periodic(exact.node_pressure(0.0),
                     {exact.distal_pressure(0, 0.0), exact.distal_pressure(1, 0.0)}, opt);
    double err = 0.0, scale = 0.0;
    for (size_t f = 0; f < s.time.size(); ++f) {
      err = std::max(err, std::abs(s.pressure[f][0] - exact.inlet_pressure(s.time[f])));
      scale = std::max(scale, std::abs(exact.inlet_pressure(s.time[f])));
      EXPECT_NEAR(s.outflow[f][0], exact.branch_flow(0, s.time[f]), 0.02 * 8e-5);
    }
    errors.push_back(err / scale);
  }
  EXPECT_LT(errors.back(), 1e-3); // 400 steps per cycle: well under 0.1 %
  for (size_t k = 1; k < errors.size(); ++k) {
    const double rate = std::log2(errors[k - 1] / errors[k]);
    EXPECT_GT(rate, 1.6) << "dt halving " << k;
    EXPECT_LT(rate, 2.4) << "dt halving " << k;
  }
}

TEST(RomNetwork, InertanceAddsLTimesTheFlowsRate) {
  // Inflow Q(t) through an RL edge into a resistance: p_in(t) = (R + R_o) Q + L dQ/dt, the
  // edge's flow being the inflow (no compliance). BDF2 at 1000 steps: a 1e-4 relative error
  // of the inertial part is (2 pi dt)^2 / 3 ~ 1.3e-5 times its size, so 1e-3 of the peak.
  const double r = 2e6, l = 5e5, ro = 1e8;
  const bc::Waveform q = pulsatile(8e-5, 6e-5);
  const LumpedNetwork net({{"in", 0.0}, {"out", 0.0}}, {{"e", 0, 1, r, l}}, {},
                          {{"o", 1, {ro, 0.0, 0.0, 0.0}}}, 0, q, kRho);
  IntegrationOptions opt;
  opt.steps_per_cycle = 1000, opt.samples_per_cycle = 100;
  const NetworkSolution s = net.periodic(0.0, {0.0}, opt);
  const double h = 1e-5;
  for (size_t f = 0; f < s.time.size(); ++f) {
    const double t = s.time[f];
    const double dq = (q(t + h) - q(t - h)) / (2 * h);
    const double expected = (r + ro) * q(t) + l * dq;
    EXPECT_NEAR(s.pressure[f][0], expected, 1e-3 * (ro * 1.4e-4)) << "t " << t;
  }
}

TEST(RomNetwork, FlapCouplingExchangesVolumeBetweenItsNodes) {
  // Two nodes joined by an edge and a coupling C; the second drains through an outlet. The
  // volume a coupling takes from one node is what the other gains: with no compliance to the
  // outside, the inflow is the outflow at every instant, so the flow into the second node
  // through the edge minus its outflow equals -C d(p_a - p_b)/dt on the second node's side.
  const double c = 2e-9, ro = 1e8, r = 5e6;
  const bc::Waveform q = pulsatile(8e-5, 6e-5);
  const LumpedNetwork net({{"a", 0.0}, {"b", 0.0}}, {{"e", 0, 1, r, 1e3}}, {{0, 1, c}},
                          {{"o", 1, {ro, 0.0, 0.0, 0.0}}}, 0, q, kRho);
  IntegrationOptions opt;
  opt.steps_per_cycle = 1000, opt.samples_per_cycle = 1000;
  const NetworkSolution s = net.periodic(0.0, {0.0}, opt);
  for (size_t f = 1; f + 1 < s.time.size(); f += 50) {
    EXPECT_NEAR(s.outflow[f][0], q(s.time[f]), 1e-6 * 1.4e-4); // no volume kept
    const double dt = s.time[f + 1] - s.time[f - 1];
    const double rate = ((s.pressure[f + 1][0] - s.pressure[f + 1][1]) -
                         (s.pressure[f - 1][0] - s.pressure[f - 1][1])) /
                        dt;
    // Node a: inflow = edge flow + C d(pa - pb)/dt (centred difference: O(dt^2) ~ 4e-6 rel.)
    EXPECT_NEAR(q(s.time[f]) - s.flow[f][0], c * rate, 1e-3 * c * 1e5) << "t " << s.time[f];
  }
}

TEST(RomNetwork, BadNetworksAreClearErrors) {
  const bc::Waveform q = pulsatile(8e-5, 6e-5);
  EXPECT_THROW(LumpedNetwork({{"a", 0.0}}, {{"e", 0, 3, 1.0}}, {}, {}, 0, q, kRho), InputError);
  EXPECT_THROW(LumpedNetwork({{"a", -1.0}}, {}, {}, {}, 0, q, kRho), InputError);
  EXPECT_THROW(LumpedNetwork({{"a", 0.0}, {"b", 0.0}}, {{"e", 0, 1, -1.0}}, {}, {}, 0, q, kRho),
               InputError);
  EXPECT_THROW(LumpedNetwork({{"a", 0.0}}, {}, {}, {{"o", 0, {1e7, 1e-9, 0.0, 0.0}}}, 0, q, kRho),
               InputError); // a capacitor without distal resistance
  EXPECT_THROW(LumpedNetwork({{"a", 0.0}}, {}, {}, {}, 0, bc::Waveform::constant(1.0), kRho),
               InputError); // no period
  NetworkEdge regained{"c", 0, 1, 1.0};
  regained.regain_edge = 5, regained.regain = 1.0; // no edge 5
  EXPECT_THROW(LumpedNetwork({{"a", 0.0}, {"b", 0.0}}, {regained}, {}, {}, 0, q, kRho), InputError);
  try {
    LumpedNetwork({{"a", 0.0}, {"b", 0.0}}, {{"e", 0, 1, std::nan("")}}, {}, {}, 0, q, kRho);
    FAIL() << "a NaN resistance was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("edge e"), std::string::npos) << e.what();
  }
}
