// Meshing labelled domains through CGAL (geometry/implicit_mesher.hpp): a straight pipe with
// its wall, whose volumes and caps are known, meshed alike twice; a pipe split into two
// channels by a flap with two holes, which must stay open; a plate floating in a pipe, which
// must not be missed; bad domains are refused with clear messages.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/implicit_mesher.hpp"

namespace tearflow::geometry {
namespace {

using ::testing::HasSubstr;
constexpr double kPi = std::numbers::pi;
constexpr double kR = 10e-3, kT = 2e-3, kL = 80e-3; // lumen radius, wall, length [m]

double radial(const Vec3& x) {
  return std::hypot(x[0], x[1]);
}

// The pipe's caps at z = 0 (inlet) and z = L (outlet), reaching 3 mm past the wall; the
// labelling functions run on along z, so that the caps cut them.
ImplicitDomain pipe_domain(std::function<int(const Vec3&)> label) {
  ImplicitDomain d;
  d.label = std::move(label);
  d.centre = {0, 0, kL / 2};
  d.radius = std::hypot(kL / 2, kR + kT) + 5e-3;
  d.caps = {{"inlet", {0, 0, 0}, {0, 0, -1}, kR + kT + 3e-3},
            {"outlet", {0, 0, kL}, {0, 0, 1}, kR + kT + 3e-3}};
  d.source = "test pipe";
  return d;
}

int straight_pipe(const Vec3& x) {
  const double r = radial(x);
  return r < kR ? 1 : r < kR + kT ? 2 : 0;
}

double area(const mesh::Mesh& m, const mesh::Face& f) {
  double a = 0;
  for (const Tri& t : f.triangles) {
    const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    a += 0.5 * std::sqrt(dot(n, n));
  }
  return a;
}

// Components of the tets with keep[t] != 0, joined across shared faces.
int components(const mesh::Mesh& m, const std::vector<char>& keep) {
  std::vector<Index> parent(m.tets.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](Index t) {
    while (parent[t] != t)
      t = parent[t] = parent[parent[t]];
    return t;
  };
  for (const auto& [a, b] : face_neighbours(m, keep))
    parent[root(a)] = root(b);
  int n = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    n += keep[t] && root(static_cast<Index>(t)) == static_cast<Index>(t);
  return n;
}

MeshReport report(const mesh::Mesh& m, double seconds) {
  const MeshReport r = check_fsi_mesh(m);
  for (const RegionQuality& q : r.regions)
    fmt::print("{}: {} tets, {:.1f} mm^3, radius ratio min {:.3f} mean {:.3f}, {} below 0.1\n",
               q.name, q.tets, q.volume * 1e9, q.min_quality, q.mean_quality, q.below_0_1);
  fmt::print("{} nodes, {} interface triangles, {:.1f} s\n", m.num_nodes(), r.interface_triangles,
             seconds);
  return r;
}

TEST(ImplicitMesher, StraightPipeHasItsVolumesCapsAndFaces) {
  ImplicitMeshOptions o;
  o.element_size = 3e-3;
  const auto start = std::chrono::steady_clock::now();
  const ImplicitDomain d = pipe_domain(straight_pipe);
  const mesh::Mesh m = mesh_implicit(d, o);
  const MeshReport r =
      report(m, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());

  for (const char* name :
       {"interface", "inlet", "outlet", "wall_inlet", "wall_outlet", "outer_wall"})
    EXPECT_TRUE(m.has_face(name)) << name;
  EXPECT_EQ(m.faces.size(), 6u);
  // Every boundary facet lies within the facet distance (a tenth of the element size) of
  // the surface, so a region's volume is off by at most its curved surfaces' area times it;
  // the rims' chords (edges of 3 mm on radii of 10 and 12 mm) are off by s^2 / 8R < 0.12 mm,
  // inside the same distance. The caps are planes and add nothing.
  const double fd = o.element_size / 10;
  ASSERT_EQ(r.regions.size(), 2u);
  const double fluid = kPi * kR * kR * kL, wall = kPi * ((kR + kT) * (kR + kT) - kR * kR) * kL;
  EXPECT_NEAR(r.regions[0].volume, fluid, 2 * kPi * kR * kL * fd);
  EXPECT_NEAR(r.regions[1].volume, wall, 2 * kPi * (2 * kR + kT) * kL * fd);
  // Each cap's disc and ring: polygons on the rims, within fd of them all around.
  for (const char* cap : {"inlet", "outlet"}) {
    EXPECT_NEAR(area(m, m.face(cap)), kPi * kR * kR, 2 * kPi * kR * fd) << cap;
    EXPECT_NEAR(area(m, m.face(std::string("wall_") + cap)),
                kPi * ((kR + kT) * (kR + kT) - kR * kR), 2 * kPi * (2 * kR + kT) * fd)
        << cap;
  }
  // The caps lie on their planes, to the bisection's 1e-6 of the bounding sphere's diameter,
  // and point out of the domain, as the other faces do.
  for (const auto& [cap, z, nz] : {std::tuple{"inlet", 0.0, -1.0}, std::tuple{"outlet", kL, 1.0}})
    for (const std::string& name : {std::string(cap), std::string("wall_") + cap})
      for (const Tri& t : m.face(name).triangles) {
        const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
        ASSERT_GT(n[2] * nz, 0) << name;
        for (Index i : t)
          ASSERT_NEAR(m.points[i][2], z, 2e-6 * d.radius) << name;
      }
  for (const char* name : {"interface", "outer_wall"}) // out of the fluid, out of the wall
    for (const Tri& t : m.face(name).triangles) {
      const Vec3 c = (1.0 / 3) * (m.points[t[0]] + m.points[t[1]] + m.points[t[2]]);
      const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
      ASSERT_GT(n[0] * c[0] + n[1] * c[1], 0) << name;
    }
  for (const RegionQuality& q : r.regions)
    EXPECT_GT(q.min_quality, 0.02) << q.name;
  std::vector<char> fluid_tets(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    fluid_tets[t] = m.tet_region[t] == 0;
  EXPECT_EQ(components(m, fluid_tets), 1);

  // Sliver removal stops on bounds and step counts, not CGAL's default time limits.
  const mesh::Mesh again = mesh_implicit(d, o);
  EXPECT_EQ(again.points, m.points);
  EXPECT_EQ(again.tets, m.tets);
}

// A 2 mm plate of wall in the pipe, rounded as a segmentation's distance fields round it:
// everything within 1 mm of its mid-surface, the plane x = 0 for |y| <= reach and
// z0 <= z <= z1 with holes of radius hole_radius around (y, z) = (0, hole) cut out, joined
// to the wall (if it reaches it) with a 1 mm fillet, a smooth minimum of the distances.
struct Plate {
  double reach, z0, z1;
  std::vector<double> holes;
  double hole_radius = 0;
};

int plate_pipe(const Vec3& x, const Plate& p) {
  const double r = radial(x), mm = 1e-3;
  if (r >= kR + kT)
    return 0;
  const double y = x[1], z = x[2];
  const double out_z = std::max({p.z0 - z, z - p.z1, 0.0});
  const double out_y = std::max(std::abs(y) - p.reach, 0.0);
  double in_plane = std::hypot(out_y, out_z); // to the mid-surface's outline
  if (in_plane == 0)
    for (const double hole : p.holes)
      in_plane = std::max(in_plane, p.hole_radius - std::hypot(y, z - hole));
  const double plate = std::hypot(x[0], in_plane) - 1 * mm;
  const double shell = std::max(kR - r, r - (kR + kT));
  const double k = 1 * mm, mix = std::max(k - std::abs(plate - shell), 0.0) / k;
  const double solid = std::min(plate, shell) - mix * mix * k / 4;
  return solid < 0 ? 2 : 1;
}

// Whether some wall tet lies on the axis at z = 40 mm (inside the plate).
bool wall_on_axis_at_40(const mesh::Mesh& m) {
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    Vec3 c{};
    for (Index i : m.tets[t])
      c = c + 0.25 * m.points[i];
    if (m.tet_region[t] == 1 && std::abs(c[0]) < 1e-3 && radial(c) < 3e-3 &&
        std::abs(c[2] - 40e-3) < 3e-3)
      return true;
  }
  return false;
}

// The pipe split along x = 0 by a flap from z = 20 to 60 mm, joined to the wall, with holes
// of 6 mm at z = 30 and 50 mm (radius 4 mm on the mid-surface, less the 1 mm rounding).
int split_pipe(const Vec3& x) {
  static const Plate flap{kR + kT, 21e-3, 59e-3, {30e-3, 50e-3}, 4e-3};
  return plate_pipe(x, flap);
}

TEST(ImplicitMesher, FlapWithHolesKeepsTheChannelsJoinedThroughThem) {
  ImplicitMeshOptions o;
  o.element_size = 2.5e-3;
  const auto start = std::chrono::steady_clock::now();
  const mesh::Mesh m = mesh_implicit(pipe_domain(split_pipe), o);
  const MeshReport r =
      report(m, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  for (const RegionQuality& q : r.regions)
    EXPECT_GT(q.min_quality, 0.02) << q.name;

  std::vector<char> fluid(m.tets.size()), beside_flap(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    Vec3 c{}, lo{1, 1, 1}, hi{-1, -1, -1};
    for (Index i : m.tets[t]) {
      c = c + 0.25 * m.points[i];
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], m.points[i][k]), hi[k] = std::max(hi[k], m.points[i][k]);
    }
    fluid[t] = m.tet_region[t] == 0;
    // Between the flap's ends (rounded from 20 to 21 and 59 to 60 mm).
    beside_flap[t] = fluid[t] && c[2] > 23e-3 && c[2] < 57e-3;
    const bool in_hole = std::abs(c[2] - 30e-3) < 5e-3 || std::abs(c[2] - 50e-3) < 5e-3;
    // Elsewhere along the flap no fluid tet reaches across it.
    if (beside_flap[t] && !in_hole && radial(c) < kR - 1e-3)
      EXPECT_FALSE(lo[0] < -0.5e-3 && hi[0] > 0.5e-3) << "fluid tet " << t << " crosses the flap";
  }
  EXPECT_TRUE(wall_on_axis_at_40(m)) << "no flap";
  EXPECT_EQ(components(m, fluid), 1);
  // Between the flap's ends the channels meet only through the holes.
  EXPECT_EQ(components(m, beside_flap), 1);
}

// A plate 10 mm square and 2 mm thick floating in the lumen, joined to nothing, so that no
// refinement along the surfaces from the rims reaches it: the seeds on its sides must find
// it. (Without them Mesh_3 found such plates by chance, as its cells happened to fall in
// them: at one setting it missed one.)
TEST(ImplicitMesher, AFloatingPlateIsFoundBySeeding) {
  ImplicitMeshOptions o;
  o.element_size = 2.5e-3;
  const auto start = std::chrono::steady_clock::now();
  const mesh::Mesh m = mesh_implicit(pipe_domain([](const Vec3& x) {
                                       static const Plate plate{4e-3, 36e-3, 44e-3, {}};
                                       return plate_pipe(x, plate);
                                     }),
                                     o);
  report(m, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  EXPECT_TRUE(wall_on_axis_at_40(m)) << "no plate";
}

std::string mesh_error(const ImplicitDomain& d) {
  try {
    mesh_implicit(d, {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ImplicitMesher, BadDomainsAreClearErrors) {
  ImplicitDomain d = pipe_domain(straight_pipe);
  d.caps[1].radius = 8e-3;
  EXPECT_THAT(mesh_error(d), HasSubstr("test pipe: cap 'outlet' does not reach past the vessel"));

  d = pipe_domain([](const Vec3& x) { return straight_pipe(x) == 2 ? 3 : straight_pipe(x); });
  EXPECT_THAT(mesh_error(d), HasSubstr("label 3 at"));

  d = pipe_domain([](const Vec3& x) { return radial(x) < kR ? 1 : 0; });
  EXPECT_THAT(mesh_error(d), HasSubstr("no wall (label 2) found"));

  d = pipe_domain(straight_pipe);
  d.caps[0].centre = {0, 0, -10e-3}; // beyond the sphere: the cap cuts nothing
  EXPECT_THAT(mesh_error(d), HasSubstr("cap 'inlet' cuts no fluid"));

  // A window 10 mm long in the wall: the fluid meets the outside there, off the caps.
  d = pipe_domain([](const Vec3& x) {
    const int l = straight_pipe(x);
    return l == 2 && x[0] > 0 && std::abs(x[2] - 40e-3) < 5e-3 ? 0 : l;
  });
  EXPECT_THAT(mesh_error(d), HasSubstr("fluid facets touch the outside off every cap, e.g. at"));
}

} // namespace
} // namespace tearflow::geometry
