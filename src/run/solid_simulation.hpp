#pragma once
// One solid-only simulation from a validated case with a `solid:` section: case -> mesh ->
// partition -> SolidProblem -> SolidSolver -> outputs (VTU `solid_*.vtu` with displacement,
// velocity, pressure, von Mises stress and J; faces.csv with each face's mean displacement;
// checkpoints). The layout of Simulation, which does the same for the fluid.
#include <memory>
#include <vector>

#include "fem/distributed_mesh.hpp"
#include "fem/solver_options.hpp"
#include "io/case.hpp"
#include "physics/solid_solver.hpp"
#include "run/simulation.hpp"

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

  int step() const { return step_; }
  double time() const { return step_ * case_.time.step; }
  const io::Case& config() const { return case_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  physics::SolidProblem& problem() { return *problem_; }
  physics::SolidSolver& solver() { return *solver_; }

  /// The whole block-4 vector on every rank, in the input mesh's node order.
  std::vector<double> gather(Vec v) const;

private:
  void write_frame();
  void append_face_rows(std::vector<std::string>& rows) const;
  void set_state(int step, const std::vector<double>& U, const std::vector<double>& D,
                 const std::vector<double>& A);

  io::Case case_;
  mesh::Mesh mesh_;
  std::unique_ptr<fem::SolverOptions> options_; ///< the run's PETSc options (simulation.hpp)
  std::unique_ptr<fem::DistributedMesh> dmesh_;
  std::unique_ptr<physics::SolidProblem> problem_;
  std::unique_ptr<physics::SolidSolver> solver_;
  int step_ = 0;
  struct Output;
  std::unique_ptr<Output> output_;
};

} // namespace tearflow::run
