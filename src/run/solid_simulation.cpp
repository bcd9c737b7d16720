#include "run/solid_simulation.hpp"

#include "fem/alike_on_every_rank.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/pipe_generator.hpp"
#include "mesh/readers.hpp"

namespace tearflow::run {

mesh::Mesh load_solid_mesh(const io::Case& c) {
  mesh::Mesh m = c.mesh.pipe ? mesh::make_pipe(*c.mesh.pipe)
                             : mesh::read_mesh(c.mesh.file, c.mesh.length_scale);
  mesh::orient_faces_outward(m);
  return m;
}

SolidSimulation::SolidSimulation(io::Case c, MPI_Comm comm)
    : SolidSimulation(c, fem::alike_on_every_rank(comm, [&] { return load_solid_mesh(c); }), comm) {
}

SolidSimulation::SolidSimulation(io::Case c, mesh::Mesh m, MPI_Comm comm)
    : case_(std::move(c)), mesh_(std::move(m)),
      options_(std::make_unique<fem::SolverOptions>(case_.petsc_options)) {
  const fem::SolverOptions::Scope options(*options_);
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, comm);
  model_ = std::make_unique<WallModel>(case_, mesh_, *dmesh_);
}

SolidSimulation::~SolidSimulation() = default;

RunSummary SolidSimulation::run(const RunOptions& options) {
  const fem::SolverOptions::Scope solver_options(*options_);
  return run_loop(*model_, options);
}

physics::StepReport SolidSimulation::advance() {
  const fem::SolverOptions::Scope options(*options_);
  return model_->advance();
}

} // namespace tearflow::run
