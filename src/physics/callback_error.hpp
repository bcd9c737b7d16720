#pragma once
// Errors thrown inside PETSc callbacks must not cross PETSc's C frames: a callback's body runs
// through CallbackError::guard, which turns an exception into an error code PETSc passes on
// and keeps its message, to be re-thrown once SNESSolve has returned.
#include <exception>
#include <string>

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
};

} // namespace tearflow::physics
