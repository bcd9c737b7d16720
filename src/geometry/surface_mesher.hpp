#pragma once
// A user's model given as surfaces, one file per named face (SimVascular's mesh-surfaces
// layout: inlet.vtp, outlet.vtp, lumen_wall.vtp, ...), meshed through Gmsh into the same
// layout as the parametric TBAD: one conforming tet mesh with regions `fluid` (and `wall`)
// and the faces named after their files.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::geometry {

/// One named face read from a surface file: triangles on their own points [m].
struct FaceSurface {
  std::string name;           ///< the file's stem, after renames
  std::filesystem::path file; ///< for messages
  std::vector<Vec3> points;
  std::vector<Tri> triangles;
};

/// A set of face files: `path` is one STL or VTP file (one face, named by its stem) or a
/// directory of them (or a SimVascular mesh-complete directory: its mesh-surfaces/).
/// `what` ("lumen", "wall") and `path` name the set in messages.
struct FaceSet {
  std::string what;
  std::filesystem::path path;
  std::vector<FaceSurface> faces;
};

/// Reads the face files at `path`, coordinates times `length_scale`, renaming faces by
/// `renames` (old, new). InputError for a missing or unreadable file, an empty directory,
/// a file whose triangles are not consistently oriented.
FaceSet read_face_set(const std::filesystem::path& path, const std::string& what,
                      double length_scale,
                      const std::vector<std::pair<std::string, std::string>>& renames);

/// Meshes the fluid enclosed by the `lumen` faces and, when `wall` has faces, the wall
/// between the lumen face called `interface` and the wall's faces (its outer surface and
/// the rings at the caps; a wall face that repeats lumen triangles, such as SimVascular's
/// wall_inner, is dropped). With `remesh`, the input triangulations are classified into
/// patches (sharp edges above 25 degrees and the faces' borders kept), reparametrized and
/// remeshed with edges of about `element_size` [m]; without, their triangles are the
/// mesh's boundary. The volumes are meshed by Delaunay (elements at most `element_size`).
/// Faces keep their names; the fluid-wall face is `interface`. InputError when the lumen
/// or the wall is not closed (edges not shared by exactly two triangles), when a wall is
/// given but no lumen face is called `interface`, or when Gmsh fails.
mesh::Mesh mesh_face_sets(const FaceSet& lumen, const FaceSet& wall, double element_size,
                          bool remesh = true, bool verbose = false);

} // namespace tearflow::geometry
