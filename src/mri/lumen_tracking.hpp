#pragma once
// The true and false lumen's areas over the cycle from a 2D cine scan at a landmark station
// (docs/mri.md, "2D cine"; what the reference study tracked at its planes for the wall and
// flap motion, with a published method without public code). Per frame, on the slice's pixels:
//   1. markers: one point per lumen; frame 0 the model's TL and FL lumen points projected onto
//      the slice (or given), each later frame the pixel of that lumen's previous region
//      farthest from its edge, so a marker follows its own lumen as the wall and flap move;
//   2. each lumen: the 4-connected region of pixels whose magnitude is >= `lumen_fraction` of
//      its blood's (the median of the 3 x 3 pixels at its marker), holding its marker. Blood
//      is bright in cine, the wall and the flap dark; at a blood-tissue edge the pixel's
//      magnitude is its blood fraction's mix, so the threshold halfway between blood and
//      tissue (0.6 of blood for tissue at 0.2) counts a pixel when most of it is blood;
//   3. where the two regions touch (a flap thinner than a pixel, or a tear in the slice): their
//      union is split by the watershed from the two markers on the inverted magnitude (ITK's
//      MorphologicalWatershedFromMarkersImageFilter), the flap being the dark ridge between
//      them. A lumen is grown from its own marker only, so the labels cannot swap; a frame
//      whose TL overlaps the previous frame's FL more than the previous TL is counted as a
//      swap all the same (a check, expected 0).
//   4. area: interior pixels 1 each; the region's edge pixels and the ring around it by blood
//      fraction (m - tissue) / (blood - tissue), blood the median over the lumen's interior,
//      tissue the median two and three pixels out from both lumina; a ring pixel touching
//      both lumina gives each half. A threshold count is unbiased only on average over edge
//      orientations: a flap along the pixel rows (the TBAD demo's, at some stations) made the
//      true lumen 5-13 % too large at 1 mm pixels (docs/mri.md).
#include <optional>
#include <string>
#include <vector>

#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

struct TrackOptions {
  double lumen_fraction = 0.6; ///< lumen: magnitude >= this x its blood's
};

struct LuminaSeries {
  std::string station;                  ///< "2" for TL2 / FL2, or an aorta landmark's name
  std::vector<double> time;             ///< per frame [s]
  std::vector<double> tl_area, fl_area; ///< [m^2]
  int split_frames = 0;                 ///< frames where the watershed split the lumina
  int swaps = 0;                        ///< frames whose labels overlap the other's before
  /// Per frame and pixel (slice order i + nx j): 0 neither, 1 true lumen, 2 false lumen.
  std::vector<std::vector<unsigned char>> labels;
};

/// Tracks the lumina of a cine scan; without `fl_point` the one lumen of an undivided aorta
/// (its area in tl_area, fl_area empty). InputError naming the station when a point lies
/// outside the slice or on no signal, or both points fall on one pixel.
LuminaSeries track_lumina(const Flow4D& cine, const std::string& station, const Vec3& tl_point,
                          const std::optional<Vec3>& fl_point, const TrackOptions& options = {});

} // namespace tearflow::mri
