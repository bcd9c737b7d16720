#include "physics/pressure_schur.hpp"

#include <cstring>

namespace tearflow::physics {

bool uses_schur_matrix(KSP ksp) {
  PC pc;
  TF_PETSC(KSPGetPC(ksp, &pc));
  PetscBool field_split = PETSC_FALSE;
  TF_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &field_split));
  if (!field_split)
    return false;
  const char* prefix = nullptr;
  TF_PETSC(KSPGetOptionsPrefix(ksp, &prefix));
  char value[64] = "";
  PetscBool set = PETSC_FALSE;
  TF_PETSC(PetscOptionsGetString(nullptr, prefix, "-pc_fieldsplit_schur_precondition", value,
                                 sizeof value, &set));
  return set && std::strcmp(value, "user") == 0;
}

void use_schur_matrix(KSP ksp, Mat S) {
  PC pc;
  TF_PETSC(KSPGetPC(ksp, &pc));
  TF_PETSC(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, S));
}

PressureSchur::PressureSchur(const fem::DistributedMesh& dmesh)
    : dofs_(dmesh, 1), inserter_(dofs_), S_(dofs_.create_matrix("schur_")) {}

void PressureSchur::assemble(const std::vector<size_t>& elements,
                             const std::vector<fem::TetGeometry>& geometry,
                             const std::vector<Stabilization>& stab, const FluidProperties& fluid,
                             double c_u, double c_a, const std::vector<NodeTerm>& open_terms) {
  if (!outside_known_) {
    // A node is in the fluid when some rank's fluid tet holds it: each rank marks its tets'
    // nodes and the marks are summed at the owners.
    fem::OwnedVec marks = dofs_.create_local(), owned = dofs_.create_global();
    {
      fem::WriteArray m(marks);
      for (size_t e : elements)
        for (Index l : dofs_.mesh().tets()[e])
          m[l] = 1.0;
    }
    dofs_.add_local_to_global(marks, owned);
    fem::ReadArray o(owned);
    for (Index l = 0; l < dofs_.mesh().num_owned(); ++l)
      if (o[l] == 0.0)
        outside_.push_back(dofs_.global_dof(l, 0));
    outside_known_ = true;
  }
  inserter_.begin(S_);
  if (!inserter_.direct()) {
    // The first pass records the pattern of every local tet, as the matrix preallocates it:
    // the inserter's direct passes need it whole (element_inserter.hpp).
    std::vector<unsigned char> fluid(dofs_.mesh().tets().size(), 0);
    for (size_t e : elements)
      fluid[e] = 1;
    const std::array<double, 16> zero{};
    for (size_t e = 0; e < fluid.size(); ++e)
      if (!fluid[e])
        inserter_.add(e, zero.data());
  }
  for (size_t e : elements) {
    const std::array<double, 16> Se = schur_element(
        geometry[e], schur_coefficient(stab[e], gradient_sum(geometry[e]), fluid, c_u, c_a));
    inserter_.add(e, Se.data());
  }
  inserter_.end();
  for (const NodeTerm& t : open_terms) {
    const PetscInt row = dofs_.global_dof(t.node, 0);
    TF_PETSC(MatSetValues(S_, 1, &row, 1, &row, &t.value, ADD_VALUES));
  }
  const PetscScalar one = 1.0;
  for (PetscInt row : outside_)
    TF_PETSC(MatSetValues(S_, 1, &row, 1, &row, &one, ADD_VALUES));
  TF_PETSC(MatAssemblyBegin(S_, MAT_FINAL_ASSEMBLY));
  TF_PETSC(MatAssemblyEnd(S_, MAT_FINAL_ASSEMBLY));
}

} // namespace tearflow::physics
