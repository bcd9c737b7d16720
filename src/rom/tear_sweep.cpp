#include "rom/tear_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/durable_file.hpp"

namespace tearflow::rom {

namespace {

double parse_number(const std::string& s, const std::string& option, const std::string& whole) {
  try {
    size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && v > 0.0 && std::isfinite(v))
      return v;
  } catch (const std::exception&) {
  }
  input_error("{} '{}': '{}' is not a tear area in mm^2 (a number > 0)", option, whole, s);
}

std::pair<double, double> parse_range(const std::string& s, const std::string& option) {
  const auto colon = s.find(':');
  if (colon == std::string::npos)
    input_error("{} '{}': expected MIN:MAX in mm^2, e.g. 30:300", option, s);
  const double lo = parse_number(s.substr(0, colon), option, s);
  const double hi = parse_number(s.substr(colon + 1), option, s);
  if (!(hi > lo))
    input_error("{} '{}': MAX must exceed MIN", option, s);
  return {lo, hi};
}

} // namespace

SweepSpec parse_sweep(const std::string& entry, const std::string& exit, int steps,
                      const std::vector<std::string>& marks) {
  SweepSpec s;
  std::tie(s.entry_min, s.entry_max) = parse_range(entry, "--entry");
  std::tie(s.exit_min, s.exit_max) = parse_range(exit, "--exit");
  if (steps < 2)
    input_error("--steps {}: at least 2 grid points per tear", steps);
  s.steps = steps;
  for (const std::string& m : marks) {
    const auto eq = m.find('=');
    const auto colon = m.find(':', eq == std::string::npos ? 0 : eq);
    if (eq == std::string::npos || colon == std::string::npos || eq == 0)
      input_error("--mark '{}': expected NAME=ENTRY:EXIT in mm^2, e.g. EN=62:227", m);
    s.marks.push_back({m.substr(0, eq), parse_number(m.substr(eq + 1, colon - eq - 1), "--mark", m),
                       parse_number(m.substr(colon + 1), "--mark", m)});
  }
  return s;
}

SweepRow station_metrics(const analysis::Analysis& a) {
  SweepRow row;
  for (int k = 1;; ++k) {
    const analysis::LandmarkSeries* tl = a.find(fmt::format("TL{}", k));
    const analysis::LandmarkSeries* fl = a.find(fmt::format("FL{}", k));
    if (!tl || !fl)
      break;
    std::vector<double> qt, qf;
    for (size_t f = 0; f < a.time.size(); ++f)
      qt.push_back(tl->samples[f].flow), qf.push_back(fl->samples[f].flow);
    const double mt = analysis::time_mean(a.time, qt), mf = analysis::time_mean(a.time, qf);
    row.fr_fl.push_back(100.0 * mf / (mf + mt));
    auto dp = [&](size_t f) {
      return (tl->samples[f].pressure - fl->samples[f].pressure) / units::mmHg;
    };
    row.dp_systole.push_back(dp(a.peak_systole));
    row.dp_diastole.push_back(dp(a.end_diastole));
  }
  return row;
}

