#include "mesh/merge.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.hpp"
#include "mesh/point_grid.hpp"

namespace tearflow::mesh {

Mesh merge_fluid_and_wall(const Mesh& fluid, const Mesh& wall) {
  const std::string sources =
      fmt::format("fluid mesh {} and wall mesh {}", fluid.source, wall.source);
  Vec3 lo = fluid.points.front(), hi = lo;
  for (const Vec3& x : fluid.points)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], x[c]);
      hi[c] = std::max(hi[c], x[c]);
    }
  const Vec3 extent = hi - lo;
  const double tol = 1e-9 * std::sqrt(dot(extent, extent));

  Mesh out;
  out.source = fmt::format("{} + {}", fluid.source, wall.source);
  out.points = fluid.points;
  out.regions = {"fluid", "wall"};
  out.tets = fluid.tets;
  out.tet_region.assign(fluid.tets.size(), 0);
  out.faces = fluid.faces;

  const PointGrid grid(fluid.points, 1e3 * tol);
  std::vector<Index> wall_to_out(wall.points.size());
  std::vector<unsigned char> matched(fluid.points.size(), 0);
  size_t shared = 0;
  for (size_t i = 0; i < wall.points.size(); ++i) {
    const Index f = grid.find(wall.points[i], tol);
    if (f >= 0) {
      wall_to_out[i] = f;
      matched[f] = 1;
      ++shared;
    } else {
      wall_to_out[i] = static_cast<Index>(out.points.size());
      out.points.push_back(wall.points[i]);
    }
  }
  if (shared == 0)
    input_error("{}: the meshes share no node, so the wall is not attached to the fluid; the "
                "interface nodes must coincide (same units, same coordinates)",
                sources);
  for (size_t e = 0; e < wall.tets.size(); ++e) {
    Tet t;
    for (int a = 0; a < 4; ++a)
      t[a] = wall_to_out[wall.tets[e][a]];
    out.tets.push_back(t);
    out.tet_region.push_back(1);
  }
  for (const Face& f : wall.faces) {
    if (fluid.has_face(f.name))
      input_error("{}: face '{}' is in both meshes; face names must be unique", sources, f.name);
    Face g{f.name, {}};
    for (const Tri& t : f.triangles)
      g.triangles.push_back({wall_to_out[t[0]], wall_to_out[t[1]], wall_to_out[t[2]]});
    out.faces.push_back(std::move(g));
  }
  // Interface triangles: faces of wall tets made of fluid nodes only that bound a fluid tet.
  // A named face with some triangles on the interface and some not is an interface whose
  // nodes coincide only in part.
  auto sorted = [](Index a, Index b, Index c) {
    std::array<Index, 3> t{a, b, c};
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<std::array<Index, 3>> wall_faces;
  for (size_t e = fluid.tets.size(); e < out.tets.size(); ++e) {
    const Tet& t = out.tets[e];
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Index, 3> f{};
      for (int a = 0, k = 0; a < 4; ++a)
        if (a != skip)
          f[k++] = t[a];
      wall_faces.push_back(sorted(f[0], f[1], f[2]));
    }
  }
  std::sort(wall_faces.begin(), wall_faces.end());
  size_t interface = 0;
  for (const Face& f : fluid.faces) {
    size_t on = 0;
    for (const Tri& t : f.triangles)
      on += std::binary_search(wall_faces.begin(), wall_faces.end(), sorted(t[0], t[1], t[2]));
    if (on > 0 && on < f.triangles.size())
      input_error("{}: {} of the {} triangles of face '{}' lie on the wall and the others do "
                  "not: the interface nodes of the two meshes coincide only in part",
                  sources, on, f.triangles.size(), f.name);
    interface += on;
  }
  if (interface == 0)
    input_error("{}: the meshes share {} nodes but no face of the fluid lies on the wall; the "
                "interface must be a named face of the fluid mesh whose nodes coincide with the "
                "wall's",
                sources, shared);
  check_mesh(out);
  return out;
}

} // namespace tearflow::mesh
