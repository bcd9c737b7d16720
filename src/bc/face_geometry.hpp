#pragma once
// Geometry of a named face on the (replicated) input mesh: area, mean outward normal,
// centroid, its nodes, and each node's distance to the face's rim (the boundary edges of
// the triangulation). Triangles must be oriented outward (mesh::orient_faces_outward).
#include <cmath>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::bc {

struct FaceGeometry {
  double area = 0.0;                ///< [m^2]
  Vec3 normal{};                    ///< area-weighted mean outward unit normal
  Vec3 centroid{};                  ///< [m]
  std::vector<Index> nodes;         ///< mesh node numbers on the face, sorted
  std::vector<double> rim_distance; ///< per entry of `nodes`: distance to the rim [m]
  double max_rim_distance = 0.0;    ///< inscribed radius of the outline [m]
  /// Largest angle between a triangle normal and `normal` [rad]: 0 for a planar face.
  double max_normal_deviation = 0.0;
};

FaceGeometry face_geometry(const mesh::Mesh& mesh, const mesh::Face& face);

/// Triangle area and outward unit normal.
inline void triangle_area_normal(const Vec3& a, const Vec3& b, const Vec3& c, double& area,
                                 Vec3& normal) {
  const Vec3 n = cross(b - a, c - a);
  const double twice = std::sqrt(dot(n, n));
  area = 0.5 * twice;
  normal = (1.0 / twice) * n;
}

} // namespace tearflow::bc
