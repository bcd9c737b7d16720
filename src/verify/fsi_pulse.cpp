// Pressure pulse in a compliant tube (Formaggia, Gerbeau, Nobile & Quarteroni 2001;
// ../shared/reference/verification.md): tube 5 cm long, inner radius a = 0.5 cm, wall
// h = 0.1 cm; fluid 1000 kg/m^3, 0.003 Pa s; wall 1200 kg/m^3, E = 3e5 Pa, nu = 0.3, ends
// clamped; inlet traction 10 mmHg for 3 ms, then zero; outlet traction zero; run to 15 ms.
//
// The pulse's edges are smoothed (smoothstep) over t_edge = 1.25 ms; the pulse lasts 3 ms at
// half height, as the reference's. A sharper edge is not resolved: the front then spans
// c t_edge = 1.3 mm at t_edge = 0.25 ms, one element, and the measured speed moved by 8 %
// with dt alone. At 1.25 ms the front spans 6.6 mm, 4.4 elements of the coarse level.
//
// Wave speed estimates. Thin-wall Moens-Korteweg c = sqrt(E h / (2 rho a)) = 5.48 m/s. The
// thick-wall estimate uses the Lame distensibility D = 2 (1 + nu) ((1 - 2 nu) a^2 + b^2) /
// (E (b^2 - a^2)) (plane strain, b = a + h), c0 = 1 / sqrt(rho D) = 5.25 m/s: the long-wave
// limit of a wall held axially. A wall free to move axially between its clamped ends
// (sigma_zz = 0, the open-ended Lame tube) has D = 2 ((1 - nu) a^2 + (1 + nu) b^2) /
// (E (b^2 - a^2)) and c = 5.07 m/s; reported beside it. A wave of wavenumber k is slower,
// by the radial inertia of the fluid and the inertia of the wall:
//   c(k)^2 / c0^2 = 1 / [(ka/2) I0(ka) / I1(ka) + rho_s h a k^2 / (2 rho)],
// 4.72 m/s at the wavenumber of the pulse's fundamental (half a wavelength over its 3 ms,
// ka = 1.0). The pulse is three radii long, so it disperses as it travels: it broadens and
// its peak falls (by 40 % from 1.5 to 3.5 cm at h 1.5 mm), and every feature of its shape
// (peak, front, steepest rise) travels at a speed between c(k) and c0 that depends on the
// distance.
//
// Measurement: the time centroid of the pressure pulse at stations z = 1.25 ... 2.5 cm (every
// 2.5 mm), t_c(z) = int t p dt / int p dt, and a least-squares line z(t_c). For a linear
// system p(z, w) = exp(-i k(w) z) p(0, w), so t_c(z) = t_c(0) + z dk/dw(0) = t_c(0) + z / c0
// whatever the dispersion and the damping at higher frequencies: the centroid travels at the
// long-wave speed, the quantity the estimates predict. The integral runs to the time the
// reflection from the open outlet can first reach the station's slab, (2 L - z_top) / c0, or
// to the end of the run, and the stations end at 2.5 cm so that the pulse has passed by then
// (h 1.5 mm: at 2.5 cm the pressure there is 2 % of the peak, and cutting 0.5 ms earlier
// moves that centroid by 0.02 ms, 0.8 % of the 2.5 ms between the first and last station;
// those up to 2 cm move by under 0.005 ms). The pressure at a station is the mean of the
// cross-section means at z - 2.5 mm, z, z + 2.5 mm (fluid nodes within 0.6 h of each): a
// single section's mean wanders by +-0.1 ms in t_c with the nodes it happens to hold. The first
// station is 2.5 radii from the clamped inlet ring. Reported beside it, from the same station
// signals: the crossing of P0 / 2 (a fixed threshold; the dispersed peak falls below it beyond
// about 2 cm), of half the station's own peak, the time of the largest dp/dt and of the peak.
//
// Acceptance (issue 10), checked by --convergence: the speed within 10 % of the thick-wall
// estimate c0 at both levels (h, dt and h, dt x 0.7), and its error not larger on the finer
// level (tolerance 0: the "does not get worse"; the truncation effect above, 0.8 %,
// is systematic and nearly the same at both levels, so it does not blur the difference).
// Without --convergence only the 10 % of the one level is checked.
//
// What the continuum itself gives for this measurement (bench/pulse_continuum.py): a linear
// model of the tube (the inlet pulse's spectrum carried with Womersley's viscous wavenumber
// and the inertia dispersion above, the same stations, section averages and cut; no mesh, no
// reflection) gives a centroid speed of 5.05 m/s for c0 = 5.25 (wall held axially) and 4.97
// m/s for the axially free wall's 5.07; without viscosity and dispersion it returns c0
// exactly. So viscosity, dispersion and the cut slow the measured centroid by 4-5 % of c0
// before any discretization error (docs/performance.md, "Pressure pulse after the LSIC fix").
//
// Status (issue 10): the centroid speed is 4.50 m/s at h 1.5 mm (dt 35, 25, 17.5 us alike),
// 4.56 at (1.05 mm, 17.5 us), 4.57 at (0.735 mm, 25 us): the error falls under refinement
// (14.3, 13.2, 13.0 %) but stays above 10 %, so --convergence fails on the 10 % bound.
//
// Where the gap is: the run splits c^2 = k A / (rho dA/dp) into its two factors (WaveBalance
// below). The wall's dynamic distensibility is close to the axially free Lame tube's (u_r / p
// 1.00e-7 m/Pa at 1.5 mm, 1.03e-7 at 1.05 mm; Lame 0.974e-7 free, 0.906e-7 plane strain), but
// the fluid is heavier than it should be: k = 0.82 at 1.5 mm and 0.90 at 1.05 mm, where the
// continuum's inviscid core has k = 1. The same k comes out of a rigid tube (E x 1e4, a
// pressure step over 5 cm: rho L dQ/dt = k A dp with k 0.817 at 1.5 mm, 0.871 at 1.0 mm) and
// with the viscosity cut 300-fold: it is the no-slip wall's first element layer, whose P1
// velocity ramps from 0 to the core's and so carries half the flow it should, 1 - k ~ 0.6
// h / a, an O(h) error. sqrt(k a / (2 rho u_r/p)) = 4.53 m/s at 1.5 mm reproduces the
// measured 4.50. It falls with h, while the wall, one element through its thickness at 1.5
// mm, softens with h; the two nearly cancel between 1.05 and 0.735 mm, which made the speed
// look converged. A pipe with boundary layers (mesh::PipeSpec::layers: six layers from 0.1 h,
// three through the wall; 54.8 k tets at 1.5 mm) brings k to 0.985 and the speed of the
// peak, of the half-peak crossing and of the steepest rise to 4.51-4.69 m/s (uniform mesh:
// 4.05-4.31) but the centroid only to 4.58 m/s, 4.63 at (1.05 mm, 17.5 us): the 3D tube
// also carries a precursor (20 % of the peak at 2.5 cm, 3 ms ahead, through the wall's
// axial waves at sqrt(E / rho_s) = 16 m/s and the incompressible fluid) and a negative tail
// that the membrane model has not. Its cost (8.7x the CPU at 1.5 mm, 28 min on 2 ranks for
// the refined level) keeps it out of this case's default; docs/performance.md, "Pressure
// pulse: where the gap is".
//
// With -o DIR the run writes the pressure along the axis over time, DIR/pulse_axis_*.csv
// (cross-section mean pressure every 2.5 mm at every step), so the pulse visibly travels.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <fmt/format.h>

