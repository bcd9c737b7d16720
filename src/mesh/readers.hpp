#pragma once
// Mesh readers. Both return meshes in SI units (coordinates times `length_scale`, metres per
// file unit), with positively oriented tets, and run check_mesh before returning.
#include <filesystem>

#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// Gmsh .msh (v2 or v4) through the Gmsh SDK. 3D physical groups give the region names,
/// 2D physical groups the face names. Tets outside any 3D physical group go to region
/// "fluid" when the file has no 3D physical groups at all, else it is an InputError.
Mesh read_gmsh(const std::filesystem::path& file, double length_scale);

/// SimVascular mesh-complete layout: `dir/mesh-complete.mesh.vtu` and one
/// `dir/mesh-surfaces/NAME.vtp` per face (face name = file stem). Face nodes map to volume
/// nodes through `GlobalNodeID` when both files carry it, else by coordinates (an InputError
/// names the face and the point when a face node matches no volume node). Region "fluid"
/// unless `region` names it otherwise.
Mesh read_simvascular(const std::filesystem::path& dir, double length_scale,
                      const std::string& region = "fluid");

/// Dispatches on the path: a directory is SimVascular, *.msh is Gmsh, else InputError.
Mesh read_mesh(const std::filesystem::path& path, double length_scale);

} // namespace tearflow::mesh