SweepResult sweep_tears(const DissectionGeometry& g, const RomInputs& in, const RomCoefficients& k,
                        const SweepSpec& spec, bool progress) {
  for (const char* name : {"entry", "exit"})
    if (std::none_of(g.tears.begin(), g.tears.end(),
                     [&](const GeometryTear& t) { return t.name == name; }))
      input_error("rom sweep: the model has no tear '{}' (a sweep varies 'entry' and 'exit')",
                  name);
  geometry::Landmarks stations; // only the paired stations are measured
  for (const GeometryNode& n : g.nodes)
    if ((n.lumen == "TL" || n.lumen == "FL") && !n.partner.empty() &&
        n.name.find('_') == std::string::npos)
      stations.planes.push_back({n.name, n.position, {0, 0, 1}, n.lumen, n.position});
  stations.planes.push_back({"inlet", {}, {0, 0, 1}, "aorta", std::nullopt});
  IntegrationOptions opt;
  opt.steps_per_cycle = spec.steps_per_cycle;
  opt.samples_per_cycle = spec.steps_per_cycle % 100 == 0 ? 100 : spec.steps_per_cycle;
  // Periodic to 0.05 mmHg: 60 times finer than the maps' accuracy (3 mmHg, docs/rom.md).
  opt.pressure_tolerance = 0.05 * units::mmHg;
  SweepResult r;
  const auto start = std::chrono::steady_clock::now();
  const int total = spec.steps * spec.steps;
  for (int i = 0; i < spec.steps; ++i)
    for (int j = 0; j < spec.steps; ++j) {
      const double e = spec.entry_min + (spec.entry_max - spec.entry_min) * i / (spec.steps - 1);
      const double x = spec.exit_min + (spec.exit_max - spec.exit_min) * j / (spec.steps - 1);
      const Prediction p =
          predict(g, in, k, stations, {{"entry", e * 1e-6}, {"exit", x * 1e-6}}, opt);
      SweepRow row = station_metrics(p.analysis);
      row.entry = e, row.exit = x, row.cycles = p.solution.cycles;
      r.rows.push_back(std::move(row));
      const int done = static_cast<int>(r.rows.size());
      if (progress && (done * 10 / total != (done - 1) * 10 / total || done == total))
        fmt::print("sweep: {}/{} variants, {:.1f} s\n", done, total,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

namespace {

/// A colour for v in [lo, hi]: viridis-like for one-signed maps, blue-white-red around 0 for
/// pressure differences that change sign.
std::string colour(double v, double lo, double hi, bool diverging) {
  auto rgb = [](double r, double g, double b) {
    return fmt::format("#{:02x}{:02x}{:02x}", int(255 * std::clamp(r, 0.0, 1.0)),
                       int(255 * std::clamp(g, 0.0, 1.0)), int(255 * std::clamp(b, 0.0, 1.0)));
  };
  if (!std::isfinite(v))
    return "#cccccc";
  if (diverging) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    const double s = m > 0 ? std::clamp(v / m, -1.0, 1.0) : 0.0;
    return s >= 0 ? rgb(1.0, 1.0 - 0.8 * s, 1.0 - 0.8 * s) : rgb(1.0 + 0.8 * s, 1.0 + 0.8 * s, 1.0);
  }
  const double s = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  // Anchors of viridis at 0, 0.25, 0.5, 0.75, 1.
  static const double a[5][3] = {{0.267, 0.005, 0.329},
                                 {0.230, 0.322, 0.546},
                                 {0.128, 0.567, 0.551},
                                 {0.369, 0.789, 0.383},
                                 {0.993, 0.906, 0.144}};
  const int k = std::min(3, static_cast<int>(s * 4));
  const double f = s * 4 - k;
  return rgb(a[k][0] + f * (a[k + 1][0] - a[k][0]), a[k][1] + f * (a[k + 1][1] - a[k][1]),
             a[k][2] + f * (a[k + 1][2] - a[k][2]));
}

std::string heat_map(const SweepResult& r, const SweepSpec& spec, const std::string& title,
                     const std::function<double(const SweepRow&)>& value, bool diverging) {
  const int n = spec.steps, cell = std::max(6, 360 / n), w = n * cell, left = 60, top = 30;
  double lo = 1e300, hi = -1e300;
  for (const SweepRow& row : r.rows)
    if (std::isfinite(value(row)))
      lo = std::min(lo, value(row)), hi = std::max(hi, value(row));
  std::ostringstream s;
  s << fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' "
                   "font-family='sans-serif' font-size='11'>\n",
                   left + w + 110, top + w + 45);
  s << fmt::format("<text x='{}' y='18' font-size='13'>{}</text>\n", left, title);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const SweepRow& row = r.rows[i * n + j];
      s << fmt::format("<rect x='{}' y='{}' width='{}' height='{}' fill='{}'><title>entry {:.0f}, "
                       "exit {:.0f} mm2: {:.2f}</title></rect>\n",
                       left + i * cell, top + (n - 1 - j) * cell, cell, cell,
                       colour(value(row), lo, hi, diverging), row.entry, row.exit, value(row));
    }
  auto px = [&](double e) {
    return left + (e - spec.entry_min) / (spec.entry_max - spec.entry_min) * (w - cell) + cell / 2;
  };
  auto py = [&](double x) {
    return top + w - cell / 2 - (x - spec.exit_min) / (spec.exit_max - spec.exit_min) * (w - cell);
  };
  for (int t = 0; t <= 4; ++t) { // axis ticks
    const double e = spec.entry_min + (spec.entry_max - spec.entry_min) * t / 4;
    const double x = spec.exit_min + (spec.exit_max - spec.exit_min) * t / 4;
    s << fmt::format("<text x='{:.0f}' y='{}' text-anchor='middle'>{:.0f}</text>\n", px(e),
                     top + w + 14, e);
    s << fmt::format("<text x='{}' y='{:.0f}' text-anchor='end'>{:.0f}</text>\n", left - 4,
                     py(x) + 4, x);
  }
  s << fmt::format("<text x='{}' y='{}' text-anchor='middle'>entry tear area [mm2]</text>\n",
                   left + w / 2, top + w + 30);
  s << fmt::format("<text x='14' y='{}' transform='rotate(-90 14 {})' text-anchor='middle'>exit "
                   "tear area [mm2]</text>\n",
                   top + w / 2, top + w / 2);
  for (const SweepMark& m : spec.marks) {
    s << fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='5' fill='none' stroke='black' "
                     "stroke-width='2'/>\n",
                     px(m.entry), py(m.exit));
    s << fmt::format("<text x='{:.1f}' y='{:.1f}' font-weight='bold'>{}</text>\n", px(m.entry) + 7,
                     py(m.exit) - 5, m.name);
  }
  for (int b = 0; b < 50; ++b) { // colour bar
    const double v = hi - (hi - lo) * b / 49.0;
    s << fmt::format("<rect x='{}' y='{:.1f}' width='14' height='{:.1f}' fill='{}'/>\n",
                     left + w + 15, top + b * w / 50.0, w / 50.0 + 0.5,
                     colour(v, lo, hi, diverging));
  }
  s << fmt::format("<text x='{}' y='{}'>{:.1f}</text>\n", left + w + 33, top + 8, hi);
  s << fmt::format("<text x='{}' y='{}'>{:.1f}</text>\n", left + w + 33, top + w, lo);
  s << "</svg>\n";
  return s.str();
}

} // namespace

