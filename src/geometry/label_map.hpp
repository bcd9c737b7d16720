#pragma once
// A segmented scan: one integer label per voxel (the true lumen, the false lumen, thrombus),
// as itk-SNAP and the public TBAD data sets write it (NIfTI, MetaImage, NRRD), and the
// distance fields the model is rebuilt from. ITK's headers stay in label_map.cpp.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/image_grid.hpp"

namespace tearflow::geometry {

struct LabelMap {
  ImageGrid grid; ///< patient (LPS) coordinates in metres, as ITK places the image
  std::vector<std::int16_t> labels;
  std::filesystem::path file; ///< for messages
};

/// Reads a 3D label map (.nii, .nii.gz, .mha, .mhd, .nrrd, .nhdr). InputError naming the
/// file: missing, unreadable, cut short, not 3D, not integer-valued, labels beyond int16.
LabelMap read_label_map(const std::filesystem::path& file);

/// InputError "WHAT 'FILE': expected ..." unless the file's name ends in an extension the
/// label maps are read and written as.
void check_label_map_name(const std::filesystem::path& file, const std::string& what);

/// Writes a label map (format by extension, as read_label_map reads it).
void write_label_map(const LabelMap& map, const std::filesystem::path& file);

/// The signed distance [m] from each voxel centre to the surface the voxels with mask != 0
/// sample (negative inside): within 6 mm of it, to the 0.5 level of the mask blurred by 0.8
/// voxels (near it) and to the nearest of those surface points (beyond); farther, ITK's
/// Maurer map with its zero moved to the voxels' faces, smoothed by a Gaussian of `sigma`
/// [m] (0: none). `curvature_corrected`: the blurred level moved back out by the blur's
/// curvature shift (label_map.cpp), for the solid sets (the lumina), not thin sheets.
std::vector<float> signed_distance(const ImageGrid& grid, const std::vector<std::uint8_t>& mask,
                                   double sigma, bool curvature_corrected = false);

} // namespace tearflow::geometry
