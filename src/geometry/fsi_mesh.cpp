#include "geometry/fsi_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <system_error>

#include <gmsh.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"

namespace tearflow::geometry {

namespace {

// Same bound as mesh::check_mesh: V below 1e-6 l_max^3 is flat to storage precision.
constexpr double kMinRelativeVolume = 1e-6;

struct TetFace {
  Tri nodes; // sorted
  Index tet;
  bool operator<(const TetFace& o) const {
    return nodes != o.nodes ? nodes < o.nodes : tet < o.tet;
  }
};

std::vector<TetFace> sorted_tet_faces(const mesh::Mesh& m, const std::vector<char>& keep) {
  std::vector<TetFace> faces;
  faces.reserve(4 * m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (!keep.empty() && !keep[t])
      continue;
    const Tet& k = m.tets[t];
    for (int skip = 0; skip < 4; ++skip) {
      Tri f = face_opposite(k, skip);
      std::sort(f.begin(), f.end());
      faces.push_back({f, static_cast<Index>(t)});
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// The tets having triangle `tri` as a face.
std::vector<Index> tets_of(const std::vector<TetFace>& faces, Tri tri) {
  std::sort(tri.begin(), tri.end());
  auto it = std::lower_bound(faces.begin(), faces.end(), TetFace{tri, -1});
  std::vector<Index> out;
  for (; it != faces.end() && it->nodes == tri; ++it)
    out.push_back(it->tet);
  return out;
}

} // namespace

double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double v = std::abs(mesh::signed_volume(a, b, c, d));
  auto area = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 n = cross(q - p, r - p);
    return 0.5 * std::sqrt(dot(n, n));
  };
  const double faces = area(a, b, c) + area(a, b, d) + area(a, c, d) + area(b, c, d);
  auto len = [](const Vec3& p, const Vec3& q) { return std::sqrt(dot(q - p, q - p)); };
  // Products of opposite edge lengths; the circumradius is sqrt of Heron's product / 24 V.
  const double p = len(a, b) * len(c, d), q = len(a, c) * len(b, d), r = len(a, d) * len(b, c);
  const double heron = (p + q + r) * (p + q - r) * (p - q + r) * (-p + q + r);
  if (!(v > 0) || !(heron > 0))
    return 0;
  const double r_in = 3 * v / faces, r_circ = std::sqrt(heron) / (24 * v);
  return 3 * r_in / r_circ;
}

std::vector<std::pair<Index, Index>> face_neighbours(const mesh::Mesh& m,
                                                     const std::vector<char>& keep) {
  const std::vector<TetFace> faces = sorted_tet_faces(m, keep);
  std::vector<std::pair<Index, Index>> pairs;
  for (std::size_t i = 0; i + 1 < faces.size(); ++i)
    if (faces[i].nodes == faces[i + 1].nodes)
      pairs.push_back({faces[i].tet, faces[i + 1].tet});
  return pairs;
}

MeshReport check_fsi_mesh(const mesh::Mesh& m) {
  const auto fluid_it = std::find(m.regions.begin(), m.regions.end(), "fluid");
  if (fluid_it == m.regions.end() || m.tets.empty())
    input_error("{}: no region 'fluid' (regions: {})", m.source, m.regions.size());
  if (m.tet_region.size() != m.tets.size())
    input_error("{}: {} region tags for {} tets", m.source, m.tet_region.size(), m.tets.size());
  const int fluid = static_cast<int>(fluid_it - m.regions.begin());
  MeshReport report;
  report.regions.resize(m.regions.size());
  for (std::size_t r = 0; r < m.regions.size(); ++r) {
    report.regions[r].name = m.regions[r];
    report.regions[r].min_quality = 1;
  }
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const Tet& k = m.tets[t];
    for (Index n : k)
      if (n < 0 || n >= m.num_nodes())
        input_error("{}: tet {} refers to node {}, expected 0 to {}", m.source, t, n,
                    m.num_nodes() - 1);
    const Vec3 &a = m.points[k[0]], &b = m.points[k[1]], &c = m.points[k[2]], &d = m.points[k[3]];
    const double v = mesh::signed_volume(a, b, c, d);
    double l2 = 0;
    for (const Vec3& e : {b - a, c - a, d - a, c - b, d - b, d - c})
      l2 = std::max(l2, dot(e, e));
    if (!(v > kMinRelativeVolume * l2 * std::sqrt(l2)))
      input_error("{}: {} element: tet {} (nodes {} {} {} {}) in region '{}' has volume {:.4g} "
                  "m^3",
                  m.source, v < 0 ? "inverted" : "degenerate", t, k[0], k[1], k[2], k[3],
                  m.regions[m.tet_region[t]], v);
    RegionQuality& q = report.regions[m.tet_region[t]];
    const double rho = radius_ratio(a, b, c, d);
    ++q.tets;
    q.volume += v;
    q.mean_quality += rho;
    q.min_quality = std::min(q.min_quality, rho);
    q.below_0_1 += rho < 0.1;
  }
  for (RegionQuality& q : report.regions)
    q.mean_quality /= std::max<std::size_t>(q.tets, 1);

  const std::vector<TetFace> faces = sorted_tet_faces(m, {});
  std::set<std::string> names;
  std::set<Index> interface_nodes;
  for (const mesh::Face& f : m.faces) {
    if (f.name.empty() || !names.insert(f.name).second)
      input_error("{}: face name '{}' is empty or used twice", m.source, f.name);
    if (f.triangles.empty())
      input_error("{}: face '{}' has no triangles", m.source, f.name);
    const bool interface = f.name == "interface";
    for (std::size_t i = 0; i < f.triangles.size(); ++i) {
      const Tri& tri = f.triangles[i];
      const std::vector<Index> tets = tets_of(faces, tri);
      const int fluid_tets = static_cast<int>(std::count_if(
          tets.begin(), tets.end(), [&](Index t) { return m.tet_region[t] == fluid; }));
      const bool ok = interface ? tets.size() == 2 && fluid_tets == 1 : tets.size() == 1;
      if (!ok && !interface && tets.size() == 2 && fluid_tets == 1)
        input_error("{}: face '{}' lies between the fluid and the wall (triangle {}, nodes {} {} "
                    "{}); the face between them must be called 'interface'",
                    m.source, f.name, i, tri[0], tri[1], tri[2]);
      if (!ok)
        input_error("{}: face '{}' triangle {} (nodes {} {} {}) is a face of {} tets ({} fluid); "
                    "expected {}",
                    m.source, f.name, i, tri[0], tri[1], tri[2], tets.size(), fluid_tets,
                    interface ? "one fluid and one wall tet sharing its nodes"
                              : "one (a boundary face)");
      if (interface)
        interface_nodes.insert(tri.begin(), tri.end());
    }
    if (interface)
      report.interface_triangles = f.triangles.size();
  }
  report.interface_nodes = interface_nodes.size();
  return report;
}

mesh::Mesh read_fsi_mesh(const std::filesystem::path& file, double length_scale) {
  const std::string source = "mesh file '" + file.string() + "'";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    input_error("{}: no such file", source);
  mesh::Mesh m;
  {
    mesh::GmshSession session;
    m = mesh::with_gmsh(source, [&] {
      gmsh::clear();
      gmsh::open(file.string());
      return mesh::mesh_from_gmsh_model(length_scale, source);
    });
  }
  mesh::drop_unused_nodes(m);
  check_fsi_mesh(m);
  return m;
}

} // namespace tearflow::geometry
