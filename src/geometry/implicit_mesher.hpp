#pragma once
// A fluid(-wall) tet mesh of a domain given by a labelling function (a segmented scan, through
// distance fields), meshed by CGAL's Mesh_3: the fluid and the wall share their interface's
// nodes, and planar caps cut the vessels open. The result has the layout of the parametric
// TBAD and of imported surfaces: regions `fluid` and `wall`, faces `interface`, one per cap,
// `wall_<cap>` and `outer_wall`.
#include <functional>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::geometry {

/// A planar cap cutting the vessel: points beyond the plane (dot(x - centre, normal) > 0) and
/// within `radius` of the axis through `centre` are outside the domain.
struct ImplicitCap {
  std::string name;        ///< the fluid's face on it ("inlet", "BCT", "outlet"); the wall's ring
                           ///< on it is "wall_" + name
  Vec3 centre{}, normal{}; ///< normal: unit, pointing out of the domain [m]
  double radius = 0;       ///< [m] the cap's reach (vessel radius + wall + margin)
};

struct ImplicitDomain {
  /// 0 outside, 1 fluid, 2 wall, for a point in metres. Called very often (millions of
  /// times): cheap, and const (thread-safe). Any other value is an InputError.
  std::function<int(const Vec3&)> label;
  Vec3 centre{};
  double radius = 0; ///< a sphere containing the domain [m]; outside it everything is outside
  std::vector<ImplicitCap> caps;
  std::string source; ///< names the domain in messages (e.g. the segmentation's file)
};

struct ImplicitMeshOptions {
  /// Target edge length [m] (cells and surface facets). Mesh_3 resolves surfaces, not
  /// thicknesses: keep it at most about 1.5 times the thinnest layer. 2 mm walls and flaps
  /// keep their tets at 2 to 3 mm; at 4 mm, 2 mm plates floating in a pipe lost theirs.
  double element_size = 3e-3;
  /// Optional local size [m] (<= element_size; larger values are cut to it), else uniform.
  std::function<double(const Vec3&)> size;
  double facet_distance = 0;   ///< surface approximation [m]; 0: element_size / 10
  double min_feature = 0.5e-3; ///< thinnest layer the initialization must see (the wall and
                               ///< the flap are about 2 mm) [m]
  bool verbose = false;        ///< log the stages and their counts
};

/// Meshes the domain: regions "fluid" (label 1) and "wall" (label 2); faces "interface"
/// (fluid|wall), each cap's name (fluid facets on its plane), "wall_<cap>" (wall facets on
/// its plane) and "outer_wall" (the other wall|outside facets). Tets are positively oriented;
/// face triangles point out of the fluid (the interface into the wall), or out of the wall.
/// The caps' rims (where the label changes on their planes) are kept as sharp edges.
/// InputError for bad arguments, a label other than 0, 1, 2, a cap that cuts no fluid or
/// whose disc does not reach past the vessel, fluid touching the outside off every cap (the
/// wall must enclose the fluid), an empty region, or CGAL failing.
mesh::Mesh mesh_implicit(const ImplicitDomain& domain, const ImplicitMeshOptions& options);

} // namespace tearflow::geometry
