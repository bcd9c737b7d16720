#pragma once
// Synthetic 4D-flow MRI of a simulation: the velocity of a run's VTU series imaged on an MRI
// grid the way synthetic.hpp images the analytic pipe:
//   - the frames: the run's last complete cycle (cycles.json; else every saved frame), its
//     span T = t_last - t_first taken as the period; MRI frame k at t_k = t_first + k T / N;
//   - time: the mean over n_t instants of the frame's window [t_k - T/2N, t_k + T/2N], the
//     velocity at an instant linear between the saved frames around it (periodic in T);
//   - space: the mean over n^3 sub-voxel points, probed in the fluid mesh (vtkProbeFilter,
//     P1 interpolation); points outside the fluid count as zero velocity. A 2D scan's pixels
//     that the fluid's boundary crosses (fluid fraction between 0 and 1, or a neighbour's
//     differs) are sampled again on a finer in-plane grid: 3 x 3 points per pixel left the
//     small true lumen of the TBAD demo (61-71 mm^2) 2.6-3.5 % too large at 1 mm pixels, 6 x 6
//     0.6-1.9 % (the edge's fraction is what the area of a cine scan is measured from);
//   - magnitude: blood 1 in the fluid fraction of the voxel, static tissue 0.2 elsewhere;
//   - noise and wrapping: add_scanner_effects.
// Since the time interpolation is linear, the sub-voxel means are taken per saved frame once
// and the window means formed from them.
#include <filesystem>
#include <vector>

#include "mri/synthetic.hpp"

namespace tearflow::mri {

struct RunScan {
  std::filesystem::path run_dir; ///< holds flow.pvd (and cycles.json)
  ImageGrid grid;                ///< size 0: the fluid's bounds plus `margin`, `voxel` spacing
  double voxel = 1.5e-3;         ///< [m] when the grid is derived
  double margin = 5e-3;          ///< [m] around the fluid's bounds when the grid is derived
  Mat3 direction{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; ///< derived grid's axes (rows)
  int frames = 20;
  int voxel_samples = 3, time_samples = 3;
  int edge_samples = 6; ///< in-plane sub-samples per axis of a 2D scan's edge pixels
  ScannerEffects effects;
  double tissue_signal = 0.2;
  /// 4D flow, or a 2D scan on a one-slice `grid` (2D phase contrast, cine: encode())
  Encoding encoding = Encoding::velocity_3d;
};

/// The scan; InputError naming the run's files when they cannot be read.
Flow4D synthesize_run(const RunScan& scan);

/// Several scans of one run on `grids` (the slices of 2D scans at several planes), each saved
/// frame read once for all.
std::vector<Flow4D> synthesize_run(const RunScan& scan, const std::vector<ImageGrid>& grids);

} // namespace tearflow::mri
