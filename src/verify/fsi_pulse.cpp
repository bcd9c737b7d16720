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
// Measurement (verification.md: "from the arrival time of the pressure peak at several
// stations"): the peak's time at stations z = 1.25 ... 2.5 cm (every 2.5 mm), refined by a
// parabola through its samples, and a least-squares line z(t) with its standard error. The
// pressure at a station is the mean of the cross-section means at z - 2.5 mm, z, z + 2.5 mm
// (fluid nodes within 0.6 h of each): a single section's mean wanders with the nodes it
// happens to hold. The signals are cut where the reflection from the open outlet can first
// reach the station's slab, (2 L - z_top) / c0. The first station is 2.5 radii from the
// clamped inlet ring. Reported beside it from the same signals: the time centroid int t p dt
// / int p dt (for a linear system it travels at dk/dw(0), the long-wave speed, whatever the
// dispersion), the crossings of P0 / 2 and of half the station's own peak, the largest dp/dt.
//
// The reference each is compared with (pulse_continuum.hpp): the same pulse, stations,
// averages and cut on the linear continuum of the tube, with Womersley's viscous wall layer
// and the dispersion above, no mesh. Its peak speed is 4.58 m/s for the axially free wall's
// long-wave 5.07 and 4.68 for the plane-strain 5.25: a pulse three radii long disperses, and
// its peak travels 10-11 % below the long-wave speed. 4.58 is 12.8 % below 5.25, so the
// issue's 10 % by the peak is out of reach of an exact solver of this tube too. The
// continuum's centroid travels at 4.95-4.96 / 5.07-5.08 m/s.
//
// The mesh. A uniform P1 mesh makes the fluid too heavy: the strongly imposed no-slip robs
// the first element layer at the wall of about half its flow (its velocity ramps from 0 to
// the core's, where the continuum's Stokes layer is 0.08 mm thick), an inertance ratio k ~ 1
// - 0.6 h / a (0.82 at 1.5 mm, measured below and in a rigid tube) and a wave sqrt(k) slower:
// the peak travelled at 4.10 m/s at 1.5 mm, 10 % below the continuum's. The pipe therefore
// has boundary layers (mesh::PipeSpec::layers: six from 0.1 h growing by 1.5, three through
// the wall; 54.8 k tets at 1.5 mm against 11.7 k), k = 0.985.
//
// The wall: clamped at its end rings and free axially between them, as the reference's.
// Its measured dynamic compliance u_r / p is the axially free Lame tube's within 3-7 %, so
// the continuum it is compared with takes 5.07 m/s; the plane-strain 5.25 assumes a wall held
// axially. Holding the wall's two surfaces axially (u_z = 0) does not make the 3D tube that
// of the estimate: it adds (most likely) shear stiffness against the axial variation of u_r, and
// the peak then travels at 5.33 / 5.46 m/s (uniform 1.5 / 1.05 mm), 5.91 with boundary layers
// (docs/performance.md, "Pressure pulse against its continuum").
//
// Acceptance (issue 10), checked: the peak's speed within 10 % of the thick-wall estimate
// (fails: see above) and within 5 % of the continuum's peak speed; with --convergence the
// same at h, dt x 0.7, and the error against the estimate not larger on the finer level
// beyond twice the two fits' combined standard error. CI's reduced form (--reduced --coarsen
// 1.5: dt 50 us, 300 steps, about 8 CPU minutes) checks the continuum alone and reports the
// estimate's error: it guards the solver's wave physics while the bound is open.
//
// Where the 3D tube differs from the continuum: the wall's axial waves (sqrt(E / rho_s) = 16
// m/s) carry a precursor, 20 % of the peak 3 ms ahead at 2.5 cm, and a negative tail, which
// move the centroid 7-8 % and the half-peak crossing 4 % below the continuum's; the front
// (P0 / 2, steepest rise) and the peak stay within 3 % of it (docs/performance.md). The run also
// splits the long-wave speed c^2 = k A / (rho dA/dp) into its measured factors (WaveBalance
// below).
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
#include "mesh/pipe_generator.hpp"
#include "verify/cases.hpp"
#include "verify/fsi_tube.hpp"
#include "verify/pulse_continuum.hpp"

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
double inlet_pressure(double t) {
  return P0 * smoothstep(t / t_edge) * (1.0 - smoothstep((t - t_pulse) / t_edge));
}

bc::Waveform inlet_pulse() {
  std::vector<double> t, v;
  const int n = 600;
  for (int i = 0; i <= n; ++i) {
    t.push_back(t_end * i / n);
    v.push_back(inlet_pressure(t.back()));
  }
  return bc::Waveform::periodic(t, v, 4.0 * t_end, "pulse inlet traction");
}

