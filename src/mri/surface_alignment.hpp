#pragma once
// Alignment of the model with the MRI by fitting the MRI's segmented lumen surface to the
// mesh's lumen surface (`tearflow mri flow --align-surface MESH_OR_RUN`, docs/mri.md):
//   1. the MRI's lumen boundary: the iso-surface (flying edges, sub-voxel by linear
//      interpolation) of the time-mean magnitude at `lumen_fraction` of its 99th percentile
//      (blood 1, static tissue 0.2 in the synthetic scanner: the level 0.6 is the half-blood
//      partial-volume surface), its points in patient coordinates;
//   2. rigid point-to-plane ICP (Chen & Medioni 1992) of those points onto the mesh's
//      boundary triangles: closest point on the surface per MRI point (points farther than
//      3x the median distance dropped as outliers: a field of view that cuts the model), the
//      small rigid motion minimising the distances along the triangles' normals, repeated
//      until the RMS distance changes by < 1e-6 of a voxel or 200 iterations;
//   3. starts: the paired-point fit when given; otherwise the centroids' shift with no
//      rotation and the four proper rotations taking the MRI points' principal axes onto the
//      mesh's. Each start runs 20 passes on every 8th point; the smallest RMS wins (within
//      5 % of it, the smallest rotation: a symmetric geometry fits several ways equally
//      well) and is refined on all points.
// The result is the transform x_mri = R x_model + t of alignment.hpp.
#include <filesystem>
#include <optional>
#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "mri/alignment.hpp"
#include "mri/flow_dataset.hpp"

namespace tearflow::mri {

/// Points of the MRI lumen's boundary (step 1) [m, patient LPS]. InputError when the image
/// holds no lumen at that level.
std::vector<Vec3> lumen_boundary_points(const Flow4D& data, double lumen_fraction = 0.6);

/// The boundary surface (triangles) of a mesh: a run folder (its first saved frame, flow.pvd)
/// or a .vtu file. InputError naming the path when it is neither.
vtkSmartPointer<vtkPolyData> read_model_surface(const std::filesystem::path& mesh_or_run);

struct SurfaceFit {
  RigidTransform transform; ///< model -> MRI; its rms the ICP's over the kept points [m]
  std::size_t points = 0, kept = 0;
  int iterations = 0;
  std::string start; ///< "paired points", "centroids" or "principal axes k"
  nlohmann::json to_json() const;
};

/// Steps 2-3. InputError for fewer than 10 points or an empty surface.
SurfaceFit fit_surface(const vtkSmartPointer<vtkPolyData>& model_surface,
                       const std::vector<Vec3>& mri_points, double voxel,
                       const std::optional<RigidTransform>& start = std::nullopt);

/// How a scan is placed on the model (`mri flow --align / --align-surface`, `pictures
/// --mri-align / --mri-align-surface`): the paired points of `align` (alignment.hpp's JSON),
/// and/or the surface fit above onto `surface` (a run folder or .vtu), started from `align`
/// when both are given; the lumen at `lumen_fraction`. `report` gets "alignment" (the fit's
/// JSON, else the transform's) and, for a fit, "alignment_s". Neither given: the identity,
/// and `report` unchanged.
struct ScanPlacement {
  RigidTransform transform;      ///< model -> MRI
  std::optional<SurfaceFit> fit; ///< when `surface` was given
};
ScanPlacement place_scan(const Flow4D& data, const std::filesystem::path& align,
                         const std::filesystem::path& surface, double lumen_fraction,
                         nlohmann::json& report);

} // namespace tearflow::mri
