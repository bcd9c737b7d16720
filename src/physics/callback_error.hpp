#pragma once
// Errors thrown inside PETSc callbacks must not cross PETSc's C frames: a callback's body runs
// through CallbackError::guard, which turns an exception into an error code PETSc passes on
// and keeps its message, to be re-thrown once SNESSolve has returned.
#include <exception>
#include <string>
#include <utility>

#include <petscsys.h>

#include "core/error.hpp"

namespace tearflow::physics {

struct CallbackError {
  std::string message;     ///< empty: no callback failed
  bool collective = false; ///< every rank raised it (SolverError::collective)

  void clear() { *this = {}; }

  template <typename F> PetscErrorCode guard(F&& body) {
    try {
      body();
      return 0;
    } catch (const SolverError& e) {
      message = e.what();
      collective = e.collective;
    } catch (const std::exception& e) {
      message = e.what();
      collective = false;
    }
    return PETSC_ERR_LIB;
  }

  /// guard, adding the body's wall time to `seconds` (a step's assembly time): the residual
  /// and Jacobian callbacks of every Newton solve (fluid_solver.cpp, solid_solver.cpp).
  template <typename F> PetscErrorCode timed_guard(double& seconds, F&& body) {
    const double t0 = MPI_Wtime();
    const PetscErrorCode err = guard(std::forward<F>(body));
    seconds += MPI_Wtime() - t0;
    return err;
  }
};

} // namespace tearflow::physics
