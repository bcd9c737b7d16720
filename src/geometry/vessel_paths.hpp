#pragma once
// Centrelines of a vessel tree given as voxels: the vessel's ends (TEASAR: Sato et al.,
// "TEASAR: tree-structure extraction algorithm for accurate and robust skeletons", 2000)
// and the medial paths between them, through voxels weighted to stay far from the wall.
#include <cstdint>
#include <vector>

#include "core/image_grid.hpp"

namespace tearflow::geometry {

/// A vessel as voxels: `inside` per voxel of `grid`, `depth` the distance from each inside
/// voxel's centre to the vessel's wall [m].
struct VesselVoxels {
  const ImageGrid* grid = nullptr;
  std::vector<std::uint8_t> inside;
  std::vector<float> depth;
};

/// The ends of the vessel tree: the farthest voxel from the deepest one, then, again and
/// again, the voxel farthest (along the vessel) from the medial paths found so far, an end
/// when its path leaves the tree by more than `min_branch` plus 1.5 times its own radius
/// beyond the tree's radius where it joins. Voxel indices, the first the root.
std::vector<std::size_t> vessel_ends(const VesselVoxels& vessel, double min_branch);

/// Medial paths to one source: per voxel, its predecessor on the cheapest path to `source`
/// where a step costs its length times 1 + 5000 (1 - depth / max depth)^16 (TEASAR's
/// penalty, which keeps paths on the medial axis). Unreached voxels: -1.
std::vector<std::int64_t> medial_paths(const VesselVoxels& vessel, std::size_t source);

/// The voxels from `from` to the source of `predecessors`.
std::vector<std::size_t> trace_voxels(const std::vector<std::int64_t>& predecessors,
                                      std::size_t from);

/// Voxels of a path as points [m], smoothed by a moving average over about half the local
/// radius (two voxels at least) to take out the voxel steps.
std::vector<Vec3> path_points(const VesselVoxels& vessel, const std::vector<std::size_t>& voxels);

} // namespace tearflow::geometry
