#include "geometry/boundary_layers.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include <fmt/ranges.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>

#include "core/error.hpp"
#include "geometry/fsi_mesh.hpp"

namespace tearflow::geometry {

namespace {

constexpr double kMm = 1e3;
// The smallest cosine between a wall node's layer direction and the inward normal of a wall
// triangle at it: below, the prisms there would be nearly flat (a fold sharper than ~160 deg).
constexpr double kMinCosine = 0.15;
// Neighbouring wall nodes' layer thicknesses differ by at most this times their distance.
constexpr double kThicknessSlope = 0.3;
// Rings of the region's nodes, counted from the wall, that make room for the layers; beyond
// them nothing moves.
constexpr int kBand = 6;

Vec3 normalized(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}
double norm(const Vec3& v) {
  return std::sqrt(dot(v, v));
}
std::string at_mm(const Vec3& x) {
  return fmt::format("({:.1f}, {:.1f}, {:.1f}) mm", x[0] * kMm, x[1] * kMm, x[2] * kMm);
}

Tri sorted(Tri t) {
  std::sort(t.begin(), t.end());
  return t;
}

/// The region's boundary triangles, outward, sorted into wall and caps (a face index each).
struct RegionBoundary {
  std::vector<Tri> wall;
  std::vector<std::pair<Tri, int>> caps;
};

RegionBoundary region_boundary(const mesh::Mesh& m, int region,
                               const std::vector<std::string>& walls) {
  std::map<Tri, std::pair<int, Tri>> faces; // sorted -> (count, outward)
  for (std::size_t e = 0; e < m.tets.size(); ++e) {
    if (m.tet_region[e] != region)
      continue;
    const Tet& t = m.tets[e];
    for (int skip = 0; skip < 4; ++skip) {
      Tri f = face_opposite(t, skip);
      const Vec3 &a = m.points[f[0]], &b = m.points[f[1]], &c = m.points[f[2]];
      if (dot(cross(b - a, c - a), m.points[t[skip]] - a) > 0)
        std::swap(f[1], f[2]); // outward: the opposite node behind
      auto [it, fresh] = faces.try_emplace(sorted(f), 0, f);
      ++it->second.first;
    }
  }
  std::map<Tri, int> named;
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (const Tri& t : m.faces[f].triangles)
      named.emplace(sorted(t), static_cast<int>(f));
  RegionBoundary out;
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1)
      continue;
    const auto it = named.find(key);
    if (it == named.end())
      input_error("{}: boundary layers: a boundary triangle of the flow region at {} belongs to "
                  "no named face",
                  m.source, at_mm(m.points[key[0]]));
    const std::string& name = m.faces[static_cast<std::size_t>(it->second)].name;
    if (std::find(walls.begin(), walls.end(), name) != walls.end())
      out.wall.push_back(entry.second);
    else
      out.caps.push_back({entry.second, it->second});
  }
  return out;
}

/// A cap's plane: outward unit normal and a point on it.
struct Plane {
  Vec3 normal{}, point{};
};

/// The rings of the region's nodes from the wall (0 on it; -1 beyond kBand), and for each
/// node the wall node it was reached from.
struct Rings {
  std::vector<int> ring;
  std::vector<Index> source;
};

/// Node adjacency of the region's tets (compressed rows).
struct Adjacency {
  std::vector<std::size_t> start;
  std::vector<Index> next;
};

Adjacency adjacency(const mesh::Mesh& m, int region) {
  std::vector<std::set<Index>> sets(m.points.size());
  for (std::size_t e = 0; e < m.tets.size(); ++e)
    if (m.tet_region[e] == region)
      for (Index a : m.tets[e])
        for (Index b : m.tets[e])
          if (a != b)
            sets[a].insert(b);
  Adjacency g;
  g.start.push_back(0);
  for (const auto& s : sets) {
    g.next.insert(g.next.end(), s.begin(), s.end());
    g.start.push_back(g.next.size());
  }
  return g;
}

