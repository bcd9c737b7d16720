#include "analysis/hemodynamics.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <vtkUnstructuredGrid.h>

#include "analysis/measured_data.hpp"
#include "analysis/run_form.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "io/vtu_series.hpp"

namespace tearflow::analysis {

namespace {

using nlohmann::json;
using Sampler = std::function<double(const SectionValues&)>;

const Sampler flow_of = [](const SectionValues& v) { return v.flow; };
const Sampler area_of = [](const SectionValues& v) { return v.area; };
const Sampler pressure_of = [](const SectionValues& v) { return v.pressure; };

const Sampler displacement_of = [](const SectionValues& v) { return v.wall_displacement; };

bool all_finite(const std::vector<double>& f) {
  return std::all_of(f.begin(), f.end(), [](double x) { return std::isfinite(x); });
}

/// Largest value; NaN when any sample is (a quantity a measurement does not give).
double largest(const std::vector<double>& f) {
  return all_finite(f) ? *std::max_element(f.begin(), f.end()) : std::nan("");
}

std::vector<double> sampled(const LandmarkSeries& s, const Sampler& f) {
  std::vector<double> out;
  for (const SectionValues& v : s.samples)
    out.push_back(f(v));
  return out;
}

/// int f dt by the trapezoidal rule over the frames.
double integral(const std::vector<double>& t, const std::vector<double>& f) {
  double sum = 0;
  for (std::size_t i = 1; i < t.size(); ++i)
    sum += 0.5 * (t[i] - t[i - 1]) * (f[i] + f[i - 1]);
  return sum;
}

json pressure_json(const std::string& stem, double p) {
  return {{stem + "_Pa", p}, {stem + "_mmHg", p / units::mmHg}};
}

// Names of the study's pressure landmarks, in its order.
bool is_pressure_landmark(const geometry::Landmark& l) {
  return l.name == "inlet" || l.name == "outlet" || station_of(l) > 0;
}

json landmark_json(const Analysis& a, const LandmarkSeries& s) {
  const std::vector<double> q = sampled(s, flow_of), area = sampled(s, area_of),
                            p = sampled(s, pressure_of);
  const double u_max = largest(sampled(s, [](const SectionValues& v) { return v.max_velocity; }));
  const double a0 = area.front(), a_max = largest(area);
  json j{{"lumen", s.landmark.lumen},
         {"net_flow_volume_m3", integral(a.time, q)},
         {"net_flow_volume_mL", integral(a.time, q) / units::mL},
         {"mean_flow_m3_per_s", time_mean(a.time, q)},
         {"peak_flow_m3_per_s", largest(q)},
         {"A_0_m2", a0},
         {"A_0_mm2", a0 / (units::mm * units::mm)},
         {"A_max_m2", a_max},
         {"A_max_mm2", a_max / (units::mm * units::mm)},
         {"A_mean_m2", time_mean(a.time, area)},
         {"A_mean_mm2", time_mean(a.time, area) / (units::mm * units::mm)},
         {"A_max_over_A_0", a_max / a0},
         {"A_peak_systole_mm2", area[a.peak_systole] / (units::mm * units::mm)},
         {"max_through_plane_velocity_m_per_s", u_max},
         {"max_wall_displacement_mm", largest(sampled(s, displacement_of)) / units::mm}};
  j.update(pressure_json("mean_pressure", time_mean(a.time, p)));
  j.update(pressure_json("peak_systolic_pressure", p[a.peak_systole]));
  j.update(pressure_json("end_diastolic_pressure", p[a.end_diastole]));
  return j;
}

/// What the analysed cycle achieved at the run's faces (cycles.json): the inflow face's
/// (the one with the most negative net outflow) systolic, diastolic and mean pressure, and
/// every outlet's flow split; what tuning aims at (docs/tuning.md).
json achieved_json(const json& cycle) {
  json out = json::object();
  if (!cycle.is_object() || !cycle.contains("faces") || !cycle["faces"].is_object())
    return out;
  const json& faces = cycle["faces"];
  std::string inlet;
  double most_in = 0;
  for (const auto& [name, f] : faces.items()) {
    const json v = f.value("net_outflow_volume_m3", json(nullptr));
    if (v.is_number() && v.get<double>() < most_in) {
      most_in = v.get<double>();
      inlet = name;
    }
    if (f.contains("flow_split_percent") && f["flow_split_percent"].is_number())
      out["flow_split_percent"][name] = f["flow_split_percent"];
  }
  if (!inlet.empty()) {
    out["inlet_face"] = inlet;
    for (const char* q : {"systolic", "diastolic", "mean"})
      out[fmt::format("inlet_{}_pressure_mmHg", q)] =
          faces[inlet].value(fmt::format("{}_pressure_mmHg", q), json(nullptr));
  }
  return out;
}

} // namespace

double time_mean(const std::vector<double>& t, const std::vector<double>& f) {
  return t.size() < 2 ? f.front() : integral(t, f) / (t.back() - t.front());
}

double interpolate(const std::vector<double>& t, const std::vector<double>& f, double at) {
  if (at <= t.front())
    return f.front();
  if (at >= t.back())
    return f.back();
  const std::size_t i = std::upper_bound(t.begin(), t.end(), at) - t.begin();
  const double w = (at - t[i - 1]) / (t[i] - t[i - 1]);
  return (1.0 - w) * f[i - 1] + w * f[i];
}

const std::vector<double>& LandmarkTable::column(const std::string& name) const {
  const auto it = columns.find(name);
  if (it == columns.end())
    input_error("{}: no column '{}'", file.string(), name);
  return it->second;
}

LandmarkTable read_landmark_table(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in)
    input_error("{}: cannot read (written by `tearflow analyze`: run it first)", csv.string());
  LandmarkTable t{csv, {}, {}};
  std::string line, cell;
  std::getline(in, line);
  for (std::istringstream h(line); std::getline(h, cell, ',');)
    t.names.push_back(cell);
  for (const std::string& c : t.names)
    t.columns[c];
  for (int row = 2; std::getline(in, line); ++row) {
    std::istringstream r(line);
    for (const std::string& c : t.names) {
      if (!std::getline(r, cell, ','))
        input_error("'{}' line {}: {} columns expected", csv.string(), row, t.names.size());
      try {
        t.columns[c].push_back(std::stod(cell));
      } catch (const std::exception&) {
        input_error("'{}' line {}, column {}: '{}' is not a number", csv.string(), row, c, cell);
      }
    }
  }
  return t;
}