#include "fem/petsc.hpp"
#include "verify/cases.hpp"
#include "verify/fsi_tube.hpp"

namespace tearflow::verify {

namespace {

constexpr double a = 0.005, h = 0.001, L = 0.05; // [m]
constexpr double rho_f = 1000.0, mu = 0.003, rho_s = 1200.0, E = 3e5, nu = 0.3;
constexpr double P0 = 1333.2, t_pulse = 0.003, t_edge = 1.25e-3, t_end = 0.015;        // [Pa], [s]
constexpr double axis_spacing = 0.0025;                                                // [m]
constexpr std::array<double, 6> kStations{0.0125, 0.015, 0.0175, 0.02, 0.0225, 0.025}; // [m]

double smoothstep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

/// Inlet traction [Pa]: rises over [0, t_edge], falls over [t_pulse, t_pulse + t_edge].
bc::Waveform inlet_pulse() {
  std::vector<double> t, v;
  const int n = 600;
  for (int i = 0; i <= n; ++i) {
    const double ti = t_end * i / n;
    t.push_back(ti);
    v.push_back(P0 * smoothstep(ti / t_edge) * (1.0 - smoothstep((ti - t_pulse) / t_edge)));
  }
  return bc::Waveform::periodic(t, v, 4.0 * t_end, "pulse inlet traction");
}

/// Long-wave speed [m/s] of a fluid-filled tube of distensibility D [1/Pa].
double long_wave_speed(double D) {
  return 1.0 / std::sqrt(rho_f * D);
}

/// Speed [m/s] of a wave of wavenumber k [1/m] in the thick tube: the long-wave speed c0
/// lowered by the fluid's radial inertia and the wall's inertia (see the file comment).
double short_wave_speed(double c0, double k) {
  const double ka = k * a;
  const double fluid = 0.5 * ka * std::cyl_bessel_i(0.0, ka) / std::cyl_bessel_i(1.0, ka);
  const double wall = rho_s * h * a * k * k / (2.0 * rho_f);
  return c0 / std::sqrt(fluid + wall);
}

/// The arrival-time variants at one station [s]; NaN where a variant is undefined.
struct Arrival {
  double centroid = 0.0;  ///< int t p dt / int p dt up to the reflection (primary)
  double threshold = 0.0; ///< crossing of P0 / 2
  double own_peak = 0.0;  ///< crossing of half the station's peak
  double max_slope = 0.0; ///< largest dp/dt
  double peak = 0.0;      ///< the peak
  double peak_pressure = 0.0, pulse_integral = 0.0; ///< [Pa], int p dt [Pa s]
};

/// First time p(t) crosses `level` upwards, linear between samples; NaN if it never does.
double crossing(const std::vector<double>& t, const std::vector<double>& p, double level) {
  for (size_t i = 1; i < p.size(); ++i)
    if (p[i - 1] < level && p[i] >= level)
      return t[i - 1] + (level - p[i - 1]) / (p[i] - p[i - 1]) * (t[i] - t[i - 1]);
  return std::numeric_limits<double>::quiet_NaN();
}

/// The arrivals of the pulse p(t) (samples at t, equally spaced) up to t_cut, the time the
/// outlet's reflection can first reach the station.
Arrival arrival(const std::vector<double>& t, const std::vector<double>& p, double t_cut) {
  Arrival r;
  size_t n = 0; // samples before t_cut
  while (n < t.size() && t[n] <= t_cut)
    ++n;
  const std::vector<double> tw(t.begin(), t.begin() + n), pw(p.begin(), p.begin() + n);
  double sum_p = 0.0, sum_tp = 0.0;
  for (size_t i = 0; i < n; ++i) {
    sum_p += pw[i];
    sum_tp += tw[i] * pw[i];
  }
  const double dt = t[1] - t[0];
  r.pulse_integral = sum_p * dt;
  r.centroid = sum_tp / sum_p;
  r.threshold = crossing(tw, pw, 0.5 * P0);
  const auto peak = static_cast<size_t>(std::max_element(pw.begin(), pw.end()) - pw.begin());
  r.peak = tw[peak];
  r.peak_pressure = pw[peak];
  r.own_peak = crossing(tw, pw, 0.5 * r.peak_pressure);
  // Largest dp/dt: differences at the step midpoints, refined by a parabola.
  size_t best = 1;
  for (size_t i = 1; i < n; ++i)
    if (pw[i] - pw[i - 1] > pw[best] - pw[best - 1])
      best = i;
  r.max_slope = tw[best] - 0.5 * dt;
  if (best >= 2 && best + 1 < n) {
    const double sm = pw[best - 1] - pw[best - 2], s0 = pw[best] - pw[best - 1],
                 sp = pw[best + 1] - pw[best], curv = sm - 2.0 * s0 + sp;
    if (curv < 0.0)
      r.max_slope += 0.5 * (sm - sp) / curv * dt;
  }
  return r;
}

/// Least-squares slope dz/dt [m/s] of the stations against their arrival times.
double speed(const std::vector<double>& t) {
  double tm = 0.0, zm = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    tm += t[i] / static_cast<double>(t.size());
    zm += kStations[i] / static_cast<double>(t.size());
  }
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    num += (t[i] - tm) * (kStations[i] - zm);
    den += (t[i] - tm) * (t[i] - tm);
  }
  return num / den;
}