/// Boundary layers (see the file comment): six layers from 0.1 h growing by 1.5 to the
/// core, three through the wall.
mesh::BoundaryLayers pulse_layers(double element_size) {
  return {6, 0.1 * element_size, 1.5, 3};
}

/// Long-wave speed [m/s] of a fluid-filled tube of distensibility D [1/Pa].
double long_wave_speed(double D) {
  return 1.0 / std::sqrt(rho_f * D);
}

/// The tube for the continuum model (pulse_continuum.hpp) with long-wave speed c0 [m/s].
ContinuumTube continuum_tube(double c0) {
  return {a, h, rho_f, mu, rho_s, c0};
}

/// The arrival-time variants at one station [s]; NaN where a variant is undefined.
struct Arrival {
  double centroid = 0.0;  ///< int t p dt / int p dt up to the reflection
  double threshold = 0.0; ///< crossing of P0 / 2
  double own_peak = 0.0;  ///< crossing of half the station's peak
  double max_slope = 0.0; ///< largest dp/dt
  double peak = 0.0;      ///< the peak (primary: verification.md's measurement)
  double peak_pressure = 0.0, pulse_integral = 0.0; ///< [Pa], int p dt [Pa s]
};

/// Offset, in samples, of the vertex of the parabola through (-1, ym), (0, y0), (1, yp) from
/// its middle sample; 0 unless the parabola opens downwards (y0 a maximum).
double vertex_offset(double ym, double y0, double yp) {
  const double curv = ym - 2.0 * y0 + yp;
  return curv < 0.0 ? 0.5 * (ym - yp) / curv : 0.0;
}

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
  if (peak >= 1 && peak + 1 < n) // the parabola through the peak and its neighbours
    r.peak += vertex_offset(pw[peak - 1], pw[peak], pw[peak + 1]) * dt;
  r.own_peak = crossing(tw, pw, 0.5 * r.peak_pressure);
  // Largest dp/dt: differences at the step midpoints, refined by a parabola.
  size_t best = 1;
  for (size_t i = 1; i < n; ++i)
    if (pw[i] - pw[i - 1] > pw[best] - pw[best - 1])
      best = i;
  r.max_slope = tw[best] - 0.5 * dt;
  if (best >= 2 && best + 1 < n)
    r.max_slope += vertex_offset(pw[best - 1] - pw[best - 2], pw[best] - pw[best - 1],
                                 pw[best + 1] - pw[best]) *
                   dt;
  return r;
}

/// A speed fitted to the stations' arrival times.
struct Speed {
  double value = 0.0;          ///< least-squares slope dz/dt [m/s]
  double standard_error = 0.0; ///< of the slope, from the stations' scatter about the line [m/s]
};

Speed speed(const std::vector<double>& t) {
  const auto n = static_cast<double>(t.size());
  double tm = 0.0, zm = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    tm += t[i] / n;
    zm += kStations[i] / n;
  }
  double num = 0.0, den = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    num += (t[i] - tm) * (kStations[i] - zm);
    den += (t[i] - tm) * (t[i] - tm);
  }
  Speed s{num / den, 0.0};
  double scatter = 0.0;
  for (size_t i = 0; i < t.size(); ++i)
    scatter += std::pow(kStations[i] - zm - s.value * (t[i] - tm), 2);
  s.standard_error = std::sqrt(scatter / (n - 2.0) / den);
  return s;
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

/// The speeds of the five arrival variants, fitted over the stations.
struct Speeds {
  Speed centroid, threshold, own_peak, max_slope, peak;
};

/// Arrivals at the stations from the axis series p[k][i] (axis point k at z = k
/// axis_spacing, sample i at t[i]): each station's signal is the mean of the axis points at
/// z - 2.5 mm, z, z + 2.5 mm, integrated until the outlet's reflection (at speed c0) can
/// reach the farthest node of the three sections (slab: their half width).
std::vector<Arrival> station_arrivals(const std::vector<double>& t,
                                      const std::vector<std::vector<double>>& p, double slab,
                                      double c0) {
  std::vector<Arrival> arrivals;
  for (double z : kStations) {
    const auto k = static_cast<size_t>(std::lround(z / axis_spacing));
    std::vector<double> station(t.size());
    for (size_t i = 0; i < t.size(); ++i)
      station[i] = (p[k - 1][i] + p[k][i] + p[k + 1][i]) / 3.0;
    const double top = z + axis_spacing + slab;
    arrivals.push_back(arrival(t, station, (2.0 * L - top) / c0));
  }
  return arrivals;
}

