#include "geometry/sections.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.hpp"
#include "geometry/fsi_mesh.hpp"

namespace tearflow::geometry {

namespace {

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

// Nodes exactly on the plane count as above it: one rule for every tet, so neighbouring tets
// agree on which shared faces the plane crosses.
bool above(double d) {
  return d >= 0;
}

// The polygon where the plane cuts a tet with node distances d, ordered around its centroid.
std::vector<Vec3> cut_polygon(const std::array<Vec3, 4>& x, const std::array<double, 4>& d,
                              const Vec3& normal) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (above(d[i]) != above(d[j])) {
        const double t = d[i] / (d[i] - d[j]);
        pts.push_back(x[i] + t * (x[j] - x[i]));
      }
  Vec3 c{0, 0, 0};
  for (const Vec3& p : pts)
    c = c + (1.0 / static_cast<double>(pts.size())) * p;
  // Order by angle in the plane.
  const Vec3 e1 =
      unit(std::abs(normal[0]) < 0.9 ? cross(normal, Vec3{1, 0, 0}) : cross(normal, Vec3{0, 1, 0}));
  const Vec3 e2 = cross(normal, e1);
  std::sort(pts.begin(), pts.end(), [&](const Vec3& a, const Vec3& b) {
    return std::atan2(dot(a - c, e2), dot(a - c, e1)) < std::atan2(dot(b - c, e2), dot(b - c, e1));
  });
  return pts;
}

double polygon_area(const std::vector<Vec3>& p, const Vec3& normal) {
  double a = 0;
  for (std::size_t i = 1; i + 1 < p.size(); ++i)
    a += 0.5 * dot(cross(p[i] - p[0], p[i + 1] - p[0]), normal);
  return std::abs(a);
}

bool polygon_contains(const std::vector<Vec3>& p, const Vec3& q, const Vec3& normal) {
  double scale = 0;
  for (const Vec3& v : p)
    scale = std::max(scale, dot(v - p[0], v - p[0]));
  const double eps = 1e-9 * scale;
  bool left = true, right = true; // q on the left (right) of every edge
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double s = dot(cross(p[(i + 1) % p.size()] - p[i], q - p[i]), normal);
    left = left && s >= -eps;
    right = right && s <= eps;
  }
  return left || right;
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

} // namespace

int Section::piece_containing(const Vec3& p) const {
  for (std::size_t i = 0; i < polygons.size(); ++i) {
    // The polygon's own normal direction does not matter for containment: use its plane.
    // The polygon's area vector (Newell): a degenerate polygon (a tet touching the plane in
    // an edge, e.g. through mesh nodes on a symmetry plane) has none and contains nothing;
    // its first three points' normal had an arbitrary direction and contained any point.
    const std::vector<Vec3>& q = polygons[i];
    if (q.size() < 3)
      continue;
    Vec3 n{0, 0, 0};
    double extent = 0;
    for (std::size_t k = 1; k + 1 < q.size(); ++k) {
      n = n + cross(q[k] - q[0], q[k + 1] - q[0]);
      extent = std::max(extent, dot(q[k] - q[0], q[k] - q[0]));
    }
    extent = std::max(extent, dot(q.back() - q[0], q.back() - q[0]));
    if (!(std::sqrt(dot(n, n)) > 1e-9 * extent))
      continue;
    if (polygon_contains(polygons[i], p, unit(n)))
      return piece_of[i];
  }
  return -1;
}

int region_index(const mesh::Mesh& mesh, const std::string& name) {
  const auto it = std::find(mesh.regions.begin(), mesh.regions.end(), name);
  if (it == mesh.regions.end())
    input_error("{}: no region '{}'", mesh.source, name);
  return static_cast<int>(it - mesh.regions.begin());
}

Section cut_region(const mesh::Mesh& mesh, int region, const Vec3& origin, const Vec3& normal_in) {
  const Vec3 normal = unit(normal_in);
  Section s;
  std::vector<std::pair<Tri, int>> crossed_faces; // (sorted face, cut-tet index)
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_region[t] != region)
      continue;
    const Tet& k = mesh.tets[t];
    std::array<Vec3, 4> x;
    std::array<double, 4> d;
    int up = 0;
    for (int i = 0; i < 4; ++i) {
      x[i] = mesh.points[k[i]];
      d[i] = dot(x[i] - origin, normal);
      up += above(d[i]);
    }
    if (up == 0 || up == 4)
      continue;
    const int index = static_cast<int>(s.tets.size());
    s.tets.push_back(static_cast<Index>(t));
    s.polygons.push_back(cut_polygon(x, d, normal));
    for (int skip = 0; skip < 4; ++skip) {
      Tri f{};
      int fu = 0;
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != skip) {
          f[j++] = k[i];
          fu += above(d[i]);
        }
      if (fu == 0 || fu == 3)
        continue;
      std::sort(f.begin(), f.end());
      crossed_faces.push_back({f, index});
    }
  }
  std::sort(crossed_faces.begin(), crossed_faces.end());
  UnionFind uf(s.tets.size());
  for (std::size_t i = 0; i + 1 < crossed_faces.size(); ++i)
    if (crossed_faces[i].first == crossed_faces[i + 1].first)
      uf.join(crossed_faces[i].second, crossed_faces[i + 1].second);
  std::vector<int> piece_of_root(s.tets.size(), -1);
  s.piece_of.resize(s.tets.size());
  std::vector<Vec3> weighted;
  for (std::size_t i = 0; i < s.tets.size(); ++i) {
    int& p = piece_of_root[uf.find(static_cast<int>(i))];
    if (p < 0) {
      p = static_cast<int>(s.areas.size());
      s.areas.push_back(0);
      weighted.push_back({0, 0, 0});
    }
    s.piece_of[i] = p;
    const double a = polygon_area(s.polygons[i], normal);
    Vec3 c{0, 0, 0};
    for (const Vec3& v : s.polygons[i])
      c = c + (1.0 / static_cast<double>(s.polygons[i].size())) * v;
    s.areas[p] += a;
    weighted[p] = weighted[p] + a * c;
  }
  for (std::size_t p = 0; p < s.areas.size(); ++p)
    s.centroids.push_back(s.areas[p] > 0 ? (1.0 / s.areas[p]) * weighted[p] : weighted[p]);
  return s;
}

