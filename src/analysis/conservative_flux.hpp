#pragma once
// The flux the flow solver conserves through a landmark plane (Hughes, Engel, Mazzei &
// Larson, "The continuous Galerkin method is locally conservative", JCP 2000).
//
// The solver's continuity equation (physics/navier_stokes_kernel.hpp) holds for every P1
// test function q:
//   (q, div u) + sum_e (tau_M / rho grad q, r_M)_e = 0,   r_M = rho (du/dt + c . grad u) + grad p.
// Its discrete velocity is therefore not pointwise divergence-free: the mass it conserves is
// carried by u - (tau_M / rho) r_M, whose PSPG part is large where the mesh is coarse for the
// pressure gradient (a jet through a tear, a true lumen three elements thick). The plane
// integral of the interpolated u then differs between planes by int div u over the volume
// between them, which no refinement of the cut removes.
//
// Take for q the P1 function psi that is 1 at the nodes downstream of a plane and 0 upstream:
// grad psi lives only in the layer L of tetrahedra the plane cuts, and integrating (psi, div u)
// by parts gives
//   F = sum_{e in L} int_e grad psi . (u - (tau_M / rho) r_M) dV = int_{dOmega} psi u . n dA,
// the flow out of the domain downstream of the plane (the wall's share is zero on a rigid
// wall, the stored volume's rate on a moving one). F is the conservative flux through the
// plane: it balances exactly between any two planes, up to the solver's tolerance. Split by
// the connected region of the section each cut tetrahedron belongs to, it gives each
// lumen's flow.
//
// The frame does not hold everything the solver used: du/dt comes from the neighbouring
// frames (a central difference, first order in the frame interval where the flow changes),
// and tau_M's lagged velocity u_n is estimated as u - dt du/dt. Both only change the PSPG
// term, by O(dt), and the balance measured on the demo says how much (docs/analysis.md).
#include <functional>
#include <vector>

#include <vtkDoubleArray.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

#include "core/types.hpp"
#include "physics/navier_stokes_kernel.hpp"

class vtkDataArray;
class vtkUnstructuredGrid;

namespace tearflow::analysis {

/// What the continuity equation needs beyond the frame's fields.
struct ContinuityForm {
  double time_step = 0.0; ///< dt of the run [s]
  physics::FluidProperties fluid;
};

/// Point fields that a frame's time derivatives add: du/dt and, on a moving mesh, the
/// mesh velocity w (from the displacement). Either may be null (then zero).
struct FrameRates {
  vtkDataArray* acceleration = nullptr;  ///< du/dt at the nodes [m/s^2]
  vtkDataArray* mesh_velocity = nullptr; ///< w [m/s]
};

/// FrameRates by central differences between the frames before and after (or one-sided,
/// when one of them is the frame itself): du/dt from `velocity` and, when the frames hold a
/// `displacement`, w from it. The arrays live as long as this object.
struct FrameDifferences {
  vtkSmartPointer<vtkDoubleArray> acceleration, mesh_velocity;
  FrameRates rates() const { return {acceleration, mesh_velocity}; }
};
FrameDifferences frame_differences(vtkUnstructuredGrid* before, double t_before,
                                   vtkUnstructuredGrid* after, double t_after);

/// The region (of the plane's section) holding a point on the plane inside a cut
/// tetrahedron, or -1 for none.
using RegionOf = std::function<vtkIdType(const Vec3& point)>;

/// F per region (index = region id, `regions` of them) through the plane (origin, unit
/// normal n, positive downstream) on `grid` (linear tetrahedra, point fields velocity and
/// pressure). InputError when the grid holds other cells.
std::vector<double> conservative_fluxes(vtkUnstructuredGrid* grid, const Vec3& origin,
                                        const Vec3& normal, const RegionOf& region_of,
                                        vtkIdType regions, const FrameRates& rates,
                                        const ContinuityForm& form);

} // namespace tearflow::analysis
