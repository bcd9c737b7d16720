#pragma once
// Built-in straight-pipe meshes (through the Gmsh SDK) for tests, verification and
// benchmarks. The pipe axis is z, from z = 0 (face `inlet`) to z = length (face `outlet`);
// the lateral surface is face `wall`; the volume region is `fluid`.
//
// With a wall thickness h > 0 the pipe gets a wall: regions `fluid` (the lumen, radius r)
// and `wall` (the annulus r..r+h), one conforming mesh sharing the interface nodes, faces
// `inlet`, `outlet` (fluid caps), `interface` (between the regions), `wall_inlet`,
// `wall_outlet` (the wall's end rings) and `outer_wall`: the compliant tube of the FSI
// verification cases.
#include <cmath>
#include <filesystem>

#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// Structured layers at the lumen's wall. A strongly imposed no-slip condition takes the
/// first element layer's flow: with P1 velocities the layer carries about half the core's
/// velocity, so a uniform mesh of size h moves an unsteady core flow (Stokes layer far
/// thinner than h) as if its area were ~(1 - 0.6 h / a) of the lumen's: a fluid inertance,
/// and a pressure-wave speed, off at O(h). Layers as thin as the physics keep that error
/// at O(first / a) without refining the core.
struct BoundaryLayers {
  int count = 0;       ///< layers in the lumen at its wall; 0: uniform unstructured mesh
  double first = 0.0;  ///< thickness of the layer at the wall [m]
  double growth = 1.3; ///< thickness ratio of neighbouring layers, inwards
  int wall_layers = 3; ///< layers through the wall's thickness (with a wall)
  /// The lumen's ring of layers: first (growth^count - 1) / (growth - 1) [m].
  double thickness() const {
    return growth == 1.0 ? count * first : first * (std::pow(growth, count) - 1.0) / (growth - 1.0);
  }
};

struct PipeSpec {
  double radius = 0.01;        ///< [m]
  double length = 0.1;         ///< [m]
  double element_size = 0.002; ///< target tetrahedron edge length [m]
  double wall_thickness = 0.0; ///< > 0: a wall region around the lumen [m]
  /// count > 0: the cross-section is meshed (unstructured core, structured ring of layers,
  /// structured wall) and extruded along z in steps of element_size, each prism cut into
  /// three tets. The faces and regions are named as for the uniform pipe.
  BoundaryLayers layers{};
};

/// Throws InputError on non-positive dimensions or a size that would give over 20 M tets.
Mesh make_pipe(const PipeSpec& spec);

/// make_pipe that also writes the Gmsh mesh, with its physical groups, to `msh_file` (format
/// from the extension, e.g. .msh): to inspect the pipe, or to test read_gmsh on it.
Mesh make_pipe(const PipeSpec& spec, const std::filesystem::path& msh_file);

} // namespace tearflow::mesh