Speeds fit_speeds(const std::vector<Arrival>& arrivals) {
  auto fit = [&](double Arrival::*variant) {
    std::vector<double> times;
    for (const Arrival& s : arrivals)
      times.push_back(s.*variant);
    return speed(times);
  };
  return {fit(&Arrival::centroid), fit(&Arrival::threshold), fit(&Arrival::own_peak),
          fit(&Arrival::max_slope), fit(&Arrival::peak)};
}

/// The same measurement on the linear continuum (pulse_continuum.hpp) of long-wave speed
/// c_long, sampled at the run's times t; c_cut: the speed the run's cut assumed.
Speeds continuum_speeds(double c_long, const std::vector<double>& t, double slab, double c_cut) {
  const PulseContinuum tube(continuum_tube(c_long), inlet_pressure, t_end);
  std::vector<std::vector<double>> p(static_cast<size_t>(std::lround(L / axis_spacing)) + 1);
  for (double z : kStations)
    for (int d : {-1, 0, 1}) {
      const auto k = static_cast<size_t>(std::lround(z / axis_spacing) + d);
      if (p[k].empty())
        p[k] = tube.pressure(static_cast<double>(k) * axis_spacing, t);
    }
  return fit_speeds(station_arrivals(t, p, slab, c_cut));
}

nlohmann::json to_json(const Speeds& s) {
  nlohmann::json j;
  for (auto [name, v] : {std::pair{"peak", s.peak},
                         {"centroid", s.centroid},
                         {"threshold", s.threshold},
                         {"half_own_peak", s.own_peak},
                         {"max_dpdt", s.max_slope}})
    j[fmt::format("speed_{}_m_per_s", name)] = v.value;
  j["speed_peak_standard_error_m_per_s"] = s.peak.standard_error;
  return j;
}

struct PulseRun {
  std::vector<Arrival> arrivals;
  Speeds speeds;
  Speeds continuum;      ///< the continuum's, for the axially free wall's long-wave speed
  Speeds continuum_held; ///< the same for the wall held axially (plane strain, c0)
  WaveBalance balance;
  int tets = 0, steps = 0, newton_max = 0, newton_total = 0, linear_total = 0;
  double element_size = 0.0, dt = 0.0, seconds = 0.0;
  std::string axis_csv;
};