const LandmarkSeries* Analysis::find(const std::string& name) const {
  for (const LandmarkSeries& s : series)
    if (s.landmark.name == name)
      return &s;
  return nullptr;
}

std::vector<FlowFrame> select_frames(const AnalyzeOptions& o, std::string& label, json* cycle) {
  std::vector<FlowFrame> frames = read_pvd(RunFiles{o.run_dir}.flow_pvd());
  if (o.all_frames) {
    label = "all saved frames";
    return frames;
  }
  const std::filesystem::path file = RunFiles{o.run_dir}.cycles_json();
  std::ifstream in(file);
  if (!in)
    input_error("'{}' does not exist: the run has no complete cardiac cycle (or no period); "
                "use --frames all to analyse every saved frame",
                file.string());
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    input_error("'{}': not valid JSON: {}", file.string(), e.what());
  }
  const json cycles = j.value("cycles", json::array());
  if (!cycles.is_array() || cycles.empty())
    input_error("'{}': the run has no complete cardiac cycle; use --frames all to analyse "
                "every saved frame",
                file.string());
  json chosen = cycles.back();
  if (o.cycle) {
    const auto it = std::find_if(cycles.begin(), cycles.end(),
                                 [&](const json& c) { return c.value("cycle", -1) == *o.cycle; });
    if (it == cycles.end())
      input_error("'{}': no complete cycle {} (the run completed cycles 1 to {})", file.string(),
                  *o.cycle, cycles.back().value("cycle", 0));
    chosen = *it;
  }
  const double t0 = chosen.at("t_begin_s").get<double>(), t1 = chosen.at("t_end_s").get<double>();
  // Frame times are printed with 10 significant digits (io/vtu_series.cpp).
  const double slack = 1e-9 * std::max(1.0, std::abs(t1)) + 1e-12;
  std::erase_if(frames,
                [&](const FlowFrame& f) { return f.time < t0 - slack || f.time > t1 + slack; });
  const int number = chosen.value("cycle", 0);
  if (frames.size() < 2)
    input_error("'{}': cycle {} (t = {} to {} s) holds {} saved frame(s) in flow.pvd; the "
                "analysis needs at least two (save frames more often: output.every)",
                file.string(), number, t0, t1, frames.size());
  label = fmt::format("cycle {}", number);
  if (cycle != nullptr)
    *cycle = chosen;
  return frames;
}

