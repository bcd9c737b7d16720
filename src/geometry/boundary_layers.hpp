#pragma once
// Prismatic boundary layers in the flow region of a tetrahedral mesh, split into tetrahedra.
//
// Why. On P1 tetrahedra oblique to the flow, the velocity's element gradient has a spurious
// streamwise part of O(h u'') even where the flow is parallel (a developed profile
// u(r)); SUPG and PSPG dissipate it as tau_M |u . grad u_h|^2 (docs/performance.md, "The
// P1 scheme's loss in a narrow lumen": most of the thin true lumen's excess loss). A layer
// of prisms on the wall, cut into tetrahedra, has in every tetrahedron an edge across the
// layer and a face on the layer's surface, on which a wall-parallel profile is constant: its
// gradient there is across the layer, as the flow's. Layers also resolve the wall's shear
// with few elements.
//
// How. The mesh is not remeshed: the flow region's nodes on the wall get a column of copies
// along the inward normal; the region's own tetrahedra take the innermost copy in place of
// the wall node and make room by a harmonic displacement of their nodes near the wall (caps'
// nodes slide in their plane); the gap between the wall and the moved surface is filled with
// `count` layers of prisms, each cut into three tetrahedra by the rule of Dompierre, Labbe,
// Vallet & Camarero (1999): every quadrilateral face is cut through its smallest node index,
// so neighbouring prisms agree. The wall's own triangles and everything outside the region
// (an FSI wall, sharing the wall nodes) stay as they are; a cap face gets the layers' sides.
// The layers thin where the lumen does (at most `max_fraction` of the distance across it
// along the normal) and vary slowly along the wall; they end where the wall folds sharply (a
// wedge of fluid) or the lumen pinches, their prisms there collapsing to pyramids and tets.
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::geometry {

struct BoundaryLayerSpec {
  int count = 0;             ///< layers; 0: none
  double first = 0.0;        ///< thickness of the layer at the wall [m]
  double growth = 1.2;       ///< thickness ratio of neighbouring layers, inwards
  double max_fraction = 0.3; ///< of the lumen's thickness along the wall's normal
  /// The first layer's thickness times (growth^count - 1) / (growth - 1) [m].
  double thickness() const;
};

struct BoundaryLayerReport {
  std::size_t wall_nodes = 0, tets_added = 0;
  double thinnest = 0.0, thickest = 0.0; ///< total layer thickness over the wall [m]
  std::size_t thinned = 0;               ///< wall nodes whose layers are thinner than asked
  std::size_t ended = 0;                 ///< of them, with no layers (a fold, a pinch)
  int displacement_sweeps = 0;           ///< of the harmonic displacement's relaxation
};

/// The mesh with `spec.count` layers in region `region` on its boundary triangles of the
/// faces `walls` (the rest of its boundary being planar caps). InputError (naming
/// `mesh.source`) for a bad spec, a wall face that does not bound the region, a cap that is
/// not planar, or a wall too sharply folded or too thin for layers; the result is checked
/// (no inverted tetrahedron).
mesh::Mesh add_boundary_layers(const mesh::Mesh& mesh, const std::string& region,
                               const std::vector<std::string>& walls, const BoundaryLayerSpec& spec,
                               BoundaryLayerReport* report = nullptr);

} // namespace tearflow::geometry
