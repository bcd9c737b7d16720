// Solid dynamics cases (../shared/reference/verification.md):
//
// robin: a 1 cm column of the study's wall material in confined compression (rollers on
//   the sides) stands on the tissue support k_s = 18 MN/m^3 (the study's) at z = 0 and is
//   loaded by a step pressure p = 100 Pa on top at t = 0. It settles to
//     u_z(top) = -(p / k_s + p L / M),   M = kappa + 4 mu / 3 (constrained modulus),
//   exact for the small strain p / M ~ 6e-5. The column oscillates on the spring at
//   omega ~ sqrt(k / (rho L)) ~ 1060 rad/s; with the study's c_s = 30 kN s/m^3 (about
//   critical damping, 2 sqrt(k rho L) = 31 kN s/m^3) it settles within a few ms, with
//   c_s = 0 it keeps ringing (rho_inf = 0.5 damps only the unresolved modes). A third run
//   adds the support's ambient pressure p_0 = 250 Pa (sigma n = -k_s u - c_s du/dt - p_0 n):
//   on the bottom face sigma n = p e_z = -k_s u_b + p_0 e_z, so the column is lifted to
//     u_z(top) = (p_0 - p) / k_s - p L / M,
//   the stress in it unchanged (confined: the faces keep their area and normal, so the
//   follower p_0 is exact).
//
// energy: a 10 cm bar, nu = 0.45, clamped at x = 0 and otherwise free, released from the
//   reference configuration with the velocity of its first axial mode,
//   v_x = v_0 sin(pi x / (2 L)), v_0 = 0.3 m/s (strain amplitude ~1 %, so geometric and
//   material nonlinearity take part), for 10 periods T = 4 L / sqrt(E / rho) with
//   rho_inf = 1. The trapezoidal rule conserves the energy of a linear system; the stage
//   energy E = 1/2 v.M v + Pi(u, p) at t_{n+1/2} (where the equations hold and the
//   pressure is known) is conserved exactly per mode for linear problems, so its drift
//   measures the nonlinear midpoint error and any non-variational term. The same bar with
//   rho_inf = 0.5 must lose energy, as much as the scheme loses on the single mode
//   x'' + omega^2 x = 0 at omega dt = 2 pi / 40 (sdof_stage_energy_loss: the closed-form
//   parameters and Newmark updates, written here apart from the solver's).
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mesh/structured_generator.hpp"
#include "physics/solid_kernel.hpp"
#include "run/solid_simulation.hpp"
#include "verify/cases.hpp"
#include "verify/solid_setup.hpp"

