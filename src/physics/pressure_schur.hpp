#pragma once
// The matrix that preconditions the pressure's Schur complement S = J_pp - J_pu A^-1 J_up in
// the velocity-pressure field split (fluid_solver.cpp) and in the FSI's motion-pressure
// split (fsi_preconditioner.cpp); BoomerAMG's V-cycle on it is the Schur block's solve.
//
// Why not PETSc's selfp, J_pp - J_pu diag(A)^-1 J_up. On P1-P1 the product couples each node
// to its neighbours' neighbours, with positive off-diagonal entries, and one V-cycle on it
// approximates its inverse worse as the mesh is refined or layered: on the dissection at six
// elements across the true lumen, an accurate inner solve of the same matrix cut GMRES from
// 323 to 57 iterations per Newton step (docs/performance.md, "The fluid solver on finer and
// layered meshes").
//
// The same approximation on the element's own stencil, from the kernel's terms
// (navier_stokes_kernel.hpp; c_u = alpha_f, c_a = alpha_m / (gamma dt)):
//   J_pp = sum_e tau_M/rho (grad q, grad p)_e                          [PSPG]
//   J_pu A^-1 J_up ~ sum_e 1 / a_e (grad q, grad p)_e
// with a_e the element's diag(A) per unit volume over c_u, as selfp takes it node by node:
//   a_e = rho c_a/c_u + rho |u|_G + (4/3 mu + rho nu_C / 3) sum_a |grad N_a|^2
// (inertia; advection at the lagged velocity's rate |u|_G = (u.G u)^1/2, tau_M's; the viscous
// and grad-div diagonals, mu (|grad N_a|^2 + (d_i N_a)^2) and rho nu_C (d_i N_a)^2 over the
// lumped mass V/4, averaged over the nodes and components). With inertia alone this is the
// Cahouet-Chabard complement c_u B (rho c_a M)^-1 B^T ~ c_u/(rho c_a) K (IJNMF 8, 1988). So
//   S_e = k_e (grad q, grad p)_e,   k_e = tau_M/rho + 1/a_e   [m^3 s/kg]
// a Laplacian with a positive coefficient per element: the 1-ring stencil AMG is built for.
// The viscous and grad-div terms matter in boundary layers, where they outweigh inertia and
// advection: without them the layered dissection took 2.4-3.4 times selfp's Krylov
// iterations (docs/performance.md).
//
// Open faces. Where the traction is prescribed (outlets, traction-free faces) the velocity is
// free and S behaves like a Laplacian with the pressure held there (in 1D, the row of
// D M^-1 D^T at a free end sums to 1/h where K's sums to 0); with natural conditions
// everywhere the Laplacian would be singular. Each open triangle (one with a node whose
// velocity is free) therefore adds k A / (3 h) to its nodes' diagonal, A its area and h the height
// of the regular tet on it, with the inertial k = c_u / (rho c_a).
//
// Rows of nodes outside the fluid (the wall's, in FSI, where the fluid pressure is an
// identity row) get 1, the Schur complement's own value there.
#include <cmath>
#include <vector>

#include "fem/dof_map.hpp"
#include "fem/element_inserter.hpp"
#include "physics/navier_stokes_kernel.hpp"

namespace tearflow::physics {

/// S_e's coefficient k_e (file comment) [m^3 s / kg]; grad_sum = sum_a |grad N_a|^2 [1/m^2].
inline double schur_coefficient(const Stabilization& stab, double grad_sum,
                                const FluidProperties& fluid, double c_u, double c_a) {
  const double rho = fluid.density;
  const double a = rho * (c_a / c_u + stab.advection) +
                   (4.0 / 3.0 * fluid.viscosity + rho * stab.nu_c / 3.0) * grad_sum;
  return stab.tau_m / rho + 1.0 / a;
}

/// sum_a |grad N_a|^2 of the element [1/m^2].
inline double gradient_sum(const fem::TetGeometry& geo) {
  double g = 0.0;
  for (int a = 0; a < 4; ++a)
    g += dot(geo.grad[a], geo.grad[a]);
  return g;
}

/// S_e = k (grad N_a, grad N_b)_e, row-major 4 x 4.
inline std::array<double, 16> schur_element(const fem::TetGeometry& geo, double k) {
  std::array<double, 16> S{};
  const double kv = k * std::abs(geo.volume);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      S[4 * a + b] = kv * dot(geo.grad[a], geo.grad[b]);
  return S;
}

/// Whether ksp's preconditioner is a Schur field split whose options ask for a user
/// matrix (-<prefix>pc_fieldsplit_schur_precondition user, the fluid's and the FSI's default).
bool uses_schur_matrix(KSP ksp);
/// Gives that field split the matrix S.
void use_schur_matrix(KSP ksp, Mat S);

/// An open triangle's term k A / (3 h) on each of its nodes' diagonal (file comment).
inline double schur_outlet_term(double area, double density, double c_u, double c_a) {
  const double edge = std::sqrt(4.0 * area / std::sqrt(3.0)); // the equilateral's
  const double height = std::sqrt(2.0 / 3.0) * edge;
  return c_u / (density * c_a) * area / (3.0 * height);
}

class PressureSchur {
public:
  /// One pressure unknown per owned node of dmesh, numbered as the field split's pressure
  /// index set numbers them (owned nodes in order, ranks in turn).
  explicit PressureSchur(const fem::DistributedMesh& dmesh);

  Mat matrix() const { return S_; }

  /// A diagonal term: local node and value.
  struct NodeTerm {
    Index node;
    double value;
  };
  /// Assembles S from the fluid's local tets `elements` with their geometry and lagged
  /// stabilization parameters, and the open faces' terms (collective).
  void assemble(const std::vector<size_t>& elements, const std::vector<fem::TetGeometry>& geometry,
                const std::vector<Stabilization>& stab, const FluidProperties& fluid, double c_u,
                double c_a, const std::vector<NodeTerm>& open_terms);

private:
  fem::DofMap dofs_;
  fem::ElementInserter inserter_;
  fem::OwnedMat S_;
  std::vector<PetscInt> outside_; ///< rows of the owned nodes outside the fluid
  bool outside_known_ = false;
};

} // namespace tearflow::physics
