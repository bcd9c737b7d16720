#pragma once
// Structured tetrahedral meshes for the solid's verification cases and benchmarks: a box and
// an annular sector (a thick-walled tube or a slice of it). A logical grid of hexahedra is
// mapped to space and each hexahedron cut into the six tets of the Kuhn (Freudenthal)
// split, which is conforming between neighbours. Boundary faces are named after the grid
// side they lie on; tets are positively oriented, faces outward, region "solid".
#include <array>

#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// [0, lx] x [0, ly] x [0, lz] in cells nx x ny x nz; faces x0, x1, y0, y1, z0, z1.
Mesh make_box(const Vec3& lengths, const std::array<int, 3>& cells);

struct AnnulusSpec {
  double inner_radius = 0.01;          ///< a [m]
  double outer_radius = 0.012;         ///< b [m]
  double length = 0.05;                ///< along z [m]
  double angle = 6.283185307179586;    ///< sector opening [rad]; 2 pi closes the tube
  std::array<int, 3> cells{2, 64, 16}; ///< radial, circumferential, axial
};

/// Axis z; faces inner, outer, z0, z1 and, for an open sector (angle < 2 pi), theta0 (the
/// plane y = 0) and theta1. Throws InputError on non-positive sizes or counts.
Mesh make_annulus(const AnnulusSpec& spec);

} // namespace tearflow::mesh
