#pragma once
// One simulation of the wall alone (a solid-only case): case -> mesh -> partition -> the
// wall's model (run/wall_model.hpp) -> the one time loop (run/time_loop.hpp) -> outputs.
// Verification drivers use `advance` and the problem and solver; the fluid-structure start
// uses it to load the wall (run/fsi_model.cpp).
#include <memory>
#include <vector>

#include "fem/distributed_mesh.hpp"
#include "fem/solver_options.hpp"
#include "io/case.hpp"
#include "run/time_loop.hpp"
#include "run/wall_model.hpp"

namespace tearflow::run {

/// The case's mesh in SI units with outward-oriented faces, checked against the solid's
/// conditions.
mesh::Mesh load_solid_mesh(const io::Case& c);

class SolidSimulation {
public:
  /// InputError unless c.solid is set.
  explicit SolidSimulation(io::Case c, MPI_Comm comm = PETSC_COMM_WORLD);
  /// With a mesh built by the caller (verification cases).
  SolidSimulation(io::Case c, mesh::Mesh m, MPI_Comm comm = PETSC_COMM_WORLD);
  ~SolidSimulation();

  RunSummary run(const RunOptions& options);
  physics::StepReport advance(); ///< one time step

  int step() const { return model_->step(); }
  double time() const { return model_->time(); }
  const io::Case& config() const { return case_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  physics::SolidProblem& problem() { return model_->problem(); }
  physics::SolidSolver& solver() { return model_->solver(); }

  /// The whole block-4 vector on every rank, in the input mesh's node order.
  std::vector<double> gather(Vec v) const { return model_->gather(v); }

private:
  io::Case case_;
  mesh::Mesh mesh_;
  std::unique_ptr<fem::SolverOptions> options_; ///< the run's PETSc options (simulation.hpp)
  std::unique_ptr<fem::DistributedMesh> dmesh_;
  std::unique_ptr<WallModel> model_;
};

} // namespace tearflow::run
