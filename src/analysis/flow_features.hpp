#pragma once
// The flow pattern of one saved frame as geometry (issue 30): streamlines seeded on a
// landmark plane and the sections of every landmark plane, written as VTP for ParaView and
// for the pictures (report/flow_pictures.hpp). No rendering here.
//
// Streamlines: vtkStreamTracer through the frame's fluid (the deformed lumen of an FSI run),
// Runge-Kutta-Fehlberg 4(5) with the step in cell lengths, traced both ways from each seed
// (each direction its own polyline starting at the seed), until the speed falls below
// kTerminalSpeed, the trace leaves the fluid or reaches its length bound. Seeds: a regular
// grid on the seed landmark's plane, kept where it lies inside that landmark's lumen section
// (not in other lumina the plane happens to cut).
//
// Plane maps: the landmark's lumen section (analysis/landmark_sections.hpp) with its
// through-plane velocity u.n, n the landmark's downstream normal, and the in-plane velocity
// u - (u.n) n sampled on a coarser regular grid of the section for arrows.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <vtkSmartPointer.h>

#include "analysis/landmark_sections.hpp"
#include "geometry/landmarks.hpp"

class vtkAbstractCellLocator;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace tearflow::analysis {

/// Point arrays of the products, every one in m/s.
inline constexpr const char* kSpeedArray = "speed";
inline constexpr const char* kThroughPlaneArray = "through_plane_velocity";
inline constexpr const char* kInPlaneArray = "in_plane_velocity";

/// A saved frame chosen for the pictures and why.
struct PictureFrame {
  FlowFrame frame;
  std::string event; ///< "peak systole", "mid-diastole" or "t = 0.25 s"
};

/// The cycle's frames the pictures show, from one pass over the run's inlet flow.
struct CycleFrames {
  /// Among the frames `analyze` would take (the last complete cycle, else every saved frame),
  /// the one of largest flow through the `inlet` landmark (else the first landmark): the
  /// analysis's own flows when its CSV is of those frames, else the plane integral of u.n.
  PictureFrame peak_systole;
  /// Halfway (in time) from the end of systole to the end of those frames, the end of
  /// systole the first frame after the peak whose inlet flow falls below a tenth of the
  /// peak's; none when the flow never falls that far.
  std::optional<PictureFrame> mid_diastole;
  std::vector<FlowFrame> frames; ///< those frames, in time order (for an animation)
};

CycleFrames cycle_frames(const std::filesystem::path& run_dir,
                         const geometry::Landmarks& landmarks);

/// The rule of CycleFrames on any series (a simulation's frames, a scan's): the index of the
/// largest flow, and of mid-diastole as defined there. InputError for no frame or unequal
/// lengths.
struct CycleEvents {
  std::size_t peak_systole = 0;
  std::optional<std::size_t> mid_diastole;
};
CycleEvents cycle_events(const std::vector<double>& time, const std::vector<double>& flow);

/// Area [m^2] and int u.n dA [m^3/s] of a section carrying `through_plane_velocity`
/// (lumen_section's).
std::pair<double, double> area_and_flow(vtkPolyData* section);

/// The saved frame nearest `time` [s]; InputError naming flow.pvd and the saved range when
/// `time` lies outside it (by more than half the largest gap between frames).
PictureFrame frame_at(const std::filesystem::path& run_dir, double time);

struct StreamlineOptions {
  /// Spacing of the seed grid on the plane [m]; 0: the section's equivalent diameter / 10.
  double seed_spacing = 0.0;
  /// Length bound of each trace [m]; 0: twice the diagonal of the fluid's bounding box.
  double max_length = 0.0;
};

/// Below this speed a trace stops [m/s]: the no-slip wall, where a seed next to it would
/// take thousands of steps to go nowhere.
inline constexpr double kTerminalSpeed = 1e-4;

/// The seed points: the regular grid (spacing as above, aligned with the landmark's point)
/// on `seed`'s plane inside its lumen section. InputError naming `frame` when none lies in it.
vtkSmartPointer<vtkPolyData> seed_points(vtkUnstructuredGrid* fluid, const geometry::Landmark& seed,
                                         const StreamlineOptions& options,
                                         const std::string& frame);

/// Streamlines from seed_points through `fluid` (point field `velocity`), both ways: polylines
/// with point arrays `velocity` and `speed` [m/s] and `IntegrationTime` [s], cell array
/// `SeedIds`. InputError naming `frame` when no seed lies in the lumen (seed_points').
vtkSmartPointer<vtkPolyData> trace_streamlines(vtkUnstructuredGrid* fluid,
                                               const geometry::Landmark& seed,
                                               const StreamlineOptions& options,
                                               const std::string& frame);

/// The same from given seed points (another field's seed_points, so that two fields are
/// traced from the same seeds); a seed outside `fluid` starts no line.
vtkSmartPointer<vtkPolyData> trace_streamlines(vtkUnstructuredGrid* fluid, vtkPolyData* seeds,
                                               const StreamlineOptions& options);

/// One landmark's plane map.
struct PlaneMap {
  geometry::Landmark landmark;
  /// The lumen section: polygons with `velocity`, `through_plane_velocity` and `speed` [m/s].
  vtkSmartPointer<vtkPolyData> section;
  /// Points of the coarser grid inside the section with `velocity` and `in_plane_velocity`
  /// [m/s] (one vertex cell each), for arrows.
  vtkSmartPointer<vtkPolyData> vectors;
  double vector_spacing = 0.0; ///< of the arrows' grid [m]
  double area = 0.0;           ///< [m^2]
  double flow = 0.0;           ///< int u.n dA over the section [m^3/s]
};

/// The plane map of `landmark`; `vector_spacing` [m] (0: equivalent diameter / 8). The
/// arrows' velocity is located in `fluid` by `fluid_locator` (built on `fluid`; pass one for
/// all the planes of a frame: on the study's meshes a build costs about a second), else by
/// one built here.
PlaneMap plane_map(vtkUnstructuredGrid* fluid, const geometry::Landmark& landmark,
                   double vector_spacing, const std::string& frame,
                   vtkAbstractCellLocator* fluid_locator = nullptr);

/// A cell locator of `fluid` for plane_map.
vtkSmartPointer<vtkAbstractCellLocator> fluid_locator(vtkUnstructuredGrid* fluid);

/// The wall of an FSI frame (the VTU's `wall` region, in its reference position, with the
/// point field `displacement` [m]); nullptr for a frame without a wall (a rigid-wall run).
vtkSmartPointer<vtkUnstructuredGrid> read_wall(const std::filesystem::path& vtu);

/// Writes `data` as a VTP file (binary, appended); InputError naming it when that fails.
void write_vtp(vtkPolyData* data, const std::filesystem::path& file);

} // namespace tearflow::analysis
