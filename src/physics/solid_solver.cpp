#include "physics/solid_solver.hpp"

#include <utility>
#include <vector>

#include <fmt/format.h>

#include "fem/petsc.hpp"

namespace tearflow::physics {

namespace {
/// Measured on bench/solid_step.py (tube wall, 100 k tets, nu = 0.49; docs/performance.md):
/// hypre's defaults took 7.2 s per Newton iteration, GAMG on the velocity block 2.5 s,
/// MUMPS LU 26 s; HMIS coarsening with ext+i interpolation, P_max 4 and one level of
/// aggressive coarsening (strong threshold 0.7 for the 3D vector block) on both blocks and
/// an upper-triangular Schur factorization 1.4 s.
fem::OptionList default_solid_options() {
  return {{"-solid_pc_type", "fieldsplit"},
          {"-solid_pc_fieldsplit_type", "schur"},
          {"-solid_pc_fieldsplit_schur_fact_type", "upper"},
          {"-solid_pc_fieldsplit_schur_precondition", "selfp"},
          {"-solid_fieldsplit_0_ksp_type", "preonly"},
          {"-solid_fieldsplit_0_pc_type", "hypre"},
          {"-solid_fieldsplit_0_pc_hypre_boomeramg_strong_threshold", "0.7"},
          {"-solid_fieldsplit_0_pc_hypre_boomeramg_coarsen_type", "HMIS"},
          {"-solid_fieldsplit_0_pc_hypre_boomeramg_interp_type", "ext+i"},
          {"-solid_fieldsplit_0_pc_hypre_boomeramg_P_max", "4"},
          {"-solid_fieldsplit_0_pc_hypre_boomeramg_agg_nl", "1"},
          {"-solid_fieldsplit_1_ksp_type", "preonly"},
          {"-solid_fieldsplit_1_pc_type", "hypre"},
          {"-solid_fieldsplit_1_pc_hypre_boomeramg_coarsen_type", "HMIS"},
          {"-solid_fieldsplit_1_pc_hypre_boomeramg_interp_type", "ext+i"},
          {"-solid_fieldsplit_1_pc_hypre_boomeramg_P_max", "4"},
          {"-solid_fieldsplit_1_pc_hypre_boomeramg_agg_nl", "1"}};
}
} // namespace

SolidSolver::SolidSolver(SolidProblem& problem, const physics::NewtonSpec& newton)
    : problem_(problem) {
  const fem::DofMap& dofs = problem.dofs();
  U_ = dofs.create_global();
  D_ = dofs.create_global();
  A_ = dofs.create_global();
  U_prev_ = dofs.create_global();
  R_ = dofs.create_global();
  J_ = dofs.create_matrix("solid_");

  TF_PETSC(SNESCreate(dofs.mesh().comm(), snes_.out()));
  TF_PETSC(SNESSetOptionsPrefix(snes_, "solid_"));
  TF_PETSC(SNESSetFunction(snes_, R_, form_residual, this));
  TF_PETSC(SNESSetJacobian(snes_, J_, J_, form_jacobian, this));
  TF_PETSC(SNESSetType(snes_, SNESNEWTONLS));
  SNESLineSearch ls;
  TF_PETSC(SNESGetLineSearch(snes_, &ls));
  TF_PETSC(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC)); // exact tangent: full steps
  TF_PETSC(SNESSetTolerances(snes_, newton.atol, newton.rtol, 0.0, newton.max_iterations, -1));
  TF_PETSC(SNESSetForceIteration(snes_, PETSC_TRUE));
  KSP ksp;
  TF_PETSC(SNESGetKSP(snes_, &ksp));
  fem::use_gmres(ksp, 200);
  TF_PETSC(KSPSetTolerances(ksp, 1e-6, 1e-50, PETSC_DEFAULT, 1000));
  fem::set_default_options(default_solid_options());
  TF_PETSC(SNESSetFromOptions(snes_));
  set_default_split();
  TF_PETSC(SNESSetConvergenceHistory(snes_, residual_history_.data(), nullptr,
                                     static_cast<PetscInt>(residual_history_.size()), PETSC_TRUE));
}

