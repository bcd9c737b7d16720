#include "run/cycle_summary.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::run {

namespace {
/// Trapezoidal integral of v over the samples' times.
double integral(const std::vector<double>& t, const std::vector<double>& v) {
  double s = 0.0;
  for (size_t k = 1; k < t.size(); ++k)
    s += 0.5 * (t[k] - t[k - 1]) * (v[k] + v[k - 1]);
  return s;
}

double peak_magnitude(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  return m;
}
} // namespace

CycleStats summarize_cycle(const CycleSamples& samples) {
  const std::vector<double>& t = samples.time;
  if (t.size() < 2)
    throw std::logic_error("a cycle needs at least two samples");
  CycleStats stats;
  stats.cycle = samples.cycle;
  stats.t_begin = t.front();
  stats.t_end = t.back();
  const double duration = t.back() - t.front();
  double outflow = 0.0;
  for (const FaceSeries& f : samples.faces) {
    FaceCycleStats s;
    s.face = f.face;
    s.systolic = *std::max_element(f.pressure.begin(), f.pressure.end());
    s.diastolic = *std::min_element(f.pressure.begin(), f.pressure.end());
    s.mean = integral(t, f.pressure) / duration;
    s.volume = integral(t, f.flow);
    if (!f.reversed.empty())
      s.reversed_volume = -integral(t, f.reversed);
    if (f.outlet)
      outflow += s.volume;
    stats.faces.push_back(s);
  }
  for (size_t i = 0; i < samples.faces.size(); ++i)
    if (samples.faces[i].outlet && outflow != 0.0)
      stats.faces[i].split_percent = 100.0 * stats.faces[i].volume / outflow;
  return stats;
}

double cycle_change(const CycleSamples& previous, const CycleSamples& current) {
  if (previous.time.size() != current.time.size() || previous.faces.size() != current.faces.size())
    throw std::logic_error("cycles of different lengths cannot be compared");
  double change = 0.0;
  for (size_t i = 0; i < current.faces.size(); ++i) {
    const FaceSeries &a = previous.faces[i], &b = current.faces[i];
    if (!b.outlet)
      continue;
    for (const auto member : {&FaceSeries::flow, &FaceSeries::pressure}) {
      const std::vector<double>&x = a.*member, &y = b.*member;
      const double scale = peak_magnitude(y);
      if (scale == 0.0)
        continue;
      for (size_t k = 0; k < y.size(); ++k)
        change = std::max(change, std::abs(y[k] - x[k]) / scale);
    }
  }
  return change;
}

double metrics_change(const CycleStats& previous, const CycleStats& current) {
  if (previous.faces.size() != current.faces.size())
    throw std::logic_error("cycles of different faces cannot be compared");
  double change = 0.0;
  for (size_t i = 0; i < current.faces.size(); ++i) {
    const FaceCycleStats &a = previous.faces[i], &b = current.faces[i];
    if (b.split_percent && a.split_percent) { // an outlet
      change = std::max(change, std::abs(*b.split_percent - *a.split_percent) / 100.0);
      continue;
    }
    if (b.volume >= 0.0)
      continue; // not an inlet (no net inflow): a wall, the fluid-wall interface
    for (const auto member :
         {&FaceCycleStats::systolic, &FaceCycleStats::diastolic, &FaceCycleStats::mean})
      if (b.*member != 0.0)
        change = std::max(change, std::abs(b.*member - a.*member) / std::abs(b.*member));
  }
  return change;
}

nlohmann::json cycles_to_json(double period, const std::vector<CycleStats>& cycles) {
  nlohmann::json out;
  out["period_s"] = period;
  out["cycles"] = nlohmann::json::array();
  for (const CycleStats& c : cycles) {
    nlohmann::json j;
    j["cycle"] = c.cycle + 1;
    j["t_begin_s"] = c.t_begin;
    j["t_end_s"] = c.t_end;
    j["change_from_previous"] = c.change ? nlohmann::json(*c.change) : nlohmann::json();
    for (const FaceCycleStats& f : c.faces) {
      nlohmann::json& g = j["faces"][f.face];
      g["systolic_pressure_Pa"] = f.systolic;
      g["diastolic_pressure_Pa"] = f.diastolic;
      g["mean_pressure_Pa"] = f.mean;
      g["systolic_pressure_mmHg"] = f.systolic / units::mmHg;
      g["diastolic_pressure_mmHg"] = f.diastolic / units::mmHg;
      g["mean_pressure_mmHg"] = f.mean / units::mmHg;
      g["net_outflow_volume_m3"] = f.volume;
      g["net_outflow_volume_mL"] = f.volume / units::mL;
      g["reversed_volume_mL"] = f.reversed_volume / units::mL;
      g["flow_split_percent"] =
          f.split_percent ? nlohmann::json(*f.split_percent) : nlohmann::json();
    }
    out["cycles"].push_back(j);
  }
  return out;
}

} // namespace tearflow::run
