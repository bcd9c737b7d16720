// Values that are not numbers in a scan: counted, described, refused (non_finite.hpp).
#include "mri/non_finite.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/names.hpp"

namespace tearflow::mri {

namespace {

/// "0-1, 5, 7-19": the frames whose count is not zero, runs joined.
std::string frame_list(const std::vector<std::size_t>& per_frame) {
  std::vector<std::string> runs;
  for (std::size_t f = 0; f < per_frame.size(); ++f) {
    if (per_frame[f] == 0)
      continue;
    std::size_t last = f;
    while (last + 1 < per_frame.size() && per_frame[last + 1] > 0)
      ++last;
    runs.push_back(last == f ? fmt::format("{}", f) : fmt::format("{}-{}", f, last));
    f = last;
  }
  return join_names(runs, "and");
}

/// "vz ('file')", or the image's name alone for a scan made in memory.
std::string named_source(const Flow4D& data, int image) {
  const std::string& source = data.sources[static_cast<std::size_t>(image)];
  return source.empty() ? image_name(data, image)
                        : fmt::format("{} ({})", image_name(data, image), source);
}

} // namespace

std::size_t NonFiniteImage::total() const {
  std::size_t n = 0;
  for (std::size_t c : per_frame)
    n += c;
  return n;
}

std::string image_name(const Flow4D& data, int image) {
  if (image == 0)
    return "magnitude";
  if (data.encoding == Encoding::through_plane)
    return "through-plane velocity";
  return std::string("v") + "xyz"[image - 1];
}

int image_count(const Flow4D& data) {
  switch (data.encoding) {
  case Encoding::velocity_3d:
    return 4;
  case Encoding::through_plane:
    return 2;
  case Encoding::magnitude:
    return 1;
  }
  return 1;
}

double image_value(const Flow4D& data, const Frame& f, int image, std::size_t v) {
  if (image == 0)
    return f.magnitude[v];
  if (data.encoding == Encoding::through_plane)
    return along(f, v, data.grid.direction[2]);
  return f.velocity[static_cast<std::size_t>(image - 1)][v];
}

std::vector<NonFiniteImage> survey_non_finite(const Flow4D& data, const std::string& where) {
  std::vector<NonFiniteImage> out;
  const std::size_t n = data.grid.count();
  for (int image = 0; image < image_count(data); ++image) {
    NonFiniteImage s;
    s.image = image;
    s.per_frame.assign(data.frames.size(), 0);
    s.lowest = data.grid.size;
    s.highest = {-1, -1, -1};
    for (std::size_t f = 0; f < data.frames.size(); ++f)
      for (std::size_t v = 0; v < n; ++v)
        if (!std::isfinite(image_value(data, data.frames[f], image, v))) {
          ++s.per_frame[f];
          const auto ijk = data.grid.ijk(v);
          for (int a = 0; a < 3; ++a) {
            s.lowest[a] = std::min(s.lowest[a], ijk[a]);
            s.highest[a] = std::max(s.highest[a], ijk[a]);
          }
        }
    if (image == 0 && n > 0 && s.total() == n * data.frames.size())
      input_error("{}: every value of the magnitude {}is not a number (NaN or infinite): it "
                  "shows no lumen and no tissue; the scan cannot be measured",
                  where, data.sources[0].empty() ? "" : "(" + data.sources[0] + ") ");
    if (s.total() > 0)
      out.push_back(std::move(s));
  }
  return out;
}

std::vector<std::string> describe_non_finite(const Flow4D& data) {
  std::vector<std::string> lines;
  const std::size_t n = data.grid.count();
  for (const NonFiniteImage& s : data.non_finite)
    lines.push_back(fmt::format(
        "{}: {} value(s) of {} are not numbers (NaN or infinite), in frame(s) {}, voxels i "
        "{}-{}, j {}-{}, k {}-{}",
        named_source(data, s.image), s.total(), n * data.frames.size(), frame_list(s.per_frame),
        s.lowest[0], s.highest[0], s.lowest[1], s.highest[1], s.lowest[2], s.highest[2]));
  return lines;
}

nlohmann::json non_finite_json(const Flow4D& data) {
  nlohmann::json j = nlohmann::json::object();
  for (const NonFiniteImage& s : data.non_finite) {
    auto mm = [&](const std::array<int, 3>& ijk) {
      const Vec3 p = data.grid.point({double(ijk[0]), double(ijk[1]), double(ijk[2])});
      return std::vector<double>{p[0] * 1e3, p[1] * 1e3, p[2] * 1e3};
    };
    j[image_name(data, s.image)] = {{"source", data.sources[static_cast<std::size_t>(s.image)]},
                                    {"values", s.total()},
                                    {"values_per_frame", s.per_frame},
                                    {"voxels_per_frame", data.grid.count()},
                                    {"index_box", {{"lowest", s.lowest}, {"highest", s.highest}}},
                                    {"box_corners_mm", {mm(s.lowest), mm(s.highest)}}};
  }
  return j;
}

void refuse_non_finite(const Flow4D& data, std::size_t frame,
                       const std::vector<std::size_t>& voxels, int first_image, int last_image,
                       const std::string& what, const std::string& region,
                       const std::string& consequence) {
  const Frame& f = data.frames[frame];
  std::size_t count = 0;
  std::vector<std::string> images;
  for (int image = first_image; image <= std::min(last_image, image_count(data) - 1); ++image) {
    const auto bad =
        static_cast<std::size_t>(std::count_if(voxels.begin(), voxels.end(), [&](std::size_t v) {
          return !std::isfinite(image_value(data, f, image, v));
        }));
    if (bad > 0)
      images.push_back(named_source(data, image));
    count += bad;
  }
  if (count > 0)
    input_error("{}, frame {} (t = {:.4g} s): {} reads {} voxel value(s) that are not numbers "
                "(NaN or infinite), from {}; {}. Repair or mask that frame of the input",
                what, frame, f.time, region, count, join_names(images, "and"), consequence);
}

} // namespace tearflow::mri
