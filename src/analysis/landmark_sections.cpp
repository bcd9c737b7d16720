#include "analysis/landmark_sections.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <regex>

#include <vtk3DLinearGridPlaneCutter.h>
#include <vtkCellData.h>
#include <vtkCellLocator.h>
#include <vtkCleanPolyData.h>
#include <vtkConnectivityFilter.h>
#include <vtkCutter.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkGeometryFilter.h>
#include <vtkIntegrateAttributes.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPointSet.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkThreshold.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/vtu_series.hpp"

namespace tearflow::analysis {

vtkSmartPointer<vtkUnstructuredGrid> cells_with(vtkPointSet* data, const char* array,
                                                vtkIdType value) {
  auto threshold = vtkSmartPointer<vtkThreshold>::New();
  threshold->SetInputData(data);
  threshold->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, array);
  threshold->SetLowerThreshold(static_cast<double>(value) - 0.5);
  threshold->SetUpperThreshold(static_cast<double>(value) + 0.5);
  threshold->SetThresholdFunction(vtkThreshold::THRESHOLD_BETWEEN);
  threshold->Update();
  return threshold->GetOutput();
}

namespace {

constexpr const char* kThroughPlane = "through_plane_velocity";
constexpr const char* kRegion = "RegionId";
constexpr const char* kDisplacement = "displacement";
// A lumen point may sit off its region by rounding in the landmarks file (mm with a few
// digits) or because a moving wall shifted the section; beyond this fraction of the
// region's equivalent radius sqrt(A / pi) it belongs to another lumen or to none.
constexpr double kPointSlack = 0.1;

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

/// The plane's fluid section with per-point u.n and its connected regions coloured.
struct PlaneSection {
  vtkSmartPointer<vtkPointSet> regions; // cell and point data "RegionId"
  vtkSmartPointer<vtkCellLocator> locator;
  vtkIdType region_count = 0;
  std::optional<PlaneFlux> flux; // when the step's continuity state is known

