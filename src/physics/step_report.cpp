#include "physics/step_report.hpp"

#include <cmath>

#include "fem/petsc.hpp"

namespace tearflow::physics {

StepReport read_step_report(SNES snes, double start, double assembly_seconds) {
  StepReport report;
  PetscInt its = 0, lits = 0;
  SNESGetIterationNumber(snes, &its);
  SNESGetLinearSolveIterations(snes, &lits);
  PetscReal fnorm = 0.0;
  SNESGetFunctionNorm(snes, &fnorm);
  // SNES records ||R|| per iteration (reset every solve); entry 0 is the initial guess's.
  PetscReal* history = nullptr;
  PetscInt history_length = 0;
  SNESGetConvergenceHistory(snes, &history, nullptr, &history_length);
  if (history_length > 0)
    report.residual_initial = history[0];
  report.newton_iterations = static_cast<int>(its);
  report.linear_iterations = static_cast<int>(lits);
  report.residual_final = fnorm;
  report.assembly_seconds = assembly_seconds;
  report.solve_seconds = MPI_Wtime() - start - assembly_seconds;
  return report;
}

std::string newton_failure(PetscErrorCode err, const CallbackError& callback,
                           SNESConvergedReason reason, double residual_final) {
  if (!callback.message.empty())
    return callback.message;
  if (err != 0)
    return fem::petsc_error_text(err);
  if (!std::isfinite(residual_final))
    return "residual is not a number";
  if (reason < 0)
    return SNESConvergedReasons[reason];
  return {};
}

} // namespace tearflow::physics
