#pragma once
// Advances a SolidProblem in time: one Newton solve (PETSc SNES, options prefix `solid_`)
// per generalized-alpha step, with the consistent tangent. Default linear solver, entered
// only where the user set nothing: GMRES with a Schur-complement field split of velocity
// (dofs 0-2) and pressure (dof 3), BoomerAMG on the velocity block (block size 3, the six
// rigid-body modes as its near null space, MatNullSpaceCreateRigidBody) and on the selfp
// Schur approximation, upper-triangular factorization; BoomerAMG tuned as measured in
// solid_solver.cpp. Every choice can be changed through PETSc options.
#include <array>
#include <string>

#include "physics/fluid_solver.hpp"
#include "physics/newton_spec.hpp"
#include "physics/solid_problem.hpp"

namespace tearflow::physics {

class SolidSolver {
public:
  SolidSolver(SolidProblem& problem, const physics::NewtonSpec& newton);

  /// The state at the current time; starts at rest in the reference configuration.
  Vec solution() const { return U_; }     ///< (v, p)
  Vec displacement() const { return D_; } ///< (u, 0)
  Vec acceleration() const { return A_; } ///< (a, 0)

  /// One step t -> t + dt. Throws SolverError naming the step if Newton fails or a NaN
  /// appears; the state is then left at time t.
  StepReport step(double t, double dt);

private:
  static PetscErrorCode form_residual(SNES, Vec U, Vec R, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec U, Mat J, Mat P, void* ctx);
  void set_default_split(); ///< velocity / pressure index sets with the rigid-body modes

  SolidProblem& problem_;
  fem::OwnedVec U_, D_, A_, U_prev_, R_;
  fem::OwnedMat J_;
  fem::OwnedSNES snes_;
  double assembly_seconds_ = 0.0;
  CallbackError callback_error_;
  std::array<PetscReal, 64> residual_history_{};
};

} // namespace tearflow::physics
