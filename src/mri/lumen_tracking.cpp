// Tracking the true and false lumen through a 2D cine scan (lumen_tracking.hpp).
#include "mri/lumen_tracking.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <itkImage.h>
#include <itkMorphologicalWatershedFromMarkersImageFilter.h>

#include "core/error.hpp"
#include "mri/non_finite.hpp"
#include "mri/pixel_regions.hpp"

namespace tearflow::mri {

namespace {

double median(std::vector<float> v) {
  if (v.empty())
    return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The 3 x 3 pixels at p (fewer at the slice's edge).
std::vector<std::size_t> around(const PixelGrid& s, std::size_t p) {
  std::vector<std::size_t> out;
  const int i = static_cast<int>(p % s.nx), j = static_cast<int>(p / s.nx);
  for (int b = std::max(0, j - 1); b <= std::min(s.ny - 1, j + 1); ++b)
    for (int a = std::max(0, i - 1); a <= std::min(s.nx - 1, i + 1); ++a)
      out.push_back(static_cast<std::size_t>(b) * s.nx + a);
  return out;
}

/// The median magnitude of the 3 x 3 pixels at p.
double blood_level(const std::vector<float>& m, const PixelGrid& s, std::size_t p) {
  std::vector<float> values;
  for (std::size_t q : around(s, p))
    values.push_back(m[q]);
  return median(std::move(values));
}

/// Splits `both` (one region holding both markers) by the watershed from the markers on the
/// inverted magnitude; pixels outside it are set above every pixel inside, so that the flood
/// fills `both` from the markers before it reaches them (the result is then read inside only).
std::pair<Pixels, Pixels> split(const Pixels& both, const std::vector<float>& m, const PixelGrid& s,
                                std::size_t tl, std::size_t fl) {
  using Image = itk::Image<float, 2>;
  using Labels = itk::Image<unsigned char, 2>;
  Image::RegionType region;
  region.SetSize({static_cast<itk::SizeValueType>(s.nx), static_cast<itk::SizeValueType>(s.ny)});
  auto height = Image::New();
  height->SetRegions(region);
  height->Allocate();
  auto markers = Labels::New();
  markers->SetRegions(region);
  markers->Allocate();
  markers->FillBuffer(0);
  // The largest number: a NaN elsewhere in the slice (reported, not read) must not be it.
  float top = std::numeric_limits<float>::lowest();
  for (float x : m)
    if (std::isfinite(x))
      top = std::max(top, x);
  float* h = height->GetBufferPointer();
  for (std::size_t p = 0; p < s.count(); ++p)
    h[p] = both[p] ? top - m[p] : 2 * top + 1;
  markers->GetBufferPointer()[tl] = 1;
  markers->GetBufferPointer()[fl] = 2;
  auto watershed = itk::MorphologicalWatershedFromMarkersImageFilter<Image, Labels>::New();
  watershed->SetInput(height);
  watershed->SetMarkerImage(markers);
  watershed->SetMarkWatershedLine(false); // every pixel to one lumen: no area lost on a line
  watershed->SetFullyConnected(false);
  watershed->Update();
  const unsigned char* label = watershed->GetOutput()->GetBufferPointer();
  Pixels a(s.count(), 0), b(s.count(), 0);
  for (std::size_t p = 0; p < s.count(); ++p)
    if (both[p])
      (label[p] == 1 ? a : b)[p] = 1;
  // Each lumen is the part connected to its own marker (a watershed basin is connected).
  return {region_of(a, s, tl), region_of(b, s, fl)};
}

/// A lumen's area in pixels, with its edge counted by blood fraction (lumen_tracking.hpp,
/// step 4): interior pixels 1 each; the region's edge pixels and the rim around it
///   f = (m - tissue) / (blood - tissue),
/// unclamped so that noise averages out; a rim pixel that touches both lumina (the flap)
/// gives each half. `blood`: the median over the region's interior.
double lumen_pixels(const Pixels& region, const Pixels& rim, const Pixels& other_rim,
                    const Pixels& other, const std::vector<float>& m, const PixelGrid& s,
                    double tissue) {
  std::vector<float> inner;
  Pixels edge(region.size(), 0);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * s.nx + i;
      if (!region[p])
        continue;
      const bool interior = i > 0 && j > 0 && i + 1 < s.nx && j + 1 < s.ny && region[p - 1] &&
                            region[p + 1] && region[p - s.nx] && region[p + s.nx];
      if (interior)
        inner.push_back(m[p]);
      else
        edge[p] = 1;
    }
  const double blood = median(inner);
  const double contrast = blood - tissue;
  double pixels = static_cast<double>(inner.size());
  for (std::size_t p = 0; p < region.size(); ++p) {
    if (!(contrast > 0) || inner.empty()) { // too small to have an inside: plain count
      pixels += edge[p];
      continue;
    }
    if (edge[p])
      pixels += (m[p] - tissue) / contrast;
    else if (rim[p] && !other[p])
      pixels += (other_rim[p] ? 0.5 : 1.0) * (m[p] - tissue) / contrast;
  }
  return pixels;
}

/// The tissue's magnitude around the lumina: the median over the pixels two and three steps
/// out from them (8-neighbourhood), none of them in a lumen or its rim.
double tissue_level(const Pixels& lumina, const std::vector<float>& m, const PixelGrid& s) {
  Pixels near = lumina;
  std::vector<float> band;
  for (int step = 1; step <= 3; ++step) {
    const Pixels ring = rim_of(near, s);
    for (std::size_t p = 0; p < ring.size(); ++p)
      if (ring[p]) {
        near[p] = 1;
        if (step >= 2)
          band.push_back(m[p]);
      }
  }
  return median(band);
}

std::size_t overlap(const Pixels& a, const Pixels& b) {
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.size(); ++p)
    n += a[p] && b[p];
  return n;
}

} // namespace

LuminaSeries track_lumina(const Flow4D& cine, const std::string& station, const Vec3& tl_point,
                          const std::optional<Vec3>& fl_point, const TrackOptions& o) {
  if (cine.grid.size[2] != 1)
    input_error("station {}: a 2D cine scan (one slice) is needed, this one has {} slices", station,
                cine.grid.size[2]);
  const ImageGrid& g = cine.grid;
  const PixelGrid s{g.size[0], g.size[1]};
  auto pixel_of = [&](const Vec3& p, const char* lumen) {
    cine.check_in_slice(p, fmt::format("station {}: the {} point", station, lumen));
    const Vec3 index = g.index(p);
    const long i = std::lround(index[0]), j = std::lround(index[1]);
    if (i < 0 || j < 0 || i >= s.nx || j >= s.ny)
      input_error("station {}: the {} point ({:.1f}, {:.1f}, {:.1f}) mm lies outside the cine "
                  "slice's field of view",
                  station, lumen, p[0] * 1e3, p[1] * 1e3, p[2] * 1e3);
    return static_cast<std::size_t>(j) * s.nx + static_cast<std::size_t>(i);
  };
  const bool two = fl_point.has_value();
  std::size_t tl = pixel_of(tl_point, two ? "true lumen" : "lumen");
  std::size_t fl = two ? pixel_of(*fl_point, "false lumen") : tl;
  if (two && tl == fl)
    input_error("station {}: the true and false lumen points fall on one pixel", station);
  const double pixel_area = g.spacing[0] * g.spacing[1];
  LuminaSeries out;
  out.station = station;
  Pixels previous_tl, previous_fl;
  for (std::size_t f = 0; f < cine.frames.size(); ++f) {
    const std::vector<float>& m = cine.frames[f].magnitude;
    std::vector<std::size_t> markers = around(s, tl);
    if (two)
      for (std::size_t q : around(s, fl))
        markers.push_back(q);
    refuse_non_finite(cine, f, markers, 0, 0, fmt::format("station {}", station),
                      "the blood level at its lumen points", "its lumina cannot be found");
    const double level_tl = blood_level(m, s, tl), level_fl = blood_level(m, s, fl);
    if (!(level_tl > 0) || !(level_fl > 0))
      input_error("station {}, frame {}: no signal at the {} lumen point", station, f,
                  level_tl > 0 ? "false" : "true");
    auto mask_of = [&](double level) {
      Pixels mask(s.count());
      for (std::size_t p = 0; p < s.count(); ++p)
        mask[p] = m[p] >= o.lumen_fraction * level;
      return mask;
    };
    Pixels tl_mask = mask_of(level_tl), fl_mask = mask_of(level_fl);
    tl_mask[tl] = fl_mask[fl] = 1; // a marker is in its lumen by definition
    Pixels tl_region = region_of(tl_mask, s, tl);
    Pixels fl_region = two ? region_of(fl_mask, s, fl) : Pixels(s.count(), 0);
    for (const Pixels* r : {&tl_region, &fl_region})
      if (border_share(*r, s) > kFloodedBorderShare)
        input_error("station {}, frame {}: the {}'s region reaches the edge of the slice: "
                    "its point is not in a lumen (a point in tissue floods it; a thrombosed, "
                    "dark lumen is not tracked) or the field of view cuts it",
                    station, f, r == &tl_region ? (two ? "true lumen" : "lumen") : "false lumen");
    if (two && (overlap(tl_region, fl_region) > 0 || tl_region[fl] || fl_region[tl])) {
      Pixels mask = mask_of(std::min(level_tl, level_fl));
      mask[tl] = mask[fl] = 1;
      // FL's part too, if not connected to the TL's at this level.
      const Pixels both = united(region_of(mask, s, tl), region_of(mask, s, fl));
      std::tie(tl_region, fl_region) = split(both, m, s, tl, fl);
      ++out.split_frames;
    }
    if (f > 0 && overlap(tl_region, previous_fl) > overlap(tl_region, previous_tl))
      ++out.swaps;
    // The areas read the magnitude out to three pixels around the lumina (edge, ring, tissue
    // band): a NaN there would make an area NaN or move the tissue level, so it is refused.
    const Pixels read = grown(united(tl_region, fl_region), s, 3);
    std::vector<std::size_t> read_pixels; // a one-slice scan: pixel p is voxel p
    for (std::size_t p = 0; p < s.count(); ++p)
      if (read[p])
        read_pixels.push_back(p);
    refuse_non_finite(cine, f, read_pixels, 0, 0, fmt::format("station {}", station),
                      "the magnitude near its lumina", "the areas would be wrong");
    const double tissue = tissue_level(united(tl_region, fl_region), m, s);
    const Pixels tl_rim = rim_of(tl_region, s), fl_rim = rim_of(fl_region, s);
    out.time.push_back(cine.frames[f].time);
    out.tl_area.push_back(lumen_pixels(tl_region, tl_rim, fl_rim, fl_region, m, s, tissue) *
                          pixel_area);
    if (two)
      out.fl_area.push_back(lumen_pixels(fl_region, fl_rim, tl_rim, tl_region, m, s, tissue) *
                            pixel_area);
    std::vector<unsigned char> labels(s.count(), 0);
    for (std::size_t p = 0; p < s.count(); ++p)
      labels[p] = tl_region[p] ? 1 : (fl_region[p] ? 2 : 0);
    out.labels.push_back(std::move(labels));
    tl = deepest_pixel(tl_region, s);
    fl = two ? deepest_pixel(fl_region, s) : tl;
    previous_tl = std::move(tl_region);
    previous_fl = std::move(fl_region);
  }
  return out;
}

} // namespace tearflow::mri
