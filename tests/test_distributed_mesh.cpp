// DistributedMesh numbers nodes in reverse Cuthill-McKee order (distributed_mesh.cpp) so
// that the nodes of a tet, and so the matrix rows an element touches, lie close together:
// the assembly rate depends on it (docs/performance.md). The numbering must stay a
// permutation that maps back to the input mesh, with the tets unchanged.
#include <algorithm>
#include <cstdio>
#include <set>

#include <gtest/gtest.h>

#include "fem/distributed_mesh.hpp"
#include "fem/petsc.hpp"
#include "mesh/pipe_generator.hpp"

using namespace tearflow;

TEST(DistributedMesh, NodeOrderIsAPermutationWithCompactTets) {
  // R 5 mm, L 40 mm, h 1 mm: about 40 cross-sections of ~100 nodes each.
  const mesh::Mesh m = mesh::make_pipe({0.005, 0.04, 0.001});
  const fem::DistributedMesh dm(m, PETSC_COMM_SELF);
  const Index n = m.num_nodes();
  ASSERT_EQ(dm.num_owned(), n);
  ASSERT_EQ(dm.num_local(), n);

  // A permutation: every input node once, at its own coordinates.
  std::vector<int> seen(n, 0);
  for (Index l = 0; l < n; ++l) {
    ++seen[dm.original_index(l)];
    EXPECT_EQ(dm.global_index(l), l);
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(dm.points()[l][c], m.points[dm.original_index(l)][c]);
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));

  // The same tets, as sets of input nodes.
  ASSERT_EQ(dm.tets().size(), m.tets.size());
  std::multiset<std::array<Index, 4>> input, local;
  for (const Tet& t : m.tets) {
    std::array<Index, 4> s{t[0], t[1], t[2], t[3]};
    std::sort(s.begin(), s.end());
    input.insert(s);
  }
  for (const Tet& t : dm.tets()) {
    std::array<Index, 4> s{dm.original_index(t[0]), dm.original_index(t[1]),
                           dm.original_index(t[2]), dm.original_index(t[3])};
    std::sort(s.begin(), s.end());
    local.insert(s);
  }
  EXPECT_TRUE(input == local);

  // Compact: a breadth-first order along the pipe puts a tet's nodes within about two
  // cross-sections (~n/20 here); the generator's order spreads them over ~n/2. Bound n/10.
  double spread = 0.0;
  for (const Tet& t : dm.tets())
    spread += *std::max_element(t.begin(), t.end()) - *std::min_element(t.begin(), t.end());
  spread /= static_cast<double>(dm.tets().size());
  double input_spread = 0.0;
  for (const Tet& t : m.tets)
    input_spread += *std::max_element(t.begin(), t.end()) - *std::min_element(t.begin(), t.end());
  input_spread /= static_cast<double>(m.tets.size());
  std::printf("mean node spread per tet: %.1f (input order %.1f) of %d nodes\n", spread,
              input_spread, static_cast<int>(n));
  EXPECT_LT(spread, 0.1 * n);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  fem::PetscSession petsc(&argc, &argv);
  return RUN_ALL_TESTS();
}
