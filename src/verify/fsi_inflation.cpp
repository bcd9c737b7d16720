// Inflation of a compliant tube (../shared/reference/verification.md, "balance checks"):
// the tube of the pressure-pulse case (inner radius a = 5 mm, wall h = 1 mm, E = 3e5 Pa,
// nu = 0.3, 1200 kg/m^3; water-like fluid), 10 mm long, filled with fluid at rest. The same
// pressure P(t) acts on both fluid caps, rising smoothly from 0 to P0 = 1 mmHg over 20 ms
// and then held; the wall's end rings are held axially only (u_z = 0), so the tube is in
// plane strain and the thick-wall Lame solution is exact:
//   u(a) = P0 a (1 + nu) ((1 - 2 nu) a^2 + b^2) / (E (b^2 - a^2)),   b = a + h
// (12.1 um; the thin-wall Laplace estimate P0 a^2 / (E h) = 11.1 um, reported beside it,
// ignores h/a = 0.2). P0 is small, so the geometric nonlinearity (u/a = 2.4e-3) stays
// below the tolerance by a factor 20. The ramp is four times the tube's breathing
// period with the fluid's added mass (~ 4.5 ms), and the radius is averaged over the hold
// (20-30 ms), so the residual oscillation averages out.
//
// Tolerance 5 % (the issue's). The error is the wall's P1 discretization, O(h^2) with 1-2
// elements through the thickness (verify lame: 1.9 % at 4 cells through a thicker wall), plus
// the geometric nonlinearity above. Measured: 0.76 % at the reduced size (0.75 mm). The
// fluid pressure at the interface is reported: it must equal P0 during the hold (traction
// balance at the interface).
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "verify/cases.hpp"
#include "verify/fsi_tube.hpp"

