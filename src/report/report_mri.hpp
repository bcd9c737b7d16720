#pragma once
// The "simulation against 4D-flow MRI" section of a `tearflow report` page: what `tearflow
// mri compare` wrote (compare.json, flow_comparison.csv; src/mri/compare.hpp, docs/mri.md)
// as a statistics table, and the data for its figures (report/report.js: Bland-Altman plot,
// flow waveforms of both per landmark). Pooled over all landmarks and frames, with
// d = Q_mri - Q_sim and m = (Q_mri + Q_sim) / 2 per pair: bias = mean d, SD = sample SD of d,
// limits of agreement bias +- 1.96 SD (Bland & Altman, Lancet 1986).
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace tearflow::report {

/// {dir, comparison: compare.json, pairs: {landmark: {time_s, simulation_mL_per_s, ...}},
/// pooled: {pairs, bias_mL_per_s, sd_mL_per_s, limits_of_agreement_mL_per_s}}. InputError
/// naming the file when either is missing or malformed.
nlohmann::json report_mri_data(const std::filesystem::path& compare_dir);

/// The section's table (HTML): per landmark mean, net volume and peak flow of both, the
/// difference as mean +- SD, the limits of agreement and r; the pooled row; FL flow ratios
/// and voxel-wise differences when compare.json has them.
std::string mri_comparison_table(const nlohmann::json& mri);

} // namespace tearflow::report
