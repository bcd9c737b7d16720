#pragma once
// A geometry directory as a segmented label map, as itk-SNAP segmentations of CT angiography
// come: true lumen, false lumen and (optionally) thrombus labelled, the flap and the wall not.
// No patient data ships, so `geometry labels` is tested by a round trip through this: the
// parametric dissection voxelized and rebuilt. ITK's headers stay inside voxelize.cpp.
#include <array>
#include <cstddef>
#include <filesystem>

#include "core/types.hpp"

namespace tearflow::geometry {

struct VoxelizeOptions {
  double spacing = 1e-3; ///< isotropic voxel size [m]
  /// Image axes rotated by these angles about x, then y, then z (fixed axes) [degrees]:
  /// the image's direction matrix Rz Ry Rx, as an oblique scan has one.
  Vec3 rotation{0, 0, 0};
  bool thrombus = false; ///< label the false lumen's blind distal end (past the exit tear)
  int true_lumen = 1, false_lumen = 2, thrombus_label = 3; ///< each in 1..255, distinct
  double margin = 4e-3;                                    ///< background around the model [m]
};

struct VoxelizeResult {
  std::size_t tl_voxels = 0, fl_voxels = 0, thrombus_voxels = 0;
  double tl_volume = 0, fl_volume = 0, thrombus_volume = 0; ///< [m^3]
  /// Fluid voxels in small pockets cut off from both lumens (thin crescent tips, corners of
  /// the tear regions) that took the label of their nearest labelled neighbour.
  std::size_t pocket_voxels = 0;
  std::array<int, 3> size{}; ///< voxels along the image axes
};

/// A geometry directory (mesh.msh + landmarks.json) as a label map: a voxel's label is the
/// lumen its centre lies in (fluid region of the mesh); flap, wall and outside 0. Written by
/// ITK: .nii/.nii.gz, .mha/.mhd or .nrrd by extension, in the model's coordinates taken as
/// millimetres of ITK's physical (LPS) space, origin/spacing/direction set.
///
/// Lumens are told apart from the landmarks alone: the fluid voxels minus each tear's region
/// (the elliptic cylinder of the tear's semi-axes plus one voxel, 3 mm either side of the
/// flap) fall into 6-connected pieces; the true lumen is the piece holding the "AAo" (else
/// "inlet") origin, the false lumen the one holding the FL planes' points; a tear region's
/// voxels go by their side of the flap (TearLandmark::normal points into the true lumen).
/// Thrombus: the false lumen more than the exit tear's axial semi-axis + 2 mm past its
/// centroid towards the "outlet" landmark. InputError naming the directory, file or option
/// for bad options, missing landmarks, lumens that the tear regions do not separate (a wall
/// between them thinner than a voxel: six-connected voxels cross nothing thicker) and fluid
/// that neither lumen reaches.
VoxelizeResult voxelize_geometry(const std::filesystem::path& geometry_dir,
                                 const VoxelizeOptions& options, const std::filesystem::path& out);

} // namespace tearflow::geometry
