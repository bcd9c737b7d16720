#pragma once
// Synthetic 4D-flow MRI of an analytic field: the exact Womersley flow in a straight rigid
// pipe (bc/womersley_exact.hpp) imaged on any oriented voxel grid, as a scanner would:
//   - velocity:   each voxel holds the mean of u over the voxel (partial volume), from
//                 n^3 sub-voxel samples, and over the frame's time window [t_k - dt/2,
//                 t_k + dt/2], dt = period / frames, from n_t samples (midpoint rules);
//   - magnitude:  blood `lumen_signal`, static tissue `tissue_signal` out to
//                 `tissue_radius`, air 0 beyond, also partial-volume averaged;
//   - noise:      magnitude noise N(0, s), s = lumen_signal / SNR (then |.|); phase noise
//                 sigma_v = sqrt(2)/pi * venc * s / m, m the voxel's magnitude (the standard
//                 phase-contrast result; Pelc et al. 1991), uniform over +-venc where m ~ 0;
//   - wrapping:   a velocity beyond +-venc aliases into [-venc, venc) (phase wrap).
// The frame's exact flow is the window mean of Q(t), computed from the Fourier modes:
//   Qbar_k = Re sum_n q_n e^{i n w t_k} sinc(n w dt / 2).
#include <cstdint>

#include "bc/womersley_exact.hpp"
#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

struct PipeScan {
  bc::WomersleyFlow flow;     ///< the exact flow: radius, modes, omega (> 0: pulsatile)
  Vec3 axis_point{};          ///< a point on the pipe axis [m] (patient LPS)
  Vec3 axis{0, 0, 1};         ///< flow direction (unit) along the axis
  double tissue_radius = 0.0; ///< static tissue out to this radius [m]; 0: 2 x pipe radius
  ImageGrid grid;             ///< where the scanner images
  int frames = 20;            ///< cardiac frames over one period 2 pi / omega
  double venc = 1.0;          ///< [m/s]
  double snr = 0.0;           ///< magnitude SNR in the lumen; 0: no noise
  bool wrap = true;           ///< alias velocities beyond venc
  int voxel_samples = 4;      ///< sub-samples per voxel axis (partial volume)
  int time_samples = 4;       ///< sub-samples per frame window
  double lumen_signal = 1.0, tissue_signal = 0.2;
  std::uint64_t seed = 1; ///< noise generator seed
  /// 4D flow, or a 2D scan (then the grid has one slice; encode() below)
  Encoding encoding = Encoding::velocity_3d;
};

/// The demonstration flow of `tearflow mri synthesize` and the tests: blood (1060 kg/m^3,
/// 4 mPa s) at 75 beats per minute, Q(t) = Q0 (1 - swing cos wt + 0.1 sin 2wt) with
/// Q0 = mean_velocity pi R^2: positive throughout for swing < 0.8, lowest near t = 0 (end
/// diastole, the trigger), so that frame 0 is the least likely to alias.
bc::WomersleyFlow pulsatile_pipe_flow(double radius, double mean_velocity = 0.35,
                                      double swing = 0.3);

/// The scan; InputError for a non-pulsatile flow, no frames, venc <= 0 or an empty grid.
Flow4D synthesize_pipe(const PipeScan& scan);

/// Keeps, of clean data, what a scan of encoding `e` measures: 2D phase contrast the velocity's
/// component along the slice normal (stored as v_n n), cine none (zero velocity). Before the
/// noise, so that a through-plane scan's phase noise is that of one encoding.
void encode(Flow4D& data, Encoding e);

/// The scanner's noise and wrapping (above), applied in place to clean data: each frame's
/// magnitude is its noise-free signal, lumen_signal the blood's (SNR is defined there). Phase
/// noise and wrapping act on each measured velocity: the three components of 4D flow, v . n of
/// a through-plane scan, none of cine.
struct ScannerEffects {
  double venc = 1.0, snr = 0.0;
  bool wrap = true;
  double lumen_signal = 1.0;
  std::uint64_t seed = 1;
};
void add_scanner_effects(Flow4D& data, const ScannerEffects& effects);

/// The exact flow averaged over frame k's window [m^3/s].
double exact_frame_flow(const PipeScan& scan, int k);

/// Adds the phase offset  v_c += sum_t coefficient * monomial(x) to every frame, with x the
/// voxel's index scaled to [-1, 1] per axis and the monomials of corrections.hpp:
/// a known background for tests of its correction.
void add_background(Flow4D& data, const std::array<std::vector<double>, 3>& coefficients);

} // namespace tearflow::mri
