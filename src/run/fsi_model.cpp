// The flow with its wall (flow_model.hpp): its problem, its part of the state, the start.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/units.hpp"
#include "fem/petsc.hpp"
#include "mesh/orient_faces.hpp"
#include "mesh/region.hpp"
#include "run/flow_model.hpp"
#include "run/solid_simulation.hpp"

namespace tearflow::run {

FsiModel::FsiModel(const io::Case& c, const mesh::Mesh& m, const fem::DistributedMesh& dmesh)
    : FlowModel(c, m, dmesh, Unstarted{}) {
  fsi_ = std::make_unique<physics::FsiProblem>(
      m, dmesh, fluid_properties(c), make_conditions(c, m), c.solid->material, c.solid->conditions,
      physics::GeneralizedAlpha::from_spectral_radius(c.time.spectral_radius),
      physics::FsiRegions{mesh::region_index(m, "fluid"), mesh::region_index(m, "wall")});
  const double stiffness = fsi_->select_solver(c.time.step);
  if (fem::mpi_rank(dmesh.comm()) == 0)
    spdlog::info("the wall's stiffness number (E / rho) dt^2 / h^2 = {:.3g}: its block by {}",
                 stiffness,
                 physics::FsiPreconditioner::wall_solved_directly(stiffness)
                     ? "MUMPS, a Jacobian every Newton iteration"
                     : "ILU(1) per rank, Newton keeping its Jacobian while it contracts");
  fluid_ = &fsi_->fluid();
  stepper_ = make_stepper(*fsi_, c.newton);
  if (c.time.start_from_0d)
    if (const std::optional<double> p0 = start_from_0d())
      load_wall(*p0);
}

FsiModel::~FsiModel() {
  stepper_.reset(); // before fsi_, which it refers to
}

std::vector<std::string> FsiModel::unknown_regions() const {
  return {"", "", "", "fluid", "wall"}; // each pressure from its own region's tets
}

std::vector<double> FsiModel::wall_state() const {
  return gather(fsi_->displacement());
}

size_t FsiModel::wall_state_size() const {
  return static_cast<size_t>(mesh_.num_nodes()) * block();
}

void FsiModel::set_wall_state(std::vector<double> displacement) {
  fsi_->set_displacement(std::move(displacement));
}

void FsiModel::load_wall(double p0) {
  // Without it the unloaded wall inflates in the first steps, drawing its stored volume
  // (about 10 mL at 46 mmHg in the 4.5 mm dissection) from the outlets' capacitors, whose
  // pressures then recover over several cycles (R_d C ~ 1.5 s): the wall is solved
  // quasi-statically under p0 on the fluid interface, with its own supports, first.
  if (std::none_of(mesh_.faces.begin(), mesh_.faces.end(),
                   [](const mesh::Face& f) { return f.name == "interface"; })) {
    if (fem::mpi_rank(dmesh_.comm()) == 0)
      spdlog::warn("the mesh names no fluid-wall face 'interface': the wall starts unloaded, "
                   "and its first steps inflate it");
    return;
  }
  io::Case wall_case = case_;
  wall_case.boundary_conditions.clear();
  wall_case.solid->quasi_static = true;
  wall_case.solid->conditions.loads.push_back({"interface", bc::Waveform::constant(p0)});
  wall_case.time.step = 1e3; // the tissue support's damping c_s du/dt then vanishes
  mesh::Mesh wall = mesh::extract_region(mesh_, "wall");
  mesh::orient_faces_outward(wall); // the interface's normal out of the wall: p0 inflates
  // One static solve of the thin wall: a direct one (the FSI's wall block is solved so too),
  // unless the options database says otherwise; the solid's default split stalls here.
  fem::set_default_options(
      {{"-solid_pc_type", "lu"}, {"-solid_pc_factor_mat_solver_type", "mumps"}});
  SolidSimulation solid(wall_case, wall, dmesh_.comm());
  const physics::StepReport r = solid.advance();
  const std::vector<double> d = solid.gather(solid.solver().displacement()),
                            v = solid.gather(solid.solver().solution());
  // The wall mesh keeps the FSI mesh's wall nodes in their order (mesh/region.hpp).
  const int region = mesh::region_index(mesh_, "wall");
  std::vector<char> in_wall(mesh_.num_nodes(), 0);
  for (size_t e = 0; e < mesh_.tets.size(); ++e)
    if (mesh_.tet_region[e] == region)
      for (Index n : mesh_.tets[e])
        in_wall[n] = 1;
  constexpr int bs = physics::FsiProblem::block, ws = physics::SolidProblem::block;
  std::vector<double> all(static_cast<size_t>(mesh_.num_nodes()) * bs, 0.0);
  std::vector<double> wall_pressure(mesh_.num_nodes(), 0.0);
  for (Index n = 0, j = 0; n < mesh_.num_nodes(); ++n)
    if (in_wall[n]) {
      for (int c = 0; c < 3; ++c)
        all[bs * n + c] = d[ws * j + c];
      wall_pressure[n] = v[ws * j + 3];
      ++j;
    }
  fsi_->set_wall_displacement(all);
  {
    fem::WriteArray u(solution());
    for (Index l = 0; l < dmesh_.num_owned(); ++l)
      u[bs * l + physics::FsiProblem::wall_pressure] = wall_pressure[dmesh_.original_index(l)];
  }
  double largest = 0.0;
  for (Index n = 0; n < mesh_.num_nodes(); ++n)
    largest =
        std::max(largest, std::sqrt(all[bs * n] * all[bs * n] + all[bs * n + 1] * all[bs * n + 1] +
                                    all[bs * n + 2] * all[bs * n + 2]));
  const double volume = fsi_->fluid_volume(); // (collective)
  start_notes_.push_back(fmt::format("wall loaded with {:.1f} mmHg on its fluid side: largest "
                                     "displacement {:.3g} mm ({} Newton iterations), fluid "
                                     "volume {:.2f} mL",
                                     p0 / units::mmHg, largest / units::mm, r.newton_iterations,
                                     volume / units::mL));
}

} // namespace tearflow::run
