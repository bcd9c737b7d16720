// The 0D outlet models: the RCR step law, the network's exact periodic state and its
// trapezoidal integration, and the per-cycle statistics.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "bc/outlet.hpp"
#include "bc/windkessel_network.hpp"
#include "core/error.hpp"
#include "run/cycle_summary.hpp"

using namespace tearflow;

namespace {

const bc::WindkesselRCR kRcr{2e7, 1.5e-9, 2e8, 500.0}; // R_d C = 0.3 s

bc::Waveform inflow() {
  std::vector<double> t, q;
  for (int k = 0; k < 100; ++k) {
    const double s = 2.0 * std::numbers::pi * k / 100.0;
    t.push_back(k / 100.0);
    q.push_back(5e-6 * (1.0 - std::cos(s)) * (1.0 + 0.5 * std::sin(s)));
  }
  return bc::Waveform::periodic(t, q, 1.0, "test");
}

} // namespace

TEST(Windkessel, StepLawIsTheTrapezoidalRuleAtAlphaF) {
  // The law P_af = p0 + r Q_af must equal P_d interpolated to t_af plus R_p Q_af, with P_d
  // advanced by the trapezoidal rule, for any end-of-step flux.
  const double pd_n = 900.0, q_n = 3e-6, dt = 0.01, af = 2.0 / 3.0;
  const bc::StepLaw law = bc::rcr_law(kRcr, pd_n, q_n, dt, af);
  for (double q_next : {0.0, 4e-6, -2e-6}) {
    const double pd_next = bc::distal_update(kRcr, pd_n, q_n, dt)(q_next);
    // The update satisfies the discrete ODE exactly.
    const double lhs = kRcr.capacitance * (pd_next - pd_n) / dt;
    const double rhs = 0.5 * (q_n + q_next) -
                       (0.5 * (pd_n + pd_next) - kRcr.reference_pressure) / kRcr.distal_resistance;
    EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(q_n));
    const double q_af = q_n + af * (q_next - q_n);
    const double expected = pd_n + af * (pd_next - pd_n) + kRcr.proximal_resistance * q_af;
    EXPECT_NEAR(law.p0 + law.resistance * q_af, expected, 1e-9 * expected);
  }
}

// --- the outlet laws through bc/outlet.hpp -------------------------------------------------

const bc::RcOutlet kRc{2.2e8, 1.5e-9, 500.0, {}}; // R C = 0.33 s

/// P(t) of the RC outlet under a constant outflow Q from P(0) = p0, stepped by the law's own
/// commit: n steps of dt.
double rc_pressure_after(double p0, double q, double dt, int n) {
  bc::RcOutlet law = kRc;
  law.initial_pressure = p0;
  bc::OutletState s = bc::initial_state(law);
  for (int k = 0; k < n; ++k)
    s = bc::commit(law, s, q, q, dt);
  return *bc::distal_pressure(law, s);
}

TEST(OutletLaws, RcStepLawIsTheTrapezoidalRuleAtAlphaF) {
  const double p_n = 9000.0, q_n = 3e-6, dt = 0.01, af = 2.0 / 3.0;
  const bc::OutletState s = bc::RcOutlet::State{p_n};
  const bc::StepLaw law = bc::step_law(kRc, s, q_n, {0.3, dt, af});
  for (double q_next : {0.0, 4e-6, -2e-6}) {
    const double p_next = *bc::distal_pressure(kRc, bc::commit(kRc, s, q_n, q_next, dt));
    // C dP/dt = Q - (P - P_ref)/R by the trapezoidal rule, to round-off.
    const double lhs = kRc.capacitance * (p_next - p_n) / dt;
    const double rhs =
        0.5 * (q_n + q_next) - (0.5 * (p_n + p_next) - kRc.reference_pressure) / kRc.resistance;
    EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(q_n));
    // No proximal resistance: the outlet pressure at t_af is P interpolated there.
    const double q_af = q_n + af * (q_next - q_n);
    EXPECT_NEAR(law.p0 + law.resistance * q_af, p_n + af * (p_next - p_n), 1e-9 * p_n);
  }
}

TEST(OutletLaws, RcRelaxesToItsExactSolutionAtSecondOrder) {
  // Constant Q from P(0) = p0: P(t) = P_inf + (p0 - P_inf) exp(-t / RC), P_inf = P_ref + R Q.
  const double q = 5e-6, p0 = 2000.0, t = 0.5, tau = kRc.resistance * kRc.capacitance;
  const double p_inf = kRc.reference_pressure + kRc.resistance * q;
  const double exact = p_inf + (p0 - p_inf) * std::exp(-t / tau);
  const double e1 = std::abs(rc_pressure_after(p0, q, 1e-2, 50) - exact);
  const double e2 = std::abs(rc_pressure_after(p0, q, 5e-3, 100) - exact);
  // The trapezoidal rule's global error on this linear ODE is about
  // t dt^2 / (12 tau^3) |p0 - P_inf| exp(-t/tau): 3 % of that margin at dt = 10 ms.
  const double bound =
      t * 1e-4 / (12 * tau * tau * tau) * std::abs(p0 - p_inf) * std::exp(-t / tau);
  EXPECT_LT(e1, 1.5 * bound);
  EXPECT_GT(e1, 0.5 * bound);     // the estimate is the error's leading term, not a loose bound
  EXPECT_NEAR(e1 / e2, 4.0, 0.1); // second order
}

