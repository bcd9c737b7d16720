#pragma once
// One FSI mesh from a fluid mesh and a wall mesh whose interface nodes coincide (the
// SimVascular layout of the field's FSI cases: `lumen/` and `wall/`, matched node for node).
#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// The union of `fluid` (region "fluid") and `wall` (region "wall"): wall nodes that lie on
/// a fluid node (within 1e-9 of the fluid mesh's extent) become that node, so the two regions
/// share the interface nodes; faces keep their names. InputError (naming both sources) when
/// the meshes share no node or no face, when a named fluid face lies on the wall only in part
/// (an interface whose nodes coincide only in part), or when a face name appears in both.
Mesh merge_fluid_and_wall(const Mesh& fluid, const Mesh& wall);

} // namespace tearflow::mesh
