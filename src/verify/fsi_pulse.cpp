// Pressure pulse in a compliant tube (Formaggia, Gerbeau, Nobile & Quarteroni 2001;
// ../shared/reference/verification.md): tube 5 cm long, inner radius a = 0.5 cm, wall
// h = 0.1 cm; fluid 1000 kg/m^3, 0.003 Pa s; wall 1200 kg/m^3, E = 3e5 Pa, nu = 0.3, ends
// clamped; inlet traction 10 mmHg for 3 ms (edges smoothed over 0.25 ms), then zero; outlet
// traction zero; run to 15 ms.
//
// Wave speed. Thin-wall Moens-Korteweg c = sqrt(E h / (2 rho a)) = 5.5 m/s; the thick-wall
// estimate uses the Lame distensibility D = 2 (1 + nu) ((1 - 2 nu) a^2 + b^2) / (E (b^2 -
// a^2)) (plane strain), c = 1 / sqrt(rho D) = 5.25 m/s. Measured from the arrival time of
// the pulse at stations z = 1, 2, 3 cm (the cross-section mean pressure): the time its
// front crosses half the pulse height, by linear interpolation between steps, and a
// least-squares line z(t). The half-height crossing is used rather than the maximum because
// the pulse has a flat top, whose maximum wanders along the plateau with the dispersion's
// ripples; the maximum's times are reported beside it. The station at 4 cm is left out: the
// wave reflected at the open outlet reaches it while the pulse passes.
//
// Tolerance 10 % (the issue's) against the thick-wall estimate. Numerical dispersion and
// damping slow and smear the front; refinement must move the speed towards the estimate
// (--convergence: a second level with h and dt scaled by 0.7).
//
// Status (open, issue 10): the measured speed depends on the resolution in a way not yet
// understood. Half-height speeds [m/s] by (h, dt): (1.5 mm, 150 us) 4.38; (1 mm, 100 us) 4.45;
// (1.5 mm, 50 us) 4.60; (1.5 mm, 25 us) 5.00; (1.05 mm, 17.5 us) 4.60. rho_inf (0.5 or 1) and
// the moving mesh (ALE or not) changed it by under 0.5 %, and a 6 ms raised-cosine pulse
// gave 4.50 at (1.5 mm, 150 us). Suspects: the arrival measurement (half of each station's
// own peak, a slab mean of nodal pressures), the station at 1 cm near the clamped inlet
// ring, and the physical dispersion of a pulse only three radii long (c(k)^2 = c0^2 2 I1(ka)
// / (ka I0(ka)) for radial fluid inertia, ~0.93 c0 at ka = 1), which puts the true answer
// below the long-wave estimate. The full verification runs it; CI does not.
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "verify/cases.hpp"
#include "verify/fsi_tube.hpp"

namespace tearflow::verify {

namespace {

constexpr double a = 0.005, h = 0.001, L = 0.05; // [m]
constexpr double rho_f = 1000.0, mu = 0.003, rho_s = 1200.0, E = 3e5, nu = 0.3;
constexpr double P0 = 1333.2, t_pulse = 0.003, t_edge = 2.5e-4, t_end = 0.015;
constexpr std::array<double, 3> kStations{0.01, 0.02, 0.03};

double smoothstep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

bc::Waveform inlet_pulse() {
  std::vector<double> t, v;
  const int n = 400;
  for (int i = 0; i <= n; ++i) {
    const double ti = t_end * i / n;
    t.push_back(ti);
    v.push_back(P0 * smoothstep(ti / t_edge) * (1.0 - smoothstep((ti - t_pulse) / t_edge)));
  }
  return bc::Waveform::periodic(t, v, 4.0 * t_end, "pulse inlet traction");
}

struct PulseRun {
  double speed_half_height = 0.0, speed_peak = 0.0;
  std::vector<double> t_half, t_peak;
  int tets = 0, steps = 0, newton_max = 0;
  double element_size = 0.0, dt = 0.0, seconds = 0.0;
};

/// Least-squares slope dz/dt of the stations against their times.
double speed(const std::vector<double>& t) {
  double tm = 0.0, zm = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    tm += t[i] / t.size();
    zm += kStations[i] / t.size();
  }
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    num += (t[i] - tm) * (kStations[i] - zm);
    den += (t[i] - tm) * (t[i] - tm);
  }
  return num / den;
}

