// `tearflow mri inflow | cine` (scan2d_command.hpp; docs/mri.md).
#include "mri/scan2d_command.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <regex>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/durable_file.hpp"
#include "mri/corrected_scan.hpp"
#include "mri/lumen_tracking.hpp"
#include "mri/measured_case.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;

namespace {

/// "DIR" or "DIR@X,Y,Z" (a seed in patient millimetres): the folder and the seed [m].
std::pair<fs::path, std::optional<Vec3>> scan_and_seed(const std::string& text,
                                                       const std::string& option) {
  const auto at = text.rfind('@');
  if (at == std::string::npos)
    return {text, std::nullopt};
  Vec3 p{};
  char tail = 0;
  if (std::sscanf(text.c_str() + at + 1, "%lf,%lf,%lf%c", &p[0], &p[1], &p[2], &tail) != 3)
    input_error("{} '{}': a seed is three numbers, x,y,z in patient millimetres (LPS), after "
                "the folder and '@'",
                option, text);
  return {text.substr(0, at), Vec3{p[0] * units::mm, p[1] * units::mm, p[2] * units::mm}};
}

/// "NAME=VALUE" split at the first '='.
std::pair<std::string, std::string> named(const std::string& text, const std::string& option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    input_error("{} '{}': NAME=FOLDER is expected", option, text);
  return {text.substr(0, eq), text.substr(eq + 1)};
}

/// "126/60/86mmHg" (systolic/diastolic/mean, unit mmHg, Pa or dyn/cm2) -> Pa.
std::array<double, 3> pressures(const std::string& text) {
  static const std::regex re(R"(\s*([0-9.eE+]+)/([0-9.eE+]+)/([0-9.eE+]+)\s*([a-zA-Z/0-9]*)\s*)");
  std::smatch m;
  const auto expected = [&] {
    input_error("--pressure '{}': SYSTOLIC/DIASTOLIC/MEAN with a unit is expected, e.g. "
                "126/60/86mmHg",
                text);
  };
  if (!std::regex_match(text, m, re))
    expected();
  const double scale =
      units::pressure_scale(m[4].str().empty() ? "mmHg" : m[4].str(), "--pressure");
  std::array<double, 3> p{};
  for (int k = 0; k < 3; ++k) {
    const std::string field = m[k + 1];
    std::size_t used = 0;
    try {
      p[k] = std::stod(field, &used) * scale;
    } catch (const std::exception&) {
      expected();
    }
    if (used != field.size())
      expected(); // "126.5.1" is not a number
  }
  if (!(p[1] < p[2] && p[2] < p[0]))
    input_error("--pressure '{}': diastolic < mean < systolic is expected", text);
  return p;
}

/// `series` sampled at `times` (periodic in `period`, linear between its own times).
std::vector<double> periodic_linear(const std::vector<double>& t, const std::vector<double>& v,
                                    double period, const std::vector<double>& times) {
  std::vector<double> out;
  for (double x : times) {
    x = t.front() + std::fmod(std::fmod(x - t.front(), period) + period, period);
    std::size_t i = 0;
    while (i + 1 < t.size() && t[i + 1] <= x)
      ++i;
    const double t1 = i + 1 < t.size() ? t[i + 1] : t.front() + period;
    const double v1 = i + 1 < t.size() ? v[i + 1] : v.front();
    out.push_back(v[i] + (v1 - v[i]) * (x - t[i]) / (t1 - t[i]));
  }
  return out;
}

} // namespace

