#pragma once
// Corrections of the measured phase, each switchable and reported (docs/mri.md):
//
// Background phase offset (eddy currents, concomitant gradients; Walker et al. 1993, Lankhaar
// et al. 2005): a slowly varying, time-constant offset b_c(x) per velocity component. Static
// tissue is found as the voxels with signal (signal_mask) and the smallest temporal standard
// deviation of velocity (max over components) times the mean magnitude: phase noise scales as 1 /
// magnitude, so this is the noise level in all static voxels, however dim, and larger in flowing
// blood (below the `static_percentile` of the signal voxels' values), and not in the flow
// region: the voxels whose value exceeds `flow_factor` times its `noise_quantile` over the
// voxels with signal (clearly flowing), dilated by `flow_margin` voxels. Without that region, slow
// bright blood at the vessel's rim (partial volume) passed the SD test and the refits, whose spread
// is set by dim tissue, and biased the fit by its mean flow: -1.1 +- 0.3 % of the flow at SNR
// 20 with no offset at all (issue 29; test_mri BackgroundCorrectionDoesNotBiasNoisyFlow).
// On those static voxels, the time-mean
// velocity is fitted by least squares with the polynomial
//   b_c(x) = sum_t a_ct m_t(x),  m = [1, x, y, z, x^2, y^2, z^2, xy, xz, yz] (up to `order`),
// x the voxel index scaled to [-1, 1] per axis, then refitted three times without the voxels
// more than 3 robust SDs off (slow blood that passed the SD test), and b_c is subtracted from
// every frame.
//
// Phase unwrapping (temporal; Xiang 1995): a velocity beyond +-venc aliases by 2 venc. Frame
// 0 (end diastole, the trigger) is taken as free of aliasing; then frame by frame
//   v_k <- v_k + 2 venc round((v_{k-1} - v_k) / (2 venc)),
// exact while the true velocity changes by less than venc between frames, so aliasing to any
// multiple of venc (twice venc included) is undone. Only voxels with a magnitude SNR above
// 10 are unwrapped: their phase noise, 0.45 venc / SNR, is then < 0.045 venc and a false jump
// by venc between two frames a 15-sigma event; dimmer voxels (tissue at the edge of the
// noise) would gain false jumps (measured on the SNR 20 pipe with a threshold of 3: 1094 of
// its values), and static tissue does not alias anyway.
#include <array>
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

/// Voxel (i, j, k)'s index scaled to [-1, 1] per axis.
Vec3 normalized_position(const ImageGrid& grid, int i, int j, int k);

/// The polynomial's monomials up to `order` (0, 1 or 2) at x, in the order above.
void monomials(const Vec3& x, int order, std::vector<double>& out);

struct BackgroundOptions {
  int order = 2;                  ///< 0 constant, 1 linear, 2 quadratic
  double noise_multiple = 3.0;    ///< signal: mean magnitude > this x the noise (signal_mask)
  double static_percentile = 0.5; ///< static: SD x magnitude in this lowest fraction of them
  /// Flowing: SD x magnitude above this multiple of its `noise_quantile` over the voxels with
  /// signal (static tissue's noise level while that many of them are static) ...
  double flow_factor = 3.0;
  double noise_quantile = 0.25;
  /// ... and the voxels within this many of those along each axis (the rim's partial volume;
  /// 2 left too little tissue in a small field of view, see docs/mri.md).
  int flow_margin = 1;
};

struct BackgroundReport {
  std::size_t static_voxels = 0;
  std::size_t flow_region_voxels = 0;              ///< excluded as flowing blood or its rim
  std::array<std::vector<double>, 3> coefficients; ///< a_ct [m/s]
  std::array<double, 3> rms_before{}, rms_after{}; ///< time-mean velocity on static tissue [m/s]
  nlohmann::json to_json() const;
};

/// Fits and removes the background offset (in place). SolverError when fewer static voxels
/// than three times the polynomial's terms are found.
BackgroundReport correct_background(Flow4D& data, const BackgroundOptions& options = {});

struct UnwrapReport {
  std::size_t values_unwrapped = 0; ///< voxel-frame-component values moved by 2 venc k
  std::size_t voxels = 0;           ///< voxels with at least one unwrapped value
  nlohmann::json to_json() const;
};

/// Temporal unwrapping (in place); InputError when the data has no venc.
UnwrapReport unwrap_temporal(Flow4D& data, double noise_multiple = 10.0);

/// The voxels with signal: time-mean magnitude > noise_multiple x the noise, the noise
/// estimated as the median over all voxels of the magnitude's temporal SD (static voxels
/// are the majority; in them it varies by noise alone). Air (Rician mean 1.25 sigma) stays
/// out, tissue down to an SNR of 3 is in; noise-free data: every voxel with signal > 0.
std::vector<char> signal_mask(const Flow4D& data, double noise_multiple = 3.0);

} // namespace tearflow::mri
