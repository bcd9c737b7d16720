#include "tuning/tune_command.hpp"

#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "fem/petsc.hpp"
#include "io/case.hpp"
#include "io/case_yaml.hpp"
#include "io/vtu_series.hpp"
#include "tuning/outlet_tuning.hpp"
#include "tuning/tuned_case.hpp"

namespace tearflow::tuning {

TuneCommand::TuneCommand(CLI::App& app) {
  command_ = app.add_subcommand(
      "tune", "fit a case's Windkessel outlets to measured inlet pressures and flow splits");
  command_->add_option("case", case_file_, "case file (YAML) with rcr or resistance outlets")
      ->required();
  command_->add_option("--targets", targets_file_, "targets file (YAML): docs/tuning.md")
      ->required();
  command_->add_option("-o,--output", output_,
                       "tuned case file (default: <case>-tuned.yaml beside the case)");
  command_
      ->add_option("--iterations", iterations_,
                   "3D correction runs, overriding the targets file (0: the 0D stage only)")
      ->check(CLI::Range(0, 1000));
  command_->add_flag("-q,--quiet", quiet_, "no progress lines");
}

int TuneCommand::run(const std::string& cli_petsc) const {
  io::Case c = io::load_case(case_file_);
  TuningTargets t = load_targets(targets_file_);
  if (iterations_ >= 0)
    t.max_iterations = iterations_;
  c.petsc_options += cli_petsc; // each 3D run's options: the case's, then these (they win)
  const TuningResult r = tune_outlets(c, t, !quiet_);
  if (fem::mpi_rank() != 0)
    return r.met ? 0 : 1;

  const std::filesystem::path in(case_file_);
  const std::filesystem::path out = output_.empty()
                                        ? in.parent_path() / (in.stem().string() + "-tuned.yaml")
                                        : std::filesystem::path(output_);
  if (out.has_parent_path())
    std::filesystem::create_directories(out.parent_path());
  const std::string tab = table(r, t);
  std::string header =
      fmt::format("# Tuned by `tearflow tune {} --targets {}`: {} after {} 3D "
                  "run(s).\n",
                  case_file_, targets_file_, r.met ? "targets met" : "targets NOT met",
                  r.steps.back().iteration);
  header += commented(tab);
  io::write_file_atomically(out, tuned_yaml(in, r.tuned, out, header));
  std::filesystem::path json = out;
  json.replace_extension(".tuning.json");
  io::write_file_atomically(json, to_json(r, t).dump(2) + "\n");
  fmt::print("{}{}\nwrote {} and {}\n", r.met ? "" : "targets NOT met within the tolerances\n", tab,
             out.string(), json.string());
  return r.met ? 0 : 1;
}

} // namespace tearflow::tuning