Rings rings(const Adjacency& g, const std::vector<int>& wall_id) {
  Rings r{std::vector<int>(wall_id.size(), -1), std::vector<Index>(wall_id.size(), -1)};
  std::vector<Index> front;
  for (std::size_t v = 0; v < wall_id.size(); ++v)
    if (wall_id[v] >= 0) {
      r.ring[v] = 0;
      r.source[v] = static_cast<Index>(v);
      front.push_back(static_cast<Index>(v));
    }
  for (int k = 1; k <= kBand; ++k) {
    std::vector<Index> next;
    for (Index v : front)
      for (std::size_t j = g.start[v]; j < g.start[v + 1]; ++j)
        if (const Index w = g.next[j]; r.ring[w] < 0) {
          r.ring[w] = k;
          r.source[w] = r.source[v];
          next.push_back(w);
        }
    front = std::move(next);
  }
  return r;
}

/// Distance along `direction` from x to the first boundary triangle, or `far` for none.
class RayCaster {
public:
  RayCaster(const mesh::Mesh& m, const RegionBoundary& b) {
    auto points = vtkSmartPointer<vtkPoints>::New();
    for (const Vec3& x : m.points)
      points->InsertNextPoint(x.data());
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    auto add = [&](const Tri& t) {
      const vtkIdType ids[3] = {t[0], t[1], t[2]};
      cells->InsertNextCell(3, ids);
    };
    for (const Tri& t : b.wall)
      add(t);
    for (const auto& [t, f] : b.caps)
      add(t);
    surface_ = vtkSmartPointer<vtkPolyData>::New();
    surface_->SetPoints(points);
    surface_->SetPolys(cells);
    locator_ = vtkSmartPointer<vtkStaticCellLocator>::New();
    locator_->SetDataSet(surface_);
    locator_->BuildLocator();
    double bounds[6];
    surface_->GetBounds(bounds);
    far_ = std::hypot(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]);
  }
  double distance(const Vec3& x, const Vec3& direction, double start) const {
    const Vec3 p0 = x + start * direction, p1 = x + far_ * direction;
    double t = 0, hit[3], pcoords[3];
    int sub = 0;
    vtkIdType cell = -1;
    double a[3] = {p0[0], p0[1], p0[2]}, b[3] = {p1[0], p1[1], p1[2]};
    if (locator_->IntersectWithLine(a, b, 0.0, t, hit, pcoords, sub, cell) == 0)
      return far_;
    return start + t * (far_ - start);
  }

private:
  vtkSmartPointer<vtkPolyData> surface_;
  vtkSmartPointer<vtkStaticCellLocator> locator_;
  double far_ = 1.0;
};

/// The three tetrahedra of a prism (bottom 0 1 2, top 3 4 5 above them, (0,1,2,3) positive)
/// by Dompierre et al.'s rule: rotate the smallest index to vertex 0, then cut the opposite
/// quadrilateral through its smallest index.
std::array<Tet, 3> split_prism(const std::array<Index, 6>& p) {
  static constexpr int rotation[6][6] = {{0, 1, 2, 3, 4, 5}, {1, 2, 0, 4, 5, 3},
                                         {2, 0, 1, 5, 3, 4}, {3, 5, 4, 0, 2, 1},
                                         {4, 3, 5, 1, 0, 2}, {5, 4, 3, 2, 1, 0}};
  const int m = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
  std::array<Index, 6> v;
  for (int i = 0; i < 6; ++i)
    v[i] = p[rotation[m][i]];
  if (std::min(v[1], v[5]) < std::min(v[2], v[4]))
    return {Tet{v[0], v[1], v[2], v[5]}, Tet{v[0], v[1], v[5], v[4]}, Tet{v[0], v[4], v[5], v[3]}};
  return {Tet{v[0], v[1], v[2], v[4]}, Tet{v[0], v[4], v[2], v[5]}, Tet{v[0], v[4], v[5], v[3]}};
}

