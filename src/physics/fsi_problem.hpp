#pragma once
// The monolithic ALE fluid-structure problem of one time step: R(U_{n+1}) = 0 with, per node,
//   U = (v_x, v_y, v_z, p_fluid, p_wall),
// one velocity shared by fluid and wall and the two pressures apart (field_layout.hpp).
//
// Coupling (Bazilevs, Calo, Hughes & Zhang, Comput. Mech. 2008; the reference study's
// svFSI): the fluid and the wall meshes share the interface nodes, so
//   - kinematic continuity u_fluid = du_wall/dt holds by construction (one velocity), and
//   - traction balance sigma_f n = sigma_s n holds weakly: the momentum rows of an interface
//     node sum the fluid's and the wall's integrals, and the interface tractions cancel.
// Both physics advance with the same generalized-alpha scheme; the wall's displacement
// follows from its velocity by Newmark (solid_problem.hpp), the fluid's acceleration by the
// same gamma relation, so one acceleration vector serves both.
//
// ALE: the fluid is assembled on the configuration x_{n+af} = X + d_n + alpha_f (d_{n+1} -
// d_n) with mesh velocity w = (d_{n+1} - d_n) / dt, where d_{n+1} is the wall's Newmark
// displacement on wall nodes and the pseudo-solid's solution (mesh_motion.hpp) inside the
// fluid. The mesh is moved at every residual evaluation, so the converged state satisfies
// the full nonlinear system. The Jacobian holds the fluid's dependence on the motion of the
// interface's nodes (their position x = X + d_n + alpha_f (d_{n+1} - d_n) and mesh velocity
// w, both moving with the wall's velocity through Newmark: dx/dv = alpha_f beta dt / gamma,
// dw/dv = beta / gamma), differenced element by element (FluidProblem::set_mesh_sensitivity);
// it leaves out the response of the mesh inside the fluid (the pseudo-solid solve), whose
// nodes the Jacobian holds fixed. Without the interface's part (svFSI's quasi-Newton method,
// -fsi_interface_shape_derivatives false) Newton contracts linearly at about beta / gamma =
// 0.5 per iteration near the solution, the factor the interface's convective velocity u - w
// keeps from the missing dw/dv; with it, at the linear solve's tolerance (measured in
// docs/performance.md). Where Newton stalls anyway, the stepper falls back to the exact
// operator by finite differences (fluid_solver.cpp).
#include <memory>
#include <vector>

#include "physics/fluid_problem.hpp"
#include "physics/fsi_preconditioner.hpp"
#include "physics/mesh_motion.hpp"
#include "physics/solid_problem.hpp"

namespace tearflow::physics {

struct FsiRegions {
  int fluid = 0; ///< region index of the fluid tets
  int wall = 1;  ///< region index of the wall tets
};

class FsiProblem {
public:
  static constexpr int block = 5;
  static constexpr int fluid_pressure = 3, wall_pressure = 4;
  static constexpr const char* options_prefix = "fsi_";

  FsiProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh, FluidProperties fluid,
             bc::FluidConditions fluid_conditions, SolidMaterial wall,
             bc::SolidConditions wall_conditions, GeneralizedAlpha scheme, FsiRegions regions,
             bool moving_mesh = true);

  const fem::DofMap& dofs() const { return dofs_; }
  FluidProblem& fluid() { return fluid_; }
  const FluidProblem& fluid() const { return fluid_; }
  SolidProblem& wall() { return wall_; }
  /// Displacement of every node at the current time (wall: Newmark; fluid: mesh motion).
  Vec displacement() const { return D_; }

