// A rigid pipe closed by one Windkessel outlet (../shared/reference/verification.md): once
// periodic, the outlet pressure must follow the outlet law's ODE, for the RCR
//   C dP_d/dt = Q - (P_d - P_ref)/R_d,  P = P_d + R_p Q,
// and for the two-element RC (`verify rc`, bc/outlet_rc.hpp) the same with R_p = 0,
// driven by the outlet flux Q, which in a rigid pipe is the inflow Q_in(t). The exact
// periodic solution comes from the frequency domain (bc/windkessel_network.hpp) through the
// law's own 0D branch. The 3D run starts from the 0D periodic state, so its second cycle is
// compared sample by sample.
//
// Time collocation: generalized-alpha balances momentum at t_{n+alpha_f}, where the outlet
// traction is P(t_{n+alpha_f}); the pressure unknown of step n+1 is the multiplier of that
// balance. The pressure a run reports (faces.csv, frames) is that stage value extrapolated to
// t_{n+1} (run/flow_model.cpp), so it is compared with the exact P at t_{n+1}.
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "bc/windkessel_network.hpp"
#include "physics/generalized_alpha.hpp"
#include "run/simulation.hpp"
#include "verify/cases.hpp"
#include "verify/pulsatile_inflow.hpp"

namespace tearflow::verify {

namespace {

constexpr double R = 0.005, L = 0.03;      // pipe [m]
constexpr double rho = 1060.0, mu = 0.004; // blood-like
constexpr double T = 1.0, dt = 0.01;       // period and step [s]
constexpr double Q_mean = 5e-6;            // [m^3/s]; peak Re ~ 500
constexpr int kCycles = 2;
const bc::WindkesselRCR kRcr{2e7, 1.5e-9, 2e8, 0.0}; // R_d C = 0.3 s
/// The RC: the RCR's total resistance and capacitance, R C = 0.33 s.
const bc::RcOutlet kRc{2.2e8, 1.5e-9, 0.0, {}};

io::Case outlet_case(const std::string& name, double element_size, const bc::OutletLaw& law) {
  io::Case c;
  c.name = "verify-" + name;
  c.mesh.pipe = mesh::PipeSpec{R, L, element_size};
  c.fluid = {rho, mu};
  c.time.step = dt;
  c.time.period = T;
  c.time.steps_per_cycle = static_cast<int>(std::round(T / dt));
  c.time.steps = kCycles * c.time.steps_per_cycle;
  c.time.spectral_radius = 0.5;
  c.boundary_conditions = {{"wall", bc::NoSlip{}},
                           {"inlet", bc::Inflow{pulsatile_inflow(Q_mean, T)}},
                           {"outlet", bc::Outlet{law}}};
  c.newton = {10, 1e-6, 1e-14};
  return c;
}

VerificationResult verify_outlet(const VerifyOptions& options, const std::string& name,
                                 const bc::OutletLaw& law) {
  const double h = R / 5.0 * options.coarsening;
  run::Simulation sim(outlet_case(name, h, law));
  const double alpha_f =
      physics::GeneralizedAlpha::from_spectral_radius(sim.config().time.spectral_radius).alpha_f;
  const bc::WindkesselNetwork network({{"outlet", *bc::zero_d_branch(law)}});
  const bc::PeriodicState exact =
      network.periodic(sim.config().boundary_conditions[1].inflow()->flow);

  // Outlet samples of the last cycle.
  const int n = sim.config().time.steps_per_cycle, total = sim.config().time.steps;
  std::vector<double> t, p, q, pd;
  int newton = 0;
  for (int s = 0; s < total; ++s) {
    const physics::StepReport r = sim.advance();
    newton += r.newton_iterations;
    if (options.progress)
      fmt::print(stderr, "{}: step {}/{} Newton {} KSP {}\n", name, s + 1, total,
                 r.newton_iterations, r.linear_iterations);
    if (sim.step() <= total - n)
      continue;
    for (const run::FaceSample& f : sim.sample().faces)
      if (f.measure.face == "outlet") {
        t.push_back(sim.time());
        p.push_back(f.measure.pressure);
        q.push_back(f.measure.flow);
        pd.push_back(f.distal_pressure.value_or(NAN));
      }
  }

  double p_max = -1e300, p_min = 1e300;
  for (int k = 0; k < 1000; ++k) {
    const double pk = exact.node_pressure(T * k / 1000.0);
    p_max = std::max(p_max, pk);
    p_min = std::min(p_min, pk);
  }
  const double pulse = p_max - p_min;
  double err_af = 0.0, err_end = 0.0, err_distal = 0.0, err_flow = 0.0;
  nlohmann::json samples = nlohmann::json::array();
  for (size_t k = 0; k < t.size(); ++k) {
    const double t_af = t[k] - (1.0 - alpha_f) * dt;
    const double p_af = exact.node_pressure(t_af);
    err_af = worst_of(err_af, std::abs(p[k] - p_af));
    err_end = worst_of(err_end, std::abs(p[k] - exact.node_pressure(t[k])));
    err_distal = worst_of(err_distal, std::abs(pd[k] - exact.distal_pressure(0, t[k])));
    err_flow = worst_of(err_flow, std::abs(q[k] - exact.branch_flow(0, t[k])));
    if (k % 5 == 0)
      samples.push_back({{"t_s", t[k]},
                         {"outlet_pressure_Pa", p[k]},
                         {"exact_pressure_Pa", exact.node_pressure(t[k])},
                         {"distal_pressure_Pa", pd[k]},
                         {"exact_distal_pressure_Pa", exact.distal_pressure(0, t[k])}});
  }

  VerificationResult res;
  res.name = name;
  // Every step of the last cycle must be compared: an empty or short sample list would make
  // the maxima above vacuous.
  res.metrics.push_back({"outlet_sample_count_error",
                         std::abs(static_cast<double>(n) - static_cast<double>(t.size())), 0.0,
                         "|steps of the last cycle - outlet samples compared|; 0"});
  // The trapezoidal rule's phase error at the k-th harmonic is (k w dt)^2 / 12 ~ 0.1 % for
  // k = 2 at dt = T/100; the linear extrapolation from t_{n+af} to t_{n+1} adds
  // ((1-af) dt)^2 |P''| / 2 ~ 0.01 % of the pulse; the outlet's mean pressure differs from the
  // imposed traction by the viscous normal stress 2 mu du_n/dn, ~0 for the developed flow.
  // 1 % of the pulse pressure (the bound) leaves a wide margin for all three.
  res.metrics.push_back(
      {"outlet_pressure_error_over_pulse", err_end / pulse, 0.01,
       fmt::format("max over the last cycle's steps of |mean outlet p - exact {} P(t_{{n+1}})| / "
                   "pulse pressure; 1 %",
                   name)});
  res.metrics.push_back({"distal_pressure_error_over_pulse", err_distal / pulse, 0.01,
                         "max |P_d - exact P_d| / pulse pressure over the last cycle; 1 %"});
  res.details = {{"radius_m", R},
                 {"length_m", L},
                 {"element_size_m", h},
                 {"tets", sim.mesh().num_tets()},
                 {"time_step_s", dt},
                 {"alpha_f", alpha_f},
                 {"cycles", kCycles},
                 {"newton_iterations_per_step", static_cast<double>(newton) / total},
                 {"outlet_law", bc::describe(law)},
                 {"pulse_pressure_Pa", pulse},
                 {"error_if_compared_at_t_n_plus_af_over_pulse", err_af / pulse},
                 {"outlet_flow_max_error_m3_per_s", err_flow},
                 {"samples", samples}};
  return res;
}

} // namespace

VerificationResult verify_rcr(const VerifyOptions& options) {
  return verify_outlet(options, "rcr", bc::RcrOutlet{kRcr, {}});
}

VerificationResult verify_rc(const VerifyOptions& options) {
  return verify_outlet(options, "rc", kRc);
}

} // namespace tearflow::verify
