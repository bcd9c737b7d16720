#pragma once
// Nodal P1 fields carried from one mesh of a domain to another mesh of the same domain (a
// coarser run's state starting a finer one: `run --start-from ... --start-case ...`).
//
// Every node of the target mesh is located, in the reference configuration, in the source's
// tets of each region it belongs to (by region name), and a field component takes the linear
// interpolant there, u(x) = sum_k lambda_k(x) u_k (lambda the barycentric coordinates): the
// fluid pressure from the fluid's tets only, the wall pressure from the wall's, so that a
// pressure never mixes with the other region's empty slot across the interface. A node that
// lies outside its region's tets in the source (two discretisations of a curved surface
// differ by O(h^2 / R)) takes the value at the region's closest point. The P1 interpolant of
// a smooth field is second-order accurate, so the transferred state is as close to the
// source's continuum state as the source itself.
#include <array>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::fem {

class NodeTransfer {
public:
  /// Locates every node of `to` in `from`. InputError naming `from.source` when `to` has a
  /// region that `from` lacks.
  NodeTransfer(const mesh::Mesh& from, const mesh::Mesh& to);

  /// The field (node-major, `block` values per node of `from`) at the nodes of `to`.
  /// `component_region[c]` names the region component c is taken from ("" any of the node's
  /// regions); a node outside that region gets 0 there.
  std::vector<double> apply(const std::vector<double>& field, int block,
                            const std::vector<std::string>& component_region) const;

  /// The farthest a node of `to` lies from its region's tets in `from` [m].
  double largest_distance() const { return largest_distance_; }

private:
  struct Location {
    Index tet = -1; ///< in `from`; -1: the node is not in that region
    std::array<double, 4> weight{};
  };
  const mesh::Mesh& from_;
  std::vector<std::string> regions_;           ///< of `to`
  std::vector<std::vector<Location>> located_; ///< per region of `to`, per node of `to`
  double largest_distance_ = 0.0;
};

} // namespace tearflow::fem
