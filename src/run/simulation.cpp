#include "run/simulation.hpp"

#include <algorithm>

namespace tearflow::run {

Simulation::Simulation(io::Case c, MPI_Comm comm)
    : case_(std::move(c)), mesh_(load_mesh(case_)),
      options_(std::make_unique<fem::SolverOptions>(case_.petsc_options)) {
  const fem::SolverOptions::Scope options(*options_);
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, comm);
  if (io::is_fsi(case_))
    model_ = std::make_unique<FsiModel>(case_, mesh_, *dmesh_);
  else
    model_ = std::make_unique<FlowModel>(case_, mesh_, *dmesh_);
}

Simulation::~Simulation() = default;

RunSummary Simulation::run(const RunOptions& options) {
  const fem::SolverOptions::Scope solver_options(*options_);
  return run_loop(*model_, options);
}

physics::StepReport Simulation::advance() {
  const fem::SolverOptions::Scope options(*options_);
  return model_->advance();
}

void Simulation::set_state(int step, const std::vector<double>& U,
                           const std::vector<double>& Udot) {
  model_->set_state(step, U, Udot);
}

void Simulation::set_outlets(const std::vector<bc::WindkesselBranch>& outlets) {
  physics::FluidProblem& problem = fluid();
  const auto& specs = problem.conditions().outlets;
  for (const bc::WindkesselBranch& w : outlets) {
    const auto it = std::find_if(specs.begin(), specs.end(),
                                 [&](const bc::TractionOutlet& o) { return o.face == w.name; });
    const bc::RcrOutlet* old = it == specs.end() ? nullptr : std::get_if<bc::RcrOutlet>(&it->law);
    if (!old)
      throw std::logic_error("set_outlets: '" + w.name + "' is no RCR outlet of the case");
    bc::RcrOutlet tuned = *old;
    tuned.rcr = w.rcr;
    tuned.rcr.reference_pressure = old->rcr.reference_pressure;
    problem.set_outlet_law(static_cast<size_t>(it - specs.begin()), tuned);
    for (bc::BoundaryCondition& b : case_.boundary_conditions)
      if (b.face == w.name)
        b.outlet()->law = tuned;
  }
}

} // namespace tearflow::run
