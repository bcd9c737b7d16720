#pragma once
// Measured data on the landmarks, read into the same Analysis that a simulation gives, so
// that `tearflow analyze` derives the same quantities (FL flow ratio, dP, pressure drops,
// areas) from both and `tearflow report` compares them on one page. A measurement folder
// holds any of three tables, one column per landmark, the unit in each column's name:
//   flow.csv      time_s,inlet_mL_per_s,AAo_mL_per_s,TL1_mL_per_s,...   (4D-flow or 2D PC MRI)
//   area.csv      time_s,AAo_mm2,TL1_mm2,...                            (2D cine MRI)
//   pressure.csv  time_s,inlet_mmHg,TL1_mmHg,...                        (catheter)
// Units: flow mL_per_s | m3_per_s, area mm2 | m2, pressure mmHg | Pa. The tables may sample
// the cycle differently (20 MRI frames, 40 cine frames, ...): every quantity is interpolated
// linearly onto the times of the first table present (flow, else area, else pressure),
// holding the end values outside a table's time range. A quantity that a table does not give
// for a landmark is NaN (null in metrics.json, "nan" in the CSVs). Landmarks TLk / FLk are
// the paired stations' true and false lumen; the others cross the undivided aorta.
#include <filesystem>

#include "analysis/hemodynamics.hpp"

namespace tearflow::analysis {

/// True when `dir` holds at least one of the measurement tables.
bool is_measurement_folder(const std::filesystem::path& dir);

/// Reads the tables of `dir` (docs/analysis.md). InputError naming the file, the line and the
/// column for a missing time column, an unknown unit, a non-number, non-increasing times, a
/// landmark given twice, or a folder with none of the tables.
Analysis read_measured(const std::filesystem::path& dir);

} // namespace tearflow::analysis