TEST(OutletLaws, CheckpointRecordRoundTrips) {
  const std::vector<std::pair<bc::OutletLaw, bc::OutletState>> cases = {
      {bc::PressureOutlet{}, bc::initial_state(bc::PressureOutlet{})},
      {bc::ResistanceOutlet{1e8, 0.0}, bc::initial_state(bc::ResistanceOutlet{1e8, 0.0})},
      {bc::RcrOutlet{kRcr, {}}, bc::RcrOutlet::State{1234.5}},
      {kRc, bc::RcOutlet::State{6789.25}}};
  for (const auto& [law, state] : cases) {
    std::vector<double> record;
    bc::append_record(law, state, record);
    ASSERT_EQ(record.size(), bc::record_size(law)) << bc::describe(law);
    const bc::OutletState back = bc::restore(law, record);
    EXPECT_EQ(back.index(), state.index());
    EXPECT_EQ(bc::distal_pressure(law, back), bc::distal_pressure(law, state)) << bc::describe(law);
  }
  EXPECT_EQ(bc::record_size(bc::PressureOutlet{}), 0u);
  EXPECT_EQ(bc::record_size(kRc), 1u);
}

TEST(OutletLaws, ZeroDBranchAndStart) {
  EXPECT_FALSE(bc::zero_d_branch(bc::PressureOutlet{})); // it sets the pressure
  const bc::WindkesselRCR r = *bc::zero_d_branch(bc::ResistanceOutlet{1e8, 300.0});
  EXPECT_EQ(r.capacitance, 0.0);
  EXPECT_EQ(r.proximal_resistance, 1e8);
  EXPECT_EQ(r.reference_pressure, 300.0);
  const bc::WindkesselRCR rc = *bc::zero_d_branch(kRc);
  EXPECT_EQ(rc.proximal_resistance, 0.0);
  EXPECT_EQ(rc.distal_resistance, kRc.resistance);
  EXPECT_EQ(rc.capacitance, kRc.capacitance);
  // The 0D start sets a law's state unless the case gave it.
  EXPECT_EQ(bc::distal_pressure(kRc, *bc::start_state(kRc, 7000.0)), 7000.0);
  bc::RcOutlet given = kRc;
  given.initial_pressure = 100.0;
  EXPECT_FALSE(bc::start_state(given, 7000.0));
  EXPECT_FALSE(bc::start_state(bc::ResistanceOutlet{1e8, 0.0}, 7000.0)); // no state
  EXPECT_FALSE(bc::coupled(bc::PressureOutlet{}));
  EXPECT_TRUE(bc::coupled(kRc));
}

TEST(WindkesselNetwork, PeriodicStateSolvesTheOde) {
  const bc::WindkesselNetwork net({{"out", kRcr}});
  const bc::PeriodicState s = net.periodic(inflow());
  // C dP_d/dt = Q - (P_d - P_ref)/R_d and P = P_d + R_p Q at several times; the derivative
  // by a central difference with h = 1e-5 s (error ~ h^2 |P_d'''| / 6, far below 1e-6 of Q).
  for (double t : {0.05, 0.3, 0.61, 0.9}) {
    const double h = 1e-5;
    const double dpd = (s.distal_pressure(0, t + h) - s.distal_pressure(0, t - h)) / (2 * h);
    const double q = s.branch_flow(0, t);
    EXPECT_NEAR(kRcr.capacitance * dpd,
                q - (s.distal_pressure(0, t) - kRcr.reference_pressure) / kRcr.distal_resistance,
                1e-6 * 5e-6);
    EXPECT_NEAR(s.node_pressure(t), s.distal_pressure(0, t) + kRcr.proximal_resistance * q, 1e-6);
    // One branch takes all the flow, up to the truncation of the Fourier series at 128
    // harmonics: a C2 spline's coefficients decay like n^-4, so the tail is ~128^-3 ~ 5e-7.
    EXPECT_NEAR(q, inflow()(t), 1e-6 * 5e-6);
  }
  // Periodic: the state repeats.
  EXPECT_NEAR(s.distal_pressure(0, 0.2), s.distal_pressure(0, 1.2), 1e-9);
}

TEST(WindkesselNetwork, ParallelBranchesSplitTheMeanFlowByResistance) {
  bc::WindkesselRCR a = kRcr, b = kRcr;
  a.reference_pressure = b.reference_pressure = 0.0;
  b.proximal_resistance *= 3.0;
  b.distal_resistance *= 3.0;
  const bc::PeriodicState s = bc::WindkesselNetwork({{"a", a}, {"b", b}}).periodic(inflow());
  EXPECT_NEAR(s.mean_branch_flow(0) / (s.mean_branch_flow(0) + s.mean_branch_flow(1)), 0.75, 1e-12);
  for (double t : {0.1, 0.5})
    EXPECT_NEAR(s.branch_flow(0, t) + s.branch_flow(1, t), inflow()(t), 1e-6 * 5e-6); // as above
}

