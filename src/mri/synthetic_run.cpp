// Synthetic 4D-flow MRI of a run's VTU series (synthetic_run.hpp for the model).
#include "mri/synthetic_run.hpp"

#include <algorithm>
#include <cmath>

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProbeFilter.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>
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

/// Sub-sample offsets in index units: n x n in-plane by nk across, midpoint rule.
std::vector<Vec3> offsets(int n, int nk) {
  std::vector<Vec3> o;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < nk; ++c)
        o.push_back({(a + 0.5) / n - 0.5, (b + 0.5) / n - 0.5, (c + 0.5) / nk - 0.5});
  return o;
}

/// Voxels of one grid to average over `samples` points each, into `means`.
struct ProbeRequest {
  const ImageGrid* grid = nullptr;
  std::vector<std::size_t> voxels;
  const std::vector<Vec3>* samples = nullptr;
  VoxelMeans* means = nullptr;
};

/// Probes every request's points in `mesh` at once (one cell locator for all; building it
/// costs more than probing a slice) and writes the voxel means.
void probe_means(vtkUnstructuredGrid* mesh, const std::vector<ProbeRequest>& requests,
                 const std::filesystem::path& file) {
  std::size_t total = 0;
  for (const ProbeRequest& r : requests)
    total += r.voxels.size() * r.samples->size();
  if (total == 0)
    return;
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(total));
  vtkIdType id = 0;
  for (const ProbeRequest& r : requests) {
    const ImageGrid& g = *r.grid;
    for (std::size_t v : r.voxels) {
      const Vec3 centre{double(v % g.size[0]), double((v / g.size[0]) % g.size[1]),
                        double(v / (static_cast<std::size_t>(g.size[0]) * g.size[1]))};
      for (const Vec3& o : *r.samples)
        points->SetPoint(id++, g.point(centre + o).data());
    }
  }
  auto probe_points = vtkSmartPointer<vtkPolyData>::New();
  probe_points->SetPoints(points);
  auto probe = vtkSmartPointer<vtkProbeFilter>::New();
  probe->SetInputData(probe_points);
  probe->SetSourceData(mesh);
  // A static cell locator: without one VTK searches by the nearest points, 5x slower here.
  probe->SetCellLocatorPrototype(vtkSmartPointer<vtkStaticCellLocator>::New());
  probe->Update();
  vtkPointData* pd = probe->GetOutput()->GetPointData();
  vtkDataArray* velocity = pd->GetArray("velocity");
  vtkDataArray* valid = pd->GetArray(probe->GetValidPointMaskArrayName());
  if (!velocity || !valid)
    input_error("'{}': probing the velocity failed", file.string());
  vtkIdType p = 0;
  for (const ProbeRequest& r : requests) {
    const std::size_t per_voxel = r.samples->size();
    for (std::size_t v : r.voxels) {
      double sum[3] = {0, 0, 0}, inside = 0;
      for (std::size_t s = 0; s < per_voxel; ++s, ++p) {
        if (valid->GetComponent(p, 0) == 0)
          continue;
        inside += 1;
        for (int c = 0; c < 3; ++c)
          sum[c] += velocity->GetComponent(p, c);
      }
      r.means->fluid[v] = static_cast<float>(inside / per_voxel);
      for (int c = 0; c < 3; ++c)
        r.means->velocity[c][v] = static_cast<float>(sum[c] / per_voxel);
    }
  }
}

/// The pixels of a one-slice grid that the fluid's boundary crosses: fraction strictly
/// between 0 and 1, or a differing 8-neighbour (a boundary between two samples' rows).
std::vector<std::size_t> edge_pixels(const ImageGrid& g, const std::vector<float>& fluid) {
  std::vector<std::size_t> edge;
  const int nx = g.size[0], ny = g.size[1];
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * nx + i;
      bool crossed = fluid[p] > 0 && fluid[p] < 1;
      for (int b = std::max(0, j - 1); b <= std::min(ny - 1, j + 1) && !crossed; ++b)
        for (int a = std::max(0, i - 1); a <= std::min(nx - 1, i + 1) && !crossed; ++a)
          crossed = fluid[static_cast<std::size_t>(b) * nx + a] != fluid[p];
      if (crossed)
        edge.push_back(p);
    }
  return edge;
}

/// The grid covering the first frame's fluid bounds plus the margin (RunScan::grid empty).
ImageGrid derived_grid(const RunScan& scan, vtkUnstructuredGrid* first) {
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
  return centred_grid(centre, scan.direction, size, {scan.voxel, scan.voxel, scan.voxel});
}

} // namespace