Analysis analyze_run(const AnalyzeOptions& o) {
  if (!std::filesystem::exists(RunFiles{o.run_dir}.flow_pvd())) {
    if (!is_measurement_folder(o.run_dir))
      input_error("'{}' holds neither a run's output (flow.pvd) nor a measurement table "
                  "(flow.csv, area.csv, pressure.csv; docs/analysis.md)",
                  o.run_dir.string());
    if (o.cycle || o.all_frames)
      input_error("'{}' holds measurements (one cycle): --cycle and --frames do not apply",
                  o.run_dir.string());
    return read_measured(o.run_dir);
  }
  const std::filesystem::path landmarks_file =
      o.landmarks.empty() ? RunFiles{o.run_dir}.geometry().landmarks() : o.landmarks;
  const geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_file);
  Analysis a;
  const std::vector<FlowFrame> frames = select_frames(o, a.frames, &a.cycle);
  for (const geometry::Landmark& l : landmarks.planes)
    a.series.push_back({l, {}});
  // The conservative flux needs the run's continuity form and du/dt, from the saved frames on
  // either side of each analysed one (also outside the analysed cycle).
  std::optional<ContinuityForm> form = find_continuity_form(o.run_dir, o.case_file);
  a.flow_method = form ? "conservative" : "plane_integral";
  const std::vector<double> steps = form ? step_times(o.run_dir) : std::vector<double>{};
  const std::vector<FlowFrame> saved = read_pvd(RunFiles{o.run_dir}.flow_pvd());
  std::map<std::filesystem::path, vtkSmartPointer<vtkUnstructuredGrid>> read;
  auto frame = [&](std::size_t i) {
    auto& grid = read[saved[i].file];
    if (!grid)
      grid = read_flow_frame(saved[i].file);
    return grid;
  };
  // The continuity state of the step that ended at saved frame i: its stage when the frame
  // before is that step's start, else the estimate from frame i; none for the initial state.
  std::shared_ptr<const WallTriangles> wall; // the run's: one mesh for every frame
  const auto state_of = [&](std::size_t i) -> std::optional<ContinuityState> {
    if (!form)
      return std::nullopt;
    if (!wall)
      wall = std::make_shared<const WallTriangles>(wall_triangles(frame(i)));
    const std::optional<double> dt = step_ending_at(steps, saved[i].time, form->time_step);
    if (!dt)
      return std::nullopt;
    ContinuityForm at = *form;
    at.time_step = *dt;
    const double slack = 1e-6 * *dt;
    if (i > 0 && std::abs(saved[i].time - saved[i - 1].time - *dt) < slack &&
        has_acceleration(frame(i)) && has_acceleration(frame(i - 1)))
      return step_stage(frame(i - 1), frame(i), at, wall);
    const std::size_t before = i > 0 ? i - 1 : i, after = i + 1 < saved.size() ? i + 1 : i;
    FrameDifferences rates;
    if (before != after)
      rates = frame_differences(frame(before), saved[before].time, frame(after), saved[after].time);
    return frame_state(frame(i), rates.rates(), at, wall);
  };
  const auto index_of = [&](const FlowFrame& f) {
    return static_cast<std::size_t>(
        std::find_if(saved.begin(), saved.end(),
                     [&](const FlowFrame& s) { return s.file == f.file; }) -
        saved.begin());
  };
  // A stage's flows are at t_n + alpha_f dt. Two consecutive stages extrapolate them to the
  // frame's t_{n+1}: F(t_{n+1}) = (2 - alpha_f) F_{n+1} - (1 - alpha_f) F_n (second order,
  // as the scheme); a linear combination of balanced fluxes balances as they do.
  std::vector<SectionValues> previous_stage; // of saved frame i - 1, when it was a stage
  std::size_t previous_index = saved.size();
  const double af = form ? form->scheme.alpha_f : 1.0;
  for (const FlowFrame& f : frames) {
    const std::size_t i = index_of(f);
    const std::optional<ContinuityState> state = state_of(i);
    const bool stage = state && state->exact;
    if (stage && i > 0 && previous_index != i - 1) { // the first frame: its step's start too
      const std::optional<ContinuityState> before = state_of(i - 1);
      previous_stage.clear();
      if (before && before->exact)
        previous_stage = measure_landmarks(frame(i - 1), landmarks, saved[i - 1].file.string(),
                                           &*before, &*form);
      previous_index = i - 1;
    }
    std::vector<SectionValues> v = measure_landmarks(
        frame(i), landmarks, f.file.string(), state ? &*state : nullptr, form ? &*form : nullptr);
    const std::vector<SectionValues> at_stage = stage ? v : std::vector<SectionValues>{};
    if (stage && !previous_stage.empty() && previous_index + 1 == i)
      for (std::size_t k = 0; k < v.size(); ++k) {
        v[k].flow = (2.0 - af) * v[k].flow - (1.0 - af) * previous_stage[k].flow;
        v[k].wall_outflow =
            (2.0 - af) * v[k].wall_outflow - (1.0 - af) * previous_stage[k].wall_outflow;
      }
    a.stage_frames += stage ? 1 : 0;
    previous_stage = at_stage;
    previous_index = i;
    for (std::size_t k = 0; k < v.size(); ++k)
      a.series[k].samples.push_back(v[k]);
    a.time.push_back(f.time);
    std::erase_if(read, [&](const auto& r) {
      return r.first != saved[i].file && (i + 1 >= saved.size() || r.first != saved[i + 1].file);
    });
  }
  mark_cycle_events(a);
  return a;
}

