#pragma once
// A 4D-flow scan's lumen as a fluid grid, so that the flow pictures (analysis/flow_features.hpp,
// report/flow_pictures.hpp) draw MRI as they draw a simulation's frame (issue 30):
//   - the lumen: the time-mean magnitude at or above `lumen_fraction` of its 99th percentile
//     (the level of surface_alignment.hpp's lumen boundary: blood 1 and static tissue 0.2 in
//     the synthetic scanner put it on the half-blood partial-volume surface);
//   - the grid: the cells between voxel centres (corners the voxels) clipped at that level
//     (vtkTableBasedClipDataSet), so that its boundary is the magnitude's iso-surface; the
//     velocity inside is the interpolation of the voxels' values, as a reader of the scan
//     interpolates them;
//   - coordinates: the model's. The scan is moved by the inverse of the model -> MRI transform
//     (alignment.hpp) and its velocities rotated with it, so that the simulation's landmarks,
//     seeds and cameras serve both pictures unchanged.
#include <cstddef>
#include <vector>

#include <vtkSmartPointer.h>

#include "mri/alignment.hpp"
#include "mri/flow_dataset.hpp"

class vtkUnstructuredGrid;

namespace tearflow::mri {

/// What the scan counts as lumen: the time-mean magnitude per voxel and its level.
struct LumenLevel {
  std::vector<float> mean_magnitude; ///< per voxel, over the frames
  double level = 0.0;                ///< lumen: mean_magnitude >= level
};

/// The level at `lumen_fraction` of the time-mean magnitude's 99th percentile. InputError
/// naming the fraction when that level is not positive (no signal).
LumenLevel lumen_level(const Flow4D& data, double lumen_fraction);

/// Frame `frame` of `data` as the fluid grid above, in model coordinates (`model_to_scan` the
/// alignment's transform; identity for a scan of the model itself), with the point fields
/// `velocity` [m/s] (model axes) and `magnitude`. InputError naming the frame when no voxel
/// is lumen.
vtkSmartPointer<vtkUnstructuredGrid> lumen_field(const Flow4D& data, std::size_t frame,
                                                 const LumenLevel& lumen,
                                                 const RigidTransform& model_to_scan);

/// The model point of scan point `x` (the inverse of `t`), and a scan vector's model axes.
Vec3 to_model(const RigidTransform& t, const Vec3& x);
Vec3 rotate_to_model(const RigidTransform& t, const Vec3& v);

} // namespace tearflow::mri