Flow4D synthesize_run(const RunScan& scan) {
  return std::move(synthesize_run(scan, {scan.grid}).front());
}

std::vector<Flow4D> synthesize_run(const RunScan& scan, const std::vector<ImageGrid>& grids_in) {
  analysis::AnalyzeOptions o;
  o.run_dir = scan.run_dir;
  o.all_frames = !std::filesystem::exists(RunFiles{scan.run_dir}.cycles_json());
  std::string label;
  const std::vector<analysis::FlowFrame> saved = analysis::select_frames(o, label);
  if (saved.size() < 2)
    input_error("'{}': a synthetic scan needs at least two saved frames", scan.run_dir.string());
  const double t0 = saved.front().time, period = saved.back().time - t0;

  // The grids: given, or the first frame's fluid bounds plus the margin.
  vtkSmartPointer<vtkUnstructuredGrid> first = analysis::read_flow_frame(saved.front().file);
  std::vector<ImageGrid> grids = grids_in;
  for (ImageGrid& g : grids)
    if (g.count() == 0)
      g = derived_grid(scan, first);

  // Voxel means per grid and saved frame: every voxel at n^3 points, then a 2D scan's edge
  // pixels at edge_samples^2 x n.
  const std::vector<Vec3> coarse = offsets(scan.voxel_samples, scan.voxel_samples);
  const std::vector<Vec3> fine = offsets(scan.edge_samples, scan.voxel_samples);
  std::vector<std::vector<VoxelMeans>> means(grids.size(), std::vector<VoxelMeans>(saved.size()));
  for (std::size_t f = 0; f < saved.size(); ++f) {
    vtkSmartPointer<vtkUnstructuredGrid> mesh =
        f == 0 ? first : analysis::read_flow_frame(saved[f].file);
    std::vector<ProbeRequest> every, edges;
    for (std::size_t s = 0; s < grids.size(); ++s) {
      VoxelMeans& m = means[s][f];
      for (auto& c : m.velocity)
        c.assign(grids[s].count(), 0.0f);
      m.fluid.assign(grids[s].count(), 0.0f);
      ProbeRequest r{&grids[s], std::vector<std::size_t>(grids[s].count()), &coarse, &m};
      for (std::size_t v = 0; v < r.voxels.size(); ++v)
        r.voxels[v] = v;
      every.push_back(std::move(r));
    }
    probe_means(mesh, every, saved[f].file);
    for (std::size_t s = 0; s < grids.size(); ++s)
      if (grids[s].size[2] == 1 && scan.edge_samples > scan.voxel_samples)
        edges.push_back({&grids[s], edge_pixels(grids[s], means[s][f].fluid), &fine, &means[s][f]});
    probe_means(mesh, edges, saved[f].file);
  }

  // MRI frames: window means of the time-interpolated voxel means.
  std::vector<Flow4D> scans;
  const double dt = period / scan.frames;
  for (std::size_t s = 0; s < grids.size(); ++s) {
    const std::size_t n = grids[s].count();
    Flow4D out;
    out.grid = grids[s];
    out.venc = scan.effects.venc;
    out.frame_window = dt;
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
                                         [](double x, const auto& v) { return x < v.time; });
        const std::size_t i1 = std::clamp<std::size_t>(it - saved.begin(), 1, saved.size() - 1);
        const std::size_t i0 = i1 - 1;
        const double w =
            std::clamp((t0 + t - saved[i0].time) / (saved[i1].time - saved[i0].time), 0.0, 1.0);
        const double share = 1.0 / scan.time_samples;
        const VoxelMeans &m0 = means[s][i0], &m1 = means[s][i1];
        for (std::size_t v = 0; v < n; ++v) {
          const double fluid = (1 - w) * m0.fluid[v] + w * m1.fluid[v];
          fr.magnitude[v] += static_cast<float>(
              share * (scan.effects.lumen_signal * fluid + scan.tissue_signal * (1 - fluid)));
          for (int c = 0; c < 3; ++c)
            fr.velocity[c][v] +=
                static_cast<float>(share * ((1 - w) * m0.velocity[c][v] + w * m1.velocity[c][v]));
        }
      }
      out.frames.push_back(std::move(fr));
    }
    out.period = period;
    encode(out, scan.encoding);
    ScannerEffects effects = scan.effects;
    effects.seed += s; // each scan its own noise
    add_scanner_effects(out, effects);
    scans.push_back(std::move(out));
  }
  return scans;
}

} // namespace tearflow::mri
