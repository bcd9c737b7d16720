#include "physics/fluid_solver.hpp"

#include "physics/fsi_problem.hpp"

#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tearflow::physics {

fem::OptionList FluidProblem::default_solver_options() {
  fem::OptionList options = {{"-fluid_pc_type", "fieldsplit"},
                             {"-fluid_pc_fieldsplit_0_fields", "0,1,2"},
                             {"-fluid_pc_fieldsplit_1_fields", "3"},
                             {"-fluid_pc_fieldsplit_type", "schur"},
                             {"-fluid_pc_fieldsplit_schur_fact_type", "full"},
                             {"-fluid_pc_fieldsplit_schur_precondition", "user"},
                             {"-fluid_fieldsplit_0_ksp_type", "preonly"},
                             {"-fluid_fieldsplit_0_pc_type", "bjacobi"},
                             {"-fluid_fieldsplit_1_ksp_type", "preonly"},
                             {"-fluid_snes_lag_preconditioner", "3"},
                             {"-fluid_snes_lag_preconditioner_persists", "true"}};
  for (auto& option : fem::boomeramg_3d_options("-fluid_fieldsplit_1_"))
    options.push_back(std::move(option));
  return options;
}

template <typename Problem>
NewtonStepper<Problem>::NewtonStepper(Problem& problem, const physics::NewtonSpec& newton)
    : problem_(problem), newton_(newton) {
  const fem::DofMap& dofs = problem.dofs();
  U_ = dofs.create_global();
  Udot_ = dofs.create_global();
  U_prev_ = dofs.create_global();
  R_ = dofs.create_global();
  P_ = dofs.create_matrix(Problem::options_prefix);

  const bool coupled_outlets = problem.has_coupled_outlets();
  MPI_Comm comm = dofs.mesh().comm();
  if (coupled_outlets) {
    const PetscInt n = dofs.num_owned_dofs();
    TF_PETSC(MatCreateShell(comm, n, n, PETSC_DETERMINE, PETSC_DETERMINE, this, J_.out()));
    TF_PETSC(MatShellSetOperation(J_, MATOP_MULT, (void (*)(void))shell_mult));
  }

  TF_PETSC(SNESCreate(comm, snes_.out()));
  TF_PETSC(SNESSetOptionsPrefix(snes_, Problem::options_prefix));
  TF_PETSC(SNESSetFunction(snes_, R_, form_residual, this));
  TF_PETSC(SNESSetJacobian(snes_, coupled_outlets ? J_.get() : P_.get(), P_, form_jacobian, this));
  TF_PETSC(SNESSetType(snes_, SNESNEWTONLS));
  SNESLineSearch ls;
  TF_PETSC(SNESGetLineSearch(snes_, &ls));
  // The exact Jacobian makes full Newton steps converge; a line search only costs residuals.
  TF_PETSC(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  TF_PETSC(SNESSetTolerances(snes_, newton.atol, newton.rtol, 0.0, newton.max_iterations, -1));
  // Every step must do at least one Newton iteration: the initial guess is never the answer.
  TF_PETSC(SNESSetForceIteration(snes_, PETSC_TRUE));
  TF_PETSC(SNESSetConvergenceTest(snes_, converged, this, nullptr));
  PetscBool monitor = PETSC_FALSE;
  TF_PETSC(PetscOptionsHasName(nullptr, Problem::options_prefix, "-newton_field_norms", &monitor));
  monitor_fields_ = monitor;
  KSP ksp;
  TF_PETSC(SNESGetKSP(snes_, &ksp));
  fem::use_gmres(ksp, 200);
  TF_PETSC(KSPSetTolerances(ksp, 1e-4, 1e-14, PETSC_DEFAULT, 1000));
  // Default preconditioner: Schur-complement field split of velocity (dofs 0-2) and
  // pressure (dof 3). The velocity block is dominated by the mass matrix / dt at cardiac
  // time steps, so block-Jacobi ILU(0) suffices; the selfp Schur approximation is a
  // pressure Laplacian and gets BoomerAMG with the HMIS / ext+i settings for 3D problems
  // (cheaper setup and V-cycle than the default Falgout coarsening at equal iterations).
  // The preconditioner is rebuilt every third Newton iteration, across time steps: the
  // operator changes little from one iteration to the next and GMRES absorbs the lag.
  // Measured on pipe-rcr (170 k tets, dt = 5 ms, 1 rank): 20 s/step with BoomerAMG on both
  // blocks rebuilt every iteration, 2.9 s/step with these defaults, same Newton iterations;
  // ILU(0) on the coupled system stalled (> 1000 GMRES iterations). Entered only where the
  // user set nothing, so any PETSc option wins.
  fem::set_default_options(Problem::default_solver_options());
  TF_PETSC(SNESSetFromOptions(snes_));
  // The preconditioner's lag is counted by lag_ (preconditioner_lag.hpp); SNES only carries it
  // out.
  PetscInt lag = 1;
  TF_PETSC(SNESGetLagPreconditioner(snes_, &lag));
  PetscBool persists = PETSC_FALSE;
  TF_PETSC(PetscOptionsGetBool(nullptr, Problem::options_prefix,
                               "-snes_lag_preconditioner_persists", &persists, nullptr));
  lag_persists_ = persists;
  TF_PETSC(SNESSetLagPreconditioner(snes_, -1));
  PetscReal contraction = 0.0;
  TF_PETSC(PetscOptionsGetReal(nullptr, Problem::options_prefix, "-jacobian_reuse_contraction",
                               &contraction, nullptr));
  if (!(contraction >= 0.0 && contraction < 1.0))
    throw InputError(fmt::format("-{}jacobian_reuse_contraction {}: expected a number in [0, 1) "
                                 "(0: a Jacobian every Newton iteration)",
                                 Problem::options_prefix, contraction));
  reuse_contraction_ = contraction;
  PetscReal growth = 0.0;
  TF_PETSC(PetscOptionsGetReal(nullptr, Problem::options_prefix, "-lag_preconditioner_growth",
                               &growth, nullptr));
  if (!(growth == 0.0 || growth > 1.0))
    throw InputError(fmt::format("-{}lag_preconditioner_growth {}: expected 0 (the lag alone) or "
                                 "a factor above 1",
                                 Problem::options_prefix, growth));
  lag_ = PreconditionerLag(static_cast<int>(lag), growth);
  if constexpr (requires(Problem & p, KSP k) { p.attach_preconditioner(k); })
    problem.attach_preconditioner(ksp);
  TF_PETSC(SNESSetConvergenceHistory(snes_, residual_history_.data(), nullptr,
                                     static_cast<PetscInt>(residual_history_.size()), PETSC_TRUE));
}

template <typename Problem> PetscErrorCode NewtonStepper<Problem>::shell_mult(Mat J, Vec x, Vec y) {
  void* ctx;
  MatShellGetContext(J, &ctx);
  auto* self = static_cast<NewtonStepper*>(ctx);
  return self->callback_error_.guard([&] {
    TF_PETSC(MatMult(self->P_, x, y));
    self->problem_.add_coupled_outlets(x, y);
  });
}

template <typename Problem> std::array<double, 3> NewtonStepper<Problem>::field_norms(Vec R) const {
  const ResidualFields fields = problem_.residual_fields();
  std::array<PetscReal, 8> two{}, one{};
  PetscInt block = 0;
  TF_PETSC(VecGetBlockSize(R, &block));
  TF_PETSC(VecStrideNormAll(R, NORM_2, two.data()));
  TF_PETSC(VecStrideNormAll(R, NORM_1, one.data()));
  double momentum = 0.0;
  for (PetscInt c = 0; c < block; ++c)
    if (c != fields.continuity && c != fields.constraint)
      momentum += two[c] * two[c];
  return {std::sqrt(momentum), one[fields.continuity],
          fields.constraint >= 0 ? two[fields.constraint] : 0.0};
}

// One norm over rows of different units (momentum in N, continuity in m^3/s) lets the larger
// hide the other: the grad-div term moves continuity error into the momentum rows, and the
// mass a step fails to conserve then depended on the grad-div scale (docs/performance.md).
// Each field is tested on its own (newton_spec.hpp); PETSc's default test still decides
// divergence (NaN, a residual grown beyond its divergence tolerance).
template <typename Problem>
PetscErrorCode NewtonStepper<Problem>::converged(SNES snes, PetscInt it, PetscReal xnorm,
                                                 PetscReal snorm, PetscReal fnorm,
                                                 SNESConvergedReason* reason, void* ctx) {
  auto* self = static_cast<NewtonStepper*>(ctx);
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (*reason < 0)
    return 0;
  *reason = SNES_CONVERGED_ITERATING;
  return self->callback_error_.guard([&] {
    Vec R;
    TF_PETSC(SNESGetFunction(snes, &R, nullptr, nullptr));
    const std::array<double, 3> n = self->field_norms(R);
    if (self->monitor_fields_ && fem::mpi_rank(self->problem_.dofs().mesh().comm()) == 0)
      fmt::print("  {} Newton field norms: momentum {:.3e} N, continuity {:.3e} m^3/s (1-norm), "
                 "wall constraint {:.3e}\n",
                 it, n[0], n[1], n[2]);
    // Each field relative to its largest norm in the step: a field can start at zero (the
    // continuity and the wall's constraint from rest) and grow in the first iteration.
    if (it == 0)
      self->largest_norms_ = n;
    for (int k = 0; k < 3; ++k)
      self->largest_norms_[k] = std::max(self->largest_norms_[k], n[k]);
    if (it == 0) // every step iterates at least once
      return;
    const NewtonSpec& spec = self->newton_;
    const auto within = [&](int k) {
      return n[k] <= std::max(spec.atol, spec.rtol * self->largest_norms_[k]);
    };
    const double flow = self->problem_.residual_fields().flow_scale;
    const bool continuity = flow > 0.0 ? n[1] <= spec.continuity * flow : within(1);
    if (within(0) && continuity && within(2))
      *reason = SNES_CONVERGED_FNORM_RELATIVE;
  });
}

template <typename Problem>
PetscErrorCode NewtonStepper<Problem>::form_residual(SNES, Vec U, Vec R, void* ctx) {
  auto* self = static_cast<NewtonStepper*>(ctx);
  return self->callback_error_.timed_guard(self->assembly_seconds_,
                                           [&] { self->problem_.residual(U, R); });
}

// Newton with the Jacobian kept while it contracts well (between Newton's method and the
// chord method, which keeps one Jacobian throughout): where the last iteration reduced ||R|| by
// the factor theta or better, the iterate moved little and the next iteration keeps the
// Jacobian; where it did not (always the first iteration of a step), the Jacobian is assembled
// anew. A kept Jacobian contracts linearly, not quadratically, so theta must be small enough
// that the linear rate still meets the tolerance in as many iterations (fsi_problem.cpp
// measures it). The decision depends on the step's own residual history alone, so a restarted
// run repeats it.
template <typename Problem> bool NewtonStepper<Problem>::jacobian_reusable(SNES snes) const {
  if (reuse_contraction_ <= 0.0 || !reuse_allowed_ || lag_.rebuild_pending() || jacobians_ == 0)
    return false;
  PetscInt k = 0, length = 0;
  PetscReal* history = nullptr;
  SNESGetIterationNumber(snes, &k);
  SNESGetConvergenceHistory(snes, &history, nullptr, &length);
  return k > 0 && k < length && history[k] <= reuse_contraction_ * history[k - 1];
}

template <typename Problem>
PetscErrorCode NewtonStepper<Problem>::form_jacobian(SNES snes, Vec U, Mat A, Mat P, void* ctx) {
  auto* self = static_cast<NewtonStepper*>(ctx);
  return self->callback_error_.timed_guard(self->assembly_seconds_, [&] {
    if (self->jacobian_reusable(snes)) { // P unchanged: the preconditioner stays too
      ++self->jacobians_reused_;
      TF_PETSC(SNESSetLagPreconditioner(snes, -1));
    } else {
      ++self->jacobians_;
      // SNES decides on the preconditioner after this callback: -2 rebuilds it once.
      KSP ksp;
      PetscInt last_iterations = 0;
      TF_PETSC(SNESGetKSP(snes, &ksp));
      TF_PETSC(KSPGetIterationNumber(ksp, &last_iterations));
      const bool build = self->lag_.due(static_cast<int>(last_iterations));
      TF_PETSC(SNESSetLagPreconditioner(snes, build ? -2 : -1));
      self->problem_.jacobian(U, P);
      if (build)
        self->problem_.assemble_schur_preconditioner();
    }
    // The operator, where it is not P: the shell adding the coupled outlets, or PETSc's
    // finite-difference one (-snes_mf_operator), which takes its base point here.
    if (A != P) {
      TF_PETSC(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
      TF_PETSC(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
    }
  });
}

template <typename Problem> bool NewtonStepper<Problem>::uses_exact_operator() const {
  PetscBool mf_operator = PETSC_FALSE, mf = PETSC_FALSE;
  TF_PETSC(SNESGetUseMatrixFree(snes_, &mf_operator, &mf));
  return exact_operator_.get() != nullptr || mf_operator || mf;
}

template <typename Problem> void NewtonStepper<Problem>::use_exact_operator() {
  if (uses_exact_operator())
    return;
  TF_PETSC(MatCreateSNESMF(snes_, exact_operator_.out()));
  TF_PETSC(SNESSetJacobian(snes_, exact_operator_, P_, form_jacobian, this));
}

template <typename Problem> void NewtonStepper<Problem>::store_pressure_change() {
  // The pressure has no time derivative in the scheme (its slot in Udot is read by no
  // residual); the slot keeps p_{n+1} - p_n, with which the frames align the stage pressure
  // to t_{n+1} (run/flow_model.cpp), and which a checkpoint carries across a restart.
  const int bs = problem_.dofs().block();
  fem::ReadArray u(U_), un(U_prev_);
  fem::WriteArray ud(Udot_);
  PetscInt n = 0;
  TF_PETSC(VecGetLocalSize(U_, &n));
  for (PetscInt i = pressure_slot; i < n; i += bs)
    ud[i] = u[i] - un[i];
}

template <typename Problem> StepReport NewtonStepper<Problem>::step(double t, double dt) {
  const double start = MPI_Wtime();
  assembly_seconds_ = 0.0;
  callback_error_.clear();
  problem_.begin_step(t, dt, U_, Udot_);
  TF_PETSC(VecCopy(U_, U_prev_));
  problem_.apply_dirichlet(U_);
  if (!lag_persists_)
    lag_.rebuild_next();
  reuse_allowed_ = true;
  jacobians_ = jacobians_reused_ = 0;
  PetscErrorCode err = SNESSolve(snes_, nullptr, U_);
  // The retries below are decided alike on every rank (SNES's reason is collective); rank 0
  // says so.
  const bool root = fem::mpi_rank(problem_.dofs().mesh().comm()) == 0;
  SNESConvergedReason reason;
  SNESGetConvergedReason(snes_, &reason);
  // Solves the step again from U_n with a freshly built preconditioner; the failed attempt's
  // iterations still count in the report (they were spent).
  int spent_its = 0, spent_lits = 0, spent_jacobians = 0;
  auto solve_again = [&] {
    const StepReport failed = read_step_report(snes_, start, assembly_seconds_);
    spent_its += failed.newton_iterations;
    spent_lits += failed.linear_iterations;
    spent_jacobians += jacobians_;
    jacobians_ = jacobians_reused_ = 0;
    TF_PETSC(VecCopy(U_prev_, U_));
    problem_.apply_dirichlet(U_);
    lag_.rebuild_next();
    err = SNESSolve(snes_, nullptr, U_);
    SNESGetConvergedReason(snes_, &reason);
  };
  // A preconditioner lagged from earlier iterations can be too stale for a sudden change
  // (a valve-like flow reversal): retry the step once with a freshly built one.
  if (err == 0 && reason == SNES_DIVERGED_LINEAR_SOLVE && lag_.lag() != 1) {
    if (root)
      spdlog::info("step t = {:.6g} s: linear solve failed with the lagged preconditioner; "
                   "retrying with a new one",
                   t + dt);
    solve_again();
  }
  // A kept Jacobian can turn stale where the step changes course (a residual that stops
  // falling, then grows): solve the step again with one every iteration before anything else.
  if (err == 0 && reason < 0 && jacobians_reused_ > 0) {
    if (root)
      spdlog::info("step t = {:.6g} s: Newton with a kept Jacobian failed ({}); retrying with one "
                   "every iteration",
                   t + dt, SNESConvergedReasons[reason]);
    reuse_allowed_ = false;
    solve_again();
  }
  // An approximate Jacobian (FSI: the mesh inside the fluid held, or with
  // -fsi_interface_shape_derivatives false the interface too) can stall in a large step where
  // the wall moves much: retry with the exact operator, the residual differenced along each
  // Krylov direction (PETSc's -snes_mf_operator), preconditioned as before, and keep it for
  // the rest of the run (the steps after such a step stall alike). Measured on the
  // dissection at 8 mm and dt 20 ms: the quasi-Newton run stalls in step 6, this one converges
  // every step in 3-8 iterations; at small steps it costs 14-35 % more, so it is the fallback,
  // not the default (docs/performance.md).
  if constexpr (requires(const Problem& p) { p.jacobian_is_approximate(); }) {
    if (err == 0 && reason < 0 && problem_.jacobian_is_approximate() && !uses_exact_operator()) {
      if (root)
        spdlog::warn("step t = {:.6g} s: Newton with the approximate Jacobian failed ({}); "
                     "retrying, and going on, with the exact operator by finite differences",
                     t + dt, SNESConvergedReasons[reason]);
      use_exact_operator();
      solve_again();
    }
  }
  StepReport report = read_step_report(snes_, start, assembly_seconds_);
  report.newton_iterations += spent_its;
  report.retried_iterations = spent_its;
  report.linear_iterations += spent_lits;
  report.jacobians = spent_jacobians + jacobians_;
  if (const std::string why = newton_failure(err, callback_error_, reason, report.residual_final);
      !why.empty()) {
    TF_PETSC(VecCopy(U_prev_, U_)); // leave the last good state in place
    // SNES's reason and the residual norm are the same on every rank; an error raised in a
    // callback (err != 0) may be one rank's only, unless it says otherwise.
    throw SolverError(fmt::format("Newton failed in the step from t = {:.6g} s to {:.6g} s after "
                                  "{} iterations (residual {:.3e}, initial {:.3e}): {}",
                                  t, t + dt, report.newton_iterations, report.residual_final,
                                  report.residual_initial, why),
                      err == 0 || callback_error_.collective);
  }
  problem_.update_acceleration(U_, U_prev_, Udot_);
  store_pressure_change();
  problem_.commit_step(U_);
  return report;
}

template class NewtonStepper<FluidProblem>;
template class NewtonStepper<FsiProblem>;

} // namespace tearflow::physics
