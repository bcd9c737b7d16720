#pragma once
// Alignment of the model with the MRI: the rigid transform x_mri = R x_model + t that best
// maps paired landmark points (least squares, Kabsch 1976 / Umeyama 1991 without scaling):
// with centroids cm, cr and H = sum (x_model - cm)(x_mri - cr)^T = U S V^T,
//   R = V diag(1, 1, det(V U^T)) U^T,   t = cr - R cm.
// The model's landmarks are then moved into the MRI's patient coordinates before the planes
// are measured (`tearflow mri flow --align POINTS.json`).
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/landmarks.hpp"

namespace tearflow::mri {

struct RigidTransform {
  Mat3 rotation{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; ///< rows
  Vec3 translation{};                               ///< [m]
  double rms = 0.0;                                 ///< residual of the fitted points [m]
  Vec3 apply(const Vec3& x) const;
  Vec3 rotate(const Vec3& v) const;
  nlohmann::json to_json() const;
};

/// InputError for fewer than three pairs, unequal counts or collinear points.
RigidTransform fit_rigid(const std::vector<Vec3>& model, const std::vector<Vec3>& mri);

/// The landmarks moved by `t` (origins and lumen points moved, normals rotated).
geometry::Landmarks transformed(const geometry::Landmarks& landmarks, const RigidTransform& t);

/// Reads {"units": "mm", "model": [[x, y, z], ...], "mri": [[x, y, z], ...]} (paired points,
/// patient LPS for the MRI) and fits the transform; InputError naming the file and key.
RigidTransform read_alignment(const std::filesystem::path& file);

} // namespace tearflow::mri