double landmark_area(const mesh::Mesh& mesh, const Landmark& l) {
  const Section s = cut_region(mesh, region_index(mesh, "fluid"), l.origin, l.normal);
  const Vec3 p = l.point.value_or(l.origin);
  // The point may sit off the plane by rounding in the landmarks file: project it.
  const Vec3 n = unit(l.normal);
  const Vec3 q = p - dot(p - l.origin, n) * n;
  const int piece = s.piece_containing(q);
  if (piece < 0)
    input_error("{}: landmark '{}': its point ({:.4g}, {:.4g}, {:.4g}) m is not inside the fluid "
                "on its plane",
                mesh.source, l.name, q[0], q[1], q[2]);
  return s.areas[piece];
}

double tear_area(const mesh::Mesh& mesh, const TearLandmark& t) {
  const Section s = cut_region(mesh, region_index(mesh, "fluid"), t.centroid, t.normal);
  const int piece = s.piece_containing(t.centroid);
  if (piece < 0)
    input_error("{}: tear '{}': its centroid is not in the fluid (is the tear open?)", mesh.source,
                t.name);
  return s.areas[piece];
}

std::vector<int> fluid_components(const mesh::Mesh& mesh, const std::vector<char>& removed) {
  const int fluid = region_index(mesh, "fluid");
  std::vector<char> keep(mesh.tets.size());
  for (std::size_t t = 0; t < keep.size(); ++t)
    keep[t] = mesh.tet_region[t] == fluid && (removed.empty() || !removed[t]);
  UnionFind uf(mesh.tets.size());
  for (const auto& [a, b] : face_neighbours(mesh, keep))
    uf.join(a, b);
  std::vector<int> component(mesh.tets.size(), -1), id_of_root(mesh.tets.size(), -1);
  int next = 0;
  for (std::size_t t = 0; t < keep.size(); ++t)
    if (keep[t]) {
      int& id = id_of_root[uf.find(static_cast<int>(t))];
      if (id < 0)
        id = next++;
      component[t] = id;
    }
  return component;
}

Index locate(const mesh::Mesh& mesh, const Vec3& p, int region) {
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (region >= 0 && mesh.tet_region[t] != region)
      continue;
    const Tet& k = mesh.tets[t];
    const Vec3 &a = mesh.points[k[0]], &b = mesh.points[k[1]], &c = mesh.points[k[2]],
               &d = mesh.points[k[3]];
    const double v = mesh::signed_volume(a, b, c, d);
    const double tol = -1e-10 * std::abs(v);
    if (mesh::signed_volume(p, b, c, d) >= tol && mesh::signed_volume(a, p, c, d) >= tol &&
        mesh::signed_volume(a, b, p, d) >= tol && mesh::signed_volume(a, b, c, p) >= tol)
      return static_cast<Index>(t);
  }
  return -1;
}

std::vector<char> tear_region(const mesh::Mesh& mesh, const TearLandmark& t, double scale) {
  const int fluid = region_index(mesh, "fluid");
  const Vec3 n = unit(t.normal), ax = unit(t.axis), ac = cross(n, ax);
  std::vector<char> marked(mesh.tets.size(), 0);
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) {
    if (mesh.tet_region[i] != fluid)
      continue;
    std::array<Vec3, 4> x;
    std::array<double, 4> d;
    int up = 0;
    for (int j = 0; j < 4; ++j) {
      x[j] = mesh.points[mesh.tets[i][j]];
      d[j] = dot(x[j] - t.centroid, n);
      up += above(d[j]);
    }
    if (up == 0 || up == 4)
      continue;
    Vec3 c{0, 0, 0};
    const std::vector<Vec3> poly = cut_polygon(x, d, n);
    for (const Vec3& v : poly)
      c = c + (1.0 / static_cast<double>(poly.size())) * v;
    const double u = dot(c - t.centroid, ax) / t.axial, w = dot(c - t.centroid, ac) / t.across;
    marked[i] = u * u + w * w <= scale * scale;
  }
  return marked;
}

} // namespace tearflow::geometry
