#pragma once
// `tearflow analyze RUN_DIR [--landmarks FILE] [--cycle N | --frames all] [-o DIR]`: the
// command-line edge of the landmark analysis (analysis/hemodynamics.hpp, docs/analysis.md).
#include <string>

#include <CLI/CLI.hpp>

namespace tearflow::analysis {

class AnalyzeCommand {
public:
  explicit AnalyzeCommand(CLI::App& app); ///< registers `analyze` on app
  bool selected() const { return command_->parsed(); }
  /// Runs it; returns the exit code. InputError for bad input.
  int run() const;

private:
  CLI::App* command_ = nullptr;
  std::string run_dir_, landmarks_, frames_ = "cycle", output_, case_file_;
  int cycle_ = 0;
  bool quiet_ = false;
};

} // namespace tearflow::analysis