  /// The region of the section cell nearest to `p`, and the distance to it.
  std::pair<vtkIdType, double> region_at(const Vec3& p) const {
    double closest[3], dist2 = 0;
    vtkIdType cell = -1;
    int sub = 0;
    locator->FindClosestPoint(p.data(), closest, cell, sub, dist2);
    return {static_cast<vtkIdType>(regions->GetCellData()->GetArray(kRegion)->GetTuple1(cell)),
            std::sqrt(dist2)};
  }
};

PlaneSection cut(vtkUnstructuredGrid* grid, const Vec3& origin, const Vec3& normal) {
  auto plane = vtkSmartPointer<vtkPlane>::New();
  plane->SetOrigin(origin[0], origin[1], origin[2]);
  plane->SetNormal(normal[0], normal[1], normal[2]);
  // The section's polygons must share the points of the fluid edges they cut, or each would
  // be a region of its own: vtkCutter hands linear cells to vtk3DLinearGridPlaneCutter, which
  // does not merge points by default, so that filter is used directly with merging on
  // (exact, by edge); other cells go through vtkCutter and a merge of coincident points.
  vtkSmartPointer<vtkPolyData> section;
  if (vtk3DLinearGridPlaneCutter::CanFullyProcessDataObject(grid)) {
    auto cutter = vtkSmartPointer<vtk3DLinearGridPlaneCutter>::New();
    cutter->SetPlane(plane);
    cutter->MergePointsOn();
    cutter->InterpolateAttributesOn();
    cutter->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
    // One thread: threads cut the grid in pieces whose order varies from call to call, and
    // with it the sums over the section (the same run's metrics differed at 1e-16 from one
    // analysis to the next); so analysis is reproducible to the last digit, at no cost measured
    // (6.1 s for the CI study's OR run either way).
    cutter->SequentialProcessingOn();
    cutter->SetInputData(grid);
    cutter->Update();
    section = vtkPolyData::SafeDownCast(cutter->GetOutputDataObject(0));
  } else {
    auto cutter = vtkSmartPointer<vtkCutter>::New();
    cutter->SetCutFunction(plane);
    cutter->SetInputData(grid);
    auto merge = vtkSmartPointer<vtkCleanPolyData>::New();
    merge->SetInputConnection(cutter->GetOutputPort());
    merge->Update();
    section = merge->GetOutput();
  }
  PlaneSection s;
  if (section == nullptr || section->GetNumberOfCells() == 0)
    return s;
  // The through-plane velocity as a point field, so that the integrator gives Q directly.
  vtkDataArray* velocity = section->GetPointData()->GetArray("velocity");
  auto un = vtkSmartPointer<vtkDoubleArray>::New();
  un->SetName(kThroughPlane);
  un->SetNumberOfTuples(section->GetNumberOfPoints());
  for (vtkIdType i = 0; i < section->GetNumberOfPoints(); ++i) {
    double u[3];
    velocity->GetTuple(i, u);
    un->SetValue(i, u[0] * normal[0] + u[1] * normal[1] + u[2] * normal[2]);
  }
  section->GetPointData()->AddArray(un);
  // The polygons share points, so the connectivity of the section follows that of the fluid.
  auto connectivity = vtkSmartPointer<vtkConnectivityFilter>::New();
  connectivity->SetInputData(section);
  connectivity->SetExtractionModeToAllRegions();
  connectivity->ColorRegionsOn();
  connectivity->Update();
  s.regions = connectivity->GetOutput();
  s.region_count = connectivity->GetNumberOfExtractedRegions();
  s.locator = vtkSmartPointer<vtkCellLocator>::New();
  s.locator->SetDataSet(s.regions);
  s.locator->BuildLocator();
  return s;
}

/// The cells of region `region` of a section.
vtkSmartPointer<vtkUnstructuredGrid> region_cells(vtkPointSet* regions, vtkIdType region) {
  return cells_with(regions, kRegion, region);
}

/// Integrals over region `region` of a section.
SectionValues integrate(vtkPointSet* regions, vtkIdType region) {
  const vtkSmartPointer<vtkUnstructuredGrid> cells = region_cells(regions, region);
  vtkUnstructuredGrid* piece = cells;
  auto integrator = vtkSmartPointer<vtkIntegrateAttributes>::New();
  integrator->SetInputData(piece);
  integrator->Update();
  vtkUnstructuredGrid* sums = integrator->GetOutput();
  SectionValues v;
  v.area = sums->GetCellData()->GetArray("Area")->GetTuple1(0);
  v.flow = sums->GetPointData()->GetArray(kThroughPlane)->GetTuple1(0);
  v.pressure = sums->GetPointData()->GetArray("pressure")->GetTuple1(0) / v.area;
  // P1 along the section: the maximum of u.n over a polygon is at one of its points.
  vtkDataArray* un = piece->GetPointData()->GetArray(kThroughPlane);
  v.max_velocity = -std::numeric_limits<double>::infinity();
  for (vtkIdType i = 0; i < un->GetNumberOfTuples(); ++i)
    v.max_velocity = std::max(v.max_velocity, un->GetTuple1(i));
  // The wall's displacement at the station: the largest |d| on the section, which is reached
  // on its rim (the lumen wall; the fluid mesh's own motion decays inwards).
  if (vtkDataArray* d = piece->GetPointData()->GetArray(kDisplacement))
    for (vtkIdType i = 0; i < d->GetNumberOfTuples(); ++i) {
      double u[3];
      d->GetTuple(i, u);
      v.wall_displacement =
          std::max(v.wall_displacement, std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    }
  return v;
}

/// The rim points (on edges that one polygon of the region holds) of region `region`.
std::vector<vtkIdType> rim_points(vtkPolyData* section, vtkIdType region) {
  vtkDataArray* ids = section->GetCellData()->GetArray(kRegion);
  std::map<std::pair<vtkIdType, vtkIdType>, int> edges;
  for (vtkIdType c = 0; c < section->GetNumberOfCells(); ++c) {
    if (static_cast<vtkIdType>(ids->GetTuple1(c)) != region)
      continue;
    vtkIdType n = 0;
    const vtkIdType* p = nullptr;
    section->GetCellPoints(c, n, p);
    for (vtkIdType a = 0; a < n; ++a) {
      const vtkIdType i = p[a], j = p[(a + 1) % n];
      ++edges[{std::min(i, j), std::max(i, j)}];
    }
  }
  std::vector<vtkIdType> rim;
  for (const auto& [edge, count] : edges)
    if (count == 1) {
      rim.push_back(edge.first);
      rim.push_back(edge.second);
    }
  std::sort(rim.begin(), rim.end());
  rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
  return rim;
}

/// The flap's displacement toward the false lumen at a station: the mean of d . e over the
/// rim points of each lumen that face the other lumen across the flap (nearer to it than
/// twice the smallest TL-FL gap, the flap's thickness at the station), e the unit vector
/// from the TL's lumen point to the FL's in the plane. NaN without a displacement field.
double flap_displacement(vtkPointSet* regions, vtkIdType tl, vtkIdType fl, const Vec3& tl_point,
                         const Vec3& fl_point, const Vec3& normal) {
  auto* section = vtkPolyData::SafeDownCast(regions);
  vtkDataArray* d = regions->GetPointData()->GetArray(kDisplacement);
  if (section == nullptr || d == nullptr)
    return std::nan("");
  Vec3 e = fl_point - tl_point;
  e = e - dot(e, normal) * normal;
  if (dot(e, e) == 0.0)
    return std::nan("");
  e = unit(e);
  const std::vector<vtkIdType> rims[2] = {rim_points(section, tl), rim_points(section, fl)};
  const auto point = [&](vtkIdType i) {
    Vec3 x;
    section->GetPoint(i, x.data());
    return x;
  };
  // Each rim point's distance to the other lumen's rim.
  std::vector<double> gap[2];
  double thinnest = std::numeric_limits<double>::infinity();
  for (int side = 0; side < 2; ++side)
    for (vtkIdType i : rims[side]) {
      double nearest = std::numeric_limits<double>::infinity();
      for (vtkIdType j : rims[1 - side]) {
        const Vec3 r = point(i) - point(j);
        nearest = std::min(nearest, dot(r, r));
      }
      gap[side].push_back(std::sqrt(nearest));
      thinnest = std::min(thinnest, gap[side].back());
    }
  double sum = 0.0;
  int count = 0;
  for (int side = 0; side < 2; ++side)
    for (std::size_t k = 0; k < rims[side].size(); ++k)
      if (gap[side][k] <= 2.0 * thinnest) {
        Vec3 u;
        d->GetTuple(rims[side][k], u.data());
        sum += dot(u, e);
        ++count;
      }
  return count > 0 ? sum / count : std::nan("");
}

/// The fluid of a frame in its deformed position: an FSI frame holds the fluid and the wall
/// (cell array `region`, names in field data) and the nodes' displacement from the reference
/// mesh; the landmark planes cut the lumen as it is at that instant.
vtkSmartPointer<vtkUnstructuredGrid> deformed_fluid(vtkSmartPointer<vtkUnstructuredGrid> grid,
                                                    const std::filesystem::path& vtu) {
  auto* names =
      vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray(io::kRegionNamesArray));
  vtkDataArray* region = grid->GetCellData()->GetArray(io::kRegionArray);
  if (names != nullptr && region != nullptr) {
    const vtkIdType fluid = names->LookupValue("fluid");
    if (fluid < 0)
      input_error("frame '{}': several volume regions and none is called 'fluid'", vtu.string());
    // The nodes the fluid shares with the wall (its outer wall and the flap): the moving
    // wall's share of the conservative flux is integrated over the faces they span.
    auto on_wall = vtkSmartPointer<vtkUnsignedCharArray>::New();
    on_wall->SetName(kOnWallArray);
    on_wall->SetNumberOfTuples(grid->GetNumberOfPoints());
    on_wall->FillValue(0);
    for (vtkIdType cell = 0; cell < grid->GetNumberOfCells(); ++cell) {
      if (static_cast<vtkIdType>(region->GetTuple1(cell)) == fluid)
        continue;
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      grid->GetCellPoints(cell, n, ids);
      for (vtkIdType a = 0; a < n; ++a)
        on_wall->SetValue(ids[a], 1);
    }
    grid->GetPointData()->AddArray(on_wall);
    grid = cells_with(grid, io::kRegionArray, fluid);
  }
  vtkDataArray* d = grid->GetPointData()->GetArray(kDisplacement);
  if (d == nullptr)
    return grid;
  if (d->GetNumberOfComponents() != 3)
    input_error("frame '{}': point field 'displacement' needs 3 components", vtu.string());
  auto moved = vtkSmartPointer<vtkPoints>::New();
  moved->SetDataTypeToDouble();
  moved->SetNumberOfPoints(grid->GetNumberOfPoints());
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {
    double x[3], u[3];
    grid->GetPoint(i, x);
    d->GetTuple(i, u);
    moved->SetPoint(i, x[0] + u[0], x[1] + u[1], x[2] + u[2]);
  }
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  out->ShallowCopy(grid);
  out->SetPoints(moved);
  return out;
}

} // namespace

