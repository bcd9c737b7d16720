#pragma once
// What outlet tuning aims at (`tearflow tune CASE --targets FILE`): the measured systolic,
// diastolic and mean pressure at the inlet and the flow split over the outlets, plus how
// close is close enough. docs/tuning.md documents the file.
#include <filesystem>
#include <string>
#include <vector>

#include "tuning/windkessel_fit.hpp"

namespace tearflow::tuning {

struct TuningTargets {
  InletPressures pressure;            ///< at the inlet [Pa]
  std::vector<OutletFraction> splits; ///< per outlet, fractions summing to 1
  double pressure_tolerance = 0.01;   ///< relative, per pressure
  double split_tolerance = 0.5;       ///< percentage points, per outlet
  int max_iterations = 4;             ///< 3D correction runs (0: the 0D stage only)
  int cycles = 2;                     ///< cardiac cycles per 3D run; the last is measured
  double domain_resistance = 0.0;     ///< the 3D domain's own resistance when known [Pa s/m^3]
  /// Stage 2 corrects the 0D model with the domain's resistance measured in each 3D run
  /// (true), or only rescales the 0D stage's aims by achieved / target (false).
  bool correct_domain = true;
  /// Per-outlet parameters: each outlet's resistance corrected by the domain's resistance to
  /// that outlet (R_i = R_T / f_i - e_i), instead of one R_T distributed by f_i.
  bool per_outlet = false;
  /// The 3D corrections happen at the cycle ends of the analysed run itself (`tearflow run
  /// --targets`, corrected_run.hpp) instead of in separate runs by `tearflow tune`: what a
  /// study does for such targets.
  bool in_run = false;
};

/// Reads and checks a targets file. InputError naming the file, line and key for unknown
/// keys, bad values, splits that do not sum to 100 % within 0.5 points (rounding), or
/// pressures no Windkessel can meet (0 < P_dias < MAP < P_sys).
TuningTargets load_targets(const std::filesystem::path& file);

} // namespace tearflow::tuning
