// Alignment by fitting the MRI lumen surface to the mesh (surface_alignment.hpp).
#include "mri/surface_alignment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <vtkCell.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStaticCellLocator.h>
#include <vtkTriangleFilter.h>
#include <vtkUnstructuredGrid.h>

#include "analysis/landmark_sections.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "mri/lumen_field.hpp"

namespace tearflow::mri {

namespace {

Eigen::Vector3d eig(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

/// The rigid transform x -> r x + t.
RigidTransform make(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  RigidTransform out;
  for (int a = 0; a < 3; ++a) {
    out.translation[a] = t(a);
    for (int b = 0; b < 3; ++b)
      out.rotation[a][b] = r(a, b);
  }
  return out;
}

Eigen::Matrix3d matrix(const RigidTransform& s) {
  Eigen::Matrix3d r;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      r(a, b) = s.rotation[a][b];
  return r;
}

double angle_deg(const RigidTransform& s) {
  const double c = std::clamp((matrix(s).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

/// Centroid and covariance of a weighted point set.
struct Moments {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

Moments moments(const std::vector<Eigen::Vector3d>& p, const std::vector<double>& w) {
  Moments m;
  double total = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    m.centroid += w[i] * p[i], total += w[i];
  m.centroid /= total;
  for (std::size_t i = 0; i < p.size(); ++i)
    m.covariance += w[i] * (p[i] - m.centroid) * (p[i] - m.centroid).transpose() / total;
  return m;
}

/// One ICP run of the MRI points (transform s: MRI -> model) from `s`.
struct IcpResult {
  RigidTransform s;
  double rms = 0;
  std::size_t kept = 0;
  int iterations = 0;
};

/// Point-to-plane ICP (Chen & Medioni 1992): per pass, with p_i the moved MRI points, c_i
/// their closest surface points and n_i the unit normals of the triangles holding them, the
/// small rotation w and shift u minimising sum ((p_i + w x p_i + u - c_i) . n_i)^2 (6 x 6
/// normal equations), composed onto s with the exact rotation of w. It converges in a few
/// passes where point-to-point ICP creeps along a long lumen.
IcpResult icp(vtkStaticCellLocator* locator, const std::vector<Eigen::Vector3d>& normals,
              const std::vector<Vec3>& q, RigidTransform s, double voxel, int passes) {
  IcpResult r;
  std::vector<Vec3> closest(q.size()), moved(q.size());
  std::vector<vtkIdType> cells(q.size());
  std::vector<double> d2(q.size()), sorted;
  double previous = std::numeric_limits<double>::infinity();
  for (r.iterations = 1; r.iterations <= passes; ++r.iterations) {
    for (std::size_t i = 0; i < q.size(); ++i) {
      moved[i] = s.apply(q[i]);
      int sub = 0;
      locator->FindClosestPoint(moved[i].data(), closest[i].data(), cells[i], sub, d2[i]);
    }
    sorted = d2;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double limit = 9.0 * sorted[sorted.size() / 2]; // (3 x median distance)^2
    Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    double sum = 0;
    r.kept = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      if (!(d2[i] <= limit || limit == 0.0))
        continue;
      const Eigen::Vector3d p = eig(moved[i]), n = normals[static_cast<std::size_t>(cells[i])];
      Eigen::Matrix<double, 6, 1> row;
      row << p.cross(n), n; // (w x p + u) . n = w . (p x n) + u . n
      a += row * row.transpose();
      b += row * (eig(closest[i]) - p).dot(n);
      sum += d2[i];
      ++r.kept;
    }
    r.rms = std::sqrt(sum / r.kept);
    r.s = s;
    if (std::abs(previous - r.rms) < 1e-6 * voxel)
      break;
    previous = r.rms;
    const Eigen::Matrix<double, 6, 1> x = a.ldlt().solve(b);
    const Eigen::Vector3d w = x.head<3>();
    const Eigen::Matrix3d dr = w.norm() > 0
                                   ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                   : Eigen::Matrix3d::Identity();
    // s <- (dr, u) o s, the small rotation taken about the origin as linearised.
    s = make(dr * matrix(s), dr * eig(s.translation) + x.tail<3>());
  }
  return r;
}

} // namespace

std::vector<Vec3> lumen_boundary_points(const Flow4D& data, double lumen_fraction) {
  const ImageGrid& g = data.grid;
  const std::size_t n = g.count();
  const LumenLevel lumen = lumen_level(data, lumen_fraction);
  const double level = lumen.level;
  auto values = vtkSmartPointer<vtkFloatArray>::New();
  values->SetNumberOfValues(static_cast<vtkIdType>(n));
  for (std::size_t v = 0; v < n; ++v)
    values->SetValue(static_cast<vtkIdType>(v), lumen.mean_magnitude[v]);
  // The image in index space (voxel centres at integer indices), as ImageGrid::point reads.
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(g.size[0], g.size[1], g.size[2]);
  image->SetOrigin(0, 0, 0);
  image->SetSpacing(1, 1, 1);
  image->GetPointData()->SetScalars(values);
  auto contour = vtkSmartPointer<vtkFlyingEdges3D>::New();
  contour->SetInputData(image);
  contour->SetValue(0, level);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkPoints* points = contour->GetOutput()->GetPoints();
  if (points == nullptr || points->GetNumberOfPoints() == 0)
    input_error("surface alignment: no lumen boundary in the MRI (time-mean magnitude level "
                "{:.3g}: {} of its 99th percentile)",
                level, lumen_fraction);
  std::vector<Vec3> out(static_cast<std::size_t>(points->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
    Vec3 index;
    points->GetPoint(i, index.data());
    out[static_cast<std::size_t>(i)] = g.point(index);
  }
  return out;
}

vtkSmartPointer<vtkPolyData> read_model_surface(const std::filesystem::path& mesh_or_run) {
  std::filesystem::path vtu = mesh_or_run;
  if (std::filesystem::is_directory(mesh_or_run)) {
    if (!std::filesystem::exists(RunFiles{mesh_or_run}.flow_pvd()))
      input_error("--align-surface '{}': a run folder holds flow.pvd (or give a .vtu mesh)",
                  mesh_or_run.string());
    vtu = analysis::read_pvd(RunFiles{mesh_or_run}.flow_pvd()).front().file;
  } else if (mesh_or_run.extension() != ".vtu") {
    input_error("--align-surface '{}': expected a run folder (flow.pvd) or a .vtu mesh",
                mesh_or_run.string());
  }
  const vtkSmartPointer<vtkUnstructuredGrid> grid = analysis::read_flow_frame(vtu);
  auto surface = vtkSmartPointer<vtkDataSetSurfaceFilter>::New();
  surface->SetInputData(grid);
  auto triangles = vtkSmartPointer<vtkTriangleFilter>::New();
  triangles->SetInputConnection(surface->GetOutputPort());
  triangles->Update();
  vtkSmartPointer<vtkPolyData> out = triangles->GetOutput();
  if (out->GetNumberOfCells() == 0)
    input_error("--align-surface '{}': the mesh has no boundary surface", vtu.string());
  return out;
}

SurfaceFit fit_surface(const vtkSmartPointer<vtkPolyData>& model, const std::vector<Vec3>& q,
                       double voxel, const std::optional<RigidTransform>& start) {
  if (q.size() < 10)
    input_error("surface alignment: {} MRI boundary points; at least 10 are needed", q.size());
  if (model == nullptr || model->GetNumberOfCells() == 0)
    input_error("surface alignment: the model's surface is empty");
  auto locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  locator->SetDataSet(model);
  locator->BuildLocator();
  std::vector<Eigen::Vector3d> normals(static_cast<std::size_t>(model->GetNumberOfCells()));
  for (vtkIdType c = 0; c < model->GetNumberOfCells(); ++c) {
    vtkPoints* p = model->GetCell(c)->GetPoints();
    Eigen::Vector3d x0, x1, x2;
    p->GetPoint(0, x0.data()), p->GetPoint(1, x1.data()), p->GetPoint(2, x2.data());
    const Eigen::Vector3d n = (x1 - x0).cross(x2 - x0);
    normals[static_cast<std::size_t>(c)] = n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : n;
  }

  std::vector<std::pair<RigidTransform, std::string>> starts;
  if (start) {
    // The paired fit maps model -> MRI; ICP moves the MRI points: its inverse.
    const Eigen::Matrix3d r = matrix(*start).transpose();
    starts.push_back({make(r, -r * eig(start->translation)), "paired points"});
  } else {
    // Area-weighted triangle centroids of the surface; the MRI points as they come (the
    // iso-surface's vertices are about evenly spread over its area).
    std::vector<Eigen::Vector3d> pm, pq;
    std::vector<double> wm, wq(q.size(), 1.0);
    for (vtkIdType c = 0; c < model->GetNumberOfCells(); ++c) {
      vtkPoints* p = model->GetCell(c)->GetPoints();
      Eigen::Vector3d a, b, d;
      p->GetPoint(0, a.data()), p->GetPoint(1, b.data()), p->GetPoint(2, d.data());
      pm.push_back((a + b + d) / 3.0);
      wm.push_back(0.5 * (b - a).cross(d - a).norm());
    }
    for (const Vec3& x : q)
      pq.push_back(eig(x));
    const Moments mm = moments(pm, wm), mq = moments(pq, wq);
    starts.push_back({make(Eigen::Matrix3d::Identity(), mm.centroid - mq.centroid), "centroids"});
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> em(mm.covariance), eq(mq.covariance);
    const Eigen::Matrix3d um = em.eigenvectors(), uq = eq.eigenvectors();
    int k = 0;
    for (double s0 : {1.0, -1.0})
      for (double s1 : {1.0, -1.0}) {
        const double s2 = s0 * s1 * um.determinant() * uq.determinant();
        const Eigen::Matrix3d r = um * Eigen::Vector3d(s0, s1, s2).asDiagonal() * uq.transpose();
        starts.push_back(
            {make(r, mm.centroid - r * mq.centroid), fmt::format("principal axes {}", ++k)});
      }
  }
  // The starts compete on every 8th point for 20 passes; the winner is refined on all.
  std::vector<Vec3> sparse;
  for (std::size_t i = 0; i < q.size(); i += 8)
    sparse.push_back(q[i]);
  std::vector<IcpResult> runs;
  for (const auto& [s, name] : starts)
    runs.push_back(icp(locator, normals, sparse, s, voxel, 20));
  double best = std::numeric_limits<double>::infinity();
  for (const IcpResult& r : runs)
    best = std::min(best, r.rms);
  std::size_t chosen = 0;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (runs[i].rms <= 1.05 * best && angle_deg(runs[i].s) < smallest)
      smallest = angle_deg(runs[i].s), chosen = i;
  const IcpResult r = icp(locator, normals, q, runs[chosen].s, voxel, 200);
  SurfaceFit fit;
  const Eigen::Matrix3d rt = matrix(r.s).transpose();
  fit.transform = make(rt, -rt * eig(r.s.translation));
  fit.transform.rms = r.rms;
  fit.points = q.size();
  fit.kept = r.kept;
  fit.iterations = r.iterations;
  fit.start = starts[chosen].second;
  return fit;
}

nlohmann::json SurfaceFit::to_json() const {
  nlohmann::json j = transform.to_json();
  j["method"] = "surface ICP";
  j["start"] = start;
  j["mri_boundary_points"] = points;
  j["points_kept"] = kept;
  j["iterations"] = iterations;
  return j;
}

ScanPlacement place_scan(const Flow4D& data, const std::filesystem::path& align,
                         const std::filesystem::path& surface, double lumen_fraction,
                         nlohmann::json& report) {
  ScanPlacement p;
  if (!align.empty())
    p.transform = read_alignment(align);
  if (!surface.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    const double voxel =
        std::min({data.grid.spacing[0], data.grid.spacing[1], data.grid.spacing[2]});
    p.fit = fit_surface(read_model_surface(surface), lumen_boundary_points(data, lumen_fraction),
                        voxel, align.empty() ? std::nullopt : std::optional(p.transform));
    p.transform = p.fit->transform;
    report["alignment"] = p.fit->to_json();
    report["alignment_s"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } else if (!align.empty()) {
    report["alignment"] = p.transform.to_json();
  }
  return p;
}

} // namespace tearflow::mri
