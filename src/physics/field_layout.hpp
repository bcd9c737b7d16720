#pragma once
// Where one physics' unknowns sit in a node block. A rigid-wall flow or a solid-only run has
// 4 unknowns per node (velocity, pressure). The FSI system has 5: the velocity is shared by
// fluid and wall (kinematic continuity at the interface, built into the unknowns), and the
// fluid's and the wall's pressures are separate fields (slots 3 and 4), since the two
// pressures differ across the interface.
#include <array>
#include <vector>

#include "fem/distributed_mesh.hpp"

namespace tearflow::physics {

struct FieldLayout {
  int block = 4;    ///< unknowns per node
  int pressure = 3; ///< slot of this physics' pressure
  int region = -1;  ///< assemble the tets of this region index only; -1: every tet

  /// Slot of element unknown c (0-2 velocity, 3 pressure).
  std::array<int, 4> slots() const { return {0, 1, 2, pressure}; }
  /// The local tets to assemble.
  std::vector<size_t> elements(const fem::DistributedMesh& dmesh) const {
    std::vector<size_t> e;
    for (size_t i = 0; i < dmesh.tets().size(); ++i)
      if (region < 0 || dmesh.tet_region()[i] == region)
        e.push_back(i);
    return e;
  }
};

/// The 16 x 16 element matrix Ke (4 unknowns per node, node-major) placed into the
/// (4 block) x (4 block) matrix Kx with unknown c of every node at slot[c]; zeros elsewhere.
inline void expand_element_matrix(const double* Ke, const FieldLayout& layout, double* Kx) {
  const int n = 4 * layout.block;
  const std::array<int, 4> slot = layout.slots();
  for (int i = 0; i < n * n; ++i)
    Kx[i] = 0.0;
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d)
        for (int k = 0; k < 4; ++k)
          Kx[(layout.block * a + slot[c]) * n + layout.block * d + slot[k]] =
              Ke[(4 * a + c) * 16 + 4 * d + k];
}

} // namespace tearflow::physics
