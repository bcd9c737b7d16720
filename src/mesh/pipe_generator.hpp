#pragma once
// Built-in straight-pipe meshes (through the Gmsh SDK) for tests, verification and
// benchmarks. The pipe axis is z, from z = 0 (face `inlet`) to z = length (face `outlet`);
// the lateral surface is face `wall`; the volume region is `fluid`.
#include <filesystem>

#include "mesh/mesh.hpp"

namespace tearflow::mesh {

struct PipeSpec {
  double radius = 0.01;        ///< [m]
  double length = 0.1;         ///< [m]
  double element_size = 0.002; ///< target tetrahedron edge length [m]
};

/// Throws InputError on non-positive dimensions or a size that would give over 20 M tets.
Mesh make_pipe(const PipeSpec& spec);

/// make_pipe that also writes the Gmsh mesh, with its physical groups, to `msh_file` (format
/// from the extension, e.g. .msh): to inspect the pipe, or to test read_gmsh on it.
Mesh make_pipe(const PipeSpec& spec, const std::filesystem::path& msh_file);

} // namespace tearflow::mesh
