#pragma once
// Degrees of freedom: `block` unknowns per node, interleaved (node-major), numbered
// block * global_node + component. Creates PETSc vectors and the preallocated matrix, and
// moves values between the global (owned) vector and the local (owned + ghost) array.
#include <string>

#include "fem/distributed_mesh.hpp"
#include "fem/petsc.hpp"

namespace tearflow::fem {

class DofMap {
public:
  DofMap(const DistributedMesh& mesh, int block);

  int block() const { return block_; }
  const DistributedMesh& mesh() const { return *mesh_; }
  PetscInt num_owned_dofs() const { return static_cast<PetscInt>(mesh_->num_owned()) * block_; }
  PetscInt num_local_dofs() const { return static_cast<PetscInt>(mesh_->num_local()) * block_; }
  /// Global dof number of component c of local node l.
  PetscInt global_dof(Index l, int c) const {
    return static_cast<PetscInt>(mesh_->global_index(l)) * block_ + c;
  }

  OwnedVec create_global() const; ///< distributed, owned dofs only
  OwnedVec create_local() const;  ///< sequential, owned then ghost dofs
  /// Preallocated AIJ (type changeable with -<prefix>mat_type), block size `block`.
  OwnedMat create_matrix(const std::string& prefix) const;

  void global_to_local(Vec global, Vec local) const;     ///< copy owned, fetch ghosts
  void add_local_to_global(Vec local, Vec global) const; ///< sum contributions to owners

private:
  const DistributedMesh* mesh_;
  int block_;
  OwnedScatter scatter_; // global -> local (owned + ghost)
  OwnedVec template_global_, template_local_;
};

} // namespace tearflow::fem