/// A quadrilateral (cyclic p0..p3) as two triangles cut through its smallest index, as the
/// prisms beside it are.
std::array<Tri, 2> split_quad(const std::array<Index, 4>& p) {
  const int m = static_cast<int>(std::min_element(p.begin(), p.end()) - p.begin());
  const Index a = p[m], b = p[(m + 1) % 4], c = p[(m + 2) % 4], d = p[(m + 3) % 4];
  return {Tri{a, b, c}, Tri{a, c, d}};
}

} // namespace

double BoundaryLayerSpec::thickness() const {
  return growth == 1.0 ? count * first : first * (std::pow(growth, count) - 1.0) / (growth - 1.0);
}

mesh::Mesh add_boundary_layers(const mesh::Mesh& m, const std::string& region_name,
                               const std::vector<std::string>& walls, const BoundaryLayerSpec& spec,
                               BoundaryLayerReport* report) {
  if (spec.count < 1 || !(spec.first > 0) || !(spec.growth >= 1.0 && spec.growth <= 3.0) ||
      !(spec.max_fraction > 0 && spec.max_fraction < 0.5))
    input_error("boundary layers: count {} (>= 1), first layer {} mm (> 0), growth {} (1 to 3) "
                "and max_fraction {} (0 to 0.5) are not all in range",
                spec.count, spec.first * kMm, spec.growth, spec.max_fraction);
  const auto region_it = std::find(m.regions.begin(), m.regions.end(), region_name);
  if (region_it == m.regions.end())
    input_error("{}: boundary layers: no region '{}'", m.source, region_name);
  const int region = static_cast<int>(region_it - m.regions.begin());
  const RegionBoundary boundary = region_boundary(m, region, walls);
  if (boundary.wall.empty())
    input_error("{}: boundary layers: none of the faces {} bounds region '{}'", m.source,
                fmt::join(walls, ", "), region_name);
  const std::size_t n0 = m.points.size();
  const int N = spec.count;

  // Wall nodes and their inward normals: the wall triangles' normals weighted by their angle
  // at the node.
  std::vector<int> wall_id(n0, -1);
  std::vector<Index> wall_nodes;
  for (const Tri& t : boundary.wall)
    for (Index v : t)
      if (wall_id[v] < 0) {
        wall_id[v] = static_cast<int>(wall_nodes.size());
        wall_nodes.push_back(v);
      }
  const std::size_t W = wall_nodes.size();
  std::vector<Vec3> normal(W, Vec3{});
  std::vector<double> edge(W, 1e300); // shortest wall edge at the node
  for (const Tri& t : boundary.wall) {
    const Vec3 n =
        normalized(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
    for (int i = 0; i < 3; ++i) {
      const Vec3 e1 = m.points[t[(i + 1) % 3]] - m.points[t[i]];
      const Vec3 e2 = m.points[t[(i + 2) % 3]] - m.points[t[i]];
      const double angle = std::acos(std::clamp(dot(e1, e2) / (norm(e1) * norm(e2)), -1.0, 1.0));
      const int w = wall_id[t[i]];
      normal[w] = normal[w] - angle * n;
      edge[w] = std::min({edge[w], norm(e1), norm(e2)});
    }
  }
  for (Vec3& n : normal)
    n = normalized(n);

  // Caps: planar; the wall's nodes on a cap's rim move in its plane.
  std::map<int, Plane> planes;
  {
    std::map<int, std::pair<Vec3, Vec3>> sums; // area-weighted normal, centroid sum
    std::map<int, double> areas;
    for (const auto& [t, f] : boundary.caps) {
      const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &c = m.points[t[2]];
      const Vec3 n2 = cross(b - a, c - a);
      sums[f].first = sums[f].first + 0.5 * n2;
      sums[f].second = sums[f].second + (norm(n2) / 6.0) * (a + b + c);
      areas[f] += 0.5 * norm(n2);
    }
    for (const auto& [f, s] : sums)
      planes[f] = {normalized(s.first), (1.0 / areas[f]) * s.second};
    for (const auto& [t, f] : boundary.caps)
      for (Index v : t)
        if (std::abs(dot(m.points[v] - planes[f].point, planes[f].normal)) >
            1e-3 * std::sqrt(areas[f]))
          input_error("{}: boundary layers: the cap '{}' is not planar (at {}): the layers' sides "
                      "must lie in a cap's plane",
                      m.source, m.faces[static_cast<std::size_t>(f)].name, at_mm(m.points[v]));
  }
  std::vector<int> cap_of(n0, -1); // per node on a cap: its face
  for (const auto& [t, f] : boundary.caps)
    for (Index v : t) {
      if (cap_of[v] >= 0 && cap_of[v] != f)
        input_error("{}: boundary layers: the caps '{}' and '{}' meet at {}", m.source,
                    m.faces[static_cast<std::size_t>(cap_of[v])].name,
                    m.faces[static_cast<std::size_t>(f)].name, at_mm(m.points[v]));
      cap_of[v] = f;
    }
  for (std::size_t w = 0; w < W; ++w)
    if (const int f = cap_of[wall_nodes[w]]; f >= 0) {
      const Vec3& c = planes[f].normal;
      normal[w] = normalized(normal[w] - dot(normal[w], c) * c);
    }
  // Where the wall folds too sharply for a layer along the averaged normal (the apex of a
  // wedge of fluid, where the flap meets the wall at a shallow angle), the layers end: the
  // wall node keeps no column and the prisms at it collapse to pyramids and tetrahedra.
  std::vector<char> collapsed(W, 0);
  for (const Tri& t : boundary.wall) {
    const Vec3 n =
        normalized(cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]));
    for (Index v : t)
      if (dot(normal[wall_id[v]], -1.0 * n) < kMinCosine)
        collapsed[wall_id[v]] = 1;
  }

  // Total thickness per wall node: at most max_fraction of the lumen across the normal, and
  // slowly varying along the wall (each node at most kThicknessSlope times its distance above
  // a neighbour's).
  const double T = spec.thickness();
  std::vector<double> thickness(W, T);
  {
    const RayCaster rays(m, boundary);
    for (std::size_t w = 0; w < W; ++w) {
      Vec3 x = m.points[wall_nodes[w]];
      if (const int f = cap_of[wall_nodes[w]]; f >= 0) // off the cap, whose plane holds the ray
        x = x - (1e-3 * edge[w]) * planes[f].normal;
      const double across = rays.distance(x, normal[w], 1e-3 * edge[w]);
      thickness[w] = collapsed[w] ? 0.0 : std::min(T, spec.max_fraction * across);
    }
  }
  std::vector<std::set<int>> wall_neighbours(W);
  for (const Tri& t : boundary.wall)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j)
          wall_neighbours[wall_id[t[i]]].insert(wall_id[t[j]]);
  const auto limit_slope = [&] {
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t w = 0; w < W; ++w)
        for (int u : wall_neighbours[w]) {
          const double cap = thickness[u] + kThicknessSlope * norm(m.points[wall_nodes[w]] -
                                                                   m.points[wall_nodes[u]]);
          if (thickness[w] > cap * (1 + 1e-12)) {
            thickness[w] = cap;
            changed = true;
          }
        }
    }
  };
  // Layers thinner than a fifth of the first one end (the lumen pinches to nothing there).
  const auto collapse_thin = [&] {
    for (bool changed = true; changed;) {
      limit_slope();
      changed = false;
      for (std::size_t w = 0; w < W; ++w)
        if (!collapsed[w] && thickness[w] < 0.2 * spec.first) {
          collapsed[w] = 1;
          thickness[w] = 0.0;
          changed = true;
        }
    }
  };
  collapse_thin();

  // The region's nodes near the wall make room by a harmonic displacement (Laplace on the
  // node graph, by over-relaxed Gauss-Seidel), the wall's copies moving by their layers'
  // thickness, caps' nodes in their plane, nodes beyond kBand rings fixed.
  const Adjacency graph = adjacency(m, region);
  const Rings band = rings(graph, wall_id);
  for (std::size_t e = 0; e < m.tets.size(); ++e) // moved nodes must be the region's alone
    if (m.tet_region[e] != region)
      for (Index v : m.tets[e])
        if (band.ring[v] > 0)
          input_error("{}: boundary layers: region '{}' shares the node at {} with region '{}' "
                      "off the wall faces",
                      m.source, region_name, at_mm(m.points[v]),
                      m.regions[static_cast<std::size_t>(m.tet_region[e])]);
  std::vector<Index> free_nodes;
  for (std::size_t v = 0; v < n0; ++v)
    if (band.ring[v] > 0)
      free_nodes.push_back(static_cast<Index>(v));

  const auto column = [&](Index v, int k) -> Index {
    return k == 0 || collapsed[wall_id[v]]
               ? v
               : static_cast<Index>(n0 + static_cast<std::size_t>(wall_id[v]) * N + (k - 1));
  };
  const auto degenerate = [](const auto& cell) {
    for (std::size_t i = 0; i < cell.size(); ++i)
      for (std::size_t j = i + 1; j < cell.size(); ++j)
        if (cell[i] == cell[j])
          return true;
    return false;
  };
  std::vector<double> fraction(N + 1); // of the total thickness, layer by layer
  for (int k = 0; k <= N; ++k)
    fraction[k] = spec.growth == 1.0
                      ? double(k) / N
                      : (std::pow(spec.growth, k) - 1.0) / (std::pow(spec.growth, N) - 1.0);

  mesh::Mesh out;
  std::vector<Vec3> displacement(n0, Vec3{});
  int sweeps = 0;
  for (int round = 0;; ++round) {
    // Displacement: wall copies fixed at their thickness, the band relaxed.
    std::fill(displacement.begin(), displacement.end(), Vec3{});
    double largest = 0.0;
    for (std::size_t w = 0; w < W; ++w) {
      displacement[wall_nodes[w]] = thickness[w] * normal[w];
      largest = std::max(largest, thickness[w]);
    }
    constexpr double omega = 1.6;
    for (sweeps = 1; sweeps <= 2000; ++sweeps) {
      double change = 0.0;
      for (Index v : free_nodes) {
        Vec3 mean{};
        const std::size_t a = graph.start[v], b = graph.start[v + 1];
        for (std::size_t j = a; j < b; ++j)
          mean = mean + displacement[graph.next[j]];
        mean = (1.0 / static_cast<double>(b - a)) * mean;
        Vec3 d = (1.0 - omega) * displacement[v] + omega * mean;
        if (const int f = cap_of[v]; f >= 0)
          d = d - dot(d, planes[f].normal) * planes[f].normal;
        change = std::max(change, norm(d - displacement[v]));
        displacement[v] = d;
      }
      if (change < 1e-4 * largest)
        break;
    }

    // The new mesh: nodes (the region's moved, the columns appended), tets, faces.
    out = mesh::Mesh{};
    out.source = m.source;
    out.regions = m.regions;
    out.points = m.points;
    for (Index v : free_nodes)
      out.points[v] = out.points[v] + displacement[v];
    out.points.resize(n0 + W * static_cast<std::size_t>(N));
    for (std::size_t w = 0; w < W; ++w)
      for (int k = 1; k <= N; ++k)
        out.points[column(wall_nodes[w], k)] =
            m.points[wall_nodes[w]] + (thickness[w] * fraction[k]) * normal[w];
    std::vector<char> bad(W, 0);
    const auto volume = [&](const Tet& t) {
      return mesh::signed_volume(out.points[t[0]], out.points[t[1]], out.points[t[2]],
                                 out.points[t[3]]);
    };
    for (std::size_t e = 0; e < m.tets.size(); ++e) {
      Tet t = m.tets[e];
      if (m.tet_region[e] == region) {
        const double before =
            mesh::signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
        for (Index& v : t)
          if (wall_id[v] >= 0)
            v = column(v, N);
        if (volume(t) < 0.05 * before) // inverted, or squeezed flat: thinner layers near it
          for (Index v : m.tets[e])
            if (band.source[v] >= 0)
              bad[wall_id[band.source[v]]] = 1;
      }
      out.tets.push_back(t);
      out.tet_region.push_back(m.tet_region[e]);
    }
    for (const Tri& t : boundary.wall) // outward (a, b, c): (a, c, b) and a column on top
      for (int k = 0; k < N; ++k) {
        const std::array<Index, 6> prism{column(t[0], k),     column(t[2], k),
                                         column(t[1], k),     column(t[0], k + 1),
                                         column(t[2], k + 1), column(t[1], k + 1)};
        for (const Tet& tet : split_prism(prism)) {
          if (degenerate(tet)) // at a collapsed column: the prism is a pyramid or a tet
            continue;
          if (volume(tet) <= 0)
            for (Index v : t)
              bad[wall_id[v]] = 1;
          out.tets.push_back(tet);
          out.tet_region.push_back(region);
        }
      }
    const std::size_t flagged = static_cast<std::size_t>(std::count(bad.begin(), bad.end(), 1));
    if (flagged == 0)
      break;
    if (round == 12)
      input_error("{}: boundary layers: {} wall nodes still have inverted elements after "
                  "thinning their layers twelve times (e.g. at {}); fewer or thinner layers",
                  m.source, flagged,
                  at_mm(m.points[wall_nodes[std::find(bad.begin(), bad.end(), 1) - bad.begin()]]));
    for (std::size_t w = 0; w < W; ++w)
      if (bad[w]) {
        thickness[w] *= 0.5;
        for (int u : wall_neighbours[w])
          thickness[u] = std::min(thickness[u], thickness[w] * 1.5);
      }
    collapse_thin();
  }

  // Faces: the wall's and other regions' as they were; a cap's triangles on the moved nodes,
  // with the layers' sides where the cap meets the wall.
  std::map<std::pair<Index, Index>, int> cap_edges; // rim edges of caps -> face
  for (const auto& [t, f] : boundary.caps)
    for (int i = 0; i < 3; ++i)
      if (wall_id[t[i]] >= 0 && wall_id[t[(i + 1) % 3]] >= 0)
        cap_edges[{std::min(t[i], t[(i + 1) % 3]), std::max(t[i], t[(i + 1) % 3])}] = f;
  std::set<Tri> cap_triangles;
  for (const auto& [t, f] : boundary.caps)
    cap_triangles.insert(sorted(t));
  out.faces = m.faces;
  for (std::size_t f = 0; f < out.faces.size(); ++f) {
    for (Tri& t : out.faces[f].triangles)
      if (cap_triangles.count(sorted(t)))
        for (Index& v : t)
          if (wall_id[v] >= 0)
            v = column(v, N);
  }
  for (const Tri& t : boundary.wall)
    for (int i = 0; i < 3; ++i) {
      const Index a = t[i], b = t[(i + 1) % 3];
      const auto it = cap_edges.find({std::min(a, b), std::max(a, b)});
      if (it == cap_edges.end())
        continue;
      const Vec3& c = planes[it->second].normal;
      for (int k = 0; k < N; ++k)
        for (Tri s : split_quad({column(a, k), column(b, k), column(b, k + 1), column(a, k + 1)})) {
          if (degenerate(s))
            continue;
          const Vec3 n =
              cross(out.points[s[1]] - out.points[s[0]], out.points[s[2]] - out.points[s[0]]);
          if (dot(n, c) < 0)
            std::swap(s[1], s[2]);
          out.faces[static_cast<std::size_t>(it->second)].triangles.push_back(s);
        }
    }

  if (report) {
    report->wall_nodes = W;
    report->tets_added = out.tets.size() - m.tets.size();
    report->thinnest = *std::min_element(thickness.begin(), thickness.end());
    report->thickest = *std::max_element(thickness.begin(), thickness.end());
    report->thinned = static_cast<std::size_t>(
        std::count_if(thickness.begin(), thickness.end(), [&](double t) { return t < 0.999 * T; }));
    report->ended = static_cast<std::size_t>(std::count(collapsed.begin(), collapsed.end(), 1));
    report->displacement_sweeps = sweeps;
  }
  return out;
}

} // namespace tearflow::geometry
