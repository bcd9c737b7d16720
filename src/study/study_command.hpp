#pragma once
// `tearflow study STUDY.yaml`: the command-line edge of the study (study/study_runner.hpp,
// docs/study.md).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tearflow::study {

class StudyCommand {
public:
  explicit StudyCommand(CLI::App& app); ///< registers `study` on app
  bool selected() const { return command_->parsed(); }
  /// Runs the study; returns the exit code. InputError for a bad study file.
  int run() const;

private:
  CLI::App* command_ = nullptr;
  std::string file_;
  bool check_ = false;
  std::vector<std::string> only_; ///< --only: these variants' stages, none of the others'
};

} // namespace tearflow::study
