// Prismatic boundary layers (geometry/boundary_layers.hpp): the layered mesh must be a valid
// conforming tet mesh of the same domain, with the layers where they were asked for.
#include <algorithm>
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "geometry/boundary_layers.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/tbad_builder.hpp"
#include "geometry/tbad_spec.hpp"
#include "mesh/pipe_generator.hpp"

using namespace tearflow;

namespace {

Tri sorted(Tri t) {
  std::sort(t.begin(), t.end());
  return t;
}

/// Volume of a region [m^3].
double region_volume(const mesh::Mesh& m, int region) {
  double v = 0.0;
  for (std::size_t e = 0; e < m.tets.size(); ++e)
    if (m.tet_region[e] == region) {
      const Tet& t = m.tets[e];
      v += mesh::signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
    }
  return v;
}

/// The region's boundary triangles (faces of one of its tets only), sorted.
std::map<Tri, int> region_faces(const mesh::Mesh& m, int region) {
  std::map<Tri, int> count;
  for (std::size_t e = 0; e < m.tets.size(); ++e)
    if (m.tet_region[e] == region)
      for (int skip = 0; skip < 4; ++skip) {
        Tri f{};
        for (int i = 0, j = 0; i < 4; ++i)
          if (i != skip)
            f[j++] = m.tets[e][i];
        ++count[sorted(f)];
      }
  return count;
}

/// Checks what every layered mesh must satisfy: positive tets, each interior triangle shared
/// by two tets of the region and its boundary exactly the named faces' triangles, the
/// region's volume unchanged (its boundary did not move), and the wall's own triangles kept.
void expect_valid_layering(const mesh::Mesh& before, const mesh::Mesh& after,
                           const std::string& wall) {
  const int fluid = 0;
  ASSERT_EQ(after.regions, before.regions);
  for (const Tet& t : after.tets)
    ASSERT_GT(mesh::signed_volume(after.points[t[0]], after.points[t[1]], after.points[t[2]],
                                  after.points[t[3]]),
              0.0);
  std::map<Tri, int> named;
  for (const mesh::Face& f : after.faces)
    for (const Tri& t : f.triangles)
      named[sorted(t)] += 1;
  std::size_t boundary = 0;
  for (const auto& [tri, n] : region_faces(after, fluid)) {
    ASSERT_LE(n, 2) << "a triangle of three tets: the layers overlap";
    if (n == 1) {
      ++boundary;
      EXPECT_TRUE(named.count(tri)) << "a boundary triangle of the fluid in no named face";
    }
  }
  // The fluid fills the same domain: the volume to round-off (1e-12 relative).
  EXPECT_NEAR(region_volume(after, fluid), region_volume(before, fluid),
              1e-12 * region_volume(before, fluid));
  // The wall's triangles are the same (the layers grow from them).
  EXPECT_EQ(after.face(wall).triangles, before.face(wall).triangles);
  EXPECT_GT(boundary, 0u);
}

} // namespace

