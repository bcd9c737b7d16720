#pragma once
// An animated PNG (APNG, W3C PNG 3rd edition: acTL, fcTL, fdAT chunks) from PNG pictures of
// one size: every browser plays it in an <img>, so the report's animations need no video
// codec and stay inside the self-contained page.
#include <filesystem>
#include <vector>

namespace tearflow::report {

/// Joins `frames` (8-bit RGB or RGBA PNG files of equal size and pixel format) into the
/// looping animation `out`, each frame shown `delay_ms` milliseconds. The frames share one
/// palette (report/palette.hpp: exact up to 256 colours) and each after the first stores only
/// the rectangle that changed: about a third of the RGB frames' bytes for the streamlines
/// (docs/analysis.md). InputError naming a frame that is not such a PNG or differs from the
/// first in size or format, or `out` when it cannot be written.
void write_apng(const std::vector<std::filesystem::path>& frames, int delay_ms,
                const std::filesystem::path& out);

} // namespace tearflow::report
