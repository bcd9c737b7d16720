#pragma once
// Regions of pixels on a 2D image (a reformatted plane or a 2D scan's slice), pixel p = i + nx j:
// what the landmark planes and the 2D scans find their lumina with.
#include <cstddef>
#include <vector>

namespace tearflow::mri {

using Pixels = std::vector<char>; ///< one flag per pixel

struct PixelGrid {
  int nx = 0, ny = 0;
  std::size_t count() const { return static_cast<std::size_t>(nx) * ny; }
};

/// The 4-connected region of `mask` holding `seed` (empty when the seed is not in the mask).
Pixels region_of(const Pixels& mask, const PixelGrid& g, std::size_t seed);

/// The pixels in `a` or in `b`.
Pixels united(Pixels a, const Pixels& b);

/// `region` grown by `steps` pixels (8-connected: a square neighbourhood per step).
Pixels grown(Pixels region, const PixelGrid& g, int steps);

/// The pixels whose 8-neighbourhood meets `region` but which are not in it.
Pixels rim_of(const Pixels& region, const PixelGrid& g);

/// The share of `region`'s edge pixels (a 4-neighbour not in it) that lie on the image's
/// border or, given `inside`, next to a pixel not inside. A lumen grown from a seed in tissue
/// floods to the border, most of its edge there; a vessel the image merely grazes has a
/// small share.
double border_share(const Pixels& region, const PixelGrid& g, const Pixels* inside = nullptr);

/// A lumen region that has flooded its surroundings: more than this share on the border.
inline constexpr double kFloodedBorderShare = 0.3;

/// The pixel of `region` farthest from its edge (chamfer 3-4 distance, two passes; the first
/// such pixel in raster order): a point deep inside a lumen. `region` must not be empty.
std::size_t deepest_pixel(const Pixels& region, const PixelGrid& g);

} // namespace tearflow::mri
