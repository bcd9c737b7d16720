#pragma once
#include "mesh/mesh.hpp"

namespace tearflow::mesh {

/// Reorders the nodes of every face triangle so that its normal (b-a) x (c-a) points out of
/// the tet it bounds. Readers do not agree on face orientation; the physics relies on it.
/// Throws InputError naming the face if a triangle bounds no tet.
void orient_faces_outward(Mesh& mesh);

} // namespace tearflow::mesh
