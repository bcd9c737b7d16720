#include "rom/rom_command.hpp"

#include <chrono>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "io/case.hpp"
#include "io/durable_file.hpp"
#include "rom/calibration.hpp"
#include "rom/dissection_network.hpp"
#include "rom/tear_sweep.hpp"

namespace tearflow::rom {

using nlohmann::json;

namespace {

void add_tear_options(CLI::App* c, double& entry, double& exit, std::vector<std::string>& tears) {
  c->add_option("--entry-tear-area", entry, "the entry tear's area [mm^2] (default: the model's)")
      ->check(CLI::PositiveNumber);
  c->add_option("--exit-tear-area", exit, "the exit tear's area [mm^2] (default: the model's)")
      ->check(CLI::PositiveNumber);
  c->add_option("--tear-area", tears, "a tear's area by name, NAME=MM2 (repeatable)");
}

/// Tear areas [m^2] by name from the options; InputError for a tear the model lacks.
std::map<std::string, double> tear_areas(const DissectionGeometry& g, double entry, double exit,
                                         const std::vector<std::string>& named) {
  std::map<std::string, double> out;
  auto set = [&](const std::string& name, double mm2, const std::string& option) {
    if (std::none_of(g.tears.begin(), g.tears.end(),
                     [&](const GeometryTear& t) { return t.name == name; })) {
      std::string known;
      for (const GeometryTear& t : g.tears)
        known += (known.empty() ? "" : ", ") + t.name;
      input_error("{}: the model has no tear '{}' (its tears: {})", option, name, known);
    }
    if (!(mm2 > 0.0))
      input_error("{}: tear area {} mm^2 (expected a number > 0)", option, mm2);
    out[name] = mm2 * 1e-6;
  };
  if (entry > 0.0)
    set("entry", entry, "--entry-tear-area");
  if (exit > 0.0)
    set("exit", exit, "--exit-tear-area");
  for (const std::string& s : named) {
    const auto eq = s.find('=');
    if (eq == std::string::npos)
      input_error("--tear-area '{}': expected NAME=MM2", s);
    double v = 0.0;
    try {
      size_t used = 0;
      v = std::stod(s.substr(eq + 1), &used);
      if (used != s.size() - eq - 1)
        throw std::invalid_argument(s);
    } catch (const std::exception&) {
      input_error("--tear-area '{}': '{}' is not a number of mm^2", s, s.substr(eq + 1));
    }
    set(s.substr(0, eq), v, "--tear-area");
  }
  return out;
}

/// Integration with `steps` per cycle, sampled 100 times per cycle when that divides it.
IntegrationOptions integration(int steps) {
  IntegrationOptions opt;
  opt.steps_per_cycle = steps;
  opt.samples_per_cycle = steps % 100 == 0 ? 100 : steps;
  return opt;
}

} // namespace

RomCommand::Model RomCommand::model() const {
  Model m;
  m.dir = model_dir_;
  m.geometry = model_geometry(m.dir, !quiet_);
  m.inputs = rom_inputs(io::load_case(case_file_), m.geometry, wall_thickness_ * 1e-3);
  m.coefficients = load_coefficients(m.dir, coefficients_file_, m.inputs.wall.has_value(), !quiet_);
  return m;
}

RomCommand::RomCommand(CLI::App& app) {
  command_ = app.add_subcommand(
      "rom", "reduced-order (0D) model of the dissection: predict, calibrate on 3D runs, sweep "
             "tear sizes (docs/rom.md)");
  command_->require_subcommand(1);

  predict_ = command_->add_subcommand(
      "predict", "the model's periodic state: metrics.json and CSVs as `analyze` writes them");
  predict_->add_option("model", model_dir_, "model directory (mesh.msh, landmarks.json)")
      ->required();
  predict_->add_option("--case", case_file_, "case file: fluid, inflow, outlets, wall")->required();
  add_tear_options(predict_, entry_area_, exit_area_, tear_areas_);
  predict_->add_option("-o,--output", output_, "output folder (default MODEL/rom/predict)");

  calibrate_ = command_->add_subcommand(
      "calibrate", "fit the model's coefficients to 3D runs of the same geometry");
  calibrate_->add_option("model", model_dir_, "model directory")->required();
  calibrate_
      ->add_option("--run", runs_,
                   "an analysed 3D run directory (repeatable; its analysis/ "
                   "folder and tuned.yaml, or --case)")
      ->required();
  calibrate_->add_option("--case", cases_,
                         "the case of each --run, in order (default: RUN/tuned.yaml)");
  calibrate_
      ->add_option("--fit", fit_,
                   "the coefficients to fit (default all that apply): viscous, arch, friction, "
                   "tears, flap, size")
      ->delimiter(',')
      ->check(CLI::IsMember({"viscous", "arch", "friction", "tears", "flap", "size"}));
  calibrate_->add_option("--run-model", run_models_,
                         "the model directory of each --run, in order, when a run is of another "
                         "tear-size variant (its tears' areas are used)");

  sweep_ = command_->add_subcommand(
      "sweep", "FL flow ratio and TL-FL pressure difference over a grid of tear areas");
  sweep_->add_option("model", model_dir_, "model directory")->required();
  sweep_->add_option("--case", case_file_, "case file")->required();
  sweep_->add_option("--entry", entry_range_, "entry tear areas MIN:MAX [mm^2]")->required();
  sweep_->add_option("--exit", exit_range_, "exit tear areas MIN:MAX [mm^2]")->required();
  sweep_->add_option("--steps", steps_, "grid points per tear (default 20)")
      ->check(CLI::Range(2, 200));
  sweep_->add_option("--mark", marks_,
                     "a 3D variant to mark on the maps, NAME=ENTRY:EXIT [mm^2] (repeatable)");
  sweep_->add_option("-o,--output", output_, "output folder (default MODEL/rom/sweep)");

  for (CLI::App* c : {predict_, calibrate_, sweep_}) {
    c->add_option("--coefficients", coefficients_file_,
                  "coefficients file (default: MODEL/rom/calibration.json if present)");
    c->add_option("--wall-thickness", wall_thickness_,
                  "wall and flap thickness [mm] (default: measured from the wall region)")
        ->check(CLI::PositiveNumber);
    c->add_option("--steps-per-cycle", steps_per_cycle_, "time steps per cycle (default 400)")
        ->check(CLI::Range(20, 100000));
    c->add_flag("-q,--quiet", quiet_, "no progress lines");
  }
}

int RomCommand::run() const {
  if (predict_->parsed())
    return predict();
  if (calibrate_->parsed())
    return calibrate();
  return sweep();
}

int RomCommand::predict() const {
  const Model m = model();
  const std::map<std::string, double> areas =
      tear_areas(m.geometry, entry_area_, exit_area_, tear_areas_);
  const auto start = std::chrono::steady_clock::now();
  const Prediction p = rom::predict(m.geometry, m.inputs, m.coefficients,
                                    geometry::read_landmarks(GeometryFiles{m.dir}.landmarks()),
                                    areas, integration(steps_per_cycle_));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::filesystem::path out =
      output_.empty() ? m.dir / "rom" / "predict" : std::filesystem::path(output_);
  // As a run's folder: OUT/analysis/ holds what `analyze` writes, so `report OUT RUN...`
  // shows the prediction beside 3D runs.
  std::filesystem::create_directories(RunFiles{out}.analysis_dir());
  analysis::write_analysis(p.analysis, RunFiles{out}.analysis_dir());
  if (!quiet_) {
    fmt::print("reduced-order model ({} walls): periodic after {} cycles ({:.3f} s)\n",
               m.inputs.wall ? "compliant" : "rigid", p.solution.cycles, seconds);
    print_summary(p.analysis);
    fmt::print("wrote {}\n", RunFiles{out}.metrics_json().string());
  }
  return 0;
}

int RomCommand::calibrate() const {
  const std::filesystem::path model_dir(model_dir_);
  if (cases_.size() > runs_.size() || run_models_.size() > runs_.size())
    input_error("rom calibrate: {} --case and {} --run-model for {} --run", cases_.size(),
                run_models_.size(), runs_.size());
  std::vector<CalibrationRun> runs;
  const DissectionGeometry g = model_geometry(model_dir, !quiet_);
  for (size_t r = 0; r < runs_.size(); ++r) {
    const std::filesystem::path dir(runs_[r]);
    const std::filesystem::path case_file =
        r < cases_.size() ? std::filesystem::path(cases_[r]) : RunFiles{dir}.tuned_case();
    if (!std::filesystem::exists(case_file))
      input_error("rom calibrate: run '{}' has no tuned.yaml; give its case with --case",
                  dir.string());
    runs.push_back(read_calibration_run(
        dir, io::load_case(case_file), g, wall_thickness_ * 1e-3,
        r < run_models_.size() ? std::filesystem::path(run_models_[r]) : std::filesystem::path()));
  }
  const geometry::Landmarks landmarks =
      geometry::read_landmarks(GeometryFiles{model_dir}.landmarks());
  const Calibration cal = calibrate_model(g, landmarks, runs, integration(steps_per_cycle_),
                                          !quiet_, std::set<std::string>(fit_.begin(), fit_.end()));
  save_calibration(model_dir, cal);
  return 0;
}

int RomCommand::sweep() const {
  SweepSpec spec = parse_sweep(entry_range_, exit_range_, steps_, marks_); // before any work
  const Model m = model();
  spec.steps_per_cycle = steps_per_cycle_;
  const std::filesystem::path out =
      output_.empty() ? m.dir / "rom" / "sweep" : std::filesystem::path(output_);
  const SweepResult r = sweep_tears(m.geometry, m.inputs, m.coefficients, spec, !quiet_);
  write_sweep(r, spec, out);
  if (!quiet_)
    fmt::print("{} variants in {:.2f} s; wrote {} and {}\n", r.rows.size(), r.seconds,
               (out / "sweep.csv").string(), (out / "sweep.html").string());
  return 0;
}

} // namespace tearflow::rom
