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
// per paired station k: FL flow ratio Qbar_FLk / (Qbar_FLk + Qbar_TLk) on both sides.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"

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

struct Comparison {
  std::vector<WaveformComparison> landmarks;
  nlohmann::json to_json() const; ///< every key names its unit; FL flow ratios included
};

/// InputError when the two share no landmark with a flow.
Comparison compare_flows(const analysis::Analysis& simulation, const analysis::Analysis& mri);

/// compare.json and flow_comparison.csv (per landmark and frame: time, both flows, their
/// difference and mean: the Bland-Altman pairs) into `dir`.
void write_comparison(const Comparison& c, const std::filesystem::path& dir);

} // namespace tearflow::mri
