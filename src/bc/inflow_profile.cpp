#include "bc/inflow_profile.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bc/womersley_exact.hpp"
#include "core/error.hpp"

namespace tearflow::bc {

InflowProfile::InflowProfile(const mesh::Mesh& mesh, const mesh::Face& face, Waveform flow,
                             ProfileShape shape, double density, double viscosity, int modes)
    : geometry_(face_geometry(mesh, face)), flow_(std::move(flow)), shape_(shape) {
  // A curved inlet has no single direction to push the fluid along; 5 degrees allows for
  // the faceting of a meshed planar cap.
  if (geometry_.max_normal_deviation > 5.0 * std::numbers::pi / 180.0)
    input_error("{}: inflow face '{}' is not planar (normals deviate by {:.1f} degrees)",
                mesh.source, face.name, geometry_.max_normal_deviation * 180.0 / std::numbers::pi);
  radius_ = std::max(geometry_.max_rim_distance, std::sqrt(geometry_.area / std::numbers::pi));
  shape_value_.resize(geometry_.nodes.size());
  for (size_t k = 0; k < shape_value_.size(); ++k) {
    const double d = std::min(geometry_.rim_distance[k] / radius_, 1.0);
    shape_value_[k] = shape == ProfileShape::Plug ? 1.0 : 1.0 - (1.0 - d) * (1.0 - d);
  }
  // int s dA of the P1 interpolant: each triangle contributes area/3 times its nodal sum.
  for (const Tri& t : face.triangles) {
    double area;
    Vec3 n;
    triangle_area_normal(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], area, n);
    for (Index v : t) {
      const auto it = std::lower_bound(geometry_.nodes.begin(), geometry_.nodes.end(), v);
      shape_integral_ += area / 3.0 * shape_value_[it - geometry_.nodes.begin()];
    }
  }
  if (shape == ProfileShape::Womersley)
    womersley_ = std::make_unique<bc::WomersleyFlow>(
        bc::womersley_from_waveform(flow_, modes, radius_, density, viscosity));
}

InflowProfile::~InflowProfile() = default;
InflowProfile::InflowProfile(InflowProfile&&) noexcept = default;
InflowProfile& InflowProfile::operator=(InflowProfile&&) noexcept = default;

Vec3 InflowProfile::velocity(size_t k, double t) const {
  double speed;
  if (shape_ == ProfileShape::Womersley) {
    const double r = std::max(0.0, radius_ - geometry_.rim_distance[k]);
    speed = womersley_->axial_velocity(r, t);
  } else {
    speed = flow_(t) / shape_integral_ * shape_value_[k];
  }
  return (-speed) * geometry_.normal; // into the domain
}

} // namespace tearflow::bc
