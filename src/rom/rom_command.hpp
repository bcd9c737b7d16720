#pragma once
// `tearflow rom predict|calibrate|sweep`: the reduced-order model's command-line edge
// (docs/rom.md).
//   rom predict MODEL_DIR --case CASE [--entry-tear-area MM2] [--exit-tear-area MM2]
//       [--tear-area NAME=MM2] [-o DIR]      metrics.json and CSVs as `analyze` writes them
//   rom calibrate MODEL_DIR --run RUN_DIR [--case CASE] ...   fits the coefficients to 3D runs
//   rom sweep MODEL_DIR --case CASE --entry A:B --exit A:B [--steps N] [--mark NAME=E:X] [-o DIR]
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rom/dissection_network.hpp"

namespace tearflow::rom {

class RomCommand {
public:
  explicit RomCommand(CLI::App& app); ///< registers `rom` on app
  bool selected() const { return command_->parsed(); }
  int run() const; ///< InputError for bad input

private:
  /// The model directory's geometry, the case's inputs and the coefficients (predict, sweep).
  struct Model {
    std::filesystem::path dir;
    DissectionGeometry geometry;
    RomInputs inputs;
    RomCoefficients coefficients;
  };
  Model model() const;
  int predict() const;
  int calibrate() const;
  int sweep() const;
  CLI::App *command_ = nullptr, *predict_ = nullptr, *calibrate_ = nullptr, *sweep_ = nullptr;
  std::string model_dir_, case_file_, output_, coefficients_file_;
  std::vector<std::string> runs_, cases_, run_models_, tear_areas_, marks_, fit_;
  double entry_area_ = 0.0, exit_area_ = 0.0, wall_thickness_ = 0.0;
  std::string entry_range_, exit_range_;
  int steps_ = 20, steps_per_cycle_ = 400;
  bool quiet_ = false;
};

} // namespace tearflow::rom
