#pragma once
// Plane sections of a mesh region and connectivity of its tets: lumen areas at landmarks,
// tear areas on the flap's mid-plane, and whether the lumina communicate.
#include <vector>

#include "core/types.hpp"
#include "geometry/landmarks.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::geometry {

/// The section of a region by a plane, split into connected pieces (two cut tets belong to
/// one piece when they share a face the plane crosses).
struct Section {
  std::vector<double> areas;                 ///< per piece [m^2]
  std::vector<Vec3> centroids;               ///< per piece
  std::vector<int> piece_of;                 ///< per cut tet (in `tets` order), its piece
  std::vector<Index> tets;                   ///< the cut tets
  std::vector<std::vector<Vec3>> polygons;   ///< per cut tet, its section polygon
  int piece_containing(const Vec3& p) const; ///< -1 if no polygon contains p
};

/// Section of the tets of region `region` by the plane through `origin` with normal `normal`.
Section cut_region(const mesh::Mesh& mesh, int region, const Vec3& origin, const Vec3& normal);

/// Index of region `name`; InputError if the mesh has none.
int region_index(const mesh::Mesh& mesh, const std::string& name);

/// Fluid area at a landmark: the piece of the fluid section containing the landmark's
/// point (its origin if it has none). InputError when that point is not in the fluid.
double landmark_area(const mesh::Mesh& mesh, const Landmark& landmark);

/// Tear area as meshed: the piece of the fluid section by the flap's mid-plane (through the
/// tear's centroid, normal to the flap) that contains the centroid, i.e. the hole.
double tear_area(const mesh::Mesh& mesh, const TearLandmark& tear);

/// Connected components of the fluid tets (face neighbours), leaving out tets with
/// removed[t] != 0. Returns per tet its component (-1 for removed and non-fluid tets).
std::vector<int> fluid_components(const mesh::Mesh& mesh, const std::vector<char>& removed);

/// The tet containing point p (-1 if none), among tets of `region` (all if -1).
Index locate(const mesh::Mesh& mesh, const Vec3& p, int region = -1);

/// Marks the fluid tets of a tear region: tets that cross the flap's mid-plane within
/// `scale` times the tear's semi-axes. Every path between the lumina through that tear
/// crosses the mid-plane inside the hole, so removing them closes the tear.
std::vector<char> tear_region(const mesh::Mesh& mesh, const TearLandmark& tear, double scale);

} // namespace tearflow::geometry