/// The two factors of the long-wave speed c^2 = k A / (rho dA/dp), measured on the run's
/// axis series at the stations (see the file comment): the wall's dynamic distensibility
/// from u_r against p, and the inertance ratio k from the axial momentum balance of a slice,
/// rho dQ/dt = k (-A dp/dz), with Q(z) = int_z^L dA/dt dz (continuity; valid while the pulse
/// has not reached the outlet). k = 1 for the continuum's inviscid core (its Stokes layer is
/// 0.08 mm thick); the strongly imposed no-slip robs the first element layer at the wall of
/// about half its flow, k ~ 1 - 0.6 h / a on these meshes.
struct WaveBalance {
  double radial_compliance = 0.0; ///< u_r / p [m/Pa], least squares over time
  double inertance_ratio = 0.0;   ///< k
  double speed = 0.0;             ///< sqrt(k a / (2 rho u_r/p)) [m/s]
};

/// p[k][i], ur[k][i]: section mean pressure and interface radial displacement at axis point
/// k (z = k spacing) and sample i (times t, equally spaced); fits up to t_max [s].
WaveBalance wave_balance(const std::vector<double>& t, const std::vector<std::vector<double>>& p,
                         const std::vector<std::vector<double>>& ur, double t_max) {
  const size_t n_axis = p.size();
  size_t n = 0;
  while (n + 1 < t.size() && t[n + 1] <= t_max)
    ++n;
  const double dt = t[1] - t[0];
  auto area = [&](size_t k, size_t i) { return std::numbers::pi * std::pow(a + ur[k][i], 2); };
  auto flow = [&](size_t k0, size_t i) { // int_z^L dA/dt dz, central differences in time
    double q = 0.0;
    for (size_t k = k0; k + 1 < n_axis; ++k)
      for (size_t m : {k, k + 1})
        q += 0.5 * axis_spacing * (area(m, i + 1) - area(m, i - 1)) / (2.0 * dt);
    return q;
  };
  double pu = 0.0, pp = 0.0, fm = 0.0, ff = 0.0;
  for (double z : kStations) {
    const auto k = static_cast<size_t>(std::lround(z / axis_spacing));
    for (size_t i = 2; i + 2 < n; ++i) {
      pu += p[k][i] * ur[k][i];
      pp += p[k][i] * p[k][i];
      const double inertia = rho_f * (flow(k, i + 1) - flow(k, i - 1)) / (2.0 * dt);
      const double force = -area(k, i) * (p[k + 1][i] - p[k - 1][i]) / (2.0 * axis_spacing);
      fm += inertia * force;
      ff += force * force;
    }
  }
  WaveBalance b;
  b.radial_compliance = pu / pp;
  b.inertance_ratio = fm / ff;
  b.speed = std::sqrt(b.inertance_ratio * a / (2.0 * rho_f * b.radial_compliance));
  return b;
}

