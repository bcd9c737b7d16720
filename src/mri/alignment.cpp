// Rigid alignment from paired points (alignment.hpp for the method).
#include "mri/alignment.hpp"

#include <cmath>
#include <fstream>

#include <Eigen/Dense>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::mri {

Vec3 RigidTransform::rotate(const Vec3& v) const {
  return {dot(rotation[0], v), dot(rotation[1], v), dot(rotation[2], v)};
}

Vec3 RigidTransform::apply(const Vec3& x) const {
  return rotate(x) + translation;
}

nlohmann::json RigidTransform::to_json() const {
  return {{"rotation_rows", rotation}, {"translation_m", translation}, {"rms_m", rms}};
}

RigidTransform fit_rigid(const std::vector<Vec3>& model, const std::vector<Vec3>& mri) {
  if (model.size() != mri.size() || model.size() < 3)
    input_error("alignment: {} model and {} MRI points; at least three pairs are needed",
                model.size(), mri.size());
  const std::size_t n = model.size();
  Eigen::Vector3d cm = Eigen::Vector3d::Zero(), cr = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    cm += Eigen::Vector3d(model[i].data()) / n;
    cr += Eigen::Vector3d(mri[i].data()) / n;
  }
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
    h +=
        (Eigen::Vector3d(model[i].data()) - cm) * (Eigen::Vector3d(mri[i].data()) - cr).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s(1) > 1e-12 * std::max(1.0, s(0))))
    input_error("alignment: the points are collinear; three or more points not on a line are "
                "needed");
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
  const Eigen::Vector3d t = cr - r * cm;
  RigidTransform out;
  for (int a = 0; a < 3; ++a) {
    out.translation[a] = t(a);
    for (int b = 0; b < 3; ++b)
      out.rotation[a][b] = r(a, b);
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 e = out.apply(model[i]) - mri[i];
    sum += dot(e, e);
  }
  out.rms = std::sqrt(sum / n);
  return out;
}

geometry::Landmarks transformed(const geometry::Landmarks& landmarks, const RigidTransform& t) {
  geometry::Landmarks out = landmarks;
  for (geometry::Landmark& l : out.planes) {
    l.origin = t.apply(l.origin);
    l.normal = t.rotate(l.normal);
    if (l.point)
      l.point = t.apply(*l.point);
  }
  for (geometry::TearLandmark& tear : out.tears) {
    tear.centroid = t.apply(tear.centroid);
    tear.normal = t.rotate(tear.normal);
    tear.axis = t.rotate(tear.axis);
  }
  return out;
}

RigidTransform read_alignment(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in)
    input_error("'{}': cannot be read (alignment points expected)", file.string());
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    input_error("'{}': not JSON ({})", file.string(), e.what());
  }
  const double scale =
      units::length_scale(j.value("units", std::string("mm")), file.string() + ": units");
  auto points = [&](const char* key) {
    if (!j.contains(key) || !j[key].is_array())
      input_error("'{}': key '{}' missing (a list of [x, y, z] points is expected)", file.string(),
                  key);
    std::vector<Vec3> p;
    for (const auto& x : j[key]) {
      if (!x.is_array() || x.size() != 3)
        input_error("'{}': '{}' holds an entry that is not [x, y, z]", file.string(), key);
      p.push_back(
          {scale * x[0].get<double>(), scale * x[1].get<double>(), scale * x[2].get<double>()});
    }
    return p;
  };
  return fit_rigid(points("model"), points("mri"));
}

} // namespace tearflow::mri
