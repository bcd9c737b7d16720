#pragma once
// The discrete rigid-wall flow problem of one time step: R(U_{n+1}) = 0 with U = (u, p) per
// node, assembled from navier_stokes_kernel.hpp and the boundary conditions:
//   - no-slip and inflow velocities are Dirichlet rows  R = U - g(t_{n+1});
//   - traction outlets add  -<w, h>  with  h = -P n + beta rho (u.n)_- u  and, during a step,
//     P = p0 + r Q (bc/outlet_step.hpp: every outlet law of bc/outlet.hpp alike).
// The outlet law couples every node of the face through Q = int u.n; its Jacobian is the
// low-rank term  r c_u v v^T  (v_ai = int N_a n_i), applied matrix-free by
// add_coupled_outlets so the assembled matrix keeps its sparsity. A law's 0D state (an RCR's
// distal pressure) advances in commit_step once the step has converged.
//
// The same class assembles the fluid part of the FSI system (fsi_problem.hpp): a
// FieldLayout places its unknowns in a larger node block and restricts it to the fluid
// region, move_mesh puts it on the current (ALE) configuration with its mesh velocity, and
// add_residual / add_jacobian add into the caller's vector and matrix.
#include <cstdint>
#include <memory>
#include <vector>

#include "bc/fluid_conditions.hpp"
#include "fem/dof_map.hpp"
#include "fem/element_inserter.hpp"
#include "physics/field_layout.hpp"
#include "physics/generalized_alpha.hpp"
#include "physics/navier_stokes_kernel.hpp"
#include "physics/newton_spec.hpp"
#include "physics/pressure_schur.hpp"

namespace tearflow::physics {

/// Flow rate, mean pressure and area of one named face.
struct FaceMeasure {
  std::string face;
  double flow = 0.0;     ///< outward flux int u.n [m^3/s]
  double pressure = 0.0; ///< area-weighted mean pressure [Pa]
  double area = 0.0;     ///< [m^2]
  double reversed = 0.0; ///< inward part int (u.n)_- of the flux, <= 0 [m^3/s]
};

class FluidProblem {
public:
  static constexpr int block = 4; // u_x, u_y, u_z, p per node on its own
  static constexpr const char* options_prefix = "fluid_";
  /// The solver defaults (fluid_solver.cpp), entered where the user set nothing.
  static fem::OptionList default_solver_options();

  FluidProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh, FluidProperties fluid,
               bc::FluidConditions conditions, GeneralizedAlpha scheme, FieldLayout layout = {});

  const fem::DofMap& dofs() const { return dofs_; }
  const FluidProperties& fluid() const { return fluid_; }
  const GeneralizedAlpha& scheme() const { return scheme_; }

  /// Prepares the step t_n -> t_n + dt from the state (U_n, Udot_n): caches their local
  /// values and the lagged stabilization parameters.
  void begin_step(double t_n, double dt, Vec U_n, Vec Udot_n);
  /// Writes the Dirichlet values at t_{n+1} into U (the Newton initial guess).
  void apply_dirichlet(Vec U) const;
  void residual(Vec U, Vec R);
  /// The assembled part of dR/dU (everything but the outlet resistances).
  void jacobian(Vec U, Mat J);

  // The pieces of residual and jacobian, for a caller that adds other physics.
  /// Adds the element and outlet terms at U (global) into the local vector R_loc.
  void add_residual(Vec U, Vec R_loc);
  /// Sets the Dirichlet rows of the global R to U - g(t_{n+1}).
  void set_dirichlet_residual(Vec U, Vec R) const;
  /// Zeroes J and adds the element and backflow terms (no assembly, no Dirichlet rows).
  void add_jacobian(Vec U, Mat J);
  /// Newton's per-field test (newton_spec.hpp): the continuity slot and the inflow's peak.
  ResidualFields residual_fields() const { return {P_, -1, peak_inflow()}; }
  /// The largest |Q| of the inflows' waveforms over a period [m^3/s]; 0 without inflow.
  double peak_inflow() const;
  /// Gives the field split of ksp the pressure Schur complement's matrix
  /// (pressure_schur.hpp) where its options ask for it (schur_precondition user).
  void attach_preconditioner(KSP ksp);
  /// Assembles that matrix, if attached, for the preconditioner being built.
  void assemble_schur_preconditioner();
  /// The matrix, created on first use (scalar, one row per owned node).
  Mat schur_preconditioner();
  /// Global rows of the owned prescribed velocities.
  const std::vector<PetscInt>& dirichlet_rows() const { return dirichlet_rows_; }
  /// Puts the fluid on the configuration x (per local node, [m]) moving with velocity w
  /// [m/s]: element geometry, outlet normals and the convective velocity u - w follow.
  void move_mesh(const std::vector<Vec3>& x, const std::vector<Vec3>& w);
  /// ALE: the nodes whose position follows their own velocity unknown during a step (in
  /// FSI the wall's nodes, by its Newmark update): x_a moves by dx_du and the mesh velocity
  /// w_a by dw_du per unit of u_a (per local node; empty: none). add_jacobian then adds each
  /// element's dependence on them, the shape derivatives of the interface; the mesh inside
  /// the fluid is held (its motion is a separate solve).
  struct MeshSensitivity {
    std::vector<std::uint8_t> follows; ///< per local node
    double dx_du = 0.0;                ///< [s]
    double dw_du = 0.0;                ///< [-]
  };
  void set_mesh_sensitivity(MeshSensitivity m);
  /// y += sum over resistance outlets of R_out c_u v (v . x).
  void add_coupled_outlets(Vec x, Vec y) const;
  /// Udot_{n+1} from U_{n+1} (generalized-alpha update); overwrites Udot.
  void update_acceleration(Vec U_next, Vec U_n, Vec Udot) const;

