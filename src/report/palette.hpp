#pragma once
// A palette of at most 256 colours for a set of pictures (median cut, Heckbert 1982): the
// report's animations are rendered with a few hundred colours (a colour map, a translucent
// surface and their antialiased edges), so one shared palette stores them at a byte a pixel.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace tearflow::report {

using Rgba = std::uint32_t; ///< 0xRRGGBBAA

/// Each colour's pixel count over the pictures.
using ColourCounts = std::unordered_map<Rgba, std::uint64_t>;

struct Palette {
  std::vector<Rgba> colours;                 ///< at most 256
  std::unordered_map<Rgba, std::uint8_t> of; ///< every counted colour -> its entry
};

/// The colours themselves when there are at most `size` (<= 256) of them (lossless); else
/// Heckbert's median cut: the box of colours whose pixels lie farthest from their mean (summed
/// squared distance) split at the weighted median of its channel of largest variance, until
/// there are `size` boxes; each box's entry its pixels' mean, every colour mapped to its
/// nearest entry.
Palette median_cut(const ColourCounts& counts, std::size_t size = 256);

} // namespace tearflow::report
