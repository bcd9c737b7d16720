#pragma once
// A scan read and corrected as every MRI command takes it (docs/mri.md, "Corrections"):
// temporal phase unwrapping, then the background phase offset fitted over static tissue,
// each switchable, each recorded with its timing in a JSON report. One path for 4D flow and
// 2D phase contrast (a one-slice grid: the background polynomial's terms along the normal
// vanish, so its fit is in-plane).
#include <filesystem>

#include <nlohmann/json.hpp>

#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

struct CorrectionChoice {
  double venc = 0.0; ///< [m/s]; > 0 overrides (or supplies) the files' venc
  bool unwrap = true;
  bool background = true;
  int background_order = 2; ///< 0, 1 or 2
};

/// Reads `input` (DICOM folder or volume folder) and applies the corrections chosen; `report`
/// gets the grid, venc, each correction's report and the seconds each step took.
Flow4D read_corrected(const std::filesystem::path& input, const CorrectionChoice& choice,
                      nlohmann::json& report);

} // namespace tearflow::mri
