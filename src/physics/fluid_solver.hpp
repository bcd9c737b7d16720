#pragma once
// Advances a FluidProblem (or the FSI problem) in time: one Newton solve (PETSc SNES,
// options prefix `fluid_` or `fsi_`) per generalized-alpha step. The Jacobian operator is a shell,
// assembled matrix plus the outlets' low-rank term; the preconditioner is built from the assembled
// matrix. Every solver choice (KSP, PC, line search, lagging) can be changed through PETSc options.
#include <array>
#include <string>

#include "physics/callback_error.hpp"
#include "physics/fluid_problem.hpp"
#include "physics/newton_spec.hpp"
#include "physics/preconditioner_lag.hpp"
#include "physics/step_report.hpp"

namespace tearflow::physics {

/// Problem: FluidProblem (options prefix `fluid_`) or FsiProblem (`fsi_`); it provides
/// dofs, begin_step, apply_dirichlet, residual, jacobian, the coupled outlets,
/// update_acceleration, commit_step, options_prefix and default_solver_options.
template <typename Problem> class NewtonStepper {
public:
  NewtonStepper(Problem& problem, const physics::NewtonSpec& newton);

  /// Starts from rest (U = 0, Udot = 0) unless the caller overwrites state().
  Vec solution() const { return U_; } ///< (u, p) at the current time
  Vec acceleration() const { return Udot_; }
  /// The pressure's slot in acceleration() (node-major, after the three velocity components)
  /// holds the pressure's change over the last step, 0 before any step.
  static constexpr int pressure_slot = 3;

  /// One step t -> t + dt. Throws SolverError naming the step if Newton fails or a NaN
  /// appears; the state is then left at time t.
  StepReport step(double t, double dt);

  /// FSI: whether Newton uses the exact operator (after a stalled step, or by
  /// -fsi_snes_mf_operator), and switching to it, so a restart continues with the method
  /// the run had reached (fluid_solver.cpp).
  bool uses_exact_operator() const;
  void use_exact_operator();

  /// The next step builds its preconditioner afresh and counts its lag from there, as a run
  /// restarted at this point does: called where a checkpoint is written, so that a restart
  /// repeats the uninterrupted run bit for bit.
  void rebuild_preconditioner_next() { lag_.rebuild_next(); }

private:
  void store_pressure_change();
  static PetscErrorCode form_residual(SNES, Vec U, Vec R, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec U, Mat J, Mat P, void* ctx);
  static PetscErrorCode shell_mult(Mat J, Vec x, Vec y);
  /// Newton's test, field by field (newton_spec.hpp).
  static PetscErrorCode converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                  PetscReal fnorm, SNESConvergedReason* reason, void* ctx);
  /// ||R|| of the momentum rows, ||R||_1 of the continuity rows, ||R|| of a wall's constraint.
  std::array<double, 3> field_norms(Vec R) const;
  /// Whether Newton iteration k keeps the Jacobian of the one before: the last iteration
  /// contracted ||R|| by at least -<prefix>jacobian_reuse_contraction (fluid_solver.cpp).
  bool jacobian_reusable(SNES snes) const;

  Problem& problem_;
  NewtonSpec newton_;
  std::array<double, 3> largest_norms_{}; ///< the largest field_norms in the step so far
  bool monitor_fields_ = false;
  ///< -<prefix>newton_field_norms: print them
  fem::OwnedVec U_, Udot_, U_prev_, R_;
  fem::OwnedMat P_, J_;
  fem::OwnedMat exact_operator_; ///< finite-difference operator, once a step needed it
  fem::OwnedSNES snes_;
  double assembly_seconds_ = 0.0;
  CallbackError callback_error_;
  /// When the preconditioner is built: -<prefix>snes_lag_preconditioner, counted here rather
  /// than by SNES so that its count can restart with the run (rebuild_preconditioner_next),
  /// and -<prefix>lag_preconditioner_growth.
  PreconditionerLag lag_{1, 0.0};
  bool lag_persists_ = false;                ///< the count goes on across steps
  double reuse_contraction_ = 0.0;           ///< 0: a Jacobian every Newton iteration
  bool reuse_allowed_ = true;                ///< off while a step that reused one is solved again
  int jacobians_ = 0, jacobians_reused_ = 0; ///< this step's attempt
  std::array<PetscReal, 64> residual_history_{}; ///< ||R|| per Newton iteration, from SNES
};

using FluidSolver = NewtonStepper<FluidProblem>;
class FsiProblem;
using FsiSolver = NewtonStepper<FsiProblem>;

} // namespace tearflow::physics