PulseRun run_pulse(double element_size, double dt, double c0, double c_open,
                   const VerifyOptions& options) {
  FsiTubeSpec spec;
  spec.pipe = {a, L, element_size, h};
  spec.pipe.layers = pulse_layers(element_size);
  spec.fluid = {rho_f, mu};
  spec.wall =
      physics::SolidMaterial::from_young_poisson(physics::SolidModel::NeoHookean, E, nu, rho_s);
  spec.fluid_conditions.outlets = {{"inlet", bc::PressureOutlet{inlet_pulse()}, 0.0},
                                   {"outlet", bc::PressureOutlet{}}};
  spec.wall_conditions.fixed = {{"wall_inlet", 0b111, {}, 0.0}, {"wall_outlet", 0b111, {}, 0.0}};
  // Newton to 1e-9 of the load's force scale: arrival times move by far less than a step.
  spec.newton = {15, 1e-8, 1e-9 * P0 * a * a};
  spec.dt = dt;
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
    if (options.progress && fem::mpi_rank() == 0)
      fmt::print(stderr,
                 "pulse: t = {:.5f} s p(1.5, 2.5, 3.5 cm) = {:.1f} {:.1f} {:.1f} Pa "
                 "Newton {} KSP {}\n",
                 tube.time(), p[6].back(), p[10].back(), p[14].back(), r.newton_iterations,
                 r.linear_iterations);
  }
  run.arrivals = station_arrivals(t, p, slab, c0);
  run.speeds = fit_speeds(run.arrivals);
  // Until the front (at the estimate's speed, faster than the discrete wave) is 5 mm from
  // the outlet: Q(L) = 0 holds that long.
  run.balance = wave_balance(t, p, ur, (L - 0.005) / c0);
  run.continuum = continuum_speeds(c_open, t, slab, c0);
  run.continuum_held = continuum_speeds(c0, t, slab, c0);
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
                      {"continuum_axially_free_wall", to_json(r.continuum)},
                      {"continuum_wall_held_axially", to_json(r.continuum_held)},
                      {"wall_radial_compliance_m_per_Pa", r.balance.radial_compliance},
                      {"inertance_ratio", r.balance.inertance_ratio},
                      {"speed_from_compliance_and_inertance_m_per_s", r.balance.speed},
                      {"seconds", r.seconds}};
  j.update(to_json(r.speeds));
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
  // h 1 mm and dt 16.7 us by default; --coarsen 1.5: h 1.5 mm, dt 25 us. --reduced doubles
  // dt: 50 us still puts 25 steps in each 1.25 ms edge, and generalized-alpha's phase error,
  // (w dt)^2 / 12 at the edge's w = 2 pi / 2.5 ms, is 0.13 %, far inside the fits' 1.2-1.5 %.
  const double size = 1e-3 * options.coarsening,
               dt = (options.reduced ? 2.0 : 1.0) * 2.5e-5 * options.coarsening / 1.5;
  // The pipe generator asks the same (a core of at least 0.3 a); checked here on every rank
  // before any meshing, so that all stop together with one message.
  if (!(pulse_layers(size).thickness() < 0.7 * a))
    collective_input_error("verify pulse: --coarsen {} gives elements of {:.2f} mm, whose boundary "
                           "layers ({:.2f} mm) leave too small a core in the {} mm radius; "
                           "expected --coarsen 1.6 or less",
                           options.coarsening, 1e3 * size, 1e3 * pulse_layers(size).thickness(),
                           1e3 * a);
  const PulseRun coarse = run_pulse(size, dt, c_thick, c_open, options);
  // The measure: the peak's speed against the thick-wall estimate; and against the
  // continuum's peak speed for the same pulse, stations and cut, the wall free axially as
  // the reference's is between its clamped ends. Tolerance 5 %: the continuum model leaves
  // out the 3D wall's axial dynamics, which move the centroid 7-8 % and the half-peak
  // crossing 4 % from the model's and the front and the peak under 3 % (h 1.5 and 1.05 mm);
  // the peak fits' own standard error is 1.2-1.5 %, the continuum's too (the peak's speed
  // varies along the tube as it disperses); the no-slip layer's inertance error on a mesh
  // without boundary layers costs the peak 10 %, which the tolerance must catch.
  auto estimate_error = [&](const PulseRun& r) {
    return std::abs(r.speeds.peak.value - c_thick) / c_thick;
  };
  auto continuum_error = [](const PulseRun& r) {
    return std::abs(r.speeds.peak.value - r.continuum.peak.value) / r.continuum.peak.value;
  };

  VerificationResult res;
  res.name = "pulse";
  // The reduced form (CI) checks the solver against its continuum and only reports the
  // estimate, which the exact solution misses too (file comment): the full form checks it.
  const Metric against_estimate{"wave_speed_relative_error", estimate_error(coarse), 0.10,
                                "|c (arrival of the pressure peak, z = 1.25-2.5 cm) - "
                                "thick-wall Lame estimate| / estimate; 10 % (issue 10)"};
  if (!options.reduced)
    res.metrics.push_back(against_estimate);
  res.metrics.push_back({"wave_speed_vs_continuum", continuum_error(coarse), 0.05,
                         "|c (peak) - the linear continuum's c (peak), same pulse, stations and "
                         "cut, wall free axially| / continuum's; 5 % (the model's 3D omissions)"});
  res.details = {{"thick_wall_estimate_m_per_s", c_thick},
                 {"thick_wall_open_ended_m_per_s", c_open},
                 {"moens_korteweg_thin_wall_m_per_s", c_mk},
                 {"moens_korteweg_plate_m_per_s", c_mk_plate},
                 {"short_wave_speed_pulse_fundamental_m_per_s",
                  dispersive_speed(continuum_tube(c_thick), k_pulse)},
                 {"edge_s", t_edge},
                 {"stations_m", kStations},
                 {"runs", nlohmann::json::array({to_json(coarse)})}};
  if (options.reduced)
    res.details["wave_speed_relative_error_not_checked"] = against_estimate.value;
  if (options.convergence) {
    const PulseRun fine = run_pulse(0.7 * size, 0.7 * dt, c_thick, c_open, options);
    res.details["runs"].push_back(to_json(fine));
    res.metrics.push_back({"wave_speed_relative_error_refined", estimate_error(fine), 0.10,
                           "the same at h, dt x 0.7; 10 % (issue 10)"});
    res.metrics.push_back({"wave_speed_vs_continuum_refined", continuum_error(fine), 0.05,
                           "the same at h, dt x 0.7; 5 %"});
    // Refinement must not move the speed away from the estimate beyond what the two fits can
    // tell apart: twice their combined standard error.
    const double resolution =
        2.0 * std::hypot(coarse.speeds.peak.standard_error, fine.speeds.peak.standard_error) /
        c_thick;
    res.metrics.push_back({"refinement_error_growth", estimate_error(fine) - estimate_error(coarse),
                           resolution,
                           "error at h, dt x 0.7 minus error at h, dt; at most twice the fits' "
                           "combined standard error (must not grow)"});
  }
  return res;
}

} // namespace tearflow::verify
