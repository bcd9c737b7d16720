#include "analysis/flow_features.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>
#include <vtkAbstractCellLocator.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellLocator.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkGenericCell.h>
#include <vtkIntegrateAttributes.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>
#include <vtkStreamTracer.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "analysis/hemodynamics.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "io/vtu_series.hpp"

namespace tearflow::analysis {

namespace {

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

/// Two unit vectors spanning the plane of normal n (n unit).
std::pair<Vec3, Vec3> plane_basis(const Vec3& n) {
  // Cross with the axis least aligned with n: never near-parallel.
  Vec3 a{1, 0, 0};
  if (std::abs(n[1]) < std::abs(n[0]) && std::abs(n[1]) <= std::abs(n[2]))
    a = {0, 1, 0};
  else if (std::abs(n[2]) < std::abs(n[0]))
    a = {0, 0, 1};
  const Vec3 e1 = unit(cross(n, a));
  return {e1, cross(n, e1)};
}

/// The points of a regular grid of spacing h on the landmark's plane, anchored at its lumen
/// point, that lie inside `section` (its polygons).
vtkSmartPointer<vtkPoints> grid_in_section(vtkPolyData* section, const geometry::Landmark& l,
                                           double h) {
  const Vec3 n = unit(l.normal);
  const auto [e1, e2] = plane_basis(n);
  const Vec3 p = l.point.value_or(l.origin);
  const Vec3 anchor = p - dot(p - l.origin, n) * n;
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  for (vtkIdType i = 0; i < section->GetNumberOfPoints(); ++i) {
    Vec3 x;
    section->GetPoint(i, x.data());
    const double s[2] = {dot(x - anchor, e1), dot(x - anchor, e2)};
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], s[k]);
      hi[k] = std::max(hi[k], s[k]);
    }
  }
  auto locator = vtkSmartPointer<vtkCellLocator>::New();
  locator->SetDataSet(section);
  locator->BuildLocator();
  // A grid point on the plane inside a polygon is at distance 0 from it up to rounding of
  // the section's coordinates (double, from the mesh's float32 points): 1e-6 h is far above
  // that and far below the grid's spacing.
  const double tol2 = 1e-12 * h * h;
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  for (long i = static_cast<long>(std::floor(lo[0] / h)); i * h <= hi[0]; ++i)
    for (long j = static_cast<long>(std::floor(lo[1] / h)); j * h <= hi[1]; ++j) {
      Vec3 x = anchor + (i * h) * e1 + (j * h) * e2;
      double closest[3], dist2 = 0;
      vtkIdType id = -1;
      int sub = 0;
      locator->FindClosestPoint(x.data(), closest, cell, id, sub, dist2);
      if (id >= 0 && dist2 <= tol2)
        points->InsertNextPoint(x.data());
    }
  return points;
}

/// The section's equivalent diameter sqrt(4 A / pi) [m].
double equivalent_diameter(double area) {
  return std::sqrt(4.0 * area / M_PI);
}

