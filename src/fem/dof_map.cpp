#include "fem/dof_map.hpp"

#include <vector>

namespace tearflow::fem {

DofMap::DofMap(const DistributedMesh& mesh, int block) : mesh_(&mesh), block_(block) {
  MPI_Comm comm = mesh.comm();
  TF_PETSC(VecCreateMPI(comm, num_owned_dofs(), static_cast<PetscInt>(mesh.num_global()) * block,
                        template_global_.out()));
  TF_PETSC(VecSetBlockSize(template_global_, block));
  TF_PETSC(VecCreateSeq(PETSC_COMM_SELF, num_local_dofs(), template_local_.out()));
  TF_PETSC(VecSetBlockSize(template_local_, block));

  std::vector<PetscInt> nodes(mesh.num_local());
  for (Index l = 0; l < mesh.num_local(); ++l)
    nodes[l] = mesh.global_index(l);
  OwnedIS from, to;
  TF_PETSC(ISCreateBlock(PETSC_COMM_SELF, block, static_cast<PetscInt>(nodes.size()), nodes.data(),
                         PETSC_COPY_VALUES, from.out()));
  TF_PETSC(ISCreateStride(PETSC_COMM_SELF, num_local_dofs(), 0, 1, to.out()));
  TF_PETSC(VecScatterCreate(template_global_, from, template_local_, to, scatter_.out()));
}

OwnedVec DofMap::create_global() const {
  OwnedVec v;
  TF_PETSC(VecDuplicate(template_global_, v.out()));
  TF_PETSC(VecZeroEntries(v));
  return v;
}

OwnedVec DofMap::create_local() const {
  OwnedVec v;
  TF_PETSC(VecDuplicate(template_local_, v.out()));
  TF_PETSC(VecZeroEntries(v));
  return v;
}

OwnedMat DofMap::create_matrix(const std::string& prefix) const {
  OwnedMat A;
  MPI_Comm comm = mesh_->comm();
  TF_PETSC(MatCreate(comm, A.out()));
  const PetscInt N = static_cast<PetscInt>(mesh_->num_global()) * block_;
  TF_PETSC(MatSetSizes(A, num_owned_dofs(), num_owned_dofs(), N, N));
  TF_PETSC(MatSetOptionsPrefix(A, prefix.c_str()));
  TF_PETSC(MatSetType(A, MATAIJ));
  TF_PETSC(MatSetBlockSize(A, block_));
  TF_PETSC(MatSetFromOptions(A));
  TF_PETSC(MatXAIJSetPreallocation(A, block_, mesh_->diag_node_counts().data(),
                                   mesh_->offdiag_node_counts().data(), nullptr, nullptr));
  // Exact preallocation: a new nonzero means a bug in the graph, not a slow insert.
  TF_PETSC(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  TF_PETSC(MatSetOption(A, MAT_IGNORE_ZERO_ENTRIES, PETSC_FALSE));
  return A;
}

void DofMap::global_to_local(Vec global, Vec local) const {
  TF_PETSC(VecScatterBegin(scatter_, global, local, INSERT_VALUES, SCATTER_FORWARD));
  TF_PETSC(VecScatterEnd(scatter_, global, local, INSERT_VALUES, SCATTER_FORWARD));
}

void DofMap::add_local_to_global(Vec local, Vec global) const {
  TF_PETSC(VecScatterBegin(scatter_, local, global, ADD_VALUES, SCATTER_REVERSE));
  TF_PETSC(VecScatterEnd(scatter_, local, global, ADD_VALUES, SCATTER_REVERSE));
}

} // namespace tearflow::fem
