// Synthetic 4D-flow MRI of a run's VTU series (synthetic_run.hpp for the model).
#include "mri/synthetic_run.hpp"

#include <algorithm>
#include <cmath>

#include <vtkCharArray.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProbeFilter.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "analysis/hemodynamics.hpp"
#include "analysis/landmark_sections.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"

namespace tearflow::mri {

namespace {

/// Per saved frame: the voxel means of velocity and the fluid fraction.
struct VoxelMeans {
  std::array<std::vector<float>, 3> velocity;
  std::vector<float> fluid;
};

} // namespace

Flow4D synthesize_run(const RunScan& scan) {
  analysis::AnalyzeOptions o;
  o.run_dir = scan.run_dir;
  o.all_frames = !std::filesystem::exists(RunFiles{scan.run_dir}.cycles_json());
  std::string label;
  const std::vector<analysis::FlowFrame> saved = analysis::select_frames(o, label);
  if (saved.size() < 2)
    input_error("'{}': a synthetic scan needs at least two saved frames", scan.run_dir.string());
  const double t0 = saved.front().time, period = saved.back().time - t0;

  // The grid: given, or the first frame's fluid bounds plus the margin.
  ImageGrid g = scan.grid;
  vtkSmartPointer<vtkUnstructuredGrid> first = analysis::read_flow_frame(saved.front().file);
  if (g.count() == 0) {
    double b[6];
    first->GetBounds(b);
    const Vec3 centre{0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])};
    // The extent along each rotated axis of the box's corners.
    std::array<int, 3> size{};
    for (int a = 0; a < 3; ++a) {
      double extent = 0;
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner{b[c & 1], b[2 + ((c >> 1) & 1)], b[4 + ((c >> 2) & 1)]};
        extent = std::max(extent, std::abs(dot(corner - centre, scan.direction[a])));
      }
      size[a] = static_cast<int>(std::ceil(2 * (extent + scan.margin) / scan.voxel)) + 1;
    }
    g = centred_grid(centre, scan.direction, size, {scan.voxel, scan.voxel, scan.voxel});
  }

  // Sub-voxel points, once.
  const int ns = scan.voxel_samples;
  const std::size_t per_voxel = static_cast<std::size_t>(ns) * ns * ns;
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(g.count() * per_voxel));
  vtkIdType id = 0;
  for (int k = 0; k < g.size[2]; ++k)
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i)
        for (int a = 0; a < ns; ++a)
          for (int b = 0; b < ns; ++b)
            for (int c = 0; c < ns; ++c) {
              const Vec3 p = g.point(
                  {i + (a + 0.5) / ns - 0.5, j + (b + 0.5) / ns - 0.5, k + (c + 0.5) / ns - 0.5});
              points->SetPoint(id++, p.data());
            }
  auto probe_points = vtkSmartPointer<vtkPolyData>::New();
  probe_points->SetPoints(points);

  // Voxel means per saved frame.
  std::vector<VoxelMeans> means(saved.size());
  const std::size_t n = g.count();
  for (std::size_t f = 0; f < saved.size(); ++f) {
    vtkSmartPointer<vtkUnstructuredGrid> mesh =
        f == 0 ? first : analysis::read_flow_frame(saved[f].file);
    auto probe = vtkSmartPointer<vtkProbeFilter>::New();
    probe->SetInputData(probe_points);
    probe->SetSourceData(mesh);
    probe->Update();
    vtkPointData* pd = probe->GetOutput()->GetPointData();
    vtkDataArray* velocity = pd->GetArray("velocity");
    vtkDataArray* valid = pd->GetArray(probe->GetValidPointMaskArrayName());
    if (!velocity || !valid)
      input_error("'{}': probing the velocity failed", saved[f].file.string());
    VoxelMeans& m = means[f];
    for (auto& c : m.velocity)
      c.assign(n, 0.0f);
    m.fluid.assign(n, 0.0f);
    for (std::size_t v = 0; v < n; ++v) {
      double sum[3] = {0, 0, 0}, inside = 0;
      for (std::size_t s = 0; s < per_voxel; ++s) {
        const vtkIdType p = static_cast<vtkIdType>(v * per_voxel + s);
        if (valid->GetComponent(p, 0) == 0)
          continue;
        inside += 1;
        for (int c = 0; c < 3; ++c)
          sum[c] += velocity->GetComponent(p, c);
      }
      m.fluid[v] = static_cast<float>(inside / per_voxel);
      for (int c = 0; c < 3; ++c)
        m.velocity[c][v] = static_cast<float>(sum[c] / per_voxel);
    }
  }

  // MRI frames: window means of the time-interpolated voxel means.
  Flow4D out;
  out.grid = g;
  out.venc = scan.effects.venc;
  out.frame_window = period / scan.frames;
  const double dt = period / scan.frames;
  for (int k = 0; k < scan.frames; ++k) {
    Frame fr;
    fr.time = k * dt; // after the cycle's start, as a trigger would count
    fr.magnitude.assign(n, 0.0f);
    for (auto& c : fr.velocity)
      c.assign(n, 0.0f);
    for (int q = 0; q < scan.time_samples; ++q) {
      double t = fr.time + ((q + 0.5) / scan.time_samples - 0.5) * dt;
      t -= period * std::floor(t / period); // periodic in the cycle
      const auto it = std::upper_bound(saved.begin(), saved.end(), t0 + t,
                                       [](double x, const auto& s) { return x < s.time; });
      const std::size_t i1 = std::clamp<std::size_t>(it - saved.begin(), 1, saved.size() - 1);
      const std::size_t i0 = i1 - 1;
      const double w =
          std::clamp((t0 + t - saved[i0].time) / (saved[i1].time - saved[i0].time), 0.0, 1.0);
      const double share = 1.0 / scan.time_samples;
      for (std::size_t v = 0; v < n; ++v) {
        const double fluid = (1 - w) * means[i0].fluid[v] + w * means[i1].fluid[v];
        fr.magnitude[v] += static_cast<float>(
            share * (scan.effects.lumen_signal * fluid + scan.tissue_signal * (1 - fluid)));
        for (int c = 0; c < 3; ++c)
          fr.velocity[c][v] += static_cast<float>(
              share * ((1 - w) * means[i0].velocity[c][v] + w * means[i1].velocity[c][v]));
      }
    }
    out.frames.push_back(std::move(fr));
  }
  add_scanner_effects(out, scan.effects);
  return out;
}

} // namespace tearflow::mri
