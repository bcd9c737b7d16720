#pragma once
// Flow through the landmark planes of one saved frame: the fluid mesh of the frame is cut by
// each landmark's plane (vtkCutter), the section is split into its connected regions
// (vtkConnectivityFilter), the region holding the landmark's lumen point is kept, and the
// fields are integrated over it (vtkIntegrateAttributes):
//   Q = int_S u.n dA,  A = int_S dA,  P = (1 / A) int_S p dA,  u_max = max_S u.n,
// n the landmark's unit normal (downstream). The fields are P1, so the section carries them
// exactly (linear along each cut edge) and the integrals are exact for the P1 fields on the
// polygonal section; what differs from a smooth vessel is only the section's shape.
//
// The section of a plane can hold more regions than the landmark's lumen (a plane through
// the descending aorta can also cut the arch, and TLk / FLk share one plane): the lumen
// point (the landmark's `point`, else its origin), projected onto the plane, picks the
// region that contains it. The two landmarks of a paired station TLk / FLk must pick two
// different regions.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "analysis/conservative_flux.hpp"
#include "geometry/landmarks.hpp"

class vtkPointSet;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace tearflow::analysis {

/// One entry of a `.pvd` collection.
struct FlowFrame {
  double time = 0.0; ///< [s]
  std::filesystem::path file;
};

/// The frames of a `.pvd` collection in time order (paths resolved against its folder);
/// InputError naming the file when it is missing or lists no frame.
std::vector<FlowFrame> read_pvd(const std::filesystem::path& pvd);

/// Reads a frame's VTU; InputError naming the file when it cannot be read or lacks the point
/// fields `velocity` (3 components) or `pressure`. A frame of a fluid-structure run is
/// reduced to its `fluid` region and moved by its `displacement` field: the deformed lumen;
/// the nodes it shares with the wall get the point field `on_wall` (kOnWallArray).
vtkSmartPointer<vtkUnstructuredGrid> read_flow_frame(const std::filesystem::path& vtu);

/// The integrals over one landmark's lumen section, SI.
struct SectionValues {
  double flow = 0.0;                       ///< Q [m^3/s]: the conservative flux, else int u.n dA
  double flow_interpolated = std::nan(""); ///< int u.n dA of the P1 velocity [m^3/s]
  double area = 0.0;                       ///< A [m^2]
  double pressure = 0.0;                   ///< area-mean pressure [Pa]
  double max_velocity = 0.0;               ///< largest through-plane velocity u.n [m/s]
  double wall_displacement = 0.0;          ///< largest |displacement| on the section (its rim) [m]
  /// The moving wall's outflow downstream of the plane (analysis/conservative_flux.hpp, W):
  /// Q - W is the same at planes with the same outlets below them [m^3/s]; 0 on rigid walls.
  double wall_outflow = 0.0;
  /// Which downstream part of its plane wall_outflow is of (TLk and FLk joined below share
  /// one; analysis/conservative_flux.hpp); -1 when unknown.
  long wall_part = -1;
  /// At a paired station (TLk and FLk alike): the flap's displacement toward the false lumen,
  /// the mean over the lumina's rims that face each other across it [m]; NaN elsewhere and
  /// without a displacement field.
  double flap_displacement = std::nan("");
};

/// The section values of every landmark in `landmarks.planes` (same order) on `grid`; with
/// the step's continuity state and the run's form, `flow` is the conservative flux
/// (analysis/conservative_flux.hpp) of the landmark's region at the state's time level and
/// `wall_outflow` its plane's W, else `flow` is the plane integral. InputError naming the landmark
/// and `frame` when a plane misses the fluid, when a lumen point is not in the plane's fluid
/// section, or when the TLk and FLk points of a station fall in one connected region.
std::vector<SectionValues> measure_landmarks(vtkUnstructuredGrid* grid,
                                             const geometry::Landmarks& landmarks,
                                             const std::string& frame,
                                             const ContinuityState* state = nullptr,
                                             const ContinuityForm* form = nullptr);

/// The fluid section of one landmark's lumen, as measure_landmarks picks it: the polygons of
/// the connected region of the plane's section that holds the landmark's lumen point, with
/// the frame's point fields and `through_plane_velocity` u.n [m/s]. InputError naming the
/// landmark and `frame` when the plane misses the fluid or the point is not in its section.
vtkSmartPointer<vtkPolyData> lumen_section(vtkUnstructuredGrid* grid,
                                           const geometry::Landmark& landmark,
                                           const std::string& frame);

/// The cells of `data` whose integer cell array `array` holds `value` (a frame's volume
/// region, a section's connected piece).
vtkSmartPointer<vtkUnstructuredGrid> cells_with(vtkPointSet* data, const char* array,
                                                vtkIdType value);

/// The station number k of a paired landmark "TLk" / "FLk" (0 for other names).
int station_of(const geometry::Landmark& landmark);

} // namespace tearflow::analysis
