#include "fem/solver_options.hpp"

#include <stdexcept>
#include <vector>

#include "fem/petsc.hpp"

namespace tearflow::fem {

namespace {
/// The databases pushed by live scopes, innermost last (PETSc keeps no way to ask).
std::vector<PetscOptions>& pushed() {
  static std::vector<PetscOptions> stack;
  return stack;
}
} // namespace

SolverOptions::SolverOptions(const std::string& options) {
  char* inherited = nullptr;
  TF_PETSC(PetscOptionsGetAll(nullptr, &inherited));
  TF_PETSC(PetscOptionsCreate(&db_));
  const PetscErrorCode copied = PetscOptionsInsertString(db_, inherited);
  PetscFree(inherited);
  TF_PETSC(copied);
  TF_PETSC(PetscOptionsInsertString(db_, options.c_str()));
}

SolverOptions::~SolverOptions() {
  PetscOptionsDestroy(&db_);
}

bool SolverOptions::get(const std::string& name, std::string* value) const {
  char text[PETSC_MAX_PATH_LEN] = "";
  PetscBool set = PETSC_FALSE;
  TF_PETSC(PetscOptionsGetString(db_, nullptr, name.c_str(), text, sizeof text, &set));
  if (set && value)
    *value = text;
  return set;
}

SolverOptions::Scope::Scope(const SolverOptions& options) {
  std::vector<PetscOptions>& stack = pushed();
  if (!stack.empty() && stack.back() == options.db_)
    return;
  for (PetscOptions db : stack)
    if (db == options.db_) // PETSc's push would link the database to itself
      throw std::logic_error("SolverOptions::Scope: a run's options pushed under another run's");
  TF_PETSC(PetscOptionsPush(options.db_));
  stack.push_back(options.db_);
  pushed_ = true;
}

SolverOptions::Scope::~Scope() {
  if (!pushed_)
    return;
  PetscOptionsPop();
  pushed().pop_back();
}

} // namespace tearflow::fem
