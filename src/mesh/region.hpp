#pragma once
// One volume region of a multi-region mesh as a mesh of its own: the fluid of an FSI mesh
// for a rigid-wall flow run. Named faces keep the triangles that bound the region (so the
// fluid-wall `interface` becomes a boundary face of the fluid); faces of the other regions
// only are dropped.
#include <string>

#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// The index of volume region `name` in mesh.regions (its tets' tet_region); InputError
/// naming the known regions if there is none.
int region_index(const Mesh& mesh, const std::string& name);

/// InputError naming the known regions if `mesh` has no region `name`.
Mesh extract_region(const Mesh& mesh, const std::string& name);

} // namespace tearflow::mesh