void mark_cycle_events(Analysis& a) {
  const LandmarkSeries* reference = a.find("inlet");
  if (reference == nullptr || !all_finite(sampled(*reference, flow_of)))
    for (const LandmarkSeries& s : a.series)
      if (all_finite(sampled(s, flow_of))) {
        reference = &s;
        break;
      }
  a.peak_systole = 0;
  if (reference != nullptr) {
    const std::vector<double> q = sampled(*reference, flow_of);
    a.peak_systole = static_cast<std::size_t>(std::max_element(q.begin(), q.end()) - q.begin());
  }
  a.end_diastole = 0;
}

json metrics_json(const Analysis& a) {
  json j{{"source", a.source},
         {"frames", a.frames},
         {"flow_method", a.flow_method},
         {"flow_stage_frames", a.stage_frames},
         {"frame_count", a.time.size()},
         {"t_begin_s", a.time.front()},
         {"t_end_s", a.time.back()},
         {"peak_systole_time_s", a.time[a.peak_systole]},
         {"end_diastole_time_s", a.time[a.end_diastole]}};
  json landmarks = json::object();
  for (const LandmarkSeries& s : a.series)
    landmarks[s.landmark.name] = landmark_json(a, s);

  // Paired stations.
  std::map<int, std::pair<const LandmarkSeries*, const LandmarkSeries*>> stations;
  for (const LandmarkSeries& s : a.series)
    if (const int k = station_of(s.landmark); k > 0)
      (s.landmark.lumen == "TL" ? stations[k].first : stations[k].second) = &s;
  json station_json = json::object();
  const LandmarkSeries *prox = a.find("DAo_prox"), *dist = a.find("DAo_dist");
  for (const auto& [k, pair] : stations) {
    const auto [tl, fl] = pair;
    if (!tl || !fl)
      continue;
    const double q_tl = time_mean(a.time, sampled(*tl, flow_of)),
                 q_fl = time_mean(a.time, sampled(*fl, flow_of));
    std::vector<double> dp;
    for (std::size_t i = 0; i < a.time.size(); ++i)
      dp.push_back(tl->samples[i].pressure - fl->samples[i].pressure);
    json s{{"FR_FL_percent", q_fl / (q_fl + q_tl) * 100.0},
           {"mean_flow_TL_m3_per_s", q_tl},
           {"mean_flow_FL_m3_per_s", q_fl}};
    s.update(pressure_json("dP_TL_minus_FL_peak_systole", dp[a.peak_systole]));
    s.update(pressure_json("dP_TL_minus_FL_end_diastole", dp[a.end_diastole]));
    s.update(pressure_json("dP_TL_minus_FL_mean", time_mean(a.time, dp)));
    // The flap's excursion over the cycle toward the FL (FSI runs): its largest minus its
    // smallest displacement at the station.
    if (const std::vector<double> flap =
            sampled(*tl, [](const SectionValues& v) { return v.flap_displacement; });
        all_finite(flap)) {
      const auto [lo, hi] = std::minmax_element(flap.begin(), flap.end());
      s["flap_excursion_mm"] = (*hi - *lo) / units::mm;
      s["flap_displacement_peak_systole_minus_end_diastole_mm"] =
          (flap[a.peak_systole] - flap[a.end_diastole]) / units::mm;
    }
    // Q_TL + Q_FL against the undivided aorta above and below the dissection: the largest
    // difference over the frames relative to the reference's peak |Q|. For a simulation also
    // that of the plane integrals of the interpolated velocity, which the discretisation does
    // not conserve (analysis/conservative_flux.hpp): what the conservative flux corrects.
    const auto conservation = [&](const LandmarkSeries& ref, double SectionValues::*q,
                                  const std::string& stem) {
      double worst = 0, peak = 0, stored = 0;
      for (std::size_t i = 0; i < a.time.size(); ++i) {
        // On a moving wall the volume between the planes changes at W_station - W_ref.
        const SectionValues &t = tl->samples[i], &f = fl->samples[i];
        const double downstream =
            t.wall_outflow + (f.wall_part != t.wall_part ? f.wall_outflow : 0.0);
        const double stored_rate = downstream - ref.samples[i].wall_outflow;
        stored = std::max(stored, std::abs(stored_rate));
        const double sum = tl->samples[i].*q + fl->samples[i].*q;
        const double difference = std::abs(sum - stored_rate - ref.samples[i].*q);
        worst = std::isnan(difference) || std::isnan(worst) ? std::nan("")
                                                            : std::max(worst, difference);
        peak = std::max(peak, std::abs(ref.samples[i].*q));
      }
      if (std::isnan(worst))
        return; // a measurement without these flows
      s[stem + "_max_abs_difference_m3_per_s"] = worst;
      s[stem + "_relative_to_peak"] = peak > 0 ? json(worst / peak) : json(nullptr);
      s[stem + "_stored_volume_rate_max_abs_m3_per_s"] = stored;
    };
    for (const auto& [name, ref] : {std::pair{"DAo_prox", prox}, {"DAo_dist", dist}}) {
      if (!ref)
        continue;
      conservation(*ref, &SectionValues::flow, fmt::format("flow_conservation_vs_{}", name));
      if (a.flow_method == "conservative")
        conservation(*ref, &SectionValues::flow_interpolated,
                     fmt::format("flow_conservation_interpolated_vs_{}", name));
    }
    station_json[std::to_string(k)] = s;
  }

  // Pressures along the dissection relative to the inlet, at peak systole.
  json normalised = json::object(), drops = json::object();
  if (const LandmarkSeries* inlet = a.find("inlet")) {
    const double p_in = inlet->samples[a.peak_systole].pressure;
    for (const LandmarkSeries& s : a.series)
      if (is_pressure_landmark(s.landmark))
        normalised[s.landmark.name] = s.samples[a.peak_systole].pressure / p_in;
  }
  auto drop = [&](const char* key, const char* from, const char* to) {
    const LandmarkSeries *f = a.find(from), *t = a.find(to);
    if (!f || !t)
      return;
    const double ps = f->samples[a.peak_systole].pressure - t->samples[a.peak_systole].pressure;
    const double mean =
        time_mean(a.time, sampled(*f, pressure_of)) - time_mean(a.time, sampled(*t, pressure_of));
    json d = pressure_json("peak_systole", ps);
    d.update(pressure_json("mean", mean));
    drops[key] = d;
  };
  drop("entry_tear_inlet_to_FL1", "inlet", "FL1");
  drop("exit_tear_FL5_to_outlet", "FL5", "outlet");
  drop("inlet_to_outlet", "inlet", "outlet");

  // Min-to-max dilation at AAo, as a diameter change: D ~ sqrt(A), so sqrt(A_max / A_min) - 1.
  if (const LandmarkSeries* aao = a.find("AAo")) {
    const std::vector<double> area = sampled(*aao, area_of);
    const auto [lo, hi] = std::minmax_element(area.begin(), area.end());
    if (all_finite(area))
      j["AAo_min_to_max_dilation_percent"] = (std::sqrt(*hi / *lo) - 1.0) * 100.0;
  }
  if (const json achieved = achieved_json(a.cycle); !achieved.empty())
    j["achieved"] = achieved;
  j["landmarks"] = landmarks;
  j["stations"] = station_json;
  j["peak_systolic_pressure_over_inlet"] = normalised;
  j["pressure_drops"] = drops;
  return j;
}