Scan2dCommands::Scan2dCommands(CLI::App& mri) {
  inflow_ = mri.add_subcommand("inflow", "2D phase-contrast scans to a case's inflow waveform and "
                                         "its targets' outlet splits (docs/mri.md)");
  inflow_->add_option("case", case_file_, "the case file to give the measured inflow")->required();
  inflow_->add_option("--inlet", inlet_, "DICOM folder of the inflow's scan [@X,Y,Z seed, mm]");
  inflow_->add_option("--outlet", outlets_, "FACE=FOLDER[@X,Y,Z]: an outlet's scan (repeat)");
  inflow_->add_option("--landmarks", landmarks_,
                      "landmarks JSON: a scan without a seed takes the lumen point of the "
                      "landmark plane in its slice (and its direction)");
  inflow_->add_option("--pressure", pressure_,
                      "inlet pressures SYS/DIA/MEAN[unit] for the targets (e.g. 126/60/86mmHg)");
  inflow_->add_option("--venc", venc_, "velocity encoding, overriding the files'");
  inflow_->add_flag("--no-background", no_background_, "no background phase-offset correction");
  inflow_->add_flag("--no-unwrap", no_unwrap_, "no temporal phase unwrapping");
  inflow_->add_option("-o,--output", output_, "output folder (case.yaml, inflow.csv, ...)")
      ->required();
  inflow_->add_flag("-q,--quiet", quiet_, "no summary lines");

  cine_ = mri.add_subcommand("cine", "2D cine scans at landmark stations to true and false "
                                     "lumen areas over the cycle (area.csv, docs/mri.md)");
  cine_
      ->add_option("--at", at_,
                   "K=FOLDER[@X,Y,Z]: a cine at station k (markers: the TLk and FLk lumen "
                   "points; @ replaces the first, patient mm), or NAME=FOLDER at an undivided "
                   "landmark (AAo, DAo_dist, ...); repeat")
      ->required();
  cine_->add_option("--landmarks", landmarks_, "landmarks JSON (the lumen points)")->required();
  cine_
      ->add_option("--lumen-fraction", lumen_fraction_,
                   "lumen: magnitude >= this x its blood's (default 0.6)")
      ->check(CLI::Range(0.05, 1.0));
  cine_->add_option("-o,--output", output_, "output folder (area.csv, cine.json)")->required();
  cine_->add_flag("-q,--quiet", quiet_, "no summary lines");
}

int Scan2dCommands::run() const {
  return inflow_->parsed() ? inflow() : cine();
}

int Scan2dCommands::inflow() const {
  if (inlet_.empty() && outlets_.empty())
    input_error("mri inflow: no scan; give --inlet FOLDER and/or --outlet FACE=FOLDER");
  CorrectionChoice choice;
  if (!venc_.empty())
    choice.venc = units::quantity(venc_, "--venc", units::Dimension::velocity);
  choice.unwrap = !no_unwrap_;
  choice.background = !no_background_;
  std::optional<geometry::Landmarks> landmarks;
  if (!landmarks_.empty())
    landmarks = geometry::read_landmarks(landmarks_);
  nlohmann::json report;
  auto measure = [&](const std::string& name, const std::string& text, const char* option) {
    const auto [folder, point] = scan_and_seed(text, option);
    nlohmann::json& r = report["scans"][name];
    const Flow4D scan = read_corrected(folder, choice, r);
    VesselSeed seed{point, landmarks ? &*landmarks : nullptr};
    VesselFlow v = measure_vessel(scan, name, seed);
    r["folder"] = folder.string();
    r["seed_from"] = v.seed_from;
    r["seed_mm"] = {v.seed[0] * 1e3, v.seed[1] * 1e3, v.seed[2] * 1e3};
    r["sign"] = v.sign;
    r["period_s"] = v.period;
    r["time_s"] = v.time;
    std::vector<double> ml, mm2;
    for (double q : v.flow)
      ml.push_back(q / units::mL);
    for (double a : v.area)
      mm2.push_back(a / (units::mm * units::mm));
    r["flow_mL_per_s"] = ml;
    r["area_mm2"] = mm2;
    r["mean_flow_mL_per_s"] = v.mean_flow() / units::mL;
    return v;
  };
  MeasuredFlows flows;
  flows.case_file = case_file_;
  if (!inlet_.empty())
    flows.inlet = measure("inflow", inlet_, "--inlet");
  for (const std::string& o : outlets_) {
    const auto [face, text] = named(o, "--outlet");
    flows.outlets.push_back(measure(face, text, "--outlet"));
  }
  if (!pressure_.empty())
    flows.pressure = pressures(pressure_);
  report["case"] = write_measured_case(flows, output_);
  io::write_file_atomically(fs::path(output_) / "mri_inflow.json", report.dump(2) + "\n");
  if (!quiet_) {
    fmt::print("{:<10} {:>14} {:>14} {:>10}  {}\n", "scan", "Qmean [mL/s]", "Qpeak [mL/s]",
               "R-R [ms]", "seed");
    auto row = [](const VesselFlow& v) {
      fmt::print("{:<10} {:>14.2f} {:>14.2f} {:>10.1f}  {}\n", v.name, v.mean_flow() / units::mL,
                 *std::max_element(v.flow.begin(), v.flow.end()) / units::mL, v.period * 1e3,
                 v.seed_from);
    };
    if (flows.inlet)
      row(*flows.inlet);
    for (const VesselFlow& v : flows.outlets)
      row(v);
    fmt::print("case.yaml{}{} and mri_inflow.json in '{}'\n", flows.inlet ? ", inflow.csv" : "",
               flows.outlets.empty() ? "" : ", targets.yaml", output_);
  }
  return 0;
}

