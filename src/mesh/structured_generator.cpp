#include "mesh/structured_generator.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "mesh/orient_faces.hpp"

namespace tearflow::mesh {

namespace {

/// A logical grid of (ni x nj x nk) cells, optionally periodic in j, mapped by `map`.
template <typename Map>
Mesh grid_mesh(std::array<int, 3> n, bool periodic_j, Map map,
               const std::array<std::array<std::string, 2>, 3>& side_names, std::string source) {
  const int nj_nodes = periodic_j ? n[1] : n[1] + 1;
  auto node = [&](int i, int j, int k) {
    j = periodic_j ? j % n[1] : j;
    return static_cast<Index>((k * nj_nodes + j) * (n[0] + 1) + i);
  };
  Mesh m;
  m.source = std::move(source);
  std::vector<std::array<int, 3>> ijk;
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j < nj_nodes; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        m.points.push_back(map(i, j, k));
        ijk.push_back({i, j, k});
      }
  // Kuhn split: one tet per permutation of the axes, from corner (0,0,0) to (1,1,1).
  constexpr std::array<std::array<int, 3>, 6> perms{
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c{i, j, k};
          Tet t;
          t[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            t[s + 1] = node(c[0], c[1], c[2]);
          }
          const auto& x = m.points;
          if (signed_volume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]) < 0.0)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
        }
  m.tet_region.assign(m.tets.size(), 0);
  m.regions = {"solid"};

  // Boundary triangles: those of exactly one tet, named by the grid side all three lie on.
  std::map<std::array<Index, 3>, int> count;
  for (const Tet& t : m.tets)
    for (int f = 0; f < 4; ++f) {
      std::array<Index, 3> tri{t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]};
      std::sort(tri.begin(), tri.end());
      ++count[tri];
    }
  std::map<std::string, std::vector<Tri>> sides;
  for (const auto& [tri, c] : count) {
    if (c != 1)
      continue;
    for (int d = 0; d < 3; ++d)
      for (int s = 0; s < 2; ++s) {
        const int at = s == 0 ? 0 : n[d];
        if (std::all_of(tri.begin(), tri.end(), [&](Index v) { return ijk[v][d] == at; }) &&
            !side_names[d][s].empty())
          sides[side_names[d][s]].push_back({tri[0], tri[1], tri[2]});
      }
  }
  for (auto& [name, tris] : sides)
    m.faces.push_back({name, std::move(tris)});
  orient_faces_outward(m);
  check_mesh(m);
  return m;
}

} // namespace

Mesh make_box(const Vec3& lengths, const std::array<int, 3>& cells) {
  for (int d = 0; d < 3; ++d)
    if (!(lengths[d] > 0.0) || cells[d] < 1)
      input_error("box: lengths must be > 0 and cell counts >= 1 (axis {}: {} m, {} cells)", d,
                  lengths[d], cells[d]);
  auto map = [&](int i, int j, int k) {
    return Vec3{lengths[0] * i / cells[0], lengths[1] * j / cells[1], lengths[2] * k / cells[2]};
  };
  return grid_mesh(cells, false, map, {{{"x0", "x1"}, {"y0", "y1"}, {"z0", "z1"}}}, "built-in box");
}

Mesh make_annulus(const AnnulusSpec& s) {
  if (!(s.inner_radius > 0.0) || !(s.outer_radius > s.inner_radius) || !(s.length > 0.0) ||
      !(s.angle > 0.0) || s.angle > 2.0 * std::numbers::pi + 1e-12 || s.cells[0] < 1 ||
      s.cells[1] < 3 || s.cells[2] < 1)
    input_error("annulus: need 0 < inner radius < outer radius, length > 0, 0 < angle <= 2 pi, "
                "cells >= (1, 3, 1); got a = {} m, b = {} m, length {} m, angle {} rad",
                s.inner_radius, s.outer_radius, s.length, s.angle);
  const bool closed = s.angle > 2.0 * std::numbers::pi - 1e-9;
  auto map = [&](int i, int j, int k) {
    const double r = s.inner_radius + (s.outer_radius - s.inner_radius) * i / s.cells[0];
    const double th = s.angle * j / s.cells[1];
    return Vec3{r * std::cos(th), r * std::sin(th), s.length * k / s.cells[2]};
  };
  const std::string theta0 = closed ? "" : "theta0", theta1 = closed ? "" : "theta1";
  return grid_mesh(s.cells, closed, map, {{{"inner", "outer"}, {theta0, theta1}, {"z0", "z1"}}},
                   "built-in annulus");
}

} // namespace tearflow::mesh
