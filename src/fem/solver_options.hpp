#pragma once
// A run's PETSc options: a database of its own, built from the options in force where the run
// is made (PETSc's command line and PETSC_OPTIONS at the top level, the enclosing run's inside
// one), then `options` (a case's petsc_options, with the command line's after them so that
// they win). While a Scope lives, it is PETSc's default database (PetscOptionsPush): the
// solvers a run builds read it, and their defaults (set_default_options) go into it. So a
// library caller gets from the case what the command line gets, and two runs in one process
// (tuning, in-run correction, a wall load inside an FSI start-up) never see each other's
// options or defaults.
#include <string>

#include <petscsys.h>

namespace tearflow::fem {

class SolverOptions {
public:
  explicit SolverOptions(const std::string& options);
  ~SolverOptions();
  SolverOptions(const SolverOptions&) = delete;
  SolverOptions& operator=(const SolverOptions&) = delete;

  /// This database is PETSc's default for the scope's life. A scope of the database already
  /// in force does nothing (a run's step inside its run loop); scopes nest like the runs.
  class Scope {
  public:
    explicit Scope(const SolverOptions& options);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

  private:
    bool pushed_ = false;
  };

  /// The value of `name` here ("" for an option without one), or false when it is not set.
  bool get(const std::string& name, std::string* value = nullptr) const;

private:
  PetscOptions db_ = nullptr;
};

} // namespace tearflow::fem