/// Adds point array `speed` = |velocity| [m/s].
void add_speed(vtkPolyData* data) {
  vtkDataArray* u = data->GetPointData()->GetArray("velocity");
  auto speed = vtkSmartPointer<vtkDoubleArray>::New();
  speed->SetName(kSpeedArray);
  speed->SetNumberOfTuples(data->GetNumberOfPoints());
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    double v[3];
    u->GetTuple(i, v);
    speed->SetValue(i, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  data->GetPointData()->AddArray(speed);
}

/// The flow through the reference landmark (inlet, else the first) at the frames `analyze`
/// would take: from the run's analysis CSV when `analyze` wrote one, else measured here.
struct FlowSeries {
  std::vector<FlowFrame> frames;
  std::vector<double> flow; ///< [m^3/s]
};

std::vector<FlowFrame> analysed_frames(const std::filesystem::path& run_dir) {
  AnalyzeOptions o;
  o.run_dir = run_dir;
  // Every saved frame when the run completed no cycle (a short look at a run).
  std::ifstream in(RunFiles{run_dir}.cycles_json());
  const nlohmann::json cycles =
      in ? nlohmann::json::parse(in, nullptr, false) : nlohmann::json(nullptr);
  o.all_frames = !(cycles.is_object() && cycles.contains("cycles") && cycles["cycles"].is_array() &&
                   !cycles["cycles"].empty());
  std::string label;
  return select_frames(o, label);
}

FlowSeries reference_flow(const std::filesystem::path& run_dir,
                          const geometry::Landmarks& landmarks) {
  if (landmarks.planes.empty())
    input_error("'{}': the landmarks hold no plane to find peak systole by", run_dir.string());
  const auto inlet = std::find_if(landmarks.planes.begin(), landmarks.planes.end(),
                                  [](const geometry::Landmark& l) { return l.name == "inlet"; });
  const geometry::Landmark& reference =
      inlet != landmarks.planes.end() ? *inlet : landmarks.planes.front();
  FlowSeries s;
  s.frames = analysed_frames(run_dir);
  const std::filesystem::path csv = RunFiles{run_dir}.analysis_dir() / (reference.name + ".csv");
  if (std::filesystem::exists(csv)) {
    // The analysis's own flows (the conservative flux) at its frames, when they are these.
    const LandmarkTable table = read_landmark_table(csv);
    const std::vector<double>& t = table.column("time_s");
    const std::vector<double>& q = table.column("flow_m3_per_s");
    if (t.size() == s.frames.size() &&
        std::equal(t.begin(), t.end(), s.frames.begin(), [](double a, const FlowFrame& f) {
          return std::abs(a - f.time) <= 1e-9 * std::max(1.0, std::abs(a));
        })) {
      s.flow = q;
      return s;
    }
  }
  for (const FlowFrame& f : s.frames) {
    const auto grid = read_flow_frame(f.file);
    const auto section = lumen_section(grid, reference, f.file.string());
    s.flow.push_back(area_and_flow(section).second);
  }
  return s;
}

} // namespace

std::pair<double, double> area_and_flow(vtkPolyData* section) {
  auto sums = vtkSmartPointer<vtkIntegrateAttributes>::New();
  sums->SetInputData(section);
  sums->Update();
  vtkUnstructuredGrid* out = sums->GetOutput();
  return {out->GetCellData()->GetArray("Area")->GetTuple1(0),
          out->GetPointData()->GetArray(kThroughPlaneArray)->GetTuple1(0)};
}

CycleFrames cycle_frames(const std::filesystem::path& run_dir,
                         const geometry::Landmarks& landmarks) {
  const FlowSeries s = reference_flow(run_dir, landmarks);
  std::vector<double> time;
  for (const FlowFrame& f : s.frames)
    time.push_back(f.time);
  const CycleEvents e = cycle_events(time, s.flow);
  CycleFrames c{{s.frames[e.peak_systole], "peak systole"}, std::nullopt, s.frames};
  if (e.mid_diastole)
    c.mid_diastole = PictureFrame{s.frames[*e.mid_diastole], "mid-diastole"};
  return c;
}

CycleEvents cycle_events(const std::vector<double>& time, const std::vector<double>& flow) {
  if (time.empty() || time.size() != flow.size())
    input_error("cycle events: {} times and {} flows (one each per frame, at least one)",
                time.size(), flow.size());
  const std::size_t peak =
      static_cast<std::size_t>(std::max_element(flow.begin(), flow.end()) - flow.begin());
  CycleEvents e{peak, std::nullopt};
  std::size_t end_systole = peak;
  while (end_systole < flow.size() && flow[end_systole] >= 0.1 * flow[peak])
    ++end_systole;
  if (end_systole == flow.size())
    return e;
  const double middle = 0.5 * (time[end_systole] + time.back());
  std::size_t nearest = end_systole;
  for (std::size_t i = end_systole; i < time.size(); ++i)
    if (std::abs(time[i] - middle) < std::abs(time[nearest] - middle))
      nearest = i;
  e.mid_diastole = nearest;
  return e;
}

