#pragma once
// Evaluating nodal P1 fields (node-major, `block` values per node, input mesh order) at
// points and integrating their error against an exact field. Used by verification and
// analysis; brute-force point location is fine for the handful of probes they need.
#include <functional>
#include <optional>
#include <vector>

#include "mesh/mesh.hpp"

namespace tearflow::fem {

struct PointLocation {
  Index tet = -1;
  std::array<double, 4> barycentric{};
};

/// The tet containing p (barycentric coordinates >= -1e-10), or nothing.
std::optional<PointLocation> locate(const mesh::Mesh& mesh, const Vec3& p);

double interpolate(const mesh::Mesh& mesh, const PointLocation& at,
                   const std::vector<double>& field, int block, int component);

/// Returns {||v_h - v||_L2, ||v||_L2} for the vector made of components [first, first +
/// count) of `field`, with the 4-point degree-2 rule on every tet; over the whole mesh, or
/// over the tets whose centroid satisfies `in_region` when it is given.
std::pair<double, double> l2_error(const mesh::Mesh& mesh, const std::vector<double>& field,
                                   int block, int first, int count,
                                   const std::function<Vec3(const Vec3&)>& exact,
                                   const std::function<bool(const Vec3&)>& in_region = {});

} // namespace tearflow::fem
