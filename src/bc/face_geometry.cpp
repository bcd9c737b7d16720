#include "bc/face_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace tearflow::bc {

namespace {
/// Distance from p to the segment [a, b].
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  const Vec3 d = p - (a + s * ab);
  return std::sqrt(dot(d, d));
}
} // namespace

FaceGeometry face_geometry(const mesh::Mesh& mesh, const mesh::Face& face) {
  FaceGeometry g;
  Vec3 weighted_normal{}, weighted_centroid{};
  std::map<std::pair<Index, Index>, int> edge_count;
  for (const Tri& t : face.triangles) {
    const Vec3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    double area;
    Vec3 n;
    triangle_area_normal(a, b, c, area, n);
    g.area += area;
    weighted_normal = weighted_normal + area * n;
    weighted_centroid = weighted_centroid + (area / 3.0) * (a + b + c);
    for (int k = 0; k < 3; ++k) {
      Index u = t[k], v = t[(k + 1) % 3];
      ++edge_count[{std::min(u, v), std::max(u, v)}];
    }
    for (Index v : t)
      g.nodes.push_back(v);
  }
  std::sort(g.nodes.begin(), g.nodes.end());
  g.nodes.erase(std::unique(g.nodes.begin(), g.nodes.end()), g.nodes.end());
  const double norm = std::sqrt(dot(weighted_normal, weighted_normal));
  g.normal = (1.0 / norm) * weighted_normal;
  g.centroid = (1.0 / g.area) * weighted_centroid;
  for (const Tri& t : face.triangles) {
    double area;
    Vec3 n;
    triangle_area_normal(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], area, n);
    g.max_normal_deviation =
        std::max(g.max_normal_deviation, std::acos(std::clamp(dot(n, g.normal), -1.0, 1.0)));
  }

  // The rim: edges used by exactly one triangle.
  std::vector<std::pair<Index, Index>> rim;
  for (const auto& [edge, count] : edge_count)
    if (count == 1)
      rim.push_back(edge);
  g.rim_distance.resize(g.nodes.size());
  for (size_t k = 0; k < g.nodes.size(); ++k) {
    const Vec3& p = mesh.points[g.nodes[k]];
    double d = rim.empty() ? 0.0 : 1e300;
    for (const auto& [u, v] : rim)
      d = std::min(d, segment_distance(p, mesh.points[u], mesh.points[v]));
    g.rim_distance[k] = d;
    g.max_rim_distance = std::max(g.max_rim_distance, d);
  }
  return g;
}

} // namespace tearflow::bc
