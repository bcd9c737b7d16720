#pragma once
// One simulation from a validated case: case -> mesh -> partition -> physics -> solver ->
// outputs. `run` is what `tearflow run` does; verification drivers use `advance` and the
// accessors to compare the state with analytic solutions.
#include <functional>
#include <memory>
#include <vector>

#include "bc/windkessel_network.hpp"
#include "fem/distributed_mesh.hpp"
#include "fem/solver_options.hpp"
#include "io/case.hpp"
#include "io/checkpoint.hpp"
#include "physics/fluid_solver.hpp"
#include "run/run_record.hpp"

namespace tearflow::run {

struct RunOptions {
  bool restart = false; ///< continue from the output directory's checkpoint
  /// A checkpoint (of this case, perhaps at another time step) whose state starts a new run
  /// at its time, e.g. a finer step from a periodic state; empty: the case's own start.
  std::filesystem::path start_from;
  /// The case of the run that wrote `start_from`, when its mesh is another one than this
  /// case's: the state is interpolated to this mesh (fem/node_transfer.hpp).
  std::filesystem::path start_case;
  bool progress = true; ///< one progress line per step on stdout
  bool write_output = true;
  /// Called at the end of every cycle with its statistics and whether it is periodic by the
  /// case's tolerance, before the cycle's last frame and checkpoint are written; returns
  /// whether the run stops there. Without it the run stops when periodic.
  std::function<bool(const run::CycleStats&, bool periodic)> on_cycle;
};

struct RunSummary {
  int steps = 0; ///< steps taken by this call
  double wall_seconds = 0.0;
  std::vector<physics::StepReport> reports;
  bool periodic = false;               ///< stopped by the periodicity tolerance
  std::vector<run::CycleStats> cycles; ///< every complete cycle of the run
};

/// The case's mesh in SI units with outward-oriented faces, checked against the case.
mesh::Mesh load_mesh(const io::Case& c);
bc::FluidConditions make_conditions(const io::Case& c, const mesh::Mesh& m);

class Simulation {
public:
  explicit Simulation(io::Case c, MPI_Comm comm = PETSC_COMM_WORLD);
  ~Simulation();

  RunSummary run(const RunOptions& options);
  physics::StepReport advance(); ///< one time step

  int step() const { return step_; }
  double time() const { return step_ * case_.time.step; }
  const io::Case& config() const { return case_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  const fem::DistributedMesh& distributed_mesh() const { return *dmesh_; }
  physics::FluidProblem& problem() { return *problem_; } ///< rigid-wall runs
  physics::FluidSolver& solver() { return *solver_; }    ///< rigid-wall runs
  /// The flow part: the rigid-wall problem, or the fluid of the FSI problem.
  physics::FluidProblem& fluid() const;
  int block() const; ///< unknowns per node: 4, or 5 with a wall (fsi_problem.hpp)
  Vec solution() const;
  Vec acceleration() const;

  /// The whole vector on every rank, in the input mesh's node order, block() per node.
  std::vector<double> gather(Vec v) const;
  /// Sets (U, Udot) from full vectors in the input mesh's node order; sets the step.
  void set_state(int step, const std::vector<double>& U, const std::vector<double>& Udot);

  /// The face measures of the current state (collective).
  StepSample sample() const;

  /// Replaces the RCRs of the named outlets from the next step on (in-run tuning); every
  /// name must be an RCR outlet of the case.
  void set_outlets(const std::vector<bc::WindkesselBranch>& outlets);

private:
  void start_from_0d();
  /// The wall in quasi-static equilibrium with the fluid pressure p0 (FSI start).
  void load_wall(double p0);
  void write_frame();
  void report_cycle(const run::CycleStats& c, bool periodic) const;
  /// The checkpoint `c` of options.start_case's run, on its mesh, checked and interpolated
  /// to this mesh in place; returns the first step.
  int take_state_of_mesh(io::Checkpoint& c, const RunOptions& options) const;
  /// The checkpoint's extra data: per outlet its law's record and Q at t_n, then (FSI) the
  /// displacement of every node.
  std::vector<double> outlet_checkpoint() const;
  void set_outlet_checkpoint(const std::vector<double>& extra, const std::filesystem::path& file);
  size_t outlet_record_size() const; ///< the outlets' part of outlet_checkpoint()
  std::vector<std::string> outlet_faces() const;

  io::Case case_;
  mesh::Mesh mesh_;
  /// The run's PETSc options (the case's, the command line's, the solvers' defaults); made
  /// before and destroyed after the solvers that read them.
  std::unique_ptr<fem::SolverOptions> options_;
  std::unique_ptr<fem::DistributedMesh> dmesh_;
  std::unique_ptr<physics::FluidProblem> problem_;
  std::unique_ptr<physics::FluidSolver> solver_;
  std::unique_ptr<physics::FsiProblem> fsi_; ///< instead of problem_ with a wall
  std::unique_ptr<physics::FsiSolver> fsi_solver_;
  int step_ = 0;
  /// How the initial state was made (0D start, wall loading): told by run() when it starts
  /// from it, not when it restarts from a checkpoint.
  std::vector<std::string> start_notes_;
  struct Output;
  std::unique_ptr<Output> output_;
};

} // namespace tearflow::run
