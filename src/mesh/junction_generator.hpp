#pragma once
// A built-in three-outlet junction (through the Gmsh SDK) for verifying outlet coupling and
// flow splits: a trunk along z from z = 0 (face `inlet`) to the junction at z = trunk_length,
// where a straight branch (face `outlet_1`) and two side branches in the x-z plane at
// +-side_angle (faces `outlet_2` at +x, `outlet_3` at -x) leave; a sphere of the trunk's
// radius rounds the junction. Lateral surfaces form face `wall`; the volume is `fluid`.
#include "mesh/mesh.hpp"

namespace tearflow::mesh {

struct JunctionSpec {
  double trunk_radius = 0.006, trunk_length = 0.03; ///< [m]
  double straight_radius = 0.004, straight_length = 0.03;
  double side_radius = 0.0035, side_length = 0.025;
  double side_angle_deg = 50.0; ///< from the z axis
  double element_size = 0.0012;
};

/// Throws InputError on non-positive dimensions or branches wider than the trunk.
Mesh make_junction(const JunctionSpec& spec);

} // namespace tearflow::mesh