int Scan2dCommands::cine() const {
  const geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_);
  TrackOptions options;
  options.lumen_fraction = lumen_fraction_;
  nlohmann::json report;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values; // per column, on the first scan's times
  std::vector<double> times;
  double period = 0.0;
  for (const std::string& item : at_) {
    const auto [name, text] = named(item, "--at");
    const bool station = std::all_of(name.begin(), name.end(), ::isdigit); // TLk and FLk
    for (const std::string& column :
         station ? std::vector{"TL" + name, "FL" + name} : std::vector{name})
      if (std::find(columns.begin(), columns.end(), column) != columns.end())
        input_error("--at {}: '{}' is measured twice; one scan per station or landmark", name,
                    column);
    const auto [folder, point] = scan_and_seed(text, "--at");
    nlohmann::json& r = report["scans"][name];
    const Flow4D cine = read_corrected(folder, {}, r);
    cine.require(Encoding::magnitude, fmt::format("--at {}: '{}'", name, folder.string()));
    // A station's TL and FL points, or one landmark's.
    const auto lumen_point = [&](const std::string& landmark) {
      const geometry::Landmark& l = landmarks.plane(landmark);
      return l.point.value_or(l.origin);
    };
    const Vec3 first = point ? *point : lumen_point(station ? "TL" + name : name);
    std::optional<Vec3> second;
    if (station)
      second = lumen_point("FL" + name);
    const LuminaSeries s = track_lumina(cine, name, first, second, options);
    const double cine_period = cine.cycle(fmt::format("--at {}: '{}'", name, folder.string()));
    if (times.empty()) {
      times = s.time;
      period = cine_period;
    }
    auto add = [&](const std::string& column, const std::vector<double>& area) {
      // Onto the first scan's times by phase in the cycle (periodic, linear).
      std::vector<double> phase_times;
      for (double t : times)
        phase_times.push_back(t / period * cine_period);
      columns.push_back(column);
      values.push_back(periodic_linear(s.time, area, cine_period, phase_times));
    };
    add(station ? "TL" + name : name, s.tl_area);
    if (station)
      add("FL" + name, s.fl_area);
    r["folder"] = folder.string();
    r["frames"] = s.time.size();
    r["split_frames"] = s.split_frames;
    r["swaps"] = s.swaps;
    r["period_s"] = cine_period;
    if (!quiet_) {
      const auto [lo, hi] = std::minmax_element(s.tl_area.begin(), s.tl_area.end());
      fmt::print("{:<8} {} frames: {} {:.1f}-{:.1f} mm2", name, s.time.size(),
                 station ? "TL" : "lumen", *lo * 1e6, *hi * 1e6);
      if (station) {
        const auto [flo, fhi] = std::minmax_element(s.fl_area.begin(), s.fl_area.end());
        fmt::print(", FL {:.1f}-{:.1f} mm2", *flo * 1e6, *fhi * 1e6);
      }
      fmt::print("{}\n", s.split_frames
                             ? fmt::format(" ({} frames split by the watershed)", s.split_frames)
                             : "");
    }
  }
  std::string csv = "time_s";
  for (const std::string& c : columns)
    csv += "," + c + "_mm2";
  csv += "\n";
  for (std::size_t k = 0; k < times.size(); ++k) {
    csv += fmt::format("{:.6g}", times[k]);
    for (const auto& v : values)
      csv += fmt::format(",{:.6g}", v[k] / (units::mm * units::mm));
    csv += "\n";
  }
  fs::create_directories(output_);
  io::write_file_atomically(fs::path(output_) / "area.csv", csv);
  io::write_file_atomically(fs::path(output_) / "cine.json", report.dump(2) + "\n");
  if (!quiet_)
    fmt::print("area.csv and cine.json in '{}'\n", output_);
  return 0;
}

} // namespace tearflow::mri
