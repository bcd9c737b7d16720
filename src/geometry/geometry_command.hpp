#pragma once
// `tearflow geometry tbad | import | report`: the command-line edge of the geometry module.
// Options are in mm and mm^2 here and converted to SI before anything else sees them.
#include <memory>

#include <CLI/CLI.hpp>

namespace tearflow::geometry {

struct GeometryOptions; // the parsed options of all three subcommands

class GeometryCommand {
public:
  /// Registers `geometry` and its subcommands on `app`.
  explicit GeometryCommand(CLI::App& app);
  ~GeometryCommand();
  /// True when the command line chose `geometry`.
  bool selected() const;
  /// Runs the chosen subcommand; returns the exit code. InputError for bad input.
  int run() const;

private:
  CLI::App* command_ = nullptr;
  CLI::App *tbad_ = nullptr, *import_ = nullptr, *report_ = nullptr;
  std::unique_ptr<GeometryOptions> options_;
};

} // namespace tearflow::geometry
