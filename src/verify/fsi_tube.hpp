#pragma once
// A compliant tube for the FSI verification cases: the built-in pipe with a wall region
// (mesh/pipe_generator.hpp), the monolithic problem and its Newton stepper.
#include <memory>
#include <vector>

#include "fem/distributed_mesh.hpp"
#include "fem/solver_options.hpp"
#include "io/case.hpp"
#include "physics/fluid_solver.hpp"
#include "physics/fsi_problem.hpp"

namespace tearflow::verify {

struct FsiTubeSpec {
  mesh::PipeSpec pipe;            ///< radius, length, element size, wall thickness [m]
  physics::FluidProperties fluid; ///< blood or water
  physics::SolidMaterial wall;    ///< the tube's material
  bc::FluidConditions fluid_conditions;
  bc::SolidConditions wall_conditions;
  double rho_inf = 0.5;
  double dt = 1e-4; ///< [s] the step the wall block's solver is chosen for (advance's)
  physics::NewtonSpec newton{15, 1e-8, 1e-14};
  bool moving_mesh = true;
};

class FsiTube {
public:
  explicit FsiTube(FsiTubeSpec spec);
  ~FsiTube();

  physics::StepReport advance(double dt); ///< one step; time() moves on by dt
  double time() const { return t_; }
  const mesh::Mesh& mesh() const { return mesh_; }
  physics::FsiProblem& problem() { return *problem_; }
  physics::FsiSolver& solver() { return *solver_; }

  /// Mean radial displacement [m] of the interface nodes with z in [z0, z1] (collective).
  double mean_radial_displacement(double z0, double z1) const;
  /// Mean fluid pressure [Pa] of the interface nodes with z in [z0, z1] (collective).
  double mean_interface_pressure(double z0, double z1) const;
  /// Total outward flow [m^3/s] through the fluid caps `inlet` and `outlet` (collective).
  double cap_outflow() const;
  /// Mean fluid pressure [Pa] of all fluid nodes with z in [z0, z1] (collective).
  double mean_fluid_pressure(double z0, double z1) const;

private:
  /// Mean over the owned nodes with flag[node] set and z in [z0, z1] of f(local node).
  template <typename F>
  double node_mean(const std::vector<unsigned char>& flag, double z0, double z1, F&& f) const;

  FsiTubeSpec spec_;
  mesh::Mesh mesh_;
  /// Its PETSc options, as a run's (fem/solver_options.hpp): its solver defaults stay its own.
  fem::SolverOptions options_{""};
  std::unique_ptr<fem::DistributedMesh> dmesh_;
  std::unique_ptr<physics::FsiProblem> problem_;
  std::unique_ptr<physics::FsiSolver> solver_;
  std::vector<unsigned char> on_interface_, in_fluid_; ///< per input-mesh node
  double t_ = 0.0;
};

} // namespace tearflow::verify