void write_sweep(const SweepResult& r, const SweepSpec& spec, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const size_t stations = r.rows.empty() ? 0 : r.rows.front().fr_fl.size();
  std::string csv = "entry_tear_area_mm2,exit_tear_area_mm2";
  for (size_t k = 1; k <= stations; ++k)
    csv += fmt::format(",FR_FL{0}_percent,dP{0}_peak_systole_mmHg,dP{0}_end_diastole_mmHg", k);
  csv += ",cycles\n";
  for (const SweepRow& row : r.rows) {
    csv += fmt::format("{:.6g},{:.6g}", row.entry, row.exit);
    for (size_t k = 0; k < stations; ++k)
      csv +=
          fmt::format(",{:.6g},{:.6g},{:.6g}", row.fr_fl[k], row.dp_systole[k], row.dp_diastole[k]);
    csv += fmt::format(",{}\n", row.cycles);
  }
  io::write_file_atomically(dir / "sweep.csv", csv);

  std::string html = "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>Tear-size "
                     "sweep</title></head>\n<body style='font-family:sans-serif'>\n";
  html += fmt::format("<h1>Tear-size sweep (reduced-order model)</h1>\n<p>{:.2f} s for all "
                      "variants.</p>\n",
                      r.seconds);
  html += "<!-- tearflow-sweep-maps begin -->\n";
  html += fmt::format("<p>{} variants of the reduced-order model, entry {:.0f} to {:.0f} "
                      "mm<sup>2</sup>, exit {:.0f} to {:.0f} mm<sup>2</sup>; circles: the 3D "
                      "variants. The FL flow ratio is the same at every station in the model "
                      "(net flows are conserved along each lumen). Hover a cell for its value; "
                      "all numbers are in sweep.csv.</p>\n",
                      r.rows.size(), spec.entry_min, spec.entry_max, spec.exit_min, spec.exit_max);
  if (stations > 0) {
    const size_t last = stations - 1;
    html += heat_map(
        r, spec, "FL flow ratio FR_FL [%]", [](const SweepRow& w) { return w.fr_fl[0]; }, false);
    html += heat_map(
        r, spec, "dP TL-FL at peak systole, station 1 [mmHg]",
        [](const SweepRow& w) { return w.dp_systole[0]; }, true);
    html += heat_map(
        r, spec, fmt::format("dP TL-FL at peak systole, station {} [mmHg]", stations),
        [last](const SweepRow& w) { return w.dp_systole[last]; }, true);
    html += heat_map(
        r, spec, "dP TL-FL at end diastole, station 1 [mmHg]",
        [](const SweepRow& w) { return w.dp_diastole[0]; }, true);
    html += heat_map(
        r, spec, fmt::format("dP TL-FL at end diastole, station {} [mmHg]", stations),
        [last](const SweepRow& w) { return w.dp_diastole[last]; }, true);
  }
  html += "<!-- tearflow-sweep-maps end -->\n</body></html>\n";
  io::write_file_atomically(dir / "sweep.html", html);
}

} // namespace tearflow::rom
