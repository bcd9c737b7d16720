#pragma once
// ALE mesh motion: the fluid mesh follows the wall. The displacement d of the fluid's nodes
// solves a linear-elastic pseudo-solid on the reference fluid mesh,
//
//   (eps(v), 2 s_e eps(d)) + (div v, s_e lambda div d) = 0   for all v vanishing on Gamma_D,
//   d = d_wall on every node of a wall tet (the interface included),
//   d = 0 on the fluid's other boundary faces (inlet and outlet caps, rigid walls),
//
// with Jacobian-based stiffening s_e = (V_mean / V_e)^chi, chi = 1 (Stein, Tezduyar & Benney,
// J. Appl. Mech. 2003): small elements, as in the thin gaps beside the flap and at the tears,
// are stiffer and move almost rigidly, so they do not invert. lambda = 1 (nu = 1/4 for the
// unit shear modulus). The operator is assembled once; each solve only lifts the boundary
// values into the right-hand side:  A_free d = -A_0 d_D.
//
// Solver: CG with BoomerAMG (PETSc options prefix `mesh_`), started from the previous
// solution or from the one set by start_from.
#include <vector>

#include "fem/dof_map.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::physics {

class MeshMotion {
public:
  /// `fluid_region`: the region index of the fluid tets in mesh.regions.
  MeshMotion(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh, int fluid_region);

  /// True where the node's displacement is the wall's (a node of a wall tet).
  bool follows_wall(Index local) const { return role_[local] == Role::Wall; }

  /// Displacement of every local node: the given value on wall nodes, 0 on the fixed
  /// boundary, the pseudo-solid's solution elsewhere. `wall` and `out` hold one Vec3 per
  /// local node (owned then ghosts); `out` may alias `wall`. Collective.
  void solve(const std::vector<Vec3>& wall, std::vector<Vec3>& out);

  /// The next solve starts from this displacement (one Vec3 per local node; only the free
  /// nodes' values are used): the state's own, so that a run restarted from a checkpoint
  /// starts its solves where the uninterrupted run does.
  void start_from(const std::vector<Vec3>& d);

  int last_iterations() const { return iterations_; }

private:
  enum class Role : unsigned char { Free, Wall, Fixed };
  const fem::DistributedMesh& dmesh_;
  fem::DofMap dofs_;
  std::vector<Role> role_; ///< per local node
  std::vector<PetscInt> constrained_rows_;
  fem::OwnedMat A0_, A_; ///< full operator, and with constrained rows and columns removed
  fem::OwnedKSP ksp_;
  fem::OwnedVec d_, b_, lift_, d_loc_;
  int iterations_ = 0;
};

} // namespace tearflow::physics
