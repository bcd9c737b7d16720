// Carrying nodal fields from one mesh of a pipe with a wall to another (fem/node_transfer.hpp).
#include <cmath>

#include <gtest/gtest.h>

#include "fem/node_transfer.hpp"
#include "mesh/pipe_generator.hpp"

using namespace tearflow;

namespace {

mesh::Mesh pipe(double element_size) {
  mesh::PipeSpec spec;
  spec.radius = 0.005;
  spec.length = 0.02;
  spec.element_size = element_size;
  spec.wall_thickness = 0.001;
  return mesh::make_pipe(spec);
}

std::vector<unsigned char> in_region(const mesh::Mesh& m, const std::string& name) {
  std::vector<unsigned char> in(m.num_nodes(), 0);
  for (size_t e = 0; e < m.tets.size(); ++e)
    if (m.regions[m.tet_region[e]] == name)
      for (Index v : m.tets[e])
        in[v] = 1;
  return in;
}

double linear(const Vec3& x) {
  return 2.0 + 30.0 * x[0] - 50.0 * x[1] + 70.0 * x[2];
}

} // namespace

TEST(NodeTransfer, LinearFieldsExactAndEachPressureFromItsRegion) {
  const mesh::Mesh coarse = pipe(0.0016), fine = pipe(0.0011);
  const std::vector<unsigned char> fluid = in_region(coarse, "fluid");
  // Block 3: a linear field everywhere; a "fluid pressure", linear on fluid nodes and a
  // value no interpolation may reach on wall-only nodes (the solver's empty slot); the same
  // for a "wall pressure" on fluid-only nodes.
  const std::vector<unsigned char> wall = in_region(coarse, "wall");
  std::vector<double> field;
  for (Index n = 0; n < coarse.num_nodes(); ++n) {
    const double f = linear(coarse.points[n]);
    field.insert(field.end(), {f, fluid[n] ? f : 1e6, wall[n] ? f : 1e6});
  }
  const fem::NodeTransfer transfer(coarse, fine);
  const std::vector<double> out = transfer.apply(field, 3, {"", "fluid", "wall"});

  // Nodes inside their region's tets get the linear field exactly (P1 reproduces it); the
  // others (the two meshes' polygons of the same circles differ) its value at the closest
  // point: off by at most |grad f| times the distance, which is O(h^2 / R).
  const double grad = std::sqrt(30.0 * 30.0 + 50.0 * 50.0 + 70.0 * 70.0);
  const double bound = grad * transfer.largest_distance() + 1e-12;
  EXPECT_GT(transfer.largest_distance(), 0.0);
  EXPECT_LT(transfer.largest_distance(), 0.0011 * 0.0011 / 0.005); // h^2 / R
  const std::vector<unsigned char> fine_fluid = in_region(fine, "fluid"),
                                   fine_wall = in_region(fine, "wall");
  int interior = 0;
  for (Index n = 0; n < fine.num_nodes(); ++n) {
    const Vec3& x = fine.points[n];
    const double f = linear(x);
    // A coarse element size away from every boundary: inside the coarse fluid, exact.
    if (std::hypot(x[0], x[1]) < 0.005 - 0.0016 && x[2] > 0.0016 && x[2] < 0.02 - 0.0016) {
      ++interior;
      EXPECT_NEAR(out[3 * n], f, 1e-12) << n;
      EXPECT_NEAR(out[3 * n + 1], f, 1e-12) << n;
    }
    EXPECT_NEAR(out[3 * n], f, bound) << n;
    EXPECT_NEAR(out[3 * n + 1], fine_fluid[n] ? f : 0.0, bound) << n;
    EXPECT_NEAR(out[3 * n + 2], fine_wall[n] ? f : 0.0, bound) << n;
  }
  EXPECT_GT(interior, 100);
}
