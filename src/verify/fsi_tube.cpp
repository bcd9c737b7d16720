#include "verify/fsi_tube.hpp"

#include <algorithm>
#include <cmath>

#include "mesh/orient_faces.hpp"
#include "mesh/pipe_generator.hpp"
#include "mesh/region.hpp"

namespace tearflow::verify {

FsiTube::FsiTube(FsiTubeSpec spec) : spec_(std::move(spec)), mesh_(mesh::make_pipe(spec_.pipe)) {
  const fem::SolverOptions::Scope options(options_);
  mesh::orient_faces_outward(mesh_);
  dmesh_ = std::make_unique<fem::DistributedMesh>(mesh_, PETSC_COMM_WORLD);
  problem_ = std::make_unique<physics::FsiProblem>(
      mesh_, *dmesh_, spec_.fluid, std::move(spec_.fluid_conditions), spec_.wall,
      spec_.wall_conditions, physics::GeneralizedAlpha::from_spectral_radius(spec_.rho_inf),
      physics::FsiRegions{mesh::region_index(mesh_, "fluid"), mesh::region_index(mesh_, "wall")},
      spec_.moving_mesh);
  problem_->select_solver(spec_.dt);
  solver_ = std::make_unique<physics::FsiSolver>(*problem_, spec_.newton);
  on_interface_.assign(mesh_.points.size(), 0);
  in_fluid_.assign(mesh_.points.size(), 0);
  const int fluid = mesh::region_index(mesh_, "fluid");
  for (size_t e = 0; e < mesh_.tets.size(); ++e)
    if (mesh_.tet_region[e] == fluid)
      for (Index v : mesh_.tets[e])
        in_fluid_[v] = 1;
  for (const Tri& t : mesh_.face("interface").triangles)
    for (Index v : t)
      on_interface_[v] = 1;
}

FsiTube::~FsiTube() {
  solver_.reset(); // before the problem it refers to
}

physics::StepReport FsiTube::advance(double dt) {
  const fem::SolverOptions::Scope options(options_);
  const physics::StepReport r = solver_->step(t_, dt);
  t_ += dt;
  return r;
}

template <typename F>
double FsiTube::node_mean(const std::vector<unsigned char>& flag, double z0, double z1,
                          F&& f) const {
  double sums[2] = {0.0, 0.0};
  for (Index l = 0; l < dmesh_->num_owned(); ++l) {
    const Vec3& x = dmesh_->points()[l];
    if (!flag[dmesh_->original_index(l)] || x[2] < z0 || x[2] > z1)
      continue;
    sums[0] += f(l);
    sums[1] += 1.0;
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, dmesh_->comm());
  return sums[0] / sums[1];
}

double FsiTube::mean_radial_displacement(double z0, double z1) const {
  fem::ReadArray d(problem_->displacement());
  constexpr int B = physics::FsiProblem::block;
  return node_mean(on_interface_, z0, z1, [&](Index l) {
    const Vec3& x = dmesh_->points()[l];
    const double r = std::hypot(x[0], x[1]);
    return (d[B * l] * x[0] + d[B * l + 1] * x[1]) / r;
  });
}

double FsiTube::mean_interface_pressure(double z0, double z1) const {
  fem::ReadArray u(solver_->solution());
  constexpr int B = physics::FsiProblem::block;
  return node_mean(on_interface_, z0, z1,
                   [&](Index l) { return u[B * l + physics::FsiProblem::fluid_pressure]; });
}

double FsiTube::cap_outflow() const {
  double q = 0.0;
  for (const physics::FaceMeasure& f : problem_->fluid().measure_faces(solver_->solution()))
    if (f.face == "inlet" || f.face == "outlet")
      q += f.flow;
  return q;
}

double FsiTube::mean_fluid_pressure(double z0, double z1) const {
  fem::ReadArray u(solver_->solution());
  constexpr int B = physics::FsiProblem::block;
  return node_mean(in_fluid_, z0, z1,
                   [&](Index l) { return u[B * l + physics::FsiProblem::fluid_pressure]; });
}

} // namespace tearflow::verify
