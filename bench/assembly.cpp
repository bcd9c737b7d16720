// Assembly rates of the rigid-wall flow problem, phase by phase; prints one JSON object.
//
//   kernel     navier_stokes_jacobian on every local tet, nothing inserted
//   insertion  fem::ElementInserter of one fixed element matrix per tet, no kernel; and
//              the matrix assembly (ghost rows to their owners)
//   jacobian   FluidProblem::add_jacobian: staging, gathering, kernel and insertion; and
//              the matrix assembly
//   residual   FluidProblem::add_residual: the same for the residual vector
//   residual_kernel  navier_stokes_residual on every local tet, nothing added
//
// on the built-in pipe (R 1 cm, L 10 cm, steady inflow 50 mL/s, resistance outlet) after
// one time step, so that the state is a real flow. Each phase is repeated and the fastest
// repetition is kept, timed in CPU time of the thread (the least disturbed by other jobs on
// a shared machine); rates are elements per second per rank (= per core). Build: `cmake --build
// build --target bench_assembly`; run: `build/bench_assembly [--element-size 0.0014] [--repeat 5]`.
#include <algorithm>
#include <cstdio>
#include <ctime>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "fem/element_inserter.hpp"
#include "fem/petsc.hpp"
#include "physics/navier_stokes_kernel.hpp"
#include "run/simulation.hpp"

using namespace tearflow;

namespace {

io::Case pipe_case(double element_size) {
  io::Case c;
  c.name = "bench-assembly";
  c.mesh.pipe = mesh::PipeSpec{0.01, 0.1, element_size};
  c.time = {0.005, 1, 0.5};
  c.boundary_conditions = {{"wall", bc::NoSlip{}},
                           {"inlet", bc::Inflow{bc::Waveform::constant(50e-6)}}, // 50 mL/s
                           {"outlet", bc::Outlet{bc::ResistanceOutlet{1.0e8, 0.0}}}};
  c.output.every = 0;
  return c;
}

/// CPU time of this thread [s]: unlike wall time it does not count the time other jobs
/// on a shared machine hold the core.
double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// Fastest of `repeat` CPU timings of f() [s], the slowest rank's time in each.
template <typename F> double fastest(int repeat, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    MPI_Barrier(PETSC_COMM_WORLD);
    const double t0 = cpu_seconds();
    f();
    double s = cpu_seconds() - t0;
    MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    best = std::min(best, s);
  }
  return best;
}

