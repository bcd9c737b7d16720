#include "mri/lumen_field.hpp"

#include <algorithm>
#include <cmath>

#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStructuredGrid.h>
#include <vtkTableBasedClipDataSet.h>
#include <vtkUnstructuredGrid.h>

#include "core/error.hpp"
#include "mri/non_finite.hpp"

namespace tearflow::mri {

namespace {

constexpr const char* kMagnitude = "magnitude";

} // namespace

Vec3 rotate_to_model(const RigidTransform& t, const Vec3& v) {
  // R is a rotation: its inverse is its transpose (rows -> columns).
  const Mat3& r = t.rotation;
  return {r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
          r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
          r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2]};
}

Vec3 to_model(const RigidTransform& t, const Vec3& x) {
  return rotate_to_model(t, x - t.translation);
}

LumenLevel lumen_level(const Flow4D& data, double lumen_fraction) {
  const std::size_t n = data.grid.count();
  LumenLevel l;
  l.mean_magnitude.assign(n, 0.0f);
  const float share = 1.0f / static_cast<float>(std::max<std::size_t>(data.frames.size(), 1));
  for (const Frame& f : data.frames)
    for (std::size_t v = 0; v < n; ++v)
      l.mean_magnitude[v] += share * f.magnitude[v];
  // The percentile over the voxels whose mean is a number (a NaN breaks nth_element's order).
  std::vector<float> sorted;
  sorted.reserve(n);
  for (float m : l.mean_magnitude)
    if (std::isfinite(m))
      sorted.push_back(m);
  const auto p99 = sorted.begin() + static_cast<long>((99 * sorted.size()) / 100);
  if (!sorted.empty())
    std::nth_element(sorted.begin(), p99, sorted.end());
  l.level = sorted.empty() ? 0.0 : lumen_fraction * *p99;
  if (!(l.level > 0))
    input_error("MRI lumen: the time-mean magnitude's level ({} of its 99th percentile) is "
                "{:.3g}: the scan holds no signal to find the lumen by",
                lumen_fraction, l.level);
  // A mean that is not a number in or beside the lumen would move its boundary: refused,
  // naming the first frame holding one. Elsewhere it is not lumen and changes nothing.
  std::vector<std::size_t> near;
  for (std::size_t v = 0; v < n; ++v) {
    if (std::isfinite(l.mean_magnitude[v]))
      continue;
    bool beside = false;
    data.grid.for_each_neighbour(v, [&](std::size_t u, int, int, int) {
      beside = beside || l.mean_magnitude[u] >= l.level;
    });
    if (beside)
      near.push_back(v);
  }
  for (std::size_t f = 0; f < data.frames.size() && !near.empty(); ++f)
    refuse_non_finite(data, f, near, 0, 0, "MRI lumen", "its boundary (the time-mean magnitude)",
                      "the lumen would be wrong");
  return l;
}

vtkSmartPointer<vtkUnstructuredGrid> lumen_field(const Flow4D& data, std::size_t frame,
                                                 const LumenLevel& lumen,
                                                 const RigidTransform& model_to_scan) {
  const ImageGrid& g = data.grid;
  const Frame& f = data.frames.at(frame);
  // The index box of the lumen voxels and one more around them (the clip's outer corners).
  std::array<int, 3> lo = g.size, hi{-1, -1, -1};
  for (std::size_t v = 0; v < g.count(); ++v)
    if (lumen.mean_magnitude[v] >= lumen.level) {
      const auto ijk = g.ijk(v);
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], std::max(ijk[a] - 1, 0));
        hi[a] = std::max(hi[a], std::min(ijk[a] + 1, g.size[a] - 1));
      }
    }
  if (hi[0] < 0)
    input_error("MRI frame {} (t = {} s): no voxel reaches the lumen level {:.3g}", frame, f.time,
                lumen.level);
  // The lumen's cells interpolate the velocity of their corners: the lumen voxels and those
  // beside them.
  std::vector<std::size_t> read;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const std::size_t v = g.linear(i, j, k);
        bool used = lumen.mean_magnitude[v] >= lumen.level;
        g.for_each_neighbour(v, [&](std::size_t u, int, int, int) {
          used = used || lumen.mean_magnitude[u] >= lumen.level;
        });
        if (used)
          read.push_back(v);
      }
  refuse_non_finite(data, frame, read, 1, 3, "MRI lumen", "its cells' velocity",
                    "the pictures would be wrong");
  const int nx = hi[0] - lo[0] + 1, ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
  const vtkIdType count = static_cast<vtkIdType>(nx) * ny * nz;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  vtkNew<vtkFloatArray> velocity, magnitude;
  velocity->SetName("velocity");
  velocity->SetNumberOfComponents(3);
  velocity->SetNumberOfTuples(count);
  magnitude->SetName(kMagnitude);
  magnitude->SetNumberOfTuples(count);
  vtkIdType id = 0; // vtkStructuredGrid's point order: i fastest, then j, then k
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i, ++id) {
        const std::size_t v = g.linear(i, j, k);
        const Vec3 x = to_model(model_to_scan, g.point({double(i), double(j), double(k)}));
        const Vec3 u =
            rotate_to_model(model_to_scan, {f.velocity[0][v], f.velocity[1][v], f.velocity[2][v]});
        points->SetPoint(id, x.data());
        velocity->SetTuple3(id, u[0], u[1], u[2]);
        magnitude->SetValue(id, lumen.mean_magnitude[v]);
      }
  vtkNew<vtkStructuredGrid> voxels;
  voxels->SetDimensions(nx, ny, nz);
  voxels->SetPoints(points);
  voxels->GetPointData()->AddArray(velocity);
  voxels->GetPointData()->SetScalars(magnitude);
  vtkNew<vtkTableBasedClipDataSet> clip;
  clip->SetInputData(voxels);
  clip->SetValue(lumen.level); // keeps magnitude >= level
  clip->Update();
  vtkSmartPointer<vtkUnstructuredGrid> out = clip->GetOutput();
  if (out->GetNumberOfCells() == 0)
    input_error("MRI frame {} (t = {} s): the lumen (magnitude >= {:.3g}) holds no cell", frame,
                f.time, lumen.level);
  return out;
}

} // namespace tearflow::mri