PulseRun run_pulse(double element_size, double dt, bool progress) {
  FsiTubeSpec spec;
  spec.pipe = {a, L, element_size, h};
  spec.fluid = {rho_f, mu};
  spec.wall =
      physics::SolidMaterial::from_young_poisson(physics::SolidModel::NeoHookean, E, nu, rho_s);
  bc::TractionOutlet inlet, outlet;
  inlet.face = "inlet";
  inlet.pressure = inlet_pulse();
  inlet.backflow_beta = 0.0;
  outlet.face = "outlet";
  spec.fluid_conditions.outlets = {inlet, outlet};
  spec.wall_conditions.fixed = {{"wall_inlet", 0b111, {}, 0.0}, {"wall_outlet", 0b111, {}, 0.0}};
  spec.newton = {15, 1e-8, 1e-9 * P0 * a * a};
  const double start = MPI_Wtime();
  FsiTube tube(std::move(spec));
  PulseRun run;
  run.tets = static_cast<int>(tube.mesh().num_tets());
  run.element_size = element_size;
  run.dt = dt;
  run.steps = static_cast<int>(std::round(t_end / dt));
  const double slab = 0.6 * element_size; // the nodes of about one layer around z_k
  std::vector<std::vector<double>> p(kStations.size());
  std::vector<double> t;
  for (int s = 0; s < run.steps; ++s) {
    const physics::StepReport r = tube.advance(dt);
    run.newton_max = std::max(run.newton_max, r.newton_iterations);
    t.push_back(tube.time());
    for (size_t k = 0; k < kStations.size(); ++k)
      p[k].push_back(tube.mean_fluid_pressure(kStations[k] - slab, kStations[k] + slab));
    if (progress)
      fmt::print(stderr, "pulse: t = {:.5f} s p = {:.1f} {:.1f} {:.1f} Pa Newton {} KSP {}\n",
                 tube.time(), p[0].back(), p[1].back(), p[2].back(), r.newton_iterations,
                 r.linear_iterations);
  }
  for (size_t k = 0; k < kStations.size(); ++k) {
    const auto peak = std::max_element(p[k].begin(), p[k].end()) - p[k].begin();
    run.t_peak.push_back(t[peak]);
    const double half = 0.5 * p[k][peak];
    double t_half = t[0];
    for (long i = 1; i <= peak; ++i)
      if (p[k][i - 1] < half && p[k][i] >= half) {
        t_half = t[i - 1] + (half - p[k][i - 1]) / (p[k][i] - p[k][i - 1]) * dt;
        break;
      }
    run.t_half.push_back(t_half);
  }
  run.speed_half_height = speed(run.t_half);
  run.speed_peak = speed(run.t_peak);
  run.seconds = MPI_Wtime() - start;
  return run;
}

nlohmann::json to_json(const PulseRun& r) {
  return {{"element_size_m", r.element_size},
          {"dt_s", r.dt},
          {"tets", r.tets},
          {"steps", r.steps},
          {"max_newton_iterations", r.newton_max},
          {"arrival_half_height_s", r.t_half},
          {"arrival_peak_s", r.t_peak},
          {"speed_half_height_m_per_s", r.speed_half_height},
          {"speed_peak_m_per_s", r.speed_peak},
          {"seconds", r.seconds}};
}

} // namespace

VerificationResult verify_pulse(const VerifyOptions& options) {
  const double b = a + h;
  const double D = 2.0 * (1.0 + nu) * ((1.0 - 2.0 * nu) * a * a + b * b) / (E * (b * b - a * a));
  const double c_thick = 1.0 / std::sqrt(rho_f * D);
  const double c_mk = std::sqrt(E * h / (2.0 * rho_f * a));
  const double size = 1e-3 * options.coarsening, dt = 2.5e-5 * options.coarsening / 1.5;
  const PulseRun coarse = run_pulse(size, dt, options.progress);
  const double error = std::abs(coarse.speed_half_height - c_thick) / c_thick;

  VerificationResult res;
  res.name = "pulse";
  res.metrics.push_back({"wave_speed_relative_error", error, 0.10,
                         "|c (half-height arrival at z = 1, 2, 3 cm) - thick-wall Lame estimate| "
                         "/ estimate; 10 % (issue 10)"});
  res.details = {{"thick_wall_estimate_m_per_s", c_thick},
                 {"moens_korteweg_thin_wall_m_per_s", c_mk},
                 {"stations_m", kStations},
                 {"runs", nlohmann::json::array({to_json(coarse)})}};
  if (options.convergence) {
    const PulseRun fine = run_pulse(0.7 * size, 0.7 * dt, options.progress);
    res.details["runs"].push_back(to_json(fine));
    const double fine_error = std::abs(fine.speed_half_height - c_thick) / c_thick;
    // Refinement must not move the speed away from the estimate, beyond 1 % of it (a tenth of
    // the tolerance; the arrival times are interpolated between steps of 25 us, 1.3 % of the
    // 2 cm between the outer stations at 5 m/s).
    res.metrics.push_back({"refinement_error_growth", fine_error - error, 0.01,
                           "error at h, dt x 0.7 minus error at h, dt; <= 1 % (must not grow)"});
  }
  return res;
}

} // namespace tearflow::verify
