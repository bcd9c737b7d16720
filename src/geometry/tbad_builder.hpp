#pragma once
// Builds the parametric TBAD in Gmsh's OpenCASCADE kernel, meshes it, and writes the
// geometry layout: DIR/mesh.msh (mm; regions `fluid` and `wall`, faces inlet, BCT, LCC,
// LSA, outlet, wall_<cap>, outer_wall, interface) and DIR/landmarks.json.
#include <filesystem>

#include "geometry/landmarks.hpp"
#include "geometry/tbad_spec.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::geometry {

struct TbadBuild {
  mesh::Mesh mesh; ///< SI units, as written
  Landmarks landmarks;
  double cad_seconds = 0, mesh_seconds = 0;
};

/// Builds and meshes the model of `spec` and writes DIR/mesh.msh and DIR/landmarks.json
/// (`dir` is created). InputError for bad parameters or when OpenCASCADE or the mesher fail.
TbadBuild build_tbad(const TbadSpec& spec, const std::filesystem::path& dir, bool verbose = false);

} // namespace tearflow::geometry
