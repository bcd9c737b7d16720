#pragma once
// The FSI's default preconditioner, a Schur-complement field split whose first block keeps
// the wall whole:
//
//   J = [ A   B_f^T ]   A: the "motion" block, every velocity and the wall's pressure
//       [ B_f  C_f  ]   B_f, C_f: the fluid pressure's rows ("pressure")
//
//   P^{-1} = lower Schur factorization, S preconditioned by the fluid's pressure Laplacian
//   (pressure_schur.hpp; PETSc's selfp C_f - B_f diag(A)^{-1} B_f^T before), and A
//   applied by one block Gauss-Seidel sweep over
//     "wall":  velocity and pressure of every wall node (interface included), by ILU(1)
//              on each rank's part or directly by MUMPS (below), and
//     "fluid": the velocity of the fluid-only nodes, one BoomerAMG V-cycle.
//
// Why. With the velocity alone as the first block (the split of the rigid-wall solver), the
// wall's pressure sits in the Schur complement, where selfp's B diag(A)^{-1} B^T, on a stiff
// thin wall (E dt^2 / (rho h^2) ~ 10^3-10^4), misses the smooth modes of the wall pressure's
// true Schur complement by (k h)^2: Krylov counts grew by a third from 4.5 to 2 mm on the
// dissection (docs/performance.md). Taking the wall's velocity and pressure out of the Schur
// complement and solving them together, as the structure solve of FaCSI does (Deparis,
// Forti, Grandperrin & Quarteroni, J. Comput. Phys. 2016), leaves the fluid pressure's selfp,
// which stays spectrally equivalent under refinement (a Stokes / Oseen pressure). The wall
// is thin: its block is a small part of the system and its direct factorization is cheap.
// Measured on the dissection (dt 5 ms, 118 k -> 286 k -> 503 k tets): 11.7 -> 12.5 -> 14.5
// Krylov iterations per Newton iteration (the velocity-only split: 15.9 -> 21.6 -> 23.2; an
// exact solve of the whole motion block: 14.0 at 503 k) and 25 % less CPU at 286 k tets;
// pipe-fsi 4.45 s/step on 2 ranks against 5.39; only the small pulse tube on 2 ranks is slower
// (0.41 against 0.35 s/step). With OpenBLAS: the reference BLAS makes MUMPS 3.4x slower
// (docs/performance.md).
//
// The wall block's solver follows its stiffness number Lambda = (E / rho) dt^2 / h^2, the
// ratio of the elastic to the inertial part of the block (h: the wall tets' mean size). Where
// inertia weighs (small Lambda) the block is close to a mass matrix and ILU(1) on each rank's
// part nearly solves it, at a fraction of a direct solve's cost and memory; where elasticity
// dominates ILU's Krylov counts grow with 1/h^2 and the direct solve pays. Measured on 2
// ranks (docs/performance.md, issue 23): pipe-fsi (Lambda 8.1) 3.1 against 4.5 s/step;
// the dissection at dt 5 ms, 4.5 mm (Lambda 3.3e3) 2.5 against 3.9 s/step (Krylov 124
// against 89 per step), 2 mm (5.3e3) 6.2 against 8.2 (123 against 80), 1 mm (1.6e4) 114
// against 103 (92 against 34 Krylov per Newton iteration, 5 against 7 GB per process). The
// crossing lies between the last two: direct from 1e4 up.
//
// Every piece stays a PETSc option (prefixes -fsi_fieldsplit_motion_,
// -fsi_fieldsplit_motion_fieldsplit_wall_, ..._fluid_, -fsi_fieldsplit_pressure_). Giving
// -fsi_pc_fieldsplit_0_fields selects PETSc's own component split instead (the index sets
// below are then not attached).
#include <vector>

#include "fem/dof_map.hpp"
#include "fem/petsc.hpp"

namespace tearflow::physics {

class FsiPreconditioner {
public:
  /// wall_node[l]: owned node l has wall tets. Velocity is unknown 0-2 of a node's block,
  /// fluid pressure `fluid_pressure`, wall pressure `wall_pressure`.
  FsiPreconditioner(const fem::DofMap& dofs, const std::vector<unsigned char>& wall_node,
                    int fluid_pressure, int wall_pressure);

  /// PETSc option defaults for this split (entered where the user set nothing), the wall
  /// block's solver apart (wall_options).
  static fem::OptionList default_options();

  /// The wall block's solver for the wall's stiffness number Lambda = (E / rho) dt^2 / h^2
  /// (FsiProblem::wall_stiffness_number): ILU(1) on each rank's part below
  /// kDirectWallAbove, MUMPS at and above it (file comment).
  static fem::OptionList wall_options(double stiffness_number);
  static constexpr double kDirectWallAbove = 1.0e4;
  /// Whether a wall of this stiffness number gets the direct solve (wall_options).
  static bool wall_solved_directly(double stiffness_number) {
    return stiffness_number >= kDirectWallAbove;
  }

  /// Names the outer split's index sets on the KSP's preconditioner, if it is a field split
  /// the user did not define by components, and arranges for the inner split to be named
  /// when PETSc creates it; returns whether it did. The object must outlive the KSP.
  bool attach(KSP ksp);

private:
  static PetscErrorCode name_inner_split(KSP ksp, Vec, Vec, void* ctx);

  fem::OwnedIS motion_, pressure_; ///< outer split, global dof numbers
  fem::OwnedIS wall_, fluid_;      ///< inner split, numbered within the motion block
  bool inner_named_ = false;
};

} // namespace tearflow::physics
