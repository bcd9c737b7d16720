#include "rom/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "io/durable_file.hpp"

namespace tearflow::rom {

using nlohmann::json;

namespace {

/// The columns `time_s`, `flow_m3_per_s` and `mean_pressure_Pa` of an analysis CSV, every
/// value finite, at least 3 frames.
void read_landmark_csv(const std::filesystem::path& file, std::vector<double>& t,
                       std::vector<double>& q, std::vector<double>& p) {
  const analysis::LandmarkTable table = analysis::read_landmark_table(file);
  t = table.column("time_s"), q = table.column("flow_m3_per_s");
  p = table.column("mean_pressure_Pa");
  for (const char* name : {"time_s", "flow_m3_per_s", "mean_pressure_Pa"}) {
    const std::vector<double>& v = table.column(name);
    for (size_t row = 0; row < v.size(); ++row)
      if (!std::isfinite(v[row]))
        input_error("{}, line {}, column {}: '{}' is not a finite number", file.string(), row + 2,
                    name, v[row]);
  }
  if (t.size() < 3)
    input_error("{}: {} frames, expected a cycle of at least 3", file.string(), t.size());
}

int station_count(const CalibrationRun& run) {
  int k = 0;
  while (run.flow.count(fmt::format("TL{}", k + 1)) && run.flow.count(fmt::format("FL{}", k + 1)))
    ++k;
  return k;
}

/// The fitted coefficients: each a reference into the coefficients, fitted in its logarithm
/// (positive ones, from at least `floor`) or as is (gamma).
struct Parameter {
  std::string name;
  std::function<double&(RomCoefficients&)> ref;
  bool logarithmic = true;
  double floor = 0.0;
  double least = 0.0; ///< a logarithmic parameter is least + exp(x)
  double bound = 0.0; ///< > 0: a linear parameter is bound tanh(x), within (-bound, bound)
};

struct Layout {
  std::vector<Parameter> parameters;
  RomCoefficients base; ///< what is not fitted
  int size() const { return static_cast<int>(parameters.size()); }
  RomCoefficients coefficients(const Eigen::VectorXd& x) const {
    RomCoefficients k = base;
    for (int i = 0; i < size(); ++i) {
      const Parameter& p = parameters[i];
      p.ref(k) = p.logarithmic   ? p.least + std::exp(x(i))
                 : p.bound > 0.0 ? p.bound * std::tanh(x(i))
                                 : x(i);
    }
    return k;
  }
  Eigen::VectorXd x(RomCoefficients k) const {
    Eigen::VectorXd x(size());
    for (int i = 0; i < size(); ++i) {
      const Parameter& p = parameters[i];
      x(i) = p.logarithmic   ? std::log(std::max(p.ref(k) - p.least, p.floor))
             : p.bound > 0.0 ? std::atanh(std::clamp(p.ref(k) / p.bound, -0.999, 0.999))
                             : p.ref(k);
    }
    return x;
  }
};

/// The parameters a fit varies: those of `fit` (names as in calibration.json's keys, short:
/// viscous, friction, arch, tears, flap, size) that apply (flap: compliant walls; size: the
/// exponent of each tear in `resized`, those the runs hold at two sizes).
Layout layout(const std::set<std::string>& fit, const DissectionGeometry& g, bool compliant,
              const std::set<std::string>& resized) {
  Layout l;
  auto wanted = [&](const char* name) { return fit.empty() || fit.count(name) > 0; };
  // alpha >= 1: Poiseuille's is the least resistance a tube's laminar flow can have (the
  // minimum-dissipation theorem of Helmholtz and Korteweg); developing and pulsatile flow only
  // add. Unbounded, the fit trades alpha for the quadratic losses down to ~0 (1e-21 on the
  // 2 mm OR run), and the TL-FL loop, undamped at small flows, then circulates through
  // diastole (2 mL/s backward in the TL, where the 3D run has +1).
  if (wanted("viscous"))
    l.parameters.push_back(
        {"viscous", [](RomCoefficients& k) -> double& { return k.viscous; }, true, 0.05, 1.0});
  if (wanted("arch")) {
    l.base.arch_loss = 1.0; // the start: 0 has no logarithm
    l.parameters.push_back(
        {"arch", [](RomCoefficients& k) -> double& { return k.arch_loss; }, true, 0.05});
  }
  if (wanted("friction"))
    l.parameters.push_back(
        {"friction", [](RomCoefficients& k) -> double& { return k.friction; }, true, 0.01});
  if (wanted("tears"))
    for (const GeometryTear& t : g.tears) {
      l.base.tear[t.name] = l.base.tear_loss;
      const std::string name = t.name;
      l.parameters.push_back(
          {"tear " + name, [name](RomCoefficients& k) -> double& { return k.tear[name]; }});
    }
  if (compliant && wanted("flap"))
    l.parameters.push_back({"flap", [](RomCoefficients& k) -> double& { return k.flap; }});
  // |gamma| < 1: an orifice's K per its own velocity head, (1/C_c - A_t/A)^2, changes by well
  // under a factor 2 between area ratios A_t/A of 0.05 and 0.5, so over a study's range of
  // sizes (3.7x) its exponent stays within about 0.6. Unbounded, a tear whose K_t the fit
  // drives to ~0 at one size makes gamma free: the six 4.5 mm runs gave the entry -10 (rigid)
  // and -29 (compliant), a K of 1e8 at 30 mm^2 in the sweep.
  if (wanted("size"))
    for (const std::string& name : resized) {
      l.base.tear_size[name] = 0.0;
      l.parameters.push_back({"size " + name,
                              [name](RomCoefficients& k) -> double& { return k.tear_size[name]; },
                              false, 0.0, 0.0, 1.0});
    }
  return l;
}

struct Objective {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  const DissectionGeometry* g;
  const geometry::Landmarks* landmarks;
  std::vector<const CalibrationRun*> runs;
  Layout layout;
  IntegrationOptions options;
  int values_ = 0;
  int* evaluations;
  int inputs() const { return layout.size(); }
  int values() const { return values_; }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    ++*evaluations;
    const RomCoefficients k = layout.coefficients(x);
    std::vector<double> r;
    for (const CalibrationRun* run : runs) {
      std::vector<double> part;
      try {
        part = misfit(predict(*g, run->inputs, k, *landmarks, run->tear_areas, options).analysis,
                      *run);
      } catch (const SolverError&) { // a trial step too far: a large residual turns LM back
        part.assign(values_ / runs.size(), 1e3);
      }
      r.insert(r.end(), part.begin(), part.end());
    }
    f = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
    return 0;
  }
};

} // namespace