  /// Advances the outlets' 0D states to t_{n+1} from the converged U_{n+1} (collective).
  void commit_step(Vec U_next);
  /// True when some outlet's law has dP/dQ != 0 (bc::coupled): the Jacobian then
  /// needs add_coupled_outlets.
  bool has_coupled_outlets() const;

  /// The 0D state of every traction outlet, in the order of conditions().outlets.
  struct OutletState {
    bc::OutletState law; ///< the outlet law's own state (bc/outlet.hpp) at t_n
    double flux = 0.0;   ///< Q at t_n [m^3/s]
  };
  std::vector<OutletState> outlet_states() const;
  void set_outlet_states(const std::vector<OutletState>& states);
  /// Replaces the parameters of outlet i's law (in the order of conditions().outlets; the
  /// same law) from the next step on; its 0D state stays (in-run tuning,
  /// tuning/corrected_run.hpp).
  void set_outlet_law(size_t i, const bc::OutletLaw& law);
  const bc::FluidConditions& conditions() const { return conditions_; }

  /// Per face of the fluid (wall-only faces of an FSI mesh left out), in mesh order.
  std::vector<FaceMeasure> measure_faces(Vec U) const;

private:
  struct OutletData {
    bc::TractionOutlet spec;
    size_t face_index;
    fem::OwnedVec v;   ///< int N_a n_i, zero on Dirichlet dofs
    double flux = 0.0; ///< Q_af of the current iterate
    OutletState state; ///< at t_n
    bc::StepLaw law;   ///< P_af = p0 + r Q_af during the current step
  };

  void stage(Vec U); ///< local U -> u_af, udot_am, p per local node
  /// sigma_h at every local node from the velocity in u_af_: the lumped L2 projection of the
  /// elements' 2 mu eps(u) (navier_stokes_kernel.hpp), summed over the ranks (collective).
  void reconstruct_viscous_flux();
  /// The staged nodal values of local tet e, with div sigma_h on it.
  void gather(size_t e, FluidElementState& s) const;
  /// K += the element residual's derivative through the motion of its following nodes
  /// (mask: bit a for node a), by forward differences of the residual kernel.
  void add_interface_motion(const Tet& t, unsigned mask, const fem::TetGeometry& geo,
                            const FluidElementState& s, const Stabilization& stab,
                            ElementMatrix& K) const;
  void update_outlet_fluxes();   ///< Q of every outlet from u_af (collective)
  void compute_outlet_vectors(); ///< v_ai = int N_a n_i on the current configuration
  double outlet_pressure(const OutletData& o) const;
  /// Outward flux through every outlet of the nodal velocities velocity(l) -> Vec3 at local
  /// nodes l (collective).
  template <typename Velocity> std::vector<double> outlet_fluxes(Velocity&& velocity) const;

  const fem::DistributedMesh& dmesh_;
  FieldLayout layout_;
  int B_, P_; ///< block size and pressure slot
  fem::DofMap dofs_;
  fem::ElementInserter inserter_;
  FluidProperties fluid_;
  bc::FluidConditions conditions_;
  GeneralizedAlpha scheme_;
  double t_n_ = 0.0, dt_ = 1.0;

  std::vector<size_t> elements_;           ///< the local tets of the fluid
  std::vector<bool> fluid_face_;           ///< per dmesh face: it bounds the fluid
  std::vector<Vec3> x_, w_;                ///< configuration and mesh velocity per local node
  std::vector<fem::TetGeometry> geometry_; ///< per local tet, on x_
  std::vector<Stabilization> stab_;        ///< per local tet, from U_n
  MeshSensitivity sensitivity_;
  std::vector<std::uint8_t> interface_mask_; ///< per local tet: its following nodes (bits)
  std::vector<std::uint8_t> dirichlet_;      ///< per local node: bit c set if u_c is prescribed
  std::vector<PetscInt> dirichlet_rows_;     ///< global rows of the owned prescribed dofs
  struct InflowNode {
    Index local;
    size_t inflow, k;
  };
  std::vector<InflowNode> inflow_nodes_; ///< owned inflow nodes (not on a wall)
  std::vector<Index> wall_nodes_;        ///< owned no-slip nodes
  std::vector<OutletData> outlets_;

  fem::OwnedVec U_loc_, R_loc_, Un_loc_, Udotn_loc_;
  std::vector<Vec3> u_af_, udot_am_;
  std::vector<double> p_;
  // The viscous flux's projection: per node the six components of sum V_e/4 sigma_e and
  // sum V_e/4 (block 7), and their quotient sigma_h.
  static constexpr int flux_block = 7;
  fem::DofMap flux_dofs_;
  fem::OwnedVec flux_loc_, flux_global_;
  std::vector<SymTensor> nodal_flux_;
  std::unique_ptr<PressureSchur> schur_; ///< once a field split uses it
};

} // namespace tearflow::physics
