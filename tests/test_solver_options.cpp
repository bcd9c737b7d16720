// Solver options per run (fem/solver_options.hpp): a library caller's case options reach its
// solvers as the command line's do; neither they nor a run's solver defaults reach PETSc's
// global database or the next run in the process.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <petscsys.h>

#include "core/error.hpp"
#include "fem/petsc.hpp"
#include "fem/solver_options.hpp"
#include "physics/preconditioner_lag.hpp"
#include "run/simulation.hpp"

namespace tearflow {
namespace {

/// A short rigid pipe, steady inflow, pressure outlet; one step is enough.
io::Case pipe_case(const std::string& petsc_options) {
  io::Case c;
  c.name = "solver-options";
  c.mesh.pipe = mesh::PipeSpec{0.005, 0.02, 0.002};
  c.time.step = 0.01;
  c.time.steps = 1;
  c.boundary_conditions = {{"wall", bc::NoSlip{}},
                           {"inlet", bc::Inflow{bc::Waveform::constant(2e-6)}},
                           {"outlet", bc::Outlet{bc::PressureOutlet{}}}};
  c.petsc_options = petsc_options;
  return c;
}

bool globally_set(const char* name) {
  PetscBool set = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, name, &set);
  return set;
}

TEST(SolverOptions, ACasesOptionsReachItsRunAndStayThere) {
  // A direct solve: one Krylov iteration per Newton iteration.
  run::Simulation direct(pipe_case("-fluid_ksp_type preonly -fluid_pc_type lu"));
  const physics::StepReport a = direct.advance();
  ASSERT_GT(a.newton_iterations, 0);
  EXPECT_EQ(a.linear_iterations, a.newton_iterations);
  // Neither the case's options nor the fluid solver's defaults went global.
  EXPECT_FALSE(globally_set("-fluid_ksp_type"));
  EXPECT_FALSE(globally_set("-fluid_pc_type"));
  EXPECT_FALSE(globally_set("-fluid_pc_fieldsplit_type"));
  // The next run, made while the first lives, solves with the defaults (GMRES, field split).
  run::Simulation iterative(pipe_case(""));
  const physics::StepReport b = iterative.advance();
  EXPECT_GT(b.linear_iterations, b.newton_iterations);
}

TEST(SolverOptions, ARunStartsFromTheOptionsInForceAndItsOwnWin) {
  PetscOptionsSetValue(nullptr, "-test_solver_options_global", "1");
  PetscOptionsSetValue(nullptr, "-test_solver_options_both", "global");
  {
    const fem::SolverOptions outer("-test_solver_options_both case -test_solver_options_flag");
    std::string value;
    EXPECT_TRUE(outer.get("-test_solver_options_global", &value));
    EXPECT_EQ(value, "1");
    EXPECT_TRUE(outer.get("-test_solver_options_both", &value));
    EXPECT_EQ(value, "case"); // the case's (and the command line's after it) win
    EXPECT_TRUE(outer.get("-test_solver_options_flag", &value));
    EXPECT_EQ(value, "");
    {
      const fem::SolverOptions::Scope scope(outer);
      EXPECT_TRUE(globally_set("-test_solver_options_flag")); // PETSc's default now
      fem::set_default_options({{"-test_solver_options_default", "x"}});
      const fem::SolverOptions::Scope again(outer); // nested: nothing changes
      const fem::SolverOptions inner(""); // a run made inside another starts from its options
      EXPECT_TRUE(inner.get("-test_solver_options_default"));
      EXPECT_TRUE(inner.get("-test_solver_options_flag"));
    }
    EXPECT_FALSE(globally_set("-test_solver_options_flag"));
    EXPECT_FALSE(globally_set("-test_solver_options_default")); // defaults stayed in the run's
    EXPECT_TRUE(outer.get("-test_solver_options_default"));
  }
  PetscOptionsClearValue(nullptr, "-test_solver_options_global");
  PetscOptionsClearValue(nullptr, "-test_solver_options_both");
}

/// The builds PreconditionerLag decides for Jacobians preceded by linear solves of these
/// Krylov counts (the first entry: the run's first Jacobian, no solve before it).
std::vector<bool> builds(physics::PreconditionerLag lag, const std::vector<int>& iterations) {
  std::vector<bool> b;
  for (int its : iterations)
    b.push_back(lag.due(its));
  return b;
}

TEST(SolverOptions, ALaggedPreconditionerIsBuiltAgainWhenItsSolvesGrow) {
  // Lag 10, growth 2: the first solve after a build took 20, so one of more than 40 builds
  // anew, and the next build's first solve (15) sets the bar at 30.
  EXPECT_EQ(builds({10, 2.0}, {0, 20, 30, 40, 41, 15, 30, 31}),
            (std::vector<bool>{true, false, false, false, true, false, false, true}));
  // A first solve under PreconditionerLag::kMinIterations counts as that many: 4 sets the bar
  // at 20, not 8.
  EXPECT_EQ(builds({10, 2.0}, {0, 4, 20, 21}), (std::vector<bool>{true, false, false, true}));
  // Without growth the lag alone decides: the 10th Jacobian after a build, whatever the counts.
  std::vector<int> growing{0};
  for (int i = 1; i <= 11; ++i)
    growing.push_back(20 * i);
  std::vector<bool> every_tenth(12, false);
  every_tenth[0] = every_tenth[10] = true;
  EXPECT_EQ(builds({10, 0.0}, growing), every_tenth);
  // A build asked for (a checkpoint) restarts the counts: the solves before it do not count.
  physics::PreconditionerLag lag(10, 2.0);
  EXPECT_TRUE(lag.due(0));
  EXPECT_FALSE(lag.due(20));
  EXPECT_FALSE(lag.due(30));
  lag.rebuild_next();
  EXPECT_TRUE(lag.due(1000));
  EXPECT_FALSE(lag.due(50));  // the first solve after this build
  EXPECT_FALSE(lag.due(100)); // twice it
  EXPECT_TRUE(lag.due(101));
}

TEST(SolverOptions, ABadPreconditionerGrowthIsRefused) {
  EXPECT_THROW(run::Simulation(pipe_case("-fluid_lag_preconditioner_growth 0.5")), InputError);
  run::Simulation grown(pipe_case("-fluid_lag_preconditioner_growth 2"));
  EXPECT_GT(grown.advance().newton_iterations, 0);
}

} // namespace
} // namespace tearflow

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  tearflow::fem::PetscSession petsc(&argc, &argv);
  return RUN_ALL_TESTS();
}