namespace tearflow::verify {

namespace {

using physics::SolidMaterial;
using physics::SolidModel;

constexpr double E = 1.2e6, rho = 1450.0;

struct RobinRun {
  double final_displacement = 0.0; ///< mean u_z of the top face at the end [m]
  double settling_time = 0.0;      ///< after it, |u - u_inf| <= 1 % |u_inf| [s]
  double overshoot = 0.0;          ///< max |u| / |u_inf| - 1
  int steps = 0, newton_max = 0;
};

constexpr double robin_L = 0.01, robin_k = 18e6, robin_p = 100.0;

/// The column with support damping c_s and ambient pressure p_0; u_inf its settled top
/// displacement (for the settling time).
RobinRun run_robin(double damping, double p0, int cells, double dt, double t_end, double u_inf,
                   bool progress) {
  io::SolidSpec spec;
  spec.material = SolidMaterial::from_young_poisson(SolidModel::NeoHookean, E, 0.3, rho);
  spec.conditions.fixed = {{"x0", 0b001, {}, 0.0},
                           {"x1", 0b001, {}, 0.0},
                           {"y0", 0b010, {}, 0.0},
                           {"y1", 0b010, {}, 0.0}};
  spec.conditions.loads = {{"z1", bc::Waveform::constant(robin_p)}};
  spec.conditions.supports = {{"z0", robin_k, damping, p0}};
  const int steps = static_cast<int>(std::lround(t_end / dt));
  const double w = robin_L / 2.0;
  run::SolidSimulation sim(solid_case("verify-robin", spec, dt, steps, 0.5, robin_p * w * w),
                           mesh::make_box({w, w, robin_L}, {1, 1, cells}));
  RobinRun out;
  out.steps = steps;
  for (int s = 0; s < steps; ++s) {
    const auto r = sim.advance();
    out.newton_max = std::max(out.newton_max, r.newton_iterations);
    double u = 0.0;
    for (const auto& f : sim.problem().measure_faces(sim.solver().displacement()))
      if (f.face == "z1")
        u = f.displacement[2];
    if (std::abs(u - u_inf) > 0.01 * std::abs(u_inf))
      out.settling_time = sim.time();
    out.overshoot = std::max(out.overshoot, std::abs(u / u_inf) - 1.0);
    out.final_displacement = u;
    if (progress && (s + 1) % 50 == 0)
      fmt::print(stderr, "robin c_s = {}, p_0 = {}: step {} u = {:.4e} Newton {} KSP {}\n", damping,
                 p0, s + 1, u, r.newton_iterations, r.linear_iterations);
  }
  return out;
}

struct EnergyRun {
  double worst_drift = 0.0, final_drift = 0.0, initial = 0.0;
  double final_signed = 0.0; ///< (E(end) - E(0)) / E(0)
  int steps = 0, tets = 0;
  double period = 0.0;
};

EnergyRun run_energy(int cells, int steps_per_period, double rho_inf, bool progress) {
  constexpr double L = 0.1, w = 0.01, v0 = 0.3;
  constexpr int periods = 10;
  io::SolidSpec spec;
  spec.material = SolidMaterial::from_young_poisson(SolidModel::NeoHookean, E, 0.45, rho);
  spec.conditions.fixed = {{"x0", 0b111, {}, 0.0}};
  const double period = 4.0 * L / std::sqrt(E / rho);
  const double dt = period / steps_per_period;
  const int steps = periods * steps_per_period;
  const int across = std::max(1, cells / 10);
  run::SolidSimulation sim(
      solid_case("verify-energy", spec, dt, steps, rho_inf, E * v0 * std::sqrt(rho / E) * w * w),
      mesh::make_box({L, w, w}, {cells, across, across}));
  { // Initial velocity of the first axial mode; u = 0, a = 0 are in equilibrium.
    const mesh::Mesh& m = sim.mesh();
    const std::vector<Index>& o2g = sim.problem().dofs().mesh().original_to_global();
    const Index begin = sim.problem().dofs().mesh().owned_begin();
    const Index owned = sim.problem().dofs().mesh().num_owned();
    fem::WriteArray v(sim.solver().solution());
    for (Index n = 0; n < m.num_nodes(); ++n)
      if (const Index l = o2g[n] - begin; l >= 0 && l < owned)
        v[4 * l] = v0 * std::sin(0.5 * std::numbers::pi * m.points[n][0] / L);
  }
  EnergyRun out;
  out.steps = steps;
  out.period = period;
  out.tets = sim.mesh().num_tets();
  for (int s = 0; s < steps; ++s) {
    const auto r = sim.advance();
    const double e = sim.problem().stage_energy(sim.solver().solution()).total();
    if (s == 0)
      out.initial = e;
    out.final_signed = (e - out.initial) / out.initial;
    out.final_drift = std::abs(out.final_signed);
    out.worst_drift = std::max(out.worst_drift, out.final_drift);
    if (progress && (s + 1) % steps_per_period == 0)
      fmt::print(stderr, "energy rho_inf = {}: period {} E = {:.6e} J drift {:.2e} Newton {}\n",
                 rho_inf, (s + 1) / steps_per_period, e, out.final_drift, r.newton_iterations);
  }
  return out;
}

/// Relative loss of the stage energy 1/2 (v^2 + omega^2 x^2) at t_{n+alpha_f} from step 1
/// to step `steps` of generalized-alpha (rho_inf; JWH alpha_m, alpha_f, gamma and
/// beta = (1 + alpha_m - alpha_f)^2 / 4) on x'' + omega^2 x = 0 with Omega = omega dt, from
/// x = 0, v = 1, a = 0. Each step solves a_{n+alpha_m} + omega^2 x_{n+alpha_f} = 0 for
/// v_{n+1} (dt = 1): a_{n+1} = (v_{n+1} - v_n) / gamma - (1 - gamma) / gamma a_n,
/// x_{n+1} = x_n + v_n + (1/2 - beta) a_n + beta a_{n+1}.
double sdof_stage_energy_loss(double rho_inf, double Omega, int steps) {
  const double am = (3.0 - rho_inf) / (2.0 * (1.0 + rho_inf)), af = 1.0 / (1.0 + rho_inf);
  const double gamma = 0.5 + am - af, beta = 0.25 * (1.0 + am - af) * (1.0 + am - af);
  const double w2 = Omega * Omega;
  double x = 0.0, v = 1.0, a = 0.0, first = 0.0, last = 0.0;
  for (int n = 0; n < steps; ++n) {
    // a1 = v1 / gamma + a0_, x1 = beta / gamma v1 + x1_: affine in v1.
    const double a0_ = -v / gamma - (1.0 - gamma) / gamma * a;
    const double x1_ = x + v + (0.5 - beta) * a + beta * a0_;
    const double v1 = -((1.0 - am) * a + am * a0_ + w2 * ((1.0 - af) * x + af * x1_)) /
                      (am / gamma + w2 * af * beta / gamma);
    const double a1 = v1 / gamma + a0_, x1 = beta / gamma * v1 + x1_;
    const double xs = x + af * (x1 - x), vs = v + af * (v1 - v);
    last = 0.5 * (vs * vs + w2 * xs * xs);
    if (n == 0)
      first = last;
    x = x1;
    v = v1;
    a = a1;
  }
  return (first - last) / first;
}

} // namespace

VerificationResult verify_robin(const VerifyOptions& options) {
  const SolidMaterial m = SolidMaterial::from_young_poisson(SolidModel::NeoHookean, E, 0.3, rho);
  const double M = m.kappa + 4.0 / 3.0 * m.mu;
  const double u_inf = -(robin_p / robin_k + robin_p * robin_L / M);
  const int cells = std::max(2, static_cast<int>(std::lround(8.0 / options.coarsening)));
  // dt = 0.1 ms: ~60 steps per period of the column on its spring (T ~ 6 ms), and a few
  // per crossing of the column by a compression wave (L / c ~ 0.3 ms).
  const double dt = 1e-4, t_end = 0.03;
  const RobinRun damped = run_robin(30e3, 0.0, cells, dt, t_end, u_inf, options.progress);
  const RobinRun undamped = run_robin(0.0, 0.0, cells, dt, t_end, u_inf, options.progress);
  constexpr double p0 = 250.0; // ambient pressure of the support [Pa]
  const double u_lifted = (p0 - robin_p) / robin_k - robin_p * robin_L / M;
  const RobinRun lifted = run_robin(30e3, p0, cells, dt, t_end, u_lifted, options.progress);
  VerificationResult res;
  res.name = "robin";
  // Confined compression is uniform strain: exact in P1, so the error at the end is the
  // left-over transient (e^{-zeta omega t} ~ 1e-12 at t = 30 ms) plus the nonlinearity
  // p / M ~ 6e-5. 1 % as the issue asks.
  res.metrics.push_back({"settled_displacement_relative_error",
                         std::abs(damped.final_displacement - u_inf) / std::abs(u_inf), 0.01,
                         "|u_z(top, 30 ms) - (p/k_s + p L/M)| / (p/k_s + p L/M) with "
                         "c_s = 30 kN s/m^3; 1 %"});
  // The same bound with p_0 = 250 Pa: its term is exact in the confined column, so the
  // error is again the transient and the p / M nonlinearity.
  res.metrics.push_back({"ambient_pressure_displacement_relative_error",
                         std::abs(lifted.final_displacement - u_lifted) / std::abs(u_lifted), 0.01,
                         "|u_z(top, 30 ms) - ((p_0 - p)/k_s - p L/M)| / |...| with p_0 = 250 Pa, "
                         "c_s = 30 kN s/m^3; 1 %"});
  // The undamped column never settles within the run, so its settling time is counted as
  // the run's length: the ratio is an upper bound. Near-critical damping settles in
  // ~ 7 / omega ~ 7 ms, a quarter of the run: 0.5 asks for a clear gain.
  res.metrics.push_back({"settling_time_ratio",
                         damped.settling_time / std::max(undamped.settling_time, dt), 0.5,
                         "time to stay within 1 % of the static answer, c_s = 30 kN s/m^3 over "
                         "c_s = 0; < 0.5: damping settles at least twice as fast"});
  res.details = {{"exact_displacement_m", u_inf},
                 {"cells_along_column", cells},
                 {"time_step_s", dt},
                 {"end_time_s", t_end},
                 {"damped",
                  {{"final_displacement_m", damped.final_displacement},
                   {"settling_time_s", damped.settling_time},
                   {"overshoot", damped.overshoot},
                   {"max_newton_iterations", damped.newton_max}}},
                 {"undamped",
                  {{"final_displacement_m", undamped.final_displacement},
                   {"settling_time_s", undamped.settling_time},
                   {"overshoot", undamped.overshoot},
                   {"max_newton_iterations", undamped.newton_max}}},
                 {"ambient_pressure_250_Pa",
                  {{"exact_displacement_m", u_lifted},
                   {"final_displacement_m", lifted.final_displacement},
                   {"settling_time_s", lifted.settling_time},
                   {"max_newton_iterations", lifted.newton_max}}}};
  return res;
}

VerificationResult verify_energy(const VerifyOptions& options) {
  const int cells = std::max(4, static_cast<int>(std::lround(20.0 / options.coarsening)));
  const int steps_per_period = 40;
  const EnergyRun run = run_energy(cells, steps_per_period, 1.0, options.progress);
  VerificationResult res;
  res.name = "energy";
  // The trapezoidal rule is exact in energy for linear systems; the 1 % strain amplitude
  // makes the nonlinear midpoint error ~ (omega dt)^2 strain ~ 1e-4 per period, bounded,
  // not accumulating. 1 % as the issue asks.
  res.metrics.push_back({"energy_drift", run.worst_drift, 0.01,
                         "max over 10 periods of |E(t) - E(0)| / E(0), E = kinetic + stored "
                         "energy at the stage, rho_inf = 1; 1 %"});
  // The contrast: rho_inf = 0.5 on the same bar against the single-mode prediction. The loss
  // per period grows as (omega dt)^3, so 20 % admits a 6 % error in the frequency of the
  // mode that carries the energy: far above P1's dispersion ((k h)^2 / 24 < 1e-3 for
  // 10 or more cells along) and the 1 % strain amplitude's nonlinearity, while a scheme
  // that did not dissipate (loss 0) is 100 % off and rho_inf = 0 several times over.
  const EnergyRun damped = run_energy(cells, steps_per_period, 0.5, options.progress);
  const double omega_dt = 2.0 * std::numbers::pi / steps_per_period;
  const double predicted_loss = sdof_stage_energy_loss(0.5, omega_dt, damped.steps);
  const double loss = -damped.final_signed;
  res.metrics.push_back({"dissipation_rho_inf_0.5_relative_error",
                         std::abs(loss - predicted_loss) / predicted_loss, 0.2,
                         "|energy loss over 10 periods with rho_inf = 0.5 - single-mode "
                         "prediction of the scheme| / prediction; 20 %"});
  // rho_inf = 1 conserves where rho_inf = 0.5 dissipates: its drift is bounded by the
  // midpoint error ~ (omega dt)^2 x strain ~ 2.5e-4, a tenth of the 2.7e-3 loss.
  res.metrics.push_back({"conservation_contrast", run.worst_drift / std::max(loss, 1e-300), 0.1,
                         "worst energy drift with rho_inf = 1 over the loss with rho_inf = 0.5; "
                         "< 0.1: conserving and dissipating are an order of magnitude apart"});
  res.details = {{"length_m", 0.1},
                 {"cells_along_bar", cells},
                 {"tets", run.tets},
                 {"period_s", run.period},
                 {"steps_per_period", steps_per_period},
                 {"initial_energy_J", run.initial},
                 {"final_drift", run.final_drift},
                 {"rho_inf_0.5",
                  {{"energy_loss", loss},
                   {"predicted_single_mode_loss", predicted_loss},
                   {"worst_drift", damped.worst_drift}}}};
  return res;
}

} // namespace tearflow::verify
