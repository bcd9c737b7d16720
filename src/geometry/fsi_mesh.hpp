#pragma once
// Meshes with a fluid and a wall region sharing their interface nodes, as the geometry
// commands write them. mesh::check_mesh expects every named face on the boundary of the tet
// mesh; the `interface` face lies between the regions, so these meshes get their own check.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::geometry {

/// Shape quality of one region: the radius ratio 3 r_in / r_circ (1 for a regular tet,
/// 0 for a flat one).
struct RegionQuality {
  std::string name;
  std::size_t tets = 0;
  double min_quality = 0, mean_quality = 0, volume = 0; ///< volume [m^3]
  std::size_t below_0_1 = 0;                            ///< tets with quality < 0.1
};

struct MeshReport {
  std::vector<RegionQuality> regions;
  std::size_t interface_triangles = 0, interface_nodes = 0;
};

/// Radius ratio 3 r_in / r_circ of a tet.
double radius_ratio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Checks a fluid(-wall) mesh: a region `fluid`; no inverted or degenerate tet; every named
/// face made of tet faces; `interface` (if present) between one fluid and one wall tet per
/// triangle, every other face on the boundary. Returns the quality per region. Throws
/// InputError naming `mesh.source`, the face and the element.
MeshReport check_fsi_mesh(const mesh::Mesh& mesh);

/// Pairs of tets sharing a face, among the tets with keep[t] != 0 (all if keep is empty).
std::vector<std::pair<Index, Index>> face_neighbours(const mesh::Mesh& mesh,
                                                     const std::vector<char>& keep = {});

/// Reads a Gmsh mesh written by the geometry commands (coordinates times `length_scale`),
/// drops unused nodes and runs check_fsi_mesh.
mesh::Mesh read_fsi_mesh(const std::filesystem::path& file, double length_scale);

} // namespace tearflow::geometry
