#pragma once
// `tearflow report RUN_DIR [RUN_DIR...] [-o FILE] [--mri COMPARE_DIR] [--rom-sweep DIR] [--png]`:
// the command-line edge of the report pages (report/report.hpp, docs/analysis.md).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tearflow::report {

class ReportCommand {
public:
  explicit ReportCommand(CLI::App& app); ///< registers `report` on app
  bool selected() const { return command_->parsed(); }
  /// Runs it; returns the exit code. InputError for bad input.
  int run() const;

private:
  CLI::App* command_ = nullptr;
  std::vector<std::string> run_dirs_;
  std::string comparison_ = "comparison.html", chromium_ = "chromium", mri_, rom_sweep_;
  bool png_ = false, quiet_ = false;
};

} // namespace tearflow::report
