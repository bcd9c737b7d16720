// Vessel ends and medial paths on voxels (vessel_paths.hpp): Dijkstra over the 26 neighbours.
#include "geometry/vessel_paths.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "core/error.hpp"

namespace tearflow::geometry {

namespace {

// Dijkstra from `sources` over the inside voxels; a step from u to v costs
// length * weight(v). Fills distance and (optionally) predecessor.
void dijkstra(const VesselVoxels& vessel, const std::vector<std::size_t>& sources,
              const std::function<double(std::size_t)>& weight, std::vector<double>& distance,
              std::vector<std::int64_t>* predecessor) {
  const ImageGrid& g = *vessel.grid;
  const std::size_t n = g.count();
  distance.assign(n, std::numeric_limits<double>::infinity());
  if (predecessor)
    predecessor->assign(n, -1);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (std::size_t s : sources) {
    distance[s] = 0;
    heap.push({0.0, s});
  }
  // The step's length to each neighbour, by (di, dj, dk) + 1 in base 3.
  std::array<double, 27> length{};
  for (int dk = -1; dk <= 1; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        length[(di + 1) + 3 * (dj + 1) + 9 * (dk + 1)] =
            std::sqrt(std::pow(di * g.spacing[0], 2) + std::pow(dj * g.spacing[1], 2) +
                      std::pow(dk * g.spacing[2], 2));
  while (!heap.empty()) {
    const auto [d, u] = heap.top();
    heap.pop();
    if (d > distance[u])
      continue;
    g.for_each_neighbour(u, [&](std::size_t v, int di, int dj, int dk) {
      if (!vessel.inside[v])
        return;
      const double nd = d + length[(di + 1) + 3 * (dj + 1) + 9 * (dk + 1)] * weight(v);
      if (nd < distance[v]) {
        distance[v] = nd;
        if (predecessor)
          (*predecessor)[v] = static_cast<std::int64_t>(u);
        heap.push({nd, v});
      }
    });
  }
}

std::size_t farthest(const std::vector<double>& distance) {
  std::size_t best = 0;
  double best_d = -1;
  for (std::size_t v = 0; v < distance.size(); ++v)
    if (std::isfinite(distance[v]) && distance[v] > best_d)
      best = v, best_d = distance[v];
  return best;
}

} // namespace

std::vector<std::int64_t> medial_paths(const VesselVoxels& vessel, std::size_t source) {
  const float max_depth = *std::max_element(vessel.depth.begin(), vessel.depth.end());
  std::vector<double> distance;
  std::vector<std::int64_t> pred;
  dijkstra(
      vessel, {source},
      [&](std::size_t v) {
        return 1 + 5000 * std::pow(std::max(0.0, 1.0 - vessel.depth[v] / max_depth), 16);
      },
      distance, &pred);
  return pred;
}

std::vector<std::size_t> vessel_ends(const VesselVoxels& vessel, double min_branch) {
  std::size_t deepest = 0;
  for (std::size_t v = 0; v < vessel.depth.size(); ++v)
    if (vessel.inside[v] && vessel.depth[v] > vessel.depth[deepest])
      deepest = v;
  if (!vessel.inside[deepest])
    input_error("vessel_ends: no voxel inside the vessel");
  std::vector<double> distance;
  auto unit = [](std::size_t) { return 1.0; };
  dijkstra(vessel, {deepest}, unit, distance, nullptr);
  const std::size_t root = farthest(distance);
  const std::vector<std::int64_t> pred = medial_paths(vessel, root);
  std::vector<std::size_t> ends{root}, tree{root};
  std::vector<std::uint8_t> on_tree(vessel.inside.size(), 0);
  on_tree[root] = 1;
  // A candidate tip counts as an end when its path leaves the tree by more than min_branch
  // plus 1.5 of its own radius (a real branch is a tube longer than it is wide; a bulge,
  // such as the false lumen's blind proximal end beside the arch, is not). Either way its
  // path joins the tree, so that the next candidate lies elsewhere.
  for (int candidate = 0; candidate < 48; ++candidate) {
    dijkstra(vessel, tree, unit, distance, nullptr);
    const std::size_t tip = farthest(distance);
    if (distance[tip] < min_branch)
      break;
    std::vector<std::size_t> path;
    std::int64_t v = static_cast<std::int64_t>(tip);
    while (v >= 0 && !on_tree[v]) {
      path.push_back(static_cast<std::size_t>(v));
      v = pred[v];
    }
    const double join_depth = v >= 0 ? vessel.depth[v] : 0.0;
    double tip_radius = 0;
    const double step =
        std::min({vessel.grid->spacing[0], vessel.grid->spacing[1], vessel.grid->spacing[2]});
    for (std::size_t i = 0; i < path.size() && i * step < 20e-3; ++i)
      tip_radius = std::max(tip_radius, double(vessel.depth[path[i]]));
    if (ends.size() == 1 || distance[tip] - join_depth >= min_branch + 1.5 * tip_radius)
      ends.push_back(tip);
    for (std::size_t p : path) {
      on_tree[p] = 1;
      tree.push_back(p);
    }
  }
  return ends;
}

std::vector<std::size_t> trace_voxels(const std::vector<std::int64_t>& predecessors,
                                      std::size_t from) {
  std::vector<std::size_t> out;
  for (std::int64_t v = static_cast<std::int64_t>(from); v >= 0; v = predecessors[v]) {
    out.push_back(static_cast<std::size_t>(v));
    if (out.size() > predecessors.size())
      break; // (a Dijkstra tree has no cycle; guard anyway)
  }
  return out;
}

std::vector<Vec3> path_points(const VesselVoxels& vessel, const std::vector<std::size_t>& voxels) {
  const ImageGrid& g = *vessel.grid;
  std::vector<Vec3> raw;
  for (std::size_t u : voxels) {
    const auto [i, j, k] = g.ijk(u);
    raw.push_back(g.point({double(i), double(j), double(k)}));
  }
  const double step = std::min({g.spacing[0], g.spacing[1], g.spacing[2]});
  std::vector<Vec3> out(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const int half = std::max(2, static_cast<int>(0.5 * vessel.depth[voxels[i]] / step));
    const std::size_t a = i >= std::size_t(half) ? i - half : 0;
    const std::size_t b = std::min(raw.size() - 1, i + half);
    Vec3 sum{0, 0, 0};
    for (std::size_t k = a; k <= b; ++k)
      sum = sum + raw[k];
    out[i] = (1.0 / double(b - a + 1)) * sum;
  }
  return out;
}

} // namespace tearflow::geometry
