#pragma once
// A ParaView state file (.pvsm) of a run's flow pictures (issue 30, docs/analysis.md "Flow
// pictures"): loaded in ParaView (File > Load State), it shows the run's flow.pvd (the time
// series, its clock at the pictured frame), that frame's streamlines, plane sections and
// in-plane arrows, coloured on the pictures' fixed scales, one layout (tab) per standard view
// with the pictures' camera. ParaView is not a dependency: this writes the XML text itself.
// A state may leave out any property, which then keeps ParaView's default (checked with
// ParaView 5.11's pvbatch, tests/test_paraview_state.cpp), so only what differs is written.
// File names are relative to the state's folder: ParaView resolves them there when the state
// is loaded with "Search files under specified directory" (its Load State dialog fills in the
// state's folder), or when it is started in that folder.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "report/flow_pictures.hpp"

namespace tearflow::report {

/// One landmark's plane section and its grid of in-plane arrows.
struct StatePlane {
  std::string name;           ///< the landmark's
  std::string section;        ///< plane_<name>.vtp, relative to the state's folder
  std::string arrows;         ///< arrows_<name>.vtp, relative to the state's folder
  double arrow_spacing = 0.0; ///< the arrows' grid step [m]
};

/// What the state shows: what the pictures command knows once it has written the frame's
/// files. Colours and views are those of the pictures (flow_pictures.hpp).
struct StateScene {
  std::string flow_pvd; ///< the run's series, relative to the state's folder
  /// The fluid's value of the cell array `region` when the mesh has several regions (an FSI
  /// run's wall beside the fluid): the lumen is drawn from those cells only.
  std::optional<long> fluid_region;
  bool displaced = false;  ///< the fluid mesh moves: the lumen is warped by `displacement`
  double time = 0.0;       ///< the pictured frame's time [s]: where the scene's clock stands
  std::string streamlines; ///< relative to the state's folder
  std::vector<StatePlane> planes;
  double speed_max = 1.5;   ///< speed on 0..speed_max, u.n on +-speed_max [m/s]
  double arrow_speed = 0.0; ///< the in-plane speed an arrow of 1.5 grid steps stands for [m/s]
  /// The lumen's box [m] (x0, x1, y0, y1, z0, z1): each camera frames it as the pictures do.
  std::array<double, 6> bounds{};
  std::vector<View> views;
};

/// The camera of a picture's view of `bounds`: what VTK's ResetCamera gives for the box
/// (focal point at its centre, distance radius / sin(15 deg) at the 30 deg view angle).
struct Camera {
  Vec3 position{}, focal_point{}, up{};
  double parallel_scale = 0.0; ///< [m] the box's radius
};
Camera picture_camera(const View& view, const std::array<double, 6>& bounds);

/// The state's XML text, for ParaView 5.11 (later versions convert a 5.11 state).
std::string paraview_state(const StateScene& scene);

} // namespace tearflow::report