TEST(BoundaryLayers, PipeLayersAreConformingAndOfTheAskedThickness) {
  mesh::PipeSpec pipe;
  pipe.radius = 4e-3;
  pipe.length = 12e-3;
  pipe.element_size = 1.5e-3;
  const mesh::Mesh m = mesh::make_pipe(pipe);
  geometry::BoundaryLayerSpec spec;
  spec.count = 3;
  spec.first = 0.2e-3;
  spec.growth = 1.3;
  geometry::BoundaryLayerReport report;
  const mesh::Mesh layered = geometry::add_boundary_layers(m, "fluid", {"wall"}, spec, &report);
  expect_valid_layering(m, layered, "wall");
  mesh::check_mesh(layered);
  // Three layers of three tets per wall triangle, and nothing thinned in a wide pipe.
  EXPECT_EQ(report.tets_added, 3u * 3u * m.face("wall").triangles.size());
  EXPECT_EQ(report.ended, 0u);
  EXPECT_NEAR(report.thickest, spec.thickness(), 1e-12);
  EXPECT_NEAR(report.thinnest, spec.thickness(), 1e-12);
  // The first layer's nodes sit `first` inside the wall: on a pipe with its wall nodes on the
  // circle, at radius R - first along the node's normal (the faceted wall's normals tilt by
  // O(h / R): 2 % of the layer here).
  int first_layer_nodes = 0;
  for (std::size_t n = m.points.size(); n < layered.points.size(); ++n) {
    const double r = std::hypot(layered.points[n][0], layered.points[n][1]);
    if (std::abs(r - (pipe.radius - spec.first)) < 0.05 * spec.first)
      ++first_layer_nodes;
  }
  EXPECT_EQ(static_cast<std::size_t>(first_layer_nodes), report.wall_nodes);
  // The caps got the layers' sides: inlet and outlet still close the fluid.
  EXPECT_GT(layered.face("inlet").triangles.size(), m.face("inlet").triangles.size());
}

TEST(BoundaryLayers, FsiPipeKeepsItsInterfaceBetweenFluidAndWall) {
  mesh::PipeSpec pipe;
  pipe.radius = 5e-3;
  pipe.length = 10e-3;
  pipe.element_size = 2e-3;
  pipe.wall_thickness = 1e-3;
  const mesh::Mesh m = mesh::make_pipe(pipe);
  geometry::BoundaryLayerSpec spec;
  spec.count = 2;
  spec.first = 0.3e-3;
  const mesh::Mesh layered = geometry::add_boundary_layers(m, "fluid", {"interface"}, spec);
  expect_valid_layering(m, layered, "interface");
  // The wall region is untouched: the same tets on the same nodes.
  const double wall_before = region_volume(m, 1), wall_after = region_volume(layered, 1);
  EXPECT_DOUBLE_EQ(wall_after, wall_before);
  geometry::check_fsi_mesh(layered); // interface between one fluid and one wall tet each
}

TEST(BoundaryLayers, DissectionWithFlapAndTearsTakesLayers) {
  // The coarse parametric dissection (the CI study's 8 mm): the flap's faces and rims, the
  // tears, the false lumen's blind ends where the flap meets the wall at a shallow angle
  // (the layers end there) and the branch caps.
  geometry::TbadSpec spec;
  spec.element_size = 8e-3;
  const std::filesystem::path dir = tearflow::testing::fresh_dir("layers-tbad");
  const geometry::TbadBuild b = geometry::build_tbad(spec, dir);
  geometry::BoundaryLayerSpec layers;
  layers.count = 2;
  layers.first = 0.4e-3;
  geometry::BoundaryLayerReport report;
  const mesh::Mesh layered =
      geometry::add_boundary_layers(b.mesh, "fluid", {"interface"}, layers, &report);
  expect_valid_layering(b.mesh, layered, "interface");
  geometry::check_fsi_mesh(layered);
  EXPECT_GT(report.tets_added, 0u);
  EXPECT_LT(report.ended, report.wall_nodes / 20) << "layers end at the folds only";
}

TEST(BoundaryLayers, BadSpecsAndFacesAreClearErrors) {
  mesh::PipeSpec pipe;
  pipe.radius = 4e-3;
  pipe.length = 8e-3;
  pipe.element_size = 2e-3;
  const mesh::Mesh m = mesh::make_pipe(pipe);
  geometry::BoundaryLayerSpec spec;
  spec.count = 2;
  spec.first = 0.0;
  EXPECT_THROW(geometry::add_boundary_layers(m, "fluid", {"wall"}, spec), InputError);
  spec.first = 0.2e-3;
  try {
    geometry::add_boundary_layers(m, "fluid", {"no_such_face"}, spec);
    FAIL() << "a wall face the region does not have";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none of the faces no_such_face"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(geometry::add_boundary_layers(m, "wall", {"wall"}, spec), InputError);
}
