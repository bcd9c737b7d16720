#pragma once
// Voxel values that are not numbers (NaN or infinite) in a scan (docs/mri.md, "Values that are
// not numbers"). A scanner's export or a conversion can leave them in a volume (a masked
// region written as NaN, a division by a zero magnitude); read as they are they would make a
// flow NaN or, summed with others, silently wrong. So every reader counts them per image and
// frame (survey_non_finite), every command reports that count and where (mri.json and the
// like), and every measurement that reads one of them refuses, naming the image's file, the
// component, the frame and what was measured (refuse_non_finite). Values elsewhere change
// nothing: the corrections leave them out (corrections.cpp).
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

/// "magnitude", "vx", "vy", "vz", or "through-plane velocity" for a 2D scan's image 1.
std::string image_name(const Flow4D& data, int image);

/// The images of `data`'s encoding: 0 magnitude; 1..3 the velocity components of 4D flow; 1
/// the through-plane value of 2D phase contrast; none more for cine.
int image_count(const Flow4D& data);

/// Frame f's value of image `image` at voxel v (a 2D scan's image 1: v . n).
double image_value(const Flow4D& data, const Frame& f, int image, std::size_t v);

/// Counts the values that are not numbers in each image and frame of `data` (the readers call
/// it; its result is `data.non_finite`). InputError naming the source when the magnitude is
/// not a number anywhere: no lumen and no tissue can be found in it.
std::vector<NonFiniteImage> survey_non_finite(const Flow4D& data, const std::string& where);

/// One line per image for the command's output: its source, how many values, in which frames
/// and in which index box.
std::vector<std::string> describe_non_finite(const Flow4D& data);

/// For the commands' JSON records: per image its source, the values, per frame, the index box
/// and its patient-coordinate corners [mm]; {} when every value is a number.
nlohmann::json non_finite_json(const Flow4D& data);

/// InputError when one of `voxels` holds a value that is not a number in frame `frame` of an
/// image in [first_image, last_image]: "<what>, frame f (t = ... s): <region> reads N voxel
/// value(s) that are not numbers (NaN or infinite), from vz ('file'), ...; <consequence>".
void refuse_non_finite(const Flow4D& data, std::size_t frame,
                       const std::vector<std::size_t>& voxels, int first_image, int last_image,
                       const std::string& what, const std::string& region,
                       const std::string& consequence);

} // namespace tearflow::mri
