#pragma once
// Simulation against 4D-flow MRI at the landmarks (`tearflow mri compare`, docs/mri.md). Both
// sides are analyses (analysis/hemodynamics.hpp): a run's, or a folder of measured tables
// such as `tearflow mri flow` writes. Times are taken from each side's first frame; the
// simulation's flow is interpolated linearly onto the MRI frames (held at its ends). Per
// landmark present in both, with d_k = Q_mri(t_k) - Q_sim(t_k) over the N MRI frames:
//   mean flow  Qbar = (1/T) int Q dt (trapezoidal over the frames, T their span),
//   net volume V = int Q dt,  peak flow max_k Q,
//   differences: bias = mean d_k, SD = sample SD of d_k (Bland-Altman: limits of agreement
//   bias +- 1.96 SD against the pair means), Pearson's r of the two waveforms;
// per paired station k: FL flow ratio Qbar_FLk / (Qbar_FLk + Qbar_TLk) on both sides; and,
// given the scan itself, voxel-wise speed and direction differences (below).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

struct WaveformComparison {
  std::string landmark;
  std::vector<double> time, simulation, mri; ///< [s], [m^3/s] on the MRI frames
  double mean_sim = 0, mean_mri = 0;         ///< [m^3/s]
  double volume_sim = 0, volume_mri = 0;     ///< [m^3]
  double peak_sim = 0, peak_mri = 0;         ///< [m^3/s]
  double bias = 0, sd = 0;                   ///< of Q_mri - Q_sim [m^3/s]
  double correlation = 0;                    ///< Pearson r
};

/// Voxel-wise velocity differences inside the lumen: the MRI against the simulation imaged
/// on the MRI's grid and frames without noise (synthetic_run.hpp). Lumen voxels: fluid
/// fraction >= 1/2 in the simulated scan; speed difference |v_mri| - |v_sim| over them and
/// all frames; the angle between v_mri and v_sim where |v_sim| >= 10 % of its frame's
/// largest speed (elsewhere the direction is noise).
struct VoxelComparison {
  std::size_t voxel_frames = 0, angle_voxel_frames = 0;
  double speed_difference_mean = 0, speed_difference_sd = 0; ///< [m/s]
  double angle_mean_deg = 0, angle_median_deg = 0;
  /// The scan's values that are not numbers (non_finite.hpp), all outside the lumen's voxels
  /// (inside, compare_voxels refuses).
  nlohmann::json scan_non_finite = nlohmann::json::object();
  nlohmann::json to_json() const;
};

/// `simulated` is the noise-free scan of the run (its magnitude the fluid fraction's signal,
/// 0.2 + 0.8 fraction). InputError for different grids or frame counts.
VoxelComparison compare_voxels(const Flow4D& simulated, const Flow4D& mri);

struct Comparison {
  std::vector<WaveformComparison> landmarks;
  std::optional<VoxelComparison> voxels;
  nlohmann::json to_json() const; ///< every key names its unit; FL flow ratios included
};

/// InputError when the two share no landmark with a flow.
Comparison compare_flows(const analysis::Analysis& simulation, const analysis::Analysis& mri);

/// compare.json and flow_comparison.csv (per landmark and frame: time, both flows, their
/// difference and mean: the Bland-Altman pairs) into `dir`.
void write_comparison(const Comparison& c, const std::filesystem::path& dir);

} // namespace tearflow::mri
