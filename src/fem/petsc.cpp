#include "fem/petsc.hpp"

namespace tearflow::fem {

PetscSession::PetscSession(int* argc, char*** argv) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    TF_PETSC(PetscInitialize(argc, argv, nullptr, nullptr));
  // Our own messages explain failures; PETSc's traceback on stderr would only repeat them.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
}

PetscSession::~PetscSession() {
  PetscFinalize();
}

std::string petsc_error_text(PetscErrorCode ierr) {
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(static_cast<int>(ierr), &text, &specific);
  std::string s = text ? text : "PETSc error " + std::to_string(ierr);
  if (specific && *specific)
    s += std::string(": ") + specific;
  // One line: PETSc breaks its longer messages with a newline and tabs.
  std::string line;
  for (char c : s)
    if (c == '\n' || c == '\t') {
      if (!line.empty() && line.back() != ' ')
        line += ' ';
    } else {
      line += c;
    }
  return line;
}

bool option_set(const std::string& name) {
  PetscBool set = PETSC_FALSE;
  TF_PETSC(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set));
  return set;
}

void set_default_options(const OptionList& options) {
  for (const auto& [name, value] : options)
    if (!option_set(name))
      TF_PETSC(PetscOptionsSetValue(nullptr, name.c_str(), value.c_str()));
}

void use_gmres(KSP ksp, PetscInt restart) {
  TF_PETSC(KSPSetType(ksp, KSPGMRES));
  TF_PETSC(KSPGMRESSetRestart(ksp, restart));
  // Over 200 directions, classical Gram-Schmidt without refinement (PETSc's default) loses
  // the basis' orthogonality: on EN with nine elements across the TL (1.04 M tets, late
  // systole) GMRES broke down at its restart (DIVERGED_BREAKDOWN at iteration 200) even with
  // a fresh preconditioner, and took 337-726 iterations per step where a second pass when
  // needed takes 179-211, in half the time (docs/performance.md).
  TF_PETSC(KSPGMRESSetCGSRefinementType(ksp, KSP_GMRES_CGS_REFINE_IFNEEDED));
}

OptionList boomeramg_3d_options(const std::string& prefix) {
  return {{prefix + "pc_type", "hypre"},
          {prefix + "pc_hypre_boomeramg_coarsen_type", "HMIS"},
          {prefix + "pc_hypre_boomeramg_interp_type", "ext+i"},
          {prefix + "pc_hypre_boomeramg_P_max", "4"},
          {prefix + "pc_hypre_boomeramg_agg_nl", "1"},
          {prefix + "pc_hypre_boomeramg_strong_threshold", "0.5"}};
}

int mpi_rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int mpi_size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

} // namespace tearflow::fem
