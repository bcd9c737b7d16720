#pragma once
// What a time step's Newton solve did, as the progress line and the run summary print it, and
// why it failed when it did: shared by the fluid/FSI stepper and the solid solver.
#include <string>

#include <petscsnes.h>

#include "physics/callback_error.hpp"

namespace tearflow::physics {

struct StepReport {
  int newton_iterations = 0; ///< every iteration spent, a failed attempt's included
  /// Of these, the iterations of attempts that failed before the step was solved again
  /// (fluid_solver.cpp): "Newton 15" of at most 10 was 5 + 10 retried.
  int retried_iterations = 0;
  int linear_iterations = 0;
  int jacobians = 0;             ///< Jacobians assembled (the others reused one, fluid_solver.hpp)
  double residual_initial = 0.0; ///< ||R|| at the step's initial guess
  double residual_final = 0.0;
  double assembly_seconds = 0.0; ///< residual and Jacobian assembly
  double solve_seconds = 0.0;    ///< everything else in the Newton loop (mostly KSP)
};

/// The numbers of the SNESSolve just finished; `start` is MPI_Wtime() at the step's start,
/// and the solve time is what assembly did not take.
StepReport read_step_report(SNES snes, double start, double assembly_seconds);

/// Why the solve failed, most specific first: a callback's exception, PETSc's error, a
/// residual that is not a number, SNES's reason. Empty when it converged.
std::string newton_failure(PetscErrorCode err, const CallbackError& callback,
                           SNESConvergedReason reason, double residual_final);

} // namespace tearflow::physics