CalibrationRun read_calibration_run(const std::filesystem::path& run_dir, const io::Case& c,
                                    const DissectionGeometry& g, double wall_thickness,
                                    const std::filesystem::path& run_model) {
  CalibrationRun run;
  run.name = run_dir.string();
  run.inputs = rom_inputs(c, g, wall_thickness);
  if (!run_model.empty())
    for (const geometry::TearLandmark& t :
         geometry::read_landmarks(GeometryFiles{run_model}.landmarks()).tears) {
      const auto own = std::find_if(g.tears.begin(), g.tears.end(),
                                    [&](const GeometryTear& m) { return m.name == t.name; });
      if (own == g.tears.end())
        input_error("{}: tear '{}' is not a tear of the calibrated model", run_model.string(),
                    t.name);
      if (std::abs(t.area - own->area) > 0.01 * own->area)
        run.tear_areas[t.name] = t.area;
    }
  const std::filesystem::path dir = run_dir / "analysis";
  std::vector<std::string> names{"inlet", "DAo_prox", "outlet"};
  for (int k = 1; std::filesystem::exists(dir / fmt::format("TL{}.csv", k)); ++k)
    names.push_back(fmt::format("TL{}", k)), names.push_back(fmt::format("FL{}", k));
  for (const std::string& name : names) {
    std::vector<double> t, q, p;
    read_landmark_csv(dir / (name + ".csv"), t, q, p);
    if (run.time.empty()) {
      run.time = t;
      for (double& x : run.time)
        x -= t.front();
    } else if (t.size() != run.time.size())
      input_error("{}: {} frames, the run's other landmarks have {}",
                  (dir / (name + ".csv")).string(), t.size(), run.time.size());
    run.flow[name] = q, run.pressure[name] = p;
  }
  if (station_count(run) == 0)
    input_error("{}: no paired stations TL1.csv / FL1.csv to calibrate on", dir.string());
  return run;
}