namespace tearflow::verify {

namespace {

constexpr double a = 0.005, h = 0.001, L = 0.01; // [m]
constexpr double E = 3e5, nu = 0.3, rho_s = 1200.0;
constexpr double P0 = 133.322; // 1 mmHg [Pa]
constexpr double t_ramp = 0.02, t_end = 0.03, dt = 5e-4;

bc::Waveform smooth_ramp() {
  std::vector<double> t, v;
  for (int i = 0; i <= 60; ++i) { // smoothstep 3s^2 - 2s^3 up to t_ramp, then P0
    const double ti = t_end * i / 60.0, s = std::min(ti / t_ramp, 1.0);
    t.push_back(ti);
    v.push_back(P0 * s * s * (3.0 - 2.0 * s));
  }
  return bc::Waveform::periodic(t, v, 4.0 * t_end, "inflation pressure");
}

} // namespace

VerificationResult verify_inflation(const VerifyOptions& options) {
  FsiTubeSpec spec;
  spec.pipe = {a, L, 0.5e-3 * options.coarsening, h};
  spec.fluid = {1000.0, 0.003};
  spec.wall =
      physics::SolidMaterial::from_young_poisson(physics::SolidModel::NeoHookean, E, nu, rho_s);
  for (const char* cap : {"inlet", "outlet"}) {
    spec.fluid_conditions.outlets.push_back({cap, bc::PressureOutlet{smooth_ramp()}, 0.0});
  }
  spec.wall_conditions.fixed = {{"wall_inlet", 0b100, {}, 0.0}, {"wall_outlet", 0b100, {}, 0.0}};
  // Newton to 1e-9 of the load's force scale: far below the 5 % checked.
  spec.newton = {15, 1e-8, 1e-9 * P0 * a * L};
  spec.dt = dt;
  FsiTube tube(std::move(spec));

  const double b = a + h;
  const double exact =
      P0 * a * (1.0 + nu) * ((1.0 - 2.0 * nu) * a * a + b * b) / (E * (b * b - a * a));
  const double laplace = P0 * a * a / (E * h);
  const int steps = static_cast<int>(std::round(t_end / dt));
  double hold_sum = 0.0, pressure_sum = 0.0;
  int hold_samples = 0, newton_max = 0;
  // Volume balance: V_{n+1} - V_n against -dt (Q_n + Q_{n+1}) / 2, Q the caps' outflow,
  // judged at every step against that step's own flux. The flux passes through zero at the
  // start (from rest) and at each turn of the breathing oscillation during the hold, where a
  // ratio to the step's own flux measures only round-off and the start-up of the scheme
  // from a zero acceleration; there the step is judged against a floor, kFluxFloor of the
  // run's largest step flux, so that an error of 1 % of the floor (5e-4 of the peak) fails.
  // Measured (--coarsen 1.5): worst 0.60 % (step 2, flux 2.9 % of the peak, against the
  // floor); worst 0.38 % among the 54 of 60 steps above the floor, about 0.3 % with the
  // flux's sign through the hold (trapezoidal flux against the scheme's own time levels);
  // step 1, the start from rest with 0.4 % of the peak flux, reads 2.1 % of its own flux.
  constexpr double kFluxFloor = 0.05;
  double volume = tube.problem().fluid_volume(), outflow = 0.0;
  std::vector<double> changes, expectations;
  nlohmann::json history = nlohmann::json::array();
  for (int s = 0; s < steps; ++s) {
    const physics::StepReport r = tube.advance(dt);
    newton_max = std::max(newton_max, r.newton_iterations);
    const double volume_next = tube.problem().fluid_volume(), outflow_next = tube.cap_outflow();
    changes.push_back(volume_next - volume);
    expectations.push_back(-0.5 * dt * (outflow + outflow_next));
    volume = volume_next;
    outflow = outflow_next;
    const double u = tube.mean_radial_displacement(L / 3.0, 2.0 * L / 3.0);
    const double p = tube.mean_interface_pressure(L / 3.0, 2.0 * L / 3.0);
    if (tube.time() > t_ramp + 1e-12) {
      hold_sum += u;
      pressure_sum += p;
      ++hold_samples;
    }
    history.push_back({{"t_s", tube.time()},
                       {"u_r_m", u},
                       {"p_Pa", p},
                       {"volume_change_m3", changes.back()},
                       {"net_inflow_dt_m3", expectations.back()}});
    if (options.progress)
      fmt::print(stderr,
                 "inflation: t = {:.4f} s u_r = {:.4e} m p = {:.2f} Pa Newton {} KSP {} "
                 "mesh CG {}\n",
                 tube.time(), u, p, r.newton_iterations, r.linear_iterations,
                 tube.problem().mesh_iterations());
  }
  const double u_mean = hold_sum / hold_samples;
  double largest_flux = 0.0; // [m^3 per step]
  for (double e : expectations)
    largest_flux = std::max(largest_flux, std::abs(e));
  double balance_error = 0.0, balance_error_above_floor = 0.0;
  int worst_step = 0, steps_above_floor = 0;
  for (size_t s = 0; s < changes.size(); ++s) {
    const double flux = std::abs(expectations[s]);
    const double e =
        std::abs(changes[s] - expectations[s]) / std::max(flux, kFluxFloor * largest_flux);
    if (e > balance_error) {
      balance_error = e;
      worst_step = static_cast<int>(s) + 1;
    }
    if (flux >= kFluxFloor * largest_flux) {
      balance_error_above_floor = std::max(balance_error_above_floor, e);
      ++steps_above_floor;
    }
  }
  VerificationResult res;
  res.name = "inflation";
  res.metrics.push_back(
      {"volume_balance_error", balance_error, 0.01,
       "max over steps of |dV - dt (Q_in - Q_out)| / max(|dt (Q_in - Q_out)|, 5 % of the "
       "largest): the fluid volume follows the caps' net inflow at every step (trapezoidal "
       "in time); 1 % (issue 10)"});
  res.metrics.push_back(
      {"radial_displacement_relative_error", std::abs(u_mean - exact) / exact, 0.05,
       "|mean u_r(a) over the hold - thick-wall Lame (plane strain)| / Lame; 5 % (issue 10)"});
  res.details = {{"inner_radius_m", a},
                 {"largest_inflow_per_step_m3", largest_flux},
                 {"volume_balance_flux_floor", kFluxFloor},
                 {"volume_balance_worst_step", worst_step},
                 {"volume_balance_error_steps_above_floor", balance_error_above_floor},
                 {"steps_above_floor", steps_above_floor},
                 {"wall_thickness_m", h},
                 {"pressure_Pa", P0},
                 {"u_r_fe_m", u_mean},
                 {"u_r_lame_m", exact},
                 {"u_r_thin_wall_laplace_m", laplace},
                 {"mean_interface_pressure_hold_Pa", pressure_sum / hold_samples},
                 {"tets", tube.mesh().num_tets()},
                 {"nodes", tube.mesh().num_nodes()},
                 {"max_newton_iterations", newton_max},
                 {"history", history}};
  return res;
}

} // namespace tearflow::verify
