#pragma once
// A voxel grid placed in patient coordinates (DICOM's LPS, metres), as images carry it: the
// MRI scans and the segmented label maps share it. Voxel (i, j, k) has its centre at
//   p = origin + sum_a index_a spacing_a direction[a],
// direction[a] the unit vector of index axis a (ITK's direction matrix has them as columns).
#include <array>
#include <cstddef>

#include "core/types.hpp"

namespace tearflow {

struct ImageGrid {
  std::array<int, 3> size{};                         ///< voxels along i, j, k
  Vec3 origin{};                                     ///< centre of voxel (0, 0, 0) [m]
  Vec3 spacing{};                                    ///< voxel size along i, j, k [m]
  Mat3 direction{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; ///< unit index axes in LPS

  std::size_t count() const { return static_cast<std::size_t>(size[0]) * size[1] * size[2]; }
  std::size_t linear(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(size[0]) * (j + std::size_t(size[1]) * k);
  }
  /// The index (i, j, k) of voxel v (v = linear(i, j, k)).
  std::array<int, 3> ijk(std::size_t v) const {
    const std::size_t nx = size[0], ny = size[1];
    return {static_cast<int>(v % nx), static_cast<int>(v / nx % ny),
            static_cast<int>(v / (nx * ny))};
  }
  /// Calls f(u, di, dj, dk) for each of voxel v's 26 neighbours u inside the grid.
  template <typename F> void for_each_neighbour(std::size_t v, F&& f) const {
    const auto [i, j, k] = ijk(v);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int a = i + di, b = j + dj, c = k + dk;
          if ((di || dj || dk) && a >= 0 && b >= 0 && c >= 0 && a < size[0] && b < size[1] &&
              c < size[2])
            f(linear(a, b, c), di, dj, dk);
        }
  }
  /// Patient point of a continuous index (i, j, k).
  Vec3 point(const Vec3& index) const;
  /// Continuous index of a patient point (the inverse of point()).
  Vec3 index(const Vec3& p) const;
  /// True when the two grids place the same voxels at the same points (within 1e-4 voxel).
  bool same_as(const ImageGrid& other) const;
};

/// A grid of `size` voxels of `spacing`, centred on `centre`, its index axes the rows of
/// `direction` (orthonormalised here).
ImageGrid centred_grid(const Vec3& centre, const Mat3& direction, std::array<int, 3> size,
                       const Vec3& spacing);

/// The rotation by `degrees` about the unit `axis` (Rodrigues), as rows: the direction
/// matrix of a grid rotated from the patient axes.
Mat3 rotation(const Vec3& axis, double degrees);

} // namespace tearflow
