#pragma once
// `tearflow geometry import`: a user's model into the geometry layout (DIR/mesh.msh and
// DIR/landmarks.json), checked on the way in.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "geometry/landmarks.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::geometry {

struct ImportOptions {
  /// A finished mesh: Gmsh .msh (regions fluid and wall) or a SimVascular mesh-complete
  /// directory (fluid only). Or, instead, the two surfaces below.
  std::filesystem::path mesh;
  /// A separate wall mesh (SimVascular mesh-complete directory or .msh) whose inner face
  /// coincides node for node with the fluid's wall, as in SimVascular's FSI cases: merged
  /// into one mesh with shared interface nodes (the wall's copy of the shared face dropped).
  std::filesystem::path wall_mesh;
  /// Face renames (old, new), e.g. {"lumen_inlet", "inlet"}, {"lumen_wall", "interface"}.
  std::vector<std::pair<std::string, std::string>> rename_faces;
  /// Or surfaces, one STL or VTP file per named face (a directory of them, or one file):
  /// the lumen's faces (caps and lumen wall) and optionally the wall's (outer surface and
  /// rings at the caps), meshed by mesh_face_sets (geometry/surface_mesher.hpp).
  std::filesystem::path lumen, wall;
  std::filesystem::path landmarks; ///< landmarks JSON (required)
  double length_scale = 1e-3;      ///< metres per input length unit (mm by default)
  double element_size = 3e-3;      ///< for surfaces [m]
  /// Surfaces: remesh them with element_size (true), or keep their triangles as the mesh's
  /// boundary and mesh only the volumes (false).
  bool remesh_surfaces = true;
  bool verbose = false; ///< Gmsh's progress, for surfaces
};

/// Checks and converts (meshes surfaces); writes DIR/mesh.msh (mm) and DIR/landmarks.json.
/// InputError for surfaces that do not close the fluid or the wall, a mesh whose named faces do not
/// close the fluid (or lack inlet and outlet), landmarks outside the fluid.
void import_geometry(const ImportOptions& options, const std::filesystem::path& dir);

/// Writes a mesh as Gmsh MSH 2.2 (ASCII), coordinates in mm, one physical group per region
/// and per face: the format read_gmsh and read_fsi_mesh read back. InputError if it cannot.
void write_msh(const mesh::Mesh& mesh, const std::filesystem::path& file);

/// Checks a model (check_fsi_mesh; every fluid boundary triangle in a named face, inlet and
/// outlet among them; every landmark in the fluid) and writes DIR/mesh.msh (mm, Gmsh 2.2)
/// and DIR/landmarks.json. InputError naming what is wrong.
void write_geometry(const mesh::Mesh& mesh, const Landmarks& landmarks,
                    const std::filesystem::path& dir);

} // namespace tearflow::geometry
