#pragma once
// The discrete solid problem of one time step: R(U_{n+1}) = 0 with U = (v, p) per node,
// assembled from solid_kernel.hpp and the surface terms of bc/solid_conditions.hpp.
//
// Time integration: generalized-alpha for second-order systems with the fluid's parameters
// (alpha_m, alpha_f, gamma of Jansen, Whiting & Hulbert 2000 from the same rho_inf) and
// beta = (1 + alpha_m - alpha_f)^2 / 4, as in the FSI of Bazilevs, Calo, Hughes & Zhang
// (Comput. Mech. 2008): second order, unconditionally stable, and for rho_inf = 1 the
// trapezoidal rule (alpha = gamma = 1/2, beta = 1/4), which conserves energy. Newmark:
//   a_{n+1} = (v_{n+1} - v_n) / (gamma dt) - (1 - gamma) / gamma a_n,
//   u_{n+1} = u_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1}),
// the momentum equation holds at u_{n+af}, v_{n+af}, a_{n+am}; the pressure is the stage's
// Lagrange multiplier. Quasi-static mode drops inertia: u_{n+1} = u_n + dt v_{n+1}.
//
// Dirichlet rows fix the velocity that puts u_{n+1} on the prescribed displacement.
#include <cstdint>
#include <string>
#include <vector>

#include "bc/solid_conditions.hpp"
#include "fem/dof_map.hpp"
#include "fem/element_inserter.hpp"
#include "physics/field_layout.hpp"
#include "physics/generalized_alpha.hpp"
#include "physics/solid_kernel.hpp"

namespace tearflow::physics {

struct SolidScheme {
  double alpha_m = 1.0, alpha_f = 1.0, gamma = 1.0, beta = 0.5;
  bool quasi_static = false;

  static SolidScheme dynamic(const GeneralizedAlpha& g) {
    const double b = 1.0 + g.alpha_m - g.alpha_f;
    return {g.alpha_m, g.alpha_f, g.gamma, 0.25 * b * b, false};
  }
  static SolidScheme static_loading() { return {1.0, 1.0, 1.0, 0.5, true}; }
  /// d u_{n+af} / d v_{n+1}
  double c_u(double dt) const { return quasi_static ? dt : alpha_f * beta * dt / gamma; }
  /// d v_{n+af} / d v_{n+1}
  double c_v() const { return quasi_static ? 1.0 : alpha_f; }
  /// d a_{n+am} / d v_{n+1}
  double c_a(double dt) const { return quasi_static ? 0.0 : alpha_m / (gamma * dt); }
};

/// Mean displacement and area of one named face.
struct FaceDisplacement {
  std::string face;
  Vec3 displacement{}; ///< area-weighted mean [m]
  double area = 0.0;   ///< reference area [m^2]
};

/// Energies of the stage state [J].
struct SolidEnergy {
  double kinetic = 0.0; ///< 1/2 v.M v
  double stored = 0.0;  ///< Pi(u, p): strain energy of the mixed form
  double support = 0.0; ///< 1/2 int k_s |u|^2 dA of the Robin springs
  double total() const { return kinetic + stored + support; }
};

class SolidProblem {
public:
  static constexpr int block = 4; // v_x, v_y, v_z, p per node on its own (the fluid's layout)

  /// `layout` places the unknowns in a larger block and restricts the solid to a region
  /// (the wall of an FSI mesh, fsi_problem.hpp).
  SolidProblem(const mesh::Mesh& mesh, const fem::DistributedMesh& dmesh, SolidMaterial material,
               bc::SolidConditions conditions, SolidScheme scheme, FieldLayout layout = {});

  const fem::DofMap& dofs() const { return dofs_; }
  const SolidMaterial& material() const { return material_; }
  const SolidScheme& scheme() const { return scheme_; }

  /// Prepares the step t_n -> t_n + dt from (U_n, D_n, A_n): velocity and pressure,
  /// displacement, acceleration (block-4 vectors, component 3 unused in D and A).
  void begin_step(double t_n, double dt, Vec U_n, Vec D_n, Vec A_n);
  void apply_dirichlet(Vec U) const; ///< the Dirichlet velocities into U (Newton guess)
  void residual(Vec U, Vec R);
  void jacobian(Vec U, Mat J);

  // The pieces of residual and jacobian, for a caller that adds other physics.
  /// Adds the element and surface terms at U (global) into the local vector R_loc.
  void add_residual(Vec U, Vec R_loc);
  /// Sets the Dirichlet rows of the global R to v - v_target.
  void set_dirichlet_residual(Vec U, Vec R) const;
  /// Adds the element and surface terms into J (MatSetValues, no assembly), skipping the
  /// element terms of the Dirichlet rows unless the caller replaces those rows itself (FSI:
  /// then the pattern keeps whole node blocks).
  void add_jacobian(Vec U, Mat J, bool skip_dirichlet_rows = true);
  /// Global rows of the owned prescribed velocity components.
  std::vector<PetscInt> dirichlet_rows() const;
  /// Per local node: bit c set if velocity component c is prescribed.
  const std::vector<std::uint8_t>& dirichlet_flags() const { return dirichlet_; }
  /// D and A at t_{n+1} from U_{n+1} (Newmark); D, A hold t_n's values on entry.
  void update_state(Vec U_next, Vec D, Vec A) const;

  std::vector<FaceDisplacement> measure_faces(Vec D) const;
  /// Energies at the stage of the step that produced U (after begin_step).
  SolidEnergy stage_energy(Vec U);
  /// Per owned node, volume-weighted means of the elements' von Mises stress [Pa] and J:
  /// components 0 and 1 of a block-4 vector.
  void nodal_stress(Vec U, Vec D, Vec out) const;

private:
  void stage(Vec U); ///< local U -> u_af, v_af, a_am, p per local node
  void gather(const Tet& t, SolidElementState& s) const;
  double load_time() const; ///< where surface loads are evaluated
  std::array<Vec3, 3> deformed(const Tri& t) const;
  /// Global dof, or -1 (skipped by PETSc) for a Dirichlet row.
  PetscInt row_index(Index l, int c) const;

  const fem::DistributedMesh& dmesh_;
  FieldLayout layout_;
  int B_, P_;                    ///< block size and pressure slot
  std::vector<size_t> elements_; ///< the local tets of the solid
  fem::DofMap dofs_;
  fem::ElementInserter inserter_; ///< whole-block insertion (FSI: no skipped rows)
  SolidMaterial material_;
  bc::SolidConditions conditions_;
  SolidScheme scheme_;
  double t_n_ = 0.0, dt_ = 1.0;
  double row_scale_ = 1.0; ///< s = mu / h_mean [Pa/m]

  std::vector<fem::TetGeometry> geometry_; ///< per local tet, reference configuration
  std::vector<PressureRow> rows_;          ///< per local tet
  std::vector<std::uint8_t> dirichlet_;    ///< per local node: bit c set if u_c is prescribed
  struct FixedNode {
    Index local;
    int comp;
    size_t spec; ///< index into conditions_.fixed
  };
  std::vector<FixedNode> fixed_nodes_;             ///< owned prescribed (node, component) pairs
  std::vector<double> dirichlet_target_;           ///< per fixed_nodes_ entry: v_{n+1}
  std::vector<size_t> load_faces_, support_faces_; ///< indices into dmesh.faces()

  fem::OwnedVec U_loc_, R_loc_, Un_loc_, Dn_loc_, An_loc_;
  std::vector<Vec3> u_af_, v_af_, a_am_;
  std::vector<double> p_;
};

} // namespace tearflow::physics