PictureFrame frame_at(const std::filesystem::path& run_dir, double time) {
  const std::filesystem::path pvd = RunFiles{run_dir}.flow_pvd();
  const std::vector<FlowFrame> frames = read_pvd(pvd);
  double gap = 0.0;
  for (std::size_t i = 1; i < frames.size(); ++i)
    gap = std::max(gap, frames[i].time - frames[i - 1].time);
  if (time < frames.front().time - 0.5 * gap || time > frames.back().time + 0.5 * gap)
    input_error("--time {} s lies outside the frames saved in '{}' (t = {} to {} s)", time,
                pvd.string(), frames.front().time, frames.back().time);
  const auto nearest =
      std::min_element(frames.begin(), frames.end(), [&](const FlowFrame& a, const FlowFrame& b) {
        return std::abs(a.time - time) < std::abs(b.time - time);
      });
  return {*nearest, fmt::format("t = {} s", nearest->time)};
}

vtkSmartPointer<vtkPolyData> seed_points(vtkUnstructuredGrid* fluid, const geometry::Landmark& seed,
                                         const StreamlineOptions& options,
                                         const std::string& frame) {
  const vtkSmartPointer<vtkPolyData> section = lumen_section(fluid, seed, frame);
  const double h = options.seed_spacing > 0
                       ? options.seed_spacing
                       : equivalent_diameter(area_and_flow(section).first) / 10.0;
  auto seeds = vtkSmartPointer<vtkPolyData>::New();
  seeds->SetPoints(grid_in_section(section, seed, h));
  if (seeds->GetNumberOfPoints() == 0)
    input_error("{}: no streamline seed lies in the lumen section of landmark '{}' (seed "
                "spacing too coarse for the section?)",
                frame, seed.name);
  return seeds;
}

vtkSmartPointer<vtkPolyData> trace_streamlines(vtkUnstructuredGrid* fluid,
                                               const geometry::Landmark& seed,
                                               const StreamlineOptions& options,
                                               const std::string& frame) {
  return trace_streamlines(fluid, seed_points(fluid, seed, options, frame), options);
}

vtkSmartPointer<vtkPolyData> trace_streamlines(vtkUnstructuredGrid* fluid, vtkPolyData* seeds,
                                               const StreamlineOptions& options) {
  double b[6];
  fluid->GetBounds(b);
  const double diagonal = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                                    (b[5] - b[4]) * (b[5] - b[4]));
  auto tracer = vtkSmartPointer<vtkStreamTracer>::New();
  tracer->SetInputData(fluid);
  tracer->SetSourceData(seeds);
  tracer->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "velocity");
  // A cell locator finds the cell of each step by position: the default (a point locator and
  // the cells around the nearest node) loses the way in a curved lumen beside the flap.
  tracer->SetInterpolatorTypeToCellLocator();
  tracer->SetIntegratorTypeToRungeKutta45();
  tracer->SetIntegrationDirectionToBoth();
  // Steps in cell lengths follow the mesh's resolution: the fine tears and the coarse arch.
  tracer->SetIntegrationStepUnit(vtkStreamTracer::CELL_LENGTH_UNIT);
  tracer->SetInitialIntegrationStep(0.2);
  tracer->SetMinimumIntegrationStep(0.01);
  tracer->SetMaximumIntegrationStep(0.5);
  tracer->SetMaximumError(1e-6);
  tracer->SetMaximumNumberOfSteps(20000);
  tracer->SetMaximumPropagation(options.max_length > 0 ? options.max_length : 2.0 * diagonal);
  tracer->SetTerminalSpeed(kTerminalSpeed);
  tracer->SetComputeVorticity(false);
  tracer->Update();
  vtkSmartPointer<vtkPolyData> lines = tracer->GetOutput();
  add_speed(lines);
  return lines;
}