TEST(WindkesselNetwork, TrapezoidalIntegrationConvergesAtSecondOrder) {
  const bc::WindkesselNetwork net({{"out", kRcr}});
  const bc::Waveform q = inflow();
  const bc::PeriodicState exact = net.periodic(q);
  // Start on the periodic state and integrate one cycle: the error at its end halves twice
  // per halving of dt if the scheme is second order.
  std::vector<double> errors;
  for (int steps : {50, 100, 200}) {
    const bc::NetworkHistory h =
        net.integrate(q, 0.0, 1.0 / steps, steps, {exact.distal_pressure(0, 0.0)});
    double e = 0.0;
    for (size_t k = 0; k < h.time.size(); ++k)
      e = std::max(e, std::abs(h.distal_pressure[0][k] - exact.distal_pressure(0, h.time[k])));
    errors.push_back(e);
  }
  for (size_t i = 1; i < errors.size(); ++i) {
    const double rate = std::log2(errors[i - 1] / errors[i]);
    EXPECT_GT(rate, 1.8) << "errors " << errors[i - 1] << " -> " << errors[i];
  }
}

TEST(WindkesselNetwork, RejectsBadBranches) {
  bc::WindkesselRCR bad = kRcr;
  bad.distal_resistance = 0.0;
  EXPECT_THROW(bc::WindkesselNetwork({{"x", bad}}), InputError);
  bad = kRcr;
  bad.capacitance = -1.0;
  EXPECT_THROW(bc::WindkesselNetwork({{"x", bad}}), InputError);
  EXPECT_THROW(bc::WindkesselNetwork({}), InputError);
}

TEST(CycleSummary, StatisticsOfAKnownCycle) {
  // P = 100 + 20 sin(2 pi t), Q_a = 2 (1 + sin), Q_b = 1 + sin over one cycle of 400 steps.
  run::CycleSamples c;
  c.faces = {{"a", true, {}, {}, {}}, {"b", true, {}, {}, {}}, {"inlet", false, {}, {}, {}}};
  const int n = 400;
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n, s = std::sin(2 * std::numbers::pi * t);
    c.time.push_back(t);
    c.faces[0].flow.push_back(2.0 * (1.0 + s));
    c.faces[1].flow.push_back(1.0 + s);
    c.faces[2].flow.push_back(-3.0 * (1.0 + s));
    for (auto& f : c.faces) {
      f.pressure.push_back(100.0 + 20.0 * s);
      f.reversed.push_back(0.0);
    }
  }
  const run::CycleStats st = run::summarize_cycle(c);
  // The trapezoidal rule integrates a full period of a sinusoid exactly; the sampled maximum
  // is within 20 (1 - cos(pi / n)) ~ 6e-4 of the true one at n = 400.
  EXPECT_NEAR(st.faces[0].mean, 100.0, 1e-9);
  EXPECT_NEAR(st.faces[0].systolic, 120.0, 1e-3);
  EXPECT_NEAR(st.faces[0].diastolic, 80.0, 1e-3);
  EXPECT_NEAR(st.faces[0].volume, 2.0, 1e-9);
  EXPECT_NEAR(*st.faces[0].split_percent, 200.0 / 3.0, 1e-9);
  EXPECT_NEAR(*st.faces[1].split_percent, 100.0 / 3.0, 1e-9);
  EXPECT_FALSE(st.faces[2].split_percent.has_value());

  // A 1 % larger pressure in the next cycle is a change of 1 / 1.2 % of its peak.
  run::CycleSamples next = c;
  for (auto& f : next.faces)
    for (double& p : f.pressure)
      p *= 1.01;
  EXPECT_NEAR(run::cycle_change(c, next), 0.01 * 120.0 / (1.01 * 120.0), 1e-3 * 0.01);
  EXPECT_EQ(run::cycle_change(c, c), 0.0);

  // By the cycle's numbers: the inlet's pressures 1 % larger (each of systolic, diastolic
  // and mean: a change of 0.01 / 1.01); then outlet a's flow 10 % larger, which moves its
  // split from 66.67 % to 68.75 % (2.08 points: 0.0208) and outweighs the pressures.
  const run::CycleStats pressures = run::summarize_cycle(next);
  EXPECT_NEAR(run::metrics_change(st, pressures), 0.01 / 1.01, 1e-9);
  run::CycleSamples more = c;
  for (double& q : more.faces[0].flow)
    q *= 1.1;
  EXPECT_NEAR(run::metrics_change(st, run::summarize_cycle(more)), (2.2 / 3.2 - 2.0 / 3.0), 1e-9);
  EXPECT_EQ(run::metrics_change(st, st), 0.0);
}