struct PulseRun {
  std::vector<Arrival> arrivals;
  double speed_centroid = 0.0, speed_threshold = 0.0, speed_own_peak = 0.0;
  double speed_max_slope = 0.0, speed_peak = 0.0;
  WaveBalance balance;
  int tets = 0, steps = 0, newton_max = 0, newton_total = 0, linear_total = 0;
  double element_size = 0.0, dt = 0.0, seconds = 0.0;
  std::string axis_csv;
};

PulseRun run_pulse(double element_size, double dt, double c0, const VerifyOptions& options) {
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
  // Newton to 1e-9 of the load's force scale: arrival times move by far less than a step.
  spec.newton = {15, 1e-8, 1e-9 * P0 * a * a};
  const double start = MPI_Wtime();
  FsiTube tube(std::move(spec));
  PulseRun run;
  run.tets = static_cast<int>(tube.mesh().num_tets());
  run.element_size = element_size;
  run.dt = dt;
  run.steps = static_cast<int>(std::round(t_end / dt));

  // Cross-section mean pressure every axis_spacing along the tube, at every step.
  const int n_axis = static_cast<int>(std::round(L / axis_spacing)) + 1;
  const double slab = 0.6 * element_size; // the nodes of about one layer around z
  std::vector<std::vector<double>> p(n_axis), ur(n_axis);
  std::vector<double> t;
  std::ofstream csv;
  if (!options.output.empty() && fem::mpi_rank() == 0) {
    std::filesystem::create_directories(options.output);
    run.axis_csv =
        (std::filesystem::path(options.output) /
         fmt::format("pulse_axis_h{:.2f}mm_dt{:.1f}us.csv", 1e3 * element_size, 1e6 * dt))
            .string();
    csv.open(run.axis_csv);
    if (!csv)
      input_error("{}: cannot write the pulse's axis series", run.axis_csv);
    csv << "t_s,z_m,p_Pa,wall_radial_displacement_m\n";
  }
  for (int s = 0; s < run.steps; ++s) {
    const physics::StepReport r = tube.advance(dt);
    run.newton_max = std::max(run.newton_max, r.newton_iterations);
    run.newton_total += r.newton_iterations;
    run.linear_total += r.linear_iterations;
    t.push_back(tube.time());
    for (int k = 0; k < n_axis; ++k) {
      const double z = k * axis_spacing;
      p[k].push_back(tube.mean_fluid_pressure(z - slab, z + slab));
      ur[k].push_back(tube.mean_radial_displacement(z - slab, z + slab));
      if (csv.is_open())
        csv << fmt::format("{:.7e},{:.5f},{:.6e},{:.6e}\n", tube.time(), z, p[k].back(),
                           ur[k].back());
    }
    if (options.progress)
      fmt::print(stderr,
                 "pulse: t = {:.5f} s p(1.5, 2.5, 3.5 cm) = {:.1f} {:.1f} {:.1f} Pa "
                 "Newton {} KSP {}\n",
                 tube.time(), p[6].back(), p[10].back(), p[14].back(), r.newton_iterations,
                 r.linear_iterations);
  }
  std::array<std::vector<double>, 5> times; // per variant, per station
  for (double z : kStations) {
    const auto k = static_cast<size_t>(std::lround(z / axis_spacing));
    std::vector<double> station(t.size());
    for (size_t i = 0; i < t.size(); ++i)
      station[i] = (p[k - 1][i] + p[k][i] + p[k + 1][i]) / 3.0;
    const double top = z + axis_spacing + slab; // the station's farthest node
    const Arrival& s = run.arrivals.emplace_back(arrival(t, station, (2.0 * L - top) / c0));
    for (auto [i, v] : {std::pair{0, s.centroid},
                        {1, s.threshold},
                        {2, s.own_peak},
                        {3, s.max_slope},
                        {4, s.peak}})
      times[i].push_back(v);
  }
  // Until the front (at the estimate's speed, faster than the discrete wave) is 5 mm from
  // the outlet: Q(L) = 0 holds that long.
  run.balance = wave_balance(t, p, ur, (L - 0.005) / c0);
  run.speed_centroid = speed(times[0]);
  run.speed_threshold = speed(times[1]);
  run.speed_own_peak = speed(times[2]);
  run.speed_max_slope = speed(times[3]);
  run.speed_peak = speed(times[4]);
  run.seconds = MPI_Wtime() - start;
  return run;
}