vtkSmartPointer<vtkAbstractCellLocator> fluid_locator(vtkUnstructuredGrid* fluid) {
  auto locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  locator->SetDataSet(fluid);
  locator->BuildLocator();
  return locator;
}

PlaneMap plane_map(vtkUnstructuredGrid* fluid, const geometry::Landmark& landmark,
                   double vector_spacing, const std::string& frame,
                   vtkAbstractCellLocator* given_locator) {
  PlaneMap m;
  m.landmark = landmark;
  m.section = lumen_section(fluid, landmark, frame);
  add_speed(m.section);
  std::tie(m.area, m.flow) = area_and_flow(m.section);
  const double h = vector_spacing > 0 ? vector_spacing : equivalent_diameter(m.area) / 8.0;
  m.vector_spacing = h;
  // The in-plane velocity at the coarse grid's points, interpolated in the fluid's cell that
  // holds each (P1: the weights are the barycentric coordinates).
  const vtkSmartPointer<vtkPoints> points = grid_in_section(m.section, landmark, h);
  const vtkSmartPointer<vtkAbstractCellLocator> own =
      given_locator ? nullptr : fluid_locator(fluid);
  vtkAbstractCellLocator* locator = given_locator ? given_locator : own.Get();
  vtkDataArray* u = fluid->GetPointData()->GetArray("velocity");
  const Vec3 n = unit(landmark.normal);
  auto velocity = vtkSmartPointer<vtkDoubleArray>::New(),
       in_plane = vtkSmartPointer<vtkDoubleArray>::New();
  velocity->SetName("velocity");
  in_plane->SetName(kInPlaneArray);
  for (auto* a : {velocity.Get(), in_plane.Get()}) {
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(points->GetNumberOfPoints());
  }
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  std::vector<double> weights(static_cast<std::size_t>(fluid->GetMaxCellSize()));
  auto vertices = vtkSmartPointer<vtkCellArray>::New();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
    double x[3], pcoords[3];
    points->GetPoint(i, x);
    const vtkIdType c = locator->FindCell(x, 0.0, cell.Get(), pcoords, weights.data());
    Vec3 v{0, 0, 0};
    if (c >= 0) // inside the section, so inside the fluid; a miss is rounding on a wall
      for (vtkIdType k = 0; k < cell->GetNumberOfPoints(); ++k) {
        double uk[3];
        u->GetTuple(cell->GetPointId(k), uk);
        v = v + weights[static_cast<std::size_t>(k)] * Vec3{uk[0], uk[1], uk[2]};
      }
    const Vec3 w = v - dot(v, n) * n;
    velocity->SetTuple(i, v.data());
    in_plane->SetTuple(i, w.data());
    vertices->InsertNextCell(1, &i);
  }
  m.vectors = vtkSmartPointer<vtkPolyData>::New();
  m.vectors->SetPoints(points);
  m.vectors->SetVerts(vertices);
  m.vectors->GetPointData()->AddArray(velocity);
  m.vectors->GetPointData()->AddArray(in_plane);
  return m;
}

vtkSmartPointer<vtkUnstructuredGrid> read_wall(const std::filesystem::path& vtu) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(vtu.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  auto* names =
      vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray(io::kRegionNamesArray));
  vtkDataArray* region = grid->GetCellData()->GetArray(io::kRegionArray);
  if (names == nullptr || region == nullptr ||
      grid->GetPointData()->GetArray("displacement") == nullptr)
    return nullptr;
  const vtkIdType wall = names->LookupValue("wall");
  if (wall < 0)
    return nullptr;
  return cells_with(grid, io::kRegionArray, wall);
}

void write_vtp(vtkPolyData* data, const std::filesystem::path& file) {
  auto writer = vtkSmartPointer<vtkXMLPolyDataWriter>::New();
  writer->SetFileName(file.c_str());
  writer->SetInputData(data);
  writer->SetDataModeToAppended();
  if (writer->Write() != 1)
    input_error("cannot write '{}'", file.string());
}

} // namespace tearflow::analysis