  // The interface the Newton stepper (fluid_solver.hpp) drives.
  void begin_step(double t_n, double dt, Vec U_n, Vec Udot_n);
  void apply_dirichlet(Vec U) const;
  void residual(Vec U, Vec R);
  void jacobian(Vec U, Mat J);
  /// The Jacobian leaves out the shape derivatives (file comment) when the mesh moves: the
  /// stepper then retries a failed step with the exact operator (fluid_solver.hpp).
  bool jacobian_is_approximate() const { return moving_mesh_; }
  bool has_coupled_outlets() const { return fluid_.has_coupled_outlets(); }
  ResidualFields residual_fields() const {
    return {fluid_pressure, wall_pressure, fluid_.peak_inflow()};
  }
  void add_coupled_outlets(Vec x, Vec y) const { fluid_.add_coupled_outlets(x, y); }
  /// Acceleration and displacement at t_{n+1} from the converged U_{n+1}.
  void update_acceleration(Vec U_next, Vec U_n, Vec Udot);
  void commit_step(Vec U_next) { fluid_.commit_step(U_next); }
  static fem::OptionList default_solver_options();
  /// Names the default preconditioner's blocks on the Newton solver's KSP
  /// (fsi_preconditioner.hpp).
  void attach_preconditioner(KSP ksp) {
    if (preconditioner_->attach(ksp))
      fluid_.attach_preconditioner(ksp); // the pressure split's Schur matrix
  }
  /// The fluid pressure's Schur matrix (pressure_schur.hpp), where the split uses one.
  void assemble_schur_preconditioner() { fluid_.assemble_schur_preconditioner(); }

  /// Sets the displacement from a full vector in the input mesh's node order (block 5 per
  /// node, as a checkpoint holds it) and puts the fluid on that configuration.
  void set_displacement(const std::vector<double>& all);
  /// Sets the displacement of the wall's nodes from a full vector in the input mesh's node
  /// order (block 5 per node; other nodes' values are ignored), extends it into the fluid by
  /// the mesh motion, and puts the fluid on that configuration (collective): a wall in
  /// equilibrium with a load at the start (run/fsi_model.cpp).
  void set_wall_displacement(const std::vector<double>& all);
  /// Volume of the fluid on the configuration X + D (collective) [m^3].
  double fluid_volume() const;
  /// The wall's stiffness number Lambda = (E / rho_0) dt^2 / h^2 at step dt, h^2 the mean over
  /// the wall's tets of the squared edge of a regular tet of the same volume (collective).
  double wall_stiffness_number(double dt) const;
  /// Enters the solver for step dt as PETSc defaults, before the Newton stepper is made: the
  /// wall block's (fsi_preconditioner.hpp) and whether Newton may keep its Jacobian
  /// (fsi_problem.cpp), both by Lambda; returns Lambda (collective).
  double select_solver(double dt) const;
  int mesh_iterations() const { return mesh_.last_iterations(); }

private:
  /// d_{n+1} on every local node from U (wall Newmark, mesh motion) and the fluid on
  /// x_{n+af} with its mesh velocity.
  void move_fluid_mesh(Vec U);
  /// Throws SolverError, on every rank, if a fluid or wall tet has non-positive volume on
  /// X + d_{n+1} (collective).
  void check_mesh() const;
  /// The fluid on X + D (local block-5 vector), at rest.
  void place_fluid(Vec D_loc);

  const fem::DistributedMesh& dmesh_;
  fem::DofMap dofs_;
  FluidProblem fluid_;
  SolidProblem wall_;
  MeshMotion mesh_;
  SolidScheme wall_scheme_;
  FsiRegions regions_;
  bool moving_mesh_;
  double dt_ = 1.0;
  std::vector<PetscInt> identity_rows_; ///< owned Dirichlet rows and unused pressure slots
  std::vector<PetscInt> unused_rows_;   ///< owned pressure slots of the other physics' nodes
  fem::OwnedVec D_, U_loc_, R_loc_, Un_loc_, An_loc_, Dn_loc_;
  std::vector<Vec3> d_next_; ///< d_{n+1} per local node, from the last move_fluid_mesh
  std::vector<std::uint8_t> follows_wall_; ///< per local node; empty: no shape derivatives
  std::unique_ptr<FsiPreconditioner> preconditioner_;
};

} // namespace tearflow::physics
