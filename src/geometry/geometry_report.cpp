#include "geometry/geometry_report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/sections.hpp"
#include "geometry/tbad_builder.hpp"

namespace tearflow::geometry {

namespace {

double triangle_area(const mesh::Mesh& m, const Tri& t) {
  const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
  return 0.5 * std::sqrt(dot(n, n));
}

} // namespace

std::vector<EdgeLengths> edge_lengths(const mesh::Mesh& mesh) {
  std::vector<EdgeLengths> out;
  for (std::size_t r = 0; r < mesh.regions.size(); ++r) {
    std::vector<std::pair<Index, Index>> edges;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      if (mesh.tet_region[t] == static_cast<int>(r))
        for (int i = 0; i < 4; ++i)
          for (int j = i + 1; j < 4; ++j)
            edges.push_back(std::minmax(mesh.tets[t][i], mesh.tets[t][j]));
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    EdgeLengths e{mesh.regions[r], edges.size()};
    if (edges.empty()) {
      out.push_back(e);
      continue;
    }
    std::vector<double> len;
    len.reserve(edges.size());
    for (const auto& [a, b] : edges) {
      const Vec3 d = mesh.points[b] - mesh.points[a];
      len.push_back(std::sqrt(dot(d, d)));
      e.mean += len.back() / static_cast<double>(edges.size());
    }
    std::sort(len.begin(), len.end());
    e.median = len[len.size() / 2];
    e.p95 = len[len.size() * 95 / 100];
    e.max = len.back();
    out.push_back(e);
  }
  return out;
}

GeometryReport measure_geometry(const mesh::Mesh& mesh, const Landmarks& landmarks) {
  GeometryReport r;
  r.quality = check_fsi_mesh(mesh);
  r.edges = edge_lengths(mesh);
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
  for (const EdgeLengths& e : r.edges)
    s += fmt::format("  {:<8} {:>9} edges, length (mm) mean {:.2f} median {:.2f} 95 % {:.2f} "
                     "max {:.2f}\n",
                     e.region, e.edges, e.mean * 1e3, e.median * 1e3, e.p95 * 1e3, e.max * 1e3);
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
  for (std::size_t i = 0; i < r.quality.regions.size(); ++i) {
    const RegionQuality& q = r.quality.regions[i];
    json region{{"name", q.name},
                {"tets", q.tets},
                {"volume_m3", q.volume},
                {"min_quality", q.min_quality},
                {"mean_quality", q.mean_quality},
                {"tets_below_0.1", q.below_0_1}};
    if (i < r.edges.size()) {
      const EdgeLengths& e = r.edges[i];
      region["edges"] = e.edges;
      region["edge_length_mean_m"] = e.mean;
      region["edge_length_median_m"] = e.median;
      region["edge_length_p95_m"] = e.p95;
      region["edge_length_max_m"] = e.max;
    }
    regions.push_back(region);
  }
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
  const mesh::Mesh mesh = read_fsi_mesh(GeometryFiles{dir}.mesh(), 1e-3);
  const Landmarks landmarks = read_landmarks(GeometryFiles{dir}.landmarks());
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