nlohmann::json to_json(const PulseRun& r) {
  nlohmann::json stations = nlohmann::json::array();
  for (size_t i = 0; i < r.arrivals.size(); ++i) {
    const Arrival& s = r.arrivals[i];
    stations.push_back({{"z_m", kStations[i]},
                        {"arrival_centroid_s", s.centroid},
                        {"arrival_threshold_s", s.threshold},
                        {"arrival_half_own_peak_s", s.own_peak},
                        {"arrival_max_dpdt_s", s.max_slope},
                        {"arrival_peak_s", s.peak},
                        {"peak_Pa", s.peak_pressure},
                        {"pulse_integral_Pa_s", s.pulse_integral}});
  }
  nlohmann::json j = {{"element_size_m", r.element_size},
                      {"dt_s", r.dt},
                      {"tets", r.tets},
                      {"steps", r.steps},
                      {"max_newton_iterations", r.newton_max},
                      {"newton_per_step", double(r.newton_total) / r.steps},
                      {"krylov_per_step", double(r.linear_total) / r.steps},
                      {"stations", stations},
                      {"speed_centroid_m_per_s", r.speed_centroid},
                      {"speed_threshold_m_per_s", r.speed_threshold},
                      {"speed_half_own_peak_m_per_s", r.speed_own_peak},
                      {"speed_max_dpdt_m_per_s", r.speed_max_slope},
                      {"speed_peak_m_per_s", r.speed_peak},
                      {"wall_radial_compliance_m_per_Pa", r.balance.radial_compliance},
                      {"inertance_ratio", r.balance.inertance_ratio},
                      {"speed_from_compliance_and_inertance_m_per_s", r.balance.speed},
                      {"seconds", r.seconds}};
  if (!r.axis_csv.empty())
    j["axis_series_csv"] = r.axis_csv;
  return j;
}

} // namespace

