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
// On a moving wall the boundary integral also holds the wall's share, W = int_wall psi u.n dA
// (u = the wall's velocity there): F - W is the outflow downstream of the plane, the same for
// every plane with the same outlets below it; W_A - W_B is the rate of the volume stored
// between planes A and B. Where a plane cuts the lumen twice, psi is taken per cut: 1 on the
// far-side nodes connected to that cut's layer only.
//
// The solver poses the step from t_n to t_{n+1} at the generalized-alpha stage: u and the
// mesh at t_n + alpha_f dt, du/dt at t_n + alpha_m dt, p at t_{n+1}, tau_M from u_n and the
// viscous flux sigma_h from u_n + alpha_f dt du/dt_n on the mesh at t_n
// (physics/fluid_problem.cpp, fsi_problem.cpp). Two frames one step apart that
// hold du/dt (`acceleration`) give that stage exactly (step_stage): its F balances to the
// Newton tolerance, at the stage's time. A frame without its step's start gives an
// approximation (frame_state): the frame's fields at t_{n+1}, du/dt from the frame (else
// differences of its neighbours), u_n estimated as u - dt du/dt; that balances to O(dt).
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include <vtkDoubleArray.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

#include "core/types.hpp"
#include "physics/generalized_alpha.hpp"
#include "physics/navier_stokes_kernel.hpp"

class vtkDataArray;
class vtkUnstructuredGrid;

namespace tearflow::analysis {

/// Point fields of a frame the flux reads beside `velocity` and `pressure`.
inline constexpr const char* kAcceleration = "acceleration"; ///< du/dt as the run held it
inline constexpr const char* kOnWallArray = "on_wall";       ///< 1 at the moving wall's nodes
/// The pressure unknown at the step's stage t_n + alpha_f dt (the frame's `pressure` is at t_{n+1})
inline constexpr const char* kStagePressure = "stage_pressure";

/// What the continuity equation needs beyond the frames' fields.
struct ContinuityForm {
  double time_step = 0.0; ///< dt of the run [s]
  physics::FluidProperties fluid;
  physics::GeneralizedAlpha scheme = physics::GeneralizedAlpha::from_spectral_radius(0.5);
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

/// Boundary triangles on the moving wall (nodes, counter-clockwise seen from outside).
using WallTriangles = std::vector<std::array<vtkIdType, 3>>;

/// The boundary triangles of a frame's fluid grid whose three nodes are marked `on_wall`
/// (kOnWallArray), oriented outwards; none without that array (a rigid wall: u = 0 there).
/// The frames of one run share them: computed once per analysis.
WallTriangles wall_triangles(vtkUnstructuredGrid* frame);

/// The fields of the continuity equation at the nodes of a frame's fluid mesh (its order).
struct ContinuityState {
  std::vector<Vec3> x;          ///< where the equation is posed [m]
  std::vector<Vec3> x_lagged;   ///< where tau_M was computed [m]
  std::vector<Vec3> u, udot, w; ///< [m/s], [m/s^2], [m/s]
  std::vector<Vec3> lagged;     ///< tau_M's convective velocity [m/s]
  std::vector<double> p;        ///< [Pa]
  /// sigma_h, the viscous flux the solver's r_M reconstructs, per node (empty: the run has no
  /// viscous correction)
  std::vector<physics::SymTensor> viscous_flux;
  double time_step = 0.0;                    ///< [s]
  std::shared_ptr<const WallTriangles> wall; ///< the run's (wall_triangles); null: none
  bool exact = false; ///< the solver's stage (step_stage), not an estimate (frame_state)
};

/// True when `frame` (a deformed fluid grid of read_flow_frame) holds du/dt.
bool has_acceleration(vtkUnstructuredGrid* frame);

/// The stage of the step from `before` to `after` (frames one step, form.time_step, apart,
/// both with `acceleration`): exact. InputError when the frames' meshes differ.
ContinuityState step_stage(vtkUnstructuredGrid* before, vtkUnstructuredGrid* after,
                           const ContinuityForm& form, std::shared_ptr<const WallTriangles> wall);

/// The estimate from one frame at t_{n+1}: du/dt from the frame when it holds it, else from
/// `rates`; w from `rates`; step `form.time_step`.
ContinuityState frame_state(vtkUnstructuredGrid* frame, const FrameRates& rates,
                            const ContinuityForm& form, std::shared_ptr<const WallTriangles> wall);

/// The region (of the plane's section) holding a point on the plane inside a cut
/// tetrahedron, or -1 for none.
using RegionOf = std::function<vtkIdType(const Vec3& point)>;

/// The conservative flux through one plane.
struct PlaneFlux {
  std::vector<double> regions; ///< F per region (index = region id) [m^3/s]
  /// W per region: the moving wall's share in the part of the fluid downstream of the plane
  /// that the region's layer bounds [m^3/s]. A plane can cut the aorta twice (a station
  /// below the arch and the ascending aorta): each cut has its own downstream part, the
  /// nodes on the plane's far side connected to its layer.
  std::vector<double> wall;
  /// Which downstream part each region bounds (regions that share one, e.g. TL and FL joined
  /// below by the exit tear, share its W); -1 for a region the plane's layer does not reach.
  std::vector<vtkIdType> part;
};

/// F per region (`regions` of them) and W through the plane (origin, unit normal n, positive
/// downstream) of `grid` (linear tetrahedra; its connectivity, with `state`'s fields).
/// InputError when the grid holds other cells.
PlaneFlux conservative_fluxes(vtkUnstructuredGrid* grid, const ContinuityState& state,
                              const Vec3& origin, const Vec3& normal, const RegionOf& region_of,
                              vtkIdType regions, const ContinuityForm& form);

} // namespace tearflow::analysis