std::vector<double> misfit(const analysis::Analysis& a, const CalibrationRun& run) {
  auto series = [&](const std::string& name, bool pressure) {
    const analysis::LandmarkSeries* s = a.find(name);
    if (!s)
      input_error("reduced-order model: no landmark {} to compare with the run", name);
    std::vector<double> v;
    for (const analysis::SectionValues& x : s->samples)
      v.push_back(pressure ? x.pressure : x.flow);
    return v;
  };
  std::vector<double> r;
  auto pressure_difference = [&](const std::string& p, const std::string& q) {
    const std::vector<double> a1 = series(p, true), a2 = series(q, true);
    for (size_t f = 0; f < run.time.size(); ++f) {
      const double rom = analysis::interpolate(a.time, a1, run.time[f]) -
                         analysis::interpolate(a.time, a2, run.time[f]);
      const double d3 = run.pressure.at(p)[f] - run.pressure.at(q)[f];
      r.push_back((rom - d3) / units::mmHg);
    }
  };
  const int stations = station_count(run);
  for (int k = 1; k <= stations; ++k)
    pressure_difference(fmt::format("TL{}", k), fmt::format("FL{}", k));
  pressure_difference("inlet", "FL1");
  pressure_difference(fmt::format("FL{}", stations), "outlet");
  pressure_difference("inlet", "DAo_prox");
  for (int k = 1; k <= stations; ++k) {
    const std::string tl = fmt::format("TL{}", k), fl = fmt::format("FL{}", k);
    const double q_tl = analysis::time_mean(a.time, series(tl, false)),
                 q_fl = analysis::time_mean(a.time, series(fl, false));
    const double m_tl = analysis::time_mean(run.time, run.flow.at(tl)),
                 m_fl = analysis::time_mean(run.time, run.flow.at(fl));
    const double fr = 100.0 * q_fl / (q_fl + q_tl), fr3 = 100.0 * m_fl / (m_fl + m_tl);
    r.push_back((fr - fr3) / 0.5);
  }
  return r;
}

Calibration calibrate_model(const DissectionGeometry& g, const geometry::Landmarks& landmarks,
                            const std::vector<CalibrationRun>& runs,
                            const IntegrationOptions& options, bool progress,
                            const std::set<std::string>& fit) {
  Calibration out;
  for (const bool compliant : {false, true}) {
    Objective obj;
    obj.g = &g, obj.landmarks = &landmarks, obj.options = options;
    for (const CalibrationRun& r : runs)
      if (r.inputs.wall.has_value() == compliant)
        obj.runs.push_back(&r);
    if (obj.runs.empty())
      continue;
    std::set<std::string> resized; // the tears some run holds at another size
    for (const CalibrationRun* r : obj.runs)
      for (const auto& [name, area] : r->tear_areas)
        resized.insert(name);
    obj.layout = layout(fit, g, compliant, resized);
    if (obj.layout.size() == 0)
      input_error("rom calibrate: nothing to fit (--fit names none of viscous, arch, friction, "
                  "tears, flap, size that apply)");
    int evaluations = 0;
    obj.evaluations = &evaluations;
    Eigen::VectorXd x = obj.layout.x(obj.layout.base); // the start: the defaults, floored
    const RomCoefficients start = obj.layout.coefficients(x);
    Eigen::VectorXd f;
    obj.values_ = 0;
    for (const CalibrationRun* r : obj.runs) // the residual count of each run
      obj.values_ += static_cast<int>(
          misfit(predict(g, r->inputs, start, landmarks, r->tear_areas, options).analysis, *r)
              .size());
    obj(x, f);
    CalibrationFit result;
    result.compliant = compliant;
    result.rms_before = std::sqrt(f.squaredNorm() / f.size());
    Eigen::NumericalDiff<Objective> functor(obj);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Objective>> lm(functor);
    lm.parameters.xtol = 1e-4; // 0.01 % in each coefficient: far below what the runs resolve
    lm.parameters.ftol = 1e-6;
    lm.parameters.maxfev = 60 * obj.layout.size();
    lm.minimize(x);
    obj(x, f);
    result.coefficients = obj.layout.coefficients(x);
    result.rms_after = std::sqrt(f.squaredNorm() / f.size());
    result.evaluations = evaluations;
    for (const CalibrationRun* r : obj.runs)
      result.runs.push_back(r->name);
    if (progress) {
      fmt::print("{} walls, {} run(s): weighted rms misfit {:.2f} -> {:.2f} ({} evaluations)\n",
                 compliant ? "compliant" : "rigid", obj.runs.size(), result.rms_before,
                 result.rms_after, evaluations);
      fmt::print("  {}\n", to_json(result.coefficients).dump());
    }
    (compliant ? out.compliant : out.rigid) = result;
  }
  return out;
}

