#pragma once
// Coincident points: a hash grid over a point list, for matching nodes that two meshes or
// surface files share (up to rounding). The cell is much larger than the matching tolerance,
// so a point and its twin lie in the same or a neighbouring cell: a query looks in all 27.
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/types.hpp"

namespace tearflow::mesh {

class PointGrid {
public:
  /// Indexes every point of `points` (which must outlive the grid; it may grow, and points
  /// added to it later are indexed with insert).
  PointGrid(const std::vector<Vec3>& points, double cell) : points_(points), cell_(cell) {
    for (std::size_t i = 0; i < points.size(); ++i)
      insert(static_cast<Index>(i));
  }
  /// Indexes points[i].
  void insert(Index i) { cells_.emplace(key(points_[i]), i); }
  /// An indexed point within `tol` of x, or -1.
  Index find(const Vec3& x, double tol) const {
    const auto [i, j, k] = cell(x);
    for (long di = -1; di <= 1; ++di)
      for (long dj = -1; dj <= 1; ++dj)
        for (long dk = -1; dk <= 1; ++dk) {
          const auto range = cells_.equal_range(hash(i + di, j + dj, k + dk));
          for (auto it = range.first; it != range.second; ++it) {
            const Vec3 d = points_[it->second] - x;
            if (dot(d, d) <= tol * tol)
              return it->second;
          }
        }
    return -1;
  }

private:
  std::array<long, 3> cell(const Vec3& x) const {
    return {std::lround(std::floor(x[0] / cell_)), std::lround(std::floor(x[1] / cell_)),
            std::lround(std::floor(x[2] / cell_))};
  }
  static std::uint64_t hash(long i, long j, long k) {
    return static_cast<std::uint64_t>(i) * 73856093u ^ static_cast<std::uint64_t>(j) * 19349663u ^
           static_cast<std::uint64_t>(k) * 83492791u;
  }
  std::uint64_t key(const Vec3& x) const {
    const auto [i, j, k] = cell(x);
    return hash(i, j, k);
  }
  const std::vector<Vec3>& points_;
  double cell_;
  std::unordered_multimap<std::uint64_t, Index> cells_;
};

} // namespace tearflow::mesh