int bench(double element_size, int repeat) {
  io::Case c = pipe_case(element_size);
  c.output.directory = std::filesystem::temp_directory_path() / "tearflow-bench-assembly";
  run::Simulation sim(c);
  sim.advance();
  physics::FluidProblem& problem = sim.fluid();
  const fem::DofMap& dofs = problem.dofs();
  const fem::DistributedMesh& dm = sim.distributed_mesh();
  const auto& tets = dm.tets();
  const size_t n = tets.size();
  Vec U = sim.solution();

  // The kernels' inputs, as FluidProblem stages them: geometry, lagged stabilization and
  // the nodal state of the converged step (acceleration and mesh velocity zero).
  std::vector<fem::TetGeometry> geo(n);
  std::vector<physics::Stabilization> stab(n);
  std::vector<physics::FluidElementState> state(n);
  {
    fem::OwnedVec U_loc = dofs.create_local();
    dofs.global_to_local(U, U_loc);
    fem::ReadArray u(U_loc);
    const auto& x = dm.points();
    for (size_t e = 0; e < n; ++e) {
      const Tet& t = tets[e];
      geo[e] = fem::tet_geometry({x[t[0]], x[t[1]], x[t[2]], x[t[3]]});
      Vec3 mean{};
      for (int a = 0; a < 4; ++a) {
        for (int i = 0; i < 3; ++i)
          state[e].u[a][i] = u[4 * t[a] + i];
        state[e].udot[a] = Vec3{};
        state[e].p[a] = u[4 * t[a] + 3];
        mean = mean + 0.25 * state[e].u[a];
      }
      stab[e] = physics::stabilization(geo[e], mean, problem.fluid(), c.time.step);
    }
  }
  const double c_u = problem.scheme().c_u(), c_a = problem.scheme().c_a(c.time.step);

  // A sink the compiler cannot drop: one entry of every element matrix summed.
  double sink = 0.0;
  physics::ElementMatrix K{};
  physics::ElementVector Re{};
  const double kernel = fastest(repeat, [&] {
    for (size_t e = 0; e < n; ++e) {
      physics::navier_stokes_jacobian(geo[e], state[e], stab[e], problem.fluid(), c_u, c_a, K);
      sink += K[e % 16][(e / 16) % 16];
    }
  });
  const double residual_kernel = fastest(repeat, [&] {
    for (size_t e = 0; e < n; ++e) {
      physics::navier_stokes_residual(geo[e], state[e], stab[e], problem.fluid(), Re);
      sink += Re[e % 16];
    }
  });

  // Insertion alone: the first pass records the pattern through MatSetValues.
  fem::OwnedMat A = dofs.create_matrix("bench_");
  fem::ElementInserter inserter(dofs);
  // Each pass ends with the matrix assembly: on several ranks it sends the ghost rows.
  auto assemble = [](Mat M) {
    TF_PETSC(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY));
    TF_PETSC(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY));
  };
  auto insert_all = [&] {
    inserter.begin(A);
    for (size_t e = 0; e < n; ++e)
      inserter.add(e, &K[0][0]);
    inserter.end();
    assemble(A);
  };
  insert_all();
  const double insertion = fastest(repeat, insert_all);

  // The whole Jacobian and residual passes of the solver, into A: its pattern is complete
  // (the problem's inserter recorded its offsets on the solver's matrix of the same pattern).
  Mat J = A;
  const double jacobian = fastest(repeat, [&] {
    problem.add_jacobian(U, J);
    assemble(J);
  });
  fem::OwnedVec R_loc = dofs.create_local();
  const double residual = fastest(repeat, [&] {
    TF_PETSC(VecZeroEntries(R_loc));
    problem.add_residual(U, R_loc);
  });

  // A fingerprint of the assembled matrix: an optimised kernel must leave it unchanged
  // (to round-off) on the same mesh and state.
  double norm_J = 0.0;
  TF_PETSC(MatNorm(J, NORM_FROBENIUS, &norm_J));

  const int ranks = fem::mpi_size();
  long long tets_total = static_cast<long long>(n);
  MPI_Allreduce(MPI_IN_PLACE, &tets_total, 1, MPI_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD);
  auto phase = [&](double seconds) {
    return nlohmann::json{{"seconds", seconds},
                          {"million_elements_per_second_per_rank", n / seconds / 1e6}};
  };
  nlohmann::json out = {{"element_size_m", element_size},
                        {"tets", tets_total},
                        {"ranks", ranks},
                        {"tets_rank0", n},
                        {"repeat", repeat},
                        {"kernel", phase(kernel)},
                        {"insertion", phase(insertion)},
                        {"jacobian", phase(jacobian)},
                        {"residual_kernel", phase(residual_kernel)},
                        {"residual", phase(residual)},
                        {"jacobian_frobenius_norm", norm_J},
                        {"sink", sink}};
  if (fem::mpi_rank() == 0)
    std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"assembly rates of the rigid-wall flow problem (JSON)"};
  double element_size = 0.0014;
  int repeat = 5;
  app.add_option("--element-size", element_size, "pipe element size [m]")
      ->check(CLI::PositiveNumber);
  app.add_option("--repeat", repeat, "repetitions per phase (the fastest is kept)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  int petsc_argc = 1;
  fem::PetscSession session(&petsc_argc, &argv);
  return bench(element_size, repeat);
}
