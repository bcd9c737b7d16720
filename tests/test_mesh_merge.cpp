// Merging a fluid mesh and a wall mesh whose interface nodes coincide (mesh/merge.hpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mesh/merge.hpp"

using namespace tearflow;
using testing::HasSubstr;

namespace {

// Fluid: the unit tet; its face (0, 1, 2) in z = 0 is the interface `lumen_wall`.
mesh::Mesh fluid_tet() {
  mesh::Mesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.tet_region = {0};
  m.regions = {"fluid"};
  m.faces = {{"lumen_wall", {{0, 2, 1}}}, {"lumen_inlet", {{0, 1, 3}}}};
  m.source = "fluid";
  return m;
}

// Wall: the tet below it, sharing that face (node order of its own).
mesh::Mesh wall_tet(double shift = 0.0, double move_one = 0.0) {
  mesh::Mesh m;
  m.points = {{0, 1, 0}, {0, 0, 0}, {1 + move_one, 0, 0}, {0, 0, -1}};
  for (auto& p : m.points)
    p[2] += shift;
  m.tets = {{0, 1, 2, 3}};
  if (mesh::signed_volume(m.points[0], m.points[1], m.points[2], m.points[3]) < 0)
    m.tets = {{1, 0, 2, 3}};
  m.tet_region = {0};
  m.regions = {"fluid"};
  m.faces = {{"wall_inner", {{0, 1, 2}}}, {"wall_outer", {{1, 3, 2}}}};
  m.source = "wall";
  return m;
}

} // namespace

TEST(MergeFluidAndWall, SharesTheInterfaceNodes) {
  const mesh::Mesh m = mesh::merge_fluid_and_wall(fluid_tet(), wall_tet());
  EXPECT_EQ(m.num_nodes(), 5); // 4 + 4 - 3 shared
  ASSERT_EQ(m.regions, (std::vector<std::string>{"fluid", "wall"}));
  EXPECT_EQ(m.tet_region, (std::vector<int>{0, 1}));
  // The wall's inner face is the fluid's wall face, node for node.
  std::vector<Index> a(m.face("lumen_wall").triangles[0].begin(),
                       m.face("lumen_wall").triangles[0].end());
  std::vector<Index> b(m.face("wall_inner").triangles[0].begin(),
                       m.face("wall_inner").triangles[0].end());
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

TEST(MergeFluidAndWall, RejectsMeshesThatDoNotTouch) {
  try {
    mesh::merge_fluid_and_wall(fluid_tet(), wall_tet(-0.5));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("fluid mesh fluid and wall mesh wall: the meshes share no "
                                    "node"));
  }
}

TEST(MergeFluidAndWall, RejectsAnInterfaceWhoseNodesDoNotCoincide) {
  try {
    mesh::merge_fluid_and_wall(fluid_tet(), wall_tet(0.0, 0.01)); // one node off by 1 %
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the meshes share 2 nodes but no face of the fluid lies on "
                                    "the wall"));
  }
}
