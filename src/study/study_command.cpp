#include "study/study_command.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/names.hpp"
#include "fem/petsc.hpp"
#include "geometry/geometry_command.hpp"
#include "study/child_process.hpp"
#include "study/study_runner.hpp"

namespace tearflow::study {

namespace {

/// The long option names of `tearflow geometry tbad`, from its own registration, so that a
/// study file is checked against exactly what the command accepts.
std::vector<std::string> geometry_tbad_options() {
  CLI::App app;
  const geometry::GeometryCommand command(app);
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_subcommand("geometry")->get_subcommand("tbad")->get_options())
    for (const std::string& name : o->get_lnames())
      names.push_back(name);
  return names;
}

} // namespace

StudyCommand::StudyCommand(CLI::App& app) {
  command_ = app.add_subcommand("study", "variants of a dissection model from geometry to "
                                         "comparison report, resumable (docs/study.md)");
  command_->add_option("study", file_, "study file (YAML)")->required();
  command_->add_flag("--check", check_, "only read and check the study file");
  command_
      ->add_option("--only", only_,
                   "run only these variants' stages (comma-separated names); the study-wide "
                   "stages (reduced-order model, report) run once every variant is done")
      ->delimiter(',')
      ->allow_extra_args(false) // `--only EN study.yaml`: the file is not a variant's name
      ->take_all();             // `--only OR --only EN` as `--only OR,EN`
}

int StudyCommand::run() const {
  if (fem::mpi_size() > 1)
    input_error("run `tearflow study` as one process: it starts its stages on the study "
                "file's `ranks` itself");
  const StudySpec spec = load_study(file_, geometry_tbad_options());
  for (const std::string& name : only_)
    if (std::none_of(spec.variants.begin(), spec.variants.end(),
                     [&](const Variant& v) { return v.name == name; })) {
      std::vector<std::string> names;
      for (const Variant& v : spec.variants)
        names.push_back(v.name);
      input_error("--only: '{}' is not a variant of study '{}' ({}); its variants: {}", name,
                  spec.name, spec.file.string(), join_names(names, "and"));
    }
  if (check_) {
    fmt::print("study '{}': {} variant(s), case '{}', {} rank(s), output '{}'\n", spec.name,
               spec.variants.size(), spec.case_file.string(), spec.ranks, spec.output.string());
    return 0;
  }
  StudyRunner runner(spec, self_executable(), only_);
  return runner.run();
}

} // namespace tearflow::study