VerificationResult verify_pulse(const VerifyOptions& options) {
  const double b = a + h, a2 = a * a, b2 = b * b;
  const double c_thick =
      long_wave_speed(2.0 * (1.0 + nu) * ((1.0 - 2.0 * nu) * a2 + b2) / (E * (b2 - a2)));
  const double c_open =
      long_wave_speed(2.0 * ((1.0 - nu) * a2 + (1.0 + nu) * b2) / (E * (b2 - a2)));
  const double c_mk = std::sqrt(E * h / (2.0 * rho_f * a));
  const double c_mk_plate = c_mk / std::sqrt(1.0 - nu * nu);
  const double k_pulse = std::numbers::pi / (c_thick * t_pulse);
  // h 1 mm and dt 16.7 us by default; --coarsen 1.5: h 1.5 mm, dt 25 us.
  const double size = 1e-3 * options.coarsening, dt = 2.5e-5 * options.coarsening / 1.5;
  const PulseRun coarse = run_pulse(size, dt, c_thick, options);
  const double error = std::abs(coarse.speed_centroid - c_thick) / c_thick;

  VerificationResult res;
  res.name = "pulse";
  res.metrics.push_back({"wave_speed_relative_error", error, 0.10,
                         "|c (pulse time centroids, z = 1.25-2.5 cm) - thick-wall Lame estimate| "
                         "/ estimate; 10 % (issue 10)"});
  res.details = {{"thick_wall_estimate_m_per_s", c_thick},
                 {"thick_wall_open_ended_m_per_s", c_open},
                 {"moens_korteweg_thin_wall_m_per_s", c_mk},
                 {"moens_korteweg_plate_m_per_s", c_mk_plate},
                 {"short_wave_speed_pulse_fundamental_m_per_s", short_wave_speed(c_thick, k_pulse)},
                 {"edge_s", t_edge},
                 {"stations_m", kStations},
                 {"runs", nlohmann::json::array({to_json(coarse)})}};
  if (options.convergence) {
    const PulseRun fine = run_pulse(0.7 * size, 0.7 * dt, c_thick, options);
    res.details["runs"].push_back(to_json(fine));
    const double fine_error = std::abs(fine.speed_centroid - c_thick) / c_thick;
    res.metrics.push_back({"wave_speed_relative_error_refined", fine_error, 0.10,
                           "the same at h, dt x 0.7; 10 % (issue 10)"});
    // Refinement must not move the speed away from the estimate (see the file comment).
    res.metrics.push_back({"refinement_error_growth", fine_error - error, 0.0,
                           "error at h, dt x 0.7 minus error at h, dt; <= 0 (must not grow)"});
  }
  return res;
}

} // namespace tearflow::verify
