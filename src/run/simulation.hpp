#pragma once
// One simulation of a flow from a validated case, in rigid walls or, when the case has a
// wall, with it (fluid-structure interaction): case -> mesh -> partition -> the flow's model
// (run/flow_model.hpp) -> the one time loop (run/time_loop.hpp) -> outputs. `run` is what
// `tearflow run` does; verification drivers and tuning use `advance` and the accessors to
// compare the state with analytic solutions or to change the outlets between cycles. The run
// owns its PETSc options (fem/solver_options.hpp): the case's, whoever makes it.
#include <memory>
#include <vector>

#include "bc/windkessel_network.hpp"
#include "fem/distributed_mesh.hpp"
#include "fem/solver_options.hpp"
#include "io/case.hpp"
#include "run/flow_model.hpp"
#include "run/time_loop.hpp"

namespace tearflow::run {

class Simulation {
public:
  explicit Simulation(io::Case c, MPI_Comm comm = PETSC_COMM_WORLD);
  ~Simulation();

  RunSummary run(const RunOptions& options);
  physics::StepReport advance(); ///< one time step

  int step() const { return model_->step(); }
  double time() const { return model_->time(); }
  const io::Case& config() const { return case_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  const fem::DistributedMesh& distributed_mesh() const { return *dmesh_; }
  /// The flow part: the rigid-wall problem, or the fluid of the FSI problem.
  physics::FluidProblem& fluid() const { return model_->fluid(); }
  int block() const { return model_->block(); } ///< 4, or 5 with a wall (fsi_problem.hpp)
  Vec solution() const { return model_->solution(); }
  Vec acceleration() const { return model_->derivative(); }

  /// The whole vector on every rank, in the input mesh's node order, block() per node.
  std::vector<double> gather(Vec v) const { return model_->gather(v); }
  /// Sets (U, Udot) from full vectors in the input mesh's node order; sets the step.
  void set_state(int step, const std::vector<double>& U, const std::vector<double>& Udot);

  /// The face measures of the current state (collective).
  StepSample sample() const { return model_->sample(); }

  /// Replaces the RCRs of the named outlets from the next step on (in-run tuning); every
  /// name must be an RCR outlet of the case.
  void set_outlets(const std::vector<bc::WindkesselBranch>& outlets);

private:
  io::Case case_;
  mesh::Mesh mesh_;
  /// The run's PETSc options (the case's, the command line's, the solvers' defaults); made
  /// before and destroyed after the solvers that read them.
  std::unique_ptr<fem::SolverOptions> options_;
  std::unique_ptr<fem::DistributedMesh> dmesh_;
  std::unique_ptr<FlowModel> model_;
};

} // namespace tearflow::run