namespace {

json fit_json(const CalibrationFit& f) {
  return {{"coefficients", to_json(f.coefficients)},
          {"runs", f.runs},
          {"weighted_rms_misfit_before", f.rms_before},
          {"weighted_rms_misfit_after", f.rms_after},
          {"evaluations", f.evaluations}};
}

/// 2: the tear nodes measured at the tears' rims and the entry's dividing-flow loss; 3: the
/// flap's width its chord, not the diameter; 4: the entry's dividing junction (its channel
/// area and the TL's regain) and alpha >= 1; 5: the exit's combining junction, the tears in
/// series with the TL's channel, no dividing-flow loss, and DAo_prox's section pressure. A fit
/// of an earlier version was made for another network.
constexpr int kCalibrationVersion = 5;

std::filesystem::path calibration_file(const std::filesystem::path& model_dir) {
  return model_dir / "rom" / "calibration.json";
}

/// A calibration file parsed; discarded where it is missing or not JSON.
json read_calibration_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  return in ? json::parse(in, nullptr, false) : json(json::value_t::discarded);
}

/// Whether a parsed calibration file is a fit of this tearflow's network.
bool of_this_version(const json& j) {
  if (!j.is_object())
    return false;
  const auto v = j.find("version");
  return v != j.end() && v->is_number_integer() && v->get<int>() == kCalibrationVersion;
}

} // namespace

void save_calibration(const std::filesystem::path& model_dir, const Calibration& c) {
  const std::filesystem::path file = calibration_file(model_dir);
  json j{{"format", "tearflow-rom-calibration"}, {"version", kCalibrationVersion}};
  if (const json old = read_calibration_json(file); of_this_version(old))
    for (const char* key : {"rigid", "compliant"})
      if (old.contains(key))
        j[key] = old[key];
  if (c.rigid)
    j["rigid"] = fit_json(*c.rigid);
  if (c.compliant)
    j["compliant"] = fit_json(*c.compliant);
  std::filesystem::create_directories(file.parent_path());
  io::write_file_atomically(file, j.dump(2) + "\n");
  fmt::print("wrote {}\n", file.string());
}

bool calibration_is_current(const std::filesystem::path& model_dir) {
  return of_this_version(read_calibration_json(calibration_file(model_dir)));
}

RomCoefficients load_coefficients(const std::filesystem::path& model_dir,
                                  const std::filesystem::path& given, bool compliant,
                                  bool progress) {
  const std::filesystem::path file = given.empty() ? calibration_file(model_dir) : given;
  if (!std::filesystem::exists(file)) {
    if (!given.empty())
      input_error("--coefficients {}: no such file", given.string());
    if (progress)
      fmt::print("reduced-order model: not calibrated (no {}): the default coefficients\n",
                 file.string());
    return {};
  }
  const json j = read_calibration_json(file);
  if (j.is_discarded() || !j.is_object())
    input_error("{}: not JSON", file.string());
  if (!of_this_version(j))
    input_error("{}: calibration version {}, this tearflow's model is version {} (its network "
                "changed): run `tearflow rom calibrate` again",
                file.string(), j.value("version", json(0)).dump(), kCalibrationVersion);
  const char* own = compliant ? "compliant" : "rigid";
  const char* other = compliant ? "rigid" : "compliant";
  const char* key = j.contains(own) ? own : other;
  if (!j.contains(key))
    input_error("{}: neither 'rigid' nor 'compliant' coefficients", file.string());
  if (progress && key != own)
    fmt::print("reduced-order model: {} has no {} fit: the {} one\n", file.string(), own, other);
  if (!j[key].contains("coefficients"))
    input_error("{}: '{}' has no 'coefficients'", file.string(), key);
  return coefficients_from_json(j[key]["coefficients"], file.string() + " (" + key + ")");
}

void print_summary(const analysis::Analysis& a) {
  const json m = analysis::metrics_json(a);
  fmt::print("  station  FR_FL [%]  dP peak systole [mmHg]  dP end diastole [mmHg]\n");
  const json stations = m.value("stations", json::object());
  for (const auto& [k, s] : stations.items())
    fmt::print("  {:>7}  {:9.1f}  {:22.2f}  {:22.2f}\n", k, s.value("FR_FL_percent", NAN),
               s.value("dP_TL_minus_FL_peak_systole_mmHg", NAN),
               s.value("dP_TL_minus_FL_end_diastole_mmHg", NAN));
  if (m.contains("achieved"))
    fmt::print("  inlet P_sys / P_dias (MAP): {:.1f} / {:.1f} ({:.1f}) mmHg\n",
               m["achieved"].value("inlet_systolic_pressure_mmHg", NAN),
               m["achieved"].value("inlet_diastolic_pressure_mmHg", NAN),
               m["achieved"].value("inlet_mean_pressure_mmHg", NAN));
}

} // namespace tearflow::rom
