#pragma once
// `rom sweep`: the reduced-order model over a grid of entry and exit tear areas. Per variant
// the FL flow ratio and the TL-FL pressure difference at peak systole and end diastole at
// every station; written as sweep.csv and as sweep.html, heat maps (inline SVG) with the 3D
// variants marked. The grid is linear in each area, `steps` points from MIN to MAX.
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "rom/dissection_network.hpp"

namespace tearflow::rom {

struct SweepMark {
  std::string name;
  double entry = 0.0, exit = 0.0; ///< [mm^2]
};

struct SweepSpec {
  double entry_min = 0.0, entry_max = 0.0, exit_min = 0.0, exit_max = 0.0; ///< [mm^2]
  int steps = 20;
  std::vector<SweepMark> marks;
  int steps_per_cycle = 400;
};

/// "MIN:MAX" ranges and NAME=ENTRY:EXIT marks; InputError naming the option otherwise.
SweepSpec parse_sweep(const std::string& entry, const std::string& exit, int steps,
                      const std::vector<std::string>& marks);

struct SweepRow {
  double entry = 0.0, exit = 0.0;              ///< [mm^2]
  std::vector<double> fr_fl;                   ///< per station [%]
  std::vector<double> dp_systole, dp_diastole; ///< per station [mmHg]
  int cycles = 0;
};

struct SweepResult {
  std::vector<SweepRow> rows; ///< exit varies fastest
  double seconds = 0.0;       ///< the model's time (building and integrating), all variants
};

/// The station metrics of one prediction.
SweepRow station_metrics(const analysis::Analysis& a);

/// Every variant of the grid; the tears named "entry" and "exit" must exist. `progress`
/// prints one line per tenth.
SweepResult sweep_tears(const DissectionGeometry& g, const RomInputs& in, const RomCoefficients& k,
                        const SweepSpec& spec, bool progress);

/// sweep.csv (units in the column names) and sweep.html into `dir`.
void write_sweep(const SweepResult& r, const SweepSpec& spec, const std::filesystem::path& dir);

} // namespace tearflow::rom