void SolidSolver::set_default_split() {
  KSP ksp;
  PC pc;
  TF_PETSC(SNESGetKSP(snes_, &ksp));
  TF_PETSC(KSPGetPC(ksp, &pc));
  PetscBool is_split = PETSC_FALSE;
  TF_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &is_split));
  if (!is_split || fem::option_set("-solid_pc_fieldsplit_0_fields") ||
      fem::option_set("-solid_pc_fieldsplit_block_size"))
    return;
  const fem::DistributedMesh& mesh = problem_.dofs().mesh();
  const Index n = mesh.num_owned();
  std::vector<PetscInt> velocity(3 * static_cast<size_t>(n)), pressure(n);
  for (Index l = 0; l < n; ++l) {
    for (int c = 0; c < 3; ++c)
      velocity[3 * l + c] = problem_.dofs().global_dof(l, c);
    pressure[l] = problem_.dofs().global_dof(l, 3);
  }
  MPI_Comm comm = mesh.comm();
  fem::OwnedIS is_v, is_p;
  TF_PETSC(ISCreateGeneral(comm, 3 * n, velocity.data(), PETSC_COPY_VALUES, is_v.out()));
  TF_PETSC(ISSetBlockSize(is_v, 3));
  TF_PETSC(ISCreateGeneral(comm, n, pressure.data(), PETSC_COPY_VALUES, is_p.out()));

  // Rigid-body modes of the reference configuration, in the velocity block's ordering.
  fem::OwnedVec coords;
  TF_PETSC(VecCreateMPI(comm, 3 * n, PETSC_DETERMINE, coords.out()));
  TF_PETSC(VecSetBlockSize(coords, 3));
  {
    fem::WriteArray x(coords);
    for (Index l = 0; l < n; ++l)
      for (int c = 0; c < 3; ++c)
        x[3 * l + c] = mesh.points()[l][c];
  }
  MatNullSpace rigid;
  TF_PETSC(MatNullSpaceCreateRigidBody(coords, &rigid));
  TF_PETSC(PetscObjectCompose(reinterpret_cast<PetscObject>(is_v.get()), "nearnullspace",
                              reinterpret_cast<PetscObject>(rigid)));
  TF_PETSC(MatNullSpaceDestroy(&rigid));
  TF_PETSC(PCFieldSplitSetIS(pc, "0", is_v));
  TF_PETSC(PCFieldSplitSetIS(pc, "1", is_p));
}

PetscErrorCode SolidSolver::form_residual(SNES, Vec U, Vec R, void* ctx) {
  auto* self = static_cast<SolidSolver*>(ctx);
  return self->callback_error_.timed_guard(self->assembly_seconds_,
                                           [&] { self->problem_.residual(U, R); });
}

PetscErrorCode SolidSolver::form_jacobian(SNES, Vec U, Mat, Mat P, void* ctx) {
  auto* self = static_cast<SolidSolver*>(ctx);
  return self->callback_error_.timed_guard(self->assembly_seconds_,
                                           [&] { self->problem_.jacobian(U, P); });
}

StepReport SolidSolver::step(double t, double dt) {
  const double start = MPI_Wtime();
  assembly_seconds_ = 0.0;
  callback_error_.clear();
  problem_.begin_step(t, dt, U_, D_, A_);
  TF_PETSC(VecCopy(U_, U_prev_));
  problem_.apply_dirichlet(U_);

  const PetscErrorCode err = SNESSolve(snes_, nullptr, U_);
  SNESConvergedReason reason;
  SNESGetConvergedReason(snes_, &reason);
  const StepReport report = read_step_report(snes_, start, assembly_seconds_);
  if (const std::string why = newton_failure(err, callback_error_, reason, report.residual_final);
      !why.empty()) {
    TF_PETSC(VecCopy(U_prev_, U_)); // D and A are still t's
    throw SolverError(fmt::format("solid: Newton failed in the step from t = {:.6g} s to {:.6g} s "
                                  "after {} iterations (residual {:.3e}, initial {:.3e}): {}",
                                  t, t + dt, report.newton_iterations, report.residual_final,
                                  report.residual_initial, why),
                      err == 0 || callback_error_.collective); // as the fluid's (fluid_solver.cpp)
  }
  problem_.update_state(U_, D_, A_);
  return report;
}

} // namespace tearflow::physics
