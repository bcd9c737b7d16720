#include "physics/fsi_preconditioner.hpp"

#include <mpi.h>

namespace tearflow::physics {

namespace {

fem::OwnedIS make_is(MPI_Comm comm, const std::vector<PetscInt>& indices, PetscInt block = 1) {
  fem::OwnedIS is;
  TF_PETSC(ISCreateGeneral(comm, static_cast<PetscInt>(indices.size()), indices.data(),
                           PETSC_COPY_VALUES, is.out()));
  if (block > 1)
    TF_PETSC(ISSetBlockSize(is, block));
  return is;
}

} // namespace

FsiPreconditioner::FsiPreconditioner(const fem::DofMap& dofs,
                                     const std::vector<unsigned char>& wall_node,
                                     int fluid_pressure, int wall_pressure) {
  const fem::DistributedMesh& dmesh = dofs.mesh();
  MPI_Comm comm = dmesh.comm();
  const int block = dofs.block();
  const Index n = dmesh.num_owned();

  // The motion block's rows are numbered in the order of its index set: this rank's come
  // after the lower ranks', each node's (block - 1) unknowns in turn.
  const PetscInt motion_local = static_cast<PetscInt>(n) * (block - 1);
  PetscInt offset = 0;
  MPI_Exscan(&motion_local, &offset, 1, MPIU_INT, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0)
    offset = 0; // MPI_Exscan leaves rank 0's result undefined

  std::vector<PetscInt> motion, pressure, wall, fluid;
  motion.reserve(static_cast<size_t>(motion_local));
  pressure.reserve(n);
  PetscInt k = offset;
  for (Index l = 0; l < n; ++l)
    for (int c = 0; c < block; ++c) {
      if (c == fluid_pressure) {
        pressure.push_back(dofs.global_dof(l, c));
        continue;
      }
      motion.push_back(dofs.global_dof(l, c));
      // A fluid-only node's wall pressure is an identity row: any block takes it, and the
      // fluid's then keeps 3 unknowns per node for BoomerAMG's systems coarsening.
      (wall_node[l] || c == wall_pressure ? wall : fluid).push_back(k++);
    }
  motion_ = make_is(comm, motion, block - 1);
  pressure_ = make_is(comm, pressure);
  wall_ = make_is(comm, wall);
  fluid_ = make_is(comm, fluid, 3);
}

fem::OptionList FsiPreconditioner::default_options() {
  fem::OptionList options = {{"-fsi_pc_type", "fieldsplit"},
                             {"-fsi_pc_fieldsplit_type", "schur"},
                             {"-fsi_pc_fieldsplit_schur_fact_type", "lower"},
                             {"-fsi_pc_fieldsplit_schur_precondition", "user"},
                             {"-fsi_fieldsplit_motion_ksp_type", "preonly"},
                             {"-fsi_fieldsplit_motion_pc_type", "fieldsplit"},
                             {"-fsi_fieldsplit_motion_pc_fieldsplit_type", "multiplicative"},
                             {"-fsi_fieldsplit_motion_fieldsplit_wall_ksp_type", "preonly"},
                             {"-fsi_fieldsplit_motion_fieldsplit_fluid_ksp_type", "preonly"},
                             {"-fsi_fieldsplit_pressure_ksp_type", "preonly"}};
  for (const char* block :
       {"-fsi_fieldsplit_motion_fieldsplit_fluid_", "-fsi_fieldsplit_pressure_"})
    for (auto& option : fem::boomeramg_3d_options(block))
      options.push_back(std::move(option));
  return options;
}

fem::OptionList FsiPreconditioner::wall_options(double stiffness_number) {
  const std::string wall = "-fsi_fieldsplit_motion_fieldsplit_wall_";
  if (!wall_solved_directly(stiffness_number))
    return {{wall + "pc_type", "bjacobi"},
            {wall + "sub_pc_type", "ilu"},
            {wall + "sub_pc_factor_levels", "1"}};
  // Block low-rank factors to 1e-3: same Krylov counts, half the factorization time on
  // pipe-fsi's thick 85 k-tet wall (docs/performance.md).
  return {{wall + "pc_type", "lu"},
          {wall + "pc_factor_mat_solver_type", "mumps"},
          {wall + "mat_mumps_icntl_35", "1"},
          {wall + "mat_mumps_cntl_7", "1e-3"}};
}

bool FsiPreconditioner::attach(KSP ksp) {
  PC pc;
  TF_PETSC(KSPGetPC(ksp, &pc));
  PetscBool field_split = PETSC_FALSE, by_components = PETSC_FALSE;
  TF_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &field_split));
  const char* prefix = nullptr;
  TF_PETSC(KSPGetOptionsPrefix(ksp, &prefix));
  TF_PETSC(PetscOptionsHasName(nullptr, prefix, "-pc_fieldsplit_0_fields", &by_components));
  if (!field_split || by_components)
    return false;
  TF_PETSC(PCFieldSplitSetIS(pc, "motion", motion_));
  TF_PETSC(PCFieldSplitSetIS(pc, "pressure", pressure_));
  TF_PETSC(KSPSetPreSolve(ksp, name_inner_split, this));
  return true;
}

// PETSc creates the motion block's KSP when the outer split is set up, inside the first
// KSPSolve; this pre-solve hook sets the outer split up itself, then names the inner split's
// index sets before the inner one is set up (on its first application).
PetscErrorCode FsiPreconditioner::name_inner_split(KSP ksp, Vec, Vec, void* ctx) {
  auto* self = static_cast<FsiPreconditioner*>(ctx);
  if (self->inner_named_)
    return 0;
  PetscCall(KSPSetUp(ksp));
  PC pc, inner;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscInt n = 0;
  KSP* sub = nullptr;
  PetscCall(PCFieldSplitGetSubKSP(pc, &n, &sub));
  PetscCall(KSPGetPC(sub[0], &inner));
  PetscCall(PetscFree(sub));
  PetscBool field_split = PETSC_FALSE;
  PetscCall(
      PetscObjectTypeCompare(reinterpret_cast<PetscObject>(inner), PCFIELDSPLIT, &field_split));
  if (field_split) {
    PetscCall(PCFieldSplitSetIS(inner, "wall", self->wall_));
    PetscCall(PCFieldSplitSetIS(inner, "fluid", self->fluid_));
  }
  self->inner_named_ = true;
  return 0;
}

} // namespace tearflow::physics
