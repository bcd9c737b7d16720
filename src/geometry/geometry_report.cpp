#include "geometry/geometry_report.hpp"

#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "geometry/sections.hpp"
#include "geometry/tbad_builder.hpp"

namespace tearflow::geometry {

namespace {

double triangle_area(const mesh::Mesh& m, const Tri& t) {
  const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
  return 0.5 * std::sqrt(dot(n, n));
}

} // namespace

GeometryReport measure_geometry(const mesh::Mesh& mesh, const Landmarks& landmarks) {
  GeometryReport r;
  r.quality = check_fsi_mesh(mesh);
  r.nodes = static_cast<std::size_t>(mesh.num_nodes());
  for (const mesh::Face& f : mesh.faces) {
    double a = 0;
    for (const Tri& t : f.triangles)
      a += triangle_area(mesh, t);
    r.face_areas.push_back({f.name, a});
  }
  for (const TearLandmark& t : landmarks.tears)
    r.tears.push_back({t.name, t.area, tear_area(mesh, t)});
  for (const Landmark& l : landmarks.planes)
    r.landmark_areas.push_back({l.name, landmark_area(mesh, l)});
  return r;
}

std::string format_report(const GeometryReport& r) {
  std::string s = fmt::format("mesh: {} nodes\n", r.nodes);
  for (const RegionQuality& q : r.quality.regions)
    s += fmt::format("  {:<8} {:>9} tets  volume {:9.1f} mm^3  quality (3 r_in/r_circ) min {:.3f} "
                     "mean {:.3f}, {} below 0.1\n",
                     q.name, q.tets, q.volume * 1e9, q.min_quality, q.mean_quality, q.below_0_1);
  if (r.quality.interface_triangles)
    s += fmt::format("  interface: {} triangles, {} nodes shared by fluid and wall\n",
                     r.quality.interface_triangles, r.quality.interface_nodes);
  s += "faces (mm^2):\n";
  for (const auto& [name, a] : r.face_areas)
    s += fmt::format("  {:<12} {:10.1f}\n", name, a * 1e6);
  if (!r.tears.empty())
    s += "tears (mm^2):     requested   measured   difference\n";
  for (const MeasuredTear& t : r.tears)
    s += fmt::format("  {:<12} {:12.1f} {:10.1f} {:+11.2f} %\n", t.name, t.requested * 1e6,
                     t.measured * 1e6, 100 * (t.measured / t.requested - 1));
  s += "lumen area at the landmarks (mm^2):\n";
  for (const auto& [name, a] : r.landmark_areas)
    s += fmt::format("  {:<12} {:10.1f}\n", name, a * 1e6);
  return s;
}

std::string report_json(const GeometryReport& r) {
  using nlohmann::json;
  json regions = json::array(), faces = json::object(), tears = json::array(),
       areas = json::object();
  for (const RegionQuality& q : r.quality.regions)
    regions.push_back({{"name", q.name},
                       {"tets", q.tets},
                       {"volume_m3", q.volume},
                       {"min_quality", q.min_quality},
                       {"mean_quality", q.mean_quality},
                       {"tets_below_0.1", q.below_0_1}});
  for (const auto& [name, a] : r.face_areas)
    faces[name] = a;
  for (const MeasuredTear& t : r.tears)
    tears.push_back({{"name", t.name}, {"requested_m2", t.requested}, {"measured_m2", t.measured}});
  for (const auto& [name, a] : r.landmark_areas)
    areas[name] = a;
  const json j{{"nodes", r.nodes},
               {"regions", regions},
               {"interface_triangles", r.quality.interface_triangles},
               {"interface_nodes", r.quality.interface_nodes},
               {"face_areas_m2", faces},
               {"tears", tears},
               {"landmark_areas_m2", areas}};
  return j.dump(2);
}

GeometryReport report_geometry(const std::filesystem::path& dir, const std::filesystem::path& png,
                               bool print) {
  const mesh::Mesh mesh = read_fsi_mesh(dir / kMeshFile, 1e-3);
  const Landmarks landmarks = read_landmarks(dir / kLandmarksFile);
  const GeometryReport r = measure_geometry(mesh, landmarks);
  if (print)
    fmt::print("{}", format_report(r));
  std::ofstream(dir / "report.json") << report_json(r) << "\n";
  if (!png.empty()) {
    render_geometry(mesh, landmarks, png);
    if (print)
      fmt::print("picture: {}\n", png.string());
  }
  return r;
}

} // namespace tearflow::geometry