int station_of(const geometry::Landmark& l) {
  static const std::regex paired(R"((TL|FL)([0-9]+))");
  std::smatch m;
  return std::regex_match(l.name, m, paired) ? std::stoi(m[2]) : 0;
}

std::vector<FlowFrame> read_pvd(const std::filesystem::path& pvd) {
  std::ifstream in(pvd);
  if (!in)
    input_error("cannot open '{}' (is this a run's output directory?)", pvd.string());
  const std::regex entry(R"re(timestep="([^"]+)".*file="([^"]+)")re");
  std::vector<FlowFrame> frames;
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, entry))
      frames.push_back({std::stod(m[1]), pvd.parent_path() / m[2].str()});
  if (frames.empty())
    input_error("'{}' lists no frame", pvd.string());
  std::stable_sort(frames.begin(), frames.end(),
                   [](const FlowFrame& a, const FlowFrame& b) { return a.time < b.time; });
  return frames;
}

vtkSmartPointer<vtkUnstructuredGrid> read_flow_frame(const std::filesystem::path& vtu) {
  if (!std::filesystem::exists(vtu))
    input_error("frame '{}' does not exist", vtu.string());
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(vtu.c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  if (grid == nullptr || grid->GetNumberOfCells() == 0)
    input_error("frame '{}': no cells (not a VTU file?)", vtu.string());
  vtkDataArray* u = grid->GetPointData()->GetArray("velocity");
  if (u == nullptr || u->GetNumberOfComponents() != 3)
    input_error("frame '{}': no point field 'velocity' with 3 components", vtu.string());
  if (grid->GetPointData()->GetArray("pressure") == nullptr)
    input_error("frame '{}': no point field 'pressure'", vtu.string());
  return deformed_fluid(grid, vtu);
}

namespace {

/// The region of a landmark's plane section its lumen point lies in (the point projected on
/// the plane: rounding may lift it off), and how far that point is from the region.
struct LandmarkRegion {
  vtkIdType region = -1;
  double distance = 0.0; ///< [m]
  Vec3 point{};
};

LandmarkRegion landmark_region(const PlaneSection& section, const geometry::Landmark& l,
                               const Vec3& n, const std::string& frame) {
  if (!section.regions)
    input_error("{}: the plane of landmark '{}' (origin ({:.2f}, {:.2f}, {:.2f}) mm) misses "
                "the fluid mesh",
                frame, l.name, l.origin[0] / units::mm, l.origin[1] / units::mm,
                l.origin[2] / units::mm);
  const Vec3 p = l.point.value_or(l.origin);
  const Vec3 q = p - dot(p - l.origin, n) * n;
  const auto [region, distance] = section.region_at(q);
  return {region, distance, q};
}

/// InputError unless the lumen point lies within kPointSlack radii of its region (`area`).
void require_inside(const LandmarkRegion& at, double area, const geometry::Landmark& l,
                    const std::string& frame) {
  if (at.distance > kPointSlack * std::sqrt(area / M_PI))
    input_error("{}: landmark '{}': its lumen point ({:.2f}, {:.2f}, {:.2f}) mm is not inside "
                "the fluid section of its plane (nearest fluid {:.2f} mm away)",
                frame, l.name, at.point[0] / units::mm, at.point[1] / units::mm,
                at.point[2] / units::mm, at.distance / units::mm);
}

} // namespace

vtkSmartPointer<vtkPolyData> lumen_section(vtkUnstructuredGrid* grid, const geometry::Landmark& l,
                                           const std::string& frame) {
  const Vec3 n = unit(l.normal);
  const PlaneSection section = cut(grid, l.origin, n);
  const LandmarkRegion at = landmark_region(section, l, n, frame);
  const vtkSmartPointer<vtkUnstructuredGrid> cells = region_cells(section.regions, at.region);
  auto surface = vtkSmartPointer<vtkGeometryFilter>::New();
  surface->SetInputData(cells);
  surface->Update();
  vtkSmartPointer<vtkPolyData> out = surface->GetOutput();
  auto sums = vtkSmartPointer<vtkIntegrateAttributes>::New();
  sums->SetInputData(cells);
  sums->Update();
  require_inside(at, sums->GetOutput()->GetCellData()->GetArray("Area")->GetTuple1(0), l, frame);
  return out;
}

std::vector<SectionValues> measure_landmarks(vtkUnstructuredGrid* grid,
                                             const geometry::Landmarks& landmarks,
                                             const std::string& frame, const ContinuityState* state,
                                             const ContinuityForm* form) {
  std::vector<SectionValues> values;
  PlaneSection section;
  int section_id = -1; // TLk and FLk share one plane: cut it once
  Vec3 cut_origin{}, cut_normal{};
  // per station: (section id, region id) of its TL and FL landmark
  std::map<int, std::map<std::string, std::pair<int, vtkIdType>>> stations;
  // per station: (lumen point on the plane, index in `values`) of its TL and FL landmark
  std::map<int, std::map<std::string, std::pair<Vec3, std::size_t>>> points;
  for (const geometry::Landmark& l : landmarks.planes) {
    const Vec3 n = unit(l.normal);
    // One plane when the normals agree and the origin lies on the last cut's plane (TLk / FLk
    // of an imported file may give different origins on their shared plane).
    const bool same_plane = section_id >= 0 && dot(n, cut_normal) > 1.0 - 1e-12 &&
                            std::abs(dot(l.origin - cut_origin, cut_normal)) < 1e-9;
    if (!same_plane) {
      section = cut(grid, l.origin, n);
      ++section_id;
      cut_origin = l.origin;
      cut_normal = n;
      if (section.regions && state != nullptr && form != nullptr)
        section.flux = conservative_fluxes(
            grid, *state, l.origin, n, [&](const Vec3& p) { return section.region_at(p).first; },
            section.region_count, *form);
    }
    const LandmarkRegion at = landmark_region(section, l, n, frame);
    const vtkIdType region = at.region;
    SectionValues v = integrate(section.regions, region);
    require_inside(at, v.area, l, frame);
    v.flow_interpolated = v.flow;
    if (section.flux) {
      v.flow = section.flux->regions[static_cast<std::size_t>(region)];
      v.wall_outflow = section.flux->wall[static_cast<std::size_t>(region)];
      v.wall_part = section.flux->part[static_cast<std::size_t>(region)];
    }
    if (const int k = station_of(l); k > 0) {
      stations[k][l.lumen] = {section_id, region};
      points[k][l.lumen] = {at.point, values.size()};
      const auto tl = stations[k].find("TL"), fl = stations[k].find("FL");
      if (tl != stations[k].end() && fl != stations[k].end() && tl->second.first == section_id &&
          fl->second.first == section_id && tl->second.second != fl->second.second) {
        const auto& [tl_point, tl_index] = points[k]["TL"];
        const auto& [fl_point, fl_index] = points[k]["FL"];
        const double flap = flap_displacement(section.regions, tl->second.second, fl->second.second,
                                              tl_point, fl_point, n);
        v.flap_displacement = flap; // this landmark's, and its partner's already measured
        for (const std::size_t index : {tl_index, fl_index})
          if (index < values.size())
            values[index].flap_displacement = flap;
      }
    }
    values.push_back(v);
  }
  for (const auto& [k, lumina] : stations) {
    const auto tl = lumina.find("TL"), fl = lumina.find("FL");
    if (tl != lumina.end() && fl != lumina.end() && tl->second == fl->second)
      input_error("{}: station {}: the points of TL{} and FL{} lie in one connected region of "
                  "the plane's fluid section; a paired station needs two (the true and the "
                  "false lumen, separated by the flap). Does the plane cross a tear?",
                  frame, k, k, k);
  }
  return values;
}

} // namespace tearflow::analysis
