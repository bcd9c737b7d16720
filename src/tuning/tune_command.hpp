#pragma once
// `tearflow tune CASE --targets FILE [-o TUNED.yaml]`: the command-line edge of outlet
// tuning. Writes the tuned case (the input case with its outlets replaced) and
// `<tuned>.tuning.json` (every step, and the target / achieved / error table).
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

namespace tearflow::tuning {

class TuneCommand {
public:
  explicit TuneCommand(CLI::App& app); ///< registers `tune` on app
  bool selected() const { return command_->parsed(); }
  /// Runs it; returns the exit code (1 when the targets were not met). InputError for bad
  /// input. `cli_petsc`: PETSc options from the command line, for the 3D runs.
  int run(const std::string& cli_petsc) const;

private:
  CLI::App* command_ = nullptr;
  std::string case_file_, targets_file_, output_;
  int iterations_ = -1;
  bool quiet_ = false;
};

} // namespace tearflow::tuning