void write_analysis(const Analysis& a, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  io::write_file_atomically(dir / RunFiles::kMetrics, metrics_json(a).dump(2) + "\n");
  for (const LandmarkSeries& s : a.series) {
    std::string csv = "time_s,flow_m3_per_s,flow_mL_per_s,area_m2,area_mm2,area_over_A_0,"
                      "mean_pressure_Pa,mean_pressure_mmHg,max_through_plane_velocity_m_per_s,"
                      "wall_displacement_mm,flow_interpolated_m3_per_s,"
                      "flap_displacement_toward_FL_mm\n";
    const double a0 = s.samples.front().area;
    for (std::size_t i = 0; i < a.time.size(); ++i) {
      const SectionValues& v = s.samples[i];
      csv += fmt::format("{:.10g},{:.10e},{:.10g},{:.10e},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{"
                         ":.10g},{:.10e},{:.10g}\n",
                         a.time[i], v.flow, v.flow / units::mL, v.area,
                         v.area / (units::mm * units::mm), v.area / a0, v.pressure,
                         v.pressure / units::mmHg, v.max_velocity, v.wall_displacement / units::mm,
                         v.flow_interpolated, v.flap_displacement / units::mm);
    }
    io::write_file_atomically(dir / (s.landmark.name + ".csv"), csv);
  }
  // dP(t) at the paired stations, one column per station.
  std::vector<std::pair<const LandmarkSeries*, const LandmarkSeries*>> pairs;
  std::string header = "time_s";
  for (const LandmarkSeries& tl : a.series) {
    const int k = station_of(tl.landmark);
    if (k == 0 || tl.landmark.lumen != "TL")
      continue;
    if (const LandmarkSeries* fl = a.find(fmt::format("FL{}", k))) {
      pairs.push_back({&tl, fl});
      header += fmt::format(",dP{}_TL_minus_FL_Pa", k);
    }
  }
  if (pairs.empty())
    return;
  std::string csv = header + "\n";
  for (std::size_t i = 0; i < a.time.size(); ++i) {
    csv += fmt::format("{:.10g}", a.time[i]);
    for (const auto& [tl, fl] : pairs)
      csv += fmt::format(",{:.10g}", tl->samples[i].pressure - fl->samples[i].pressure);
    csv += "\n";
  }
  io::write_file_atomically(dir / "pressure_difference.csv", csv);
}

} // namespace tearflow::analysis
