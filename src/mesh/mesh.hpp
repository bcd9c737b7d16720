#pragma once
// A tetrahedral mesh with named volume regions and named boundary faces, in SI units.
// Readers (Gmsh, SimVascular mesh-complete) and the pipe generator produce it; everything
// downstream (partition, physics, output) reads it and never changes it.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/types.hpp"

namespace tearflow::mesh {

/// A named boundary face: triangles whose nodes index Mesh::points.
struct Face {
  std::string name;
  std::vector<Tri> triangles;
};

struct Mesh {
  std::vector<Vec3> points;         ///< node coordinates [m]
  std::vector<Tet> tets;            ///< positively oriented (det J > 0) node quadruples
  std::vector<int> tet_region;      ///< per tet, an index into `regions`
  std::vector<std::string> regions; ///< volume region names, e.g. "fluid", "wall"
  std::vector<Face> faces;          ///< named boundary faces
  std::string source;               ///< where it came from, for messages

  Index num_nodes() const { return static_cast<Index>(points.size()); }
  Index num_tets() const { return static_cast<Index>(tets.size()); }
  bool has_face(std::string_view name) const;
  /// The face called `name`; throws InputError listing the known names otherwise.
  const Face& face(std::string_view name) const;
};

/// FNV-1a of the nodes, the tets and their regions: what a run computes on (its fingerprint,
/// run/run_fingerprint.cpp; checkpoints keep it, so it must not change).
std::uint64_t solution_digest(const Mesh& mesh);

/// solution_digest continued with the region and face names and the faces' triangles:
/// everything a run takes from the mesh (the ranks compare it, fem/distributed_mesh.cpp).
std::uint64_t digest(const Mesh& mesh);

/// Signed volume of tet (a, b, c, d): det[b-a, c-a, d-a] / 6.
double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Validates a mesh just read: every tet has positive volume above a relative tolerance
/// (inverted or degenerate elements are an InputError naming the element and `mesh.source`),
/// every face triangle lies on the boundary of the tet mesh, face names are unique and
/// non-empty. Throws InputError.
void check_mesh(const Mesh& mesh);

/// Removes nodes used by no tet and renumbers tets and faces (readers call it before
/// check_mesh). Throws InputError if a face triangle uses such a node.
void drop_unused_nodes(Mesh& mesh);

} // namespace tearflow::mesh
