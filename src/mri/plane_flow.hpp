#pragma once
// Flow through the landmark planes of a 4D-flow dataset, per frame (docs/mri.md):
//   1. reformat: the plane is sampled on a square pixel grid (side 2 `half_width`, pixel
//      `pixel`, default half the smallest voxel) spanned by two unit vectors e1, e2 normal
//      to the landmark's n; magnitude and velocity there by trilinear interpolation;
//   2. lumen: pixels whose magnitude is >= `lumen_fraction` of the magnitude at the lumen
//      point (the landmark's `point`, else its origin; median of the 3 x 3 pixels there),
//      the 4-connected region holding the lumen point kept: TL and FL of a station are told
//      apart by their points;
//   3. integrate, with pixel area dA:
//        A = sum_lumen dA,   Q = sum_{lumen + margin} (v . n) dA,   v_peak = max_lumen v . n,
//      the flow over the lumen grown by `flow_margin` (default half a voxel): no-slip makes
//      u vanish at the wall, but the voxels astride it hold partial-volume velocity that
//      belongs to the lumen's flow (the voxel: in-plane pixel of a one-slice 2D scan). Measured on
//      the analytic pipe (tests/test_mri.cpp): no margin loses 2-3 % of the flow, half a voxel
//      0.1-0.2 %, one voxel 0.04 % but adds the noise of a ring of tissue (SNR 20, 6 mm pipe: worst
//      frame 4.5 % -> 6-7 %).
// The pixel sums are the midpoint rule on the interpolated field; with pixels of half a voxel
// their error is far below that of the partial-volume images themselves.
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/landmarks.hpp"
#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

struct PlaneOptions {
  double pixel = 0.0;          ///< reformat pixel [m]; 0: half the smallest voxel spacing
  double half_width = 0.04;    ///< half the reformatted square's side [m]
  double lumen_fraction = 0.6; ///< lumen: magnitude >= this x the lumen point's
  double flow_margin = -1.0;   ///< flow region = lumen grown by this [m]; < 0: half a voxel
  /// Follow a moving vessel: each frame's lumen point is the previous frame's lumen pixel
  /// farthest from its edge (a 2D scan through the aortic root moves by ~1 cm over the cycle)
  bool track = false;
};

/// One landmark's values per frame, SI.
struct PlaneSeries {
  std::string name;
  std::vector<double> flow;          ///< Q [m^3/s]
  std::vector<double> area;          ///< A [m^2]
  std::vector<double> peak_velocity; ///< max v.n over the lumen [m/s]
};

/// Every landmark plane of `landmarks` (same order). InputError naming the landmark and the
/// frame when the plane lies outside the image or its lumen point is not in a lumen, or
/// naming TLk and FLk when their points fall in one lumen region (an unresolved flap).
std::vector<PlaneSeries> measure_planes(const Flow4D& data, const geometry::Landmarks& landmarks,
                                        const PlaneOptions& options = {});

/// Writes flow.csv (time_s, <landmark>_mL_per_s), area.csv (<landmark>_mm2) and
/// velocity.csv (<landmark>_peak_m_per_s) into `dir`: the measured layout that `tearflow
/// analyze` and `tearflow report` read (docs/analysis.md).
void write_measured_tables(const Flow4D& data, const std::vector<PlaneSeries>& series,
                           const std::filesystem::path& dir);

} // namespace tearflow::mri
