// Pixel regions (pixel_regions.hpp).
#include "mri/pixel_regions.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace tearflow::mri {

Pixels region_of(const Pixels& mask, const PixelGrid& g, std::size_t seed) {
  Pixels region(mask.size(), 0);
  if (!mask[seed])
    return region;
  std::vector<std::size_t> stack{seed};
  region[seed] = 1;
  while (!stack.empty()) {
    const std::size_t p = stack.back();
    stack.pop_back();
    const int i = static_cast<int>(p % g.nx), j = static_cast<int>(p / g.nx);
    const std::array<std::pair<int, int>, 4> next{{{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}}};
    for (auto [a, b] : next) {
      if (a < 0 || b < 0 || a >= g.nx || b >= g.ny)
        continue;
      const std::size_t q = static_cast<std::size_t>(b) * g.nx + a;
      if (mask[q] && !region[q]) {
        region[q] = 1;
        stack.push_back(q);
      }
    }
  }
  return region;
}

Pixels rim_of(const Pixels& region, const PixelGrid& g) {
  Pixels rim(region.size(), 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      if (!region[static_cast<std::size_t>(j) * g.nx + i])
        continue;
      for (int b = std::max(0, j - 1); b <= std::min(g.ny - 1, j + 1); ++b)
        for (int a = std::max(0, i - 1); a <= std::min(g.nx - 1, i + 1); ++a)
          if (const std::size_t q = static_cast<std::size_t>(b) * g.nx + a; !region[q])
            rim[q] = 1;
    }
  return rim;
}

Pixels united(Pixels a, const Pixels& b) {
  for (std::size_t p = 0; p < a.size(); ++p)
    a[p] = a[p] || b[p];
  return a;
}

Pixels grown(Pixels region, const PixelGrid& g, int steps) {
  for (int s = 0; s < steps; ++s) {
    const Pixels rim = rim_of(region, g);
    region = united(std::move(region), rim);
  }
  return region;
}

double border_share(const Pixels& region, const PixelGrid& g, const Pixels* inside) {
  std::size_t edge = 0, on_border = 0;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * g.nx + i;
      if (!region[p])
        continue;
      const bool border = i == 0 || j == 0 || i + 1 == g.nx || j + 1 == g.ny;
      if (!border && region[p - 1] && region[p + 1] && region[p - g.nx] && region[p + g.nx])
        continue; // interior
      ++edge;
      on_border += border || (inside && (!(*inside)[p - 1] || !(*inside)[p + 1] ||
                                         !(*inside)[p - g.nx] || !(*inside)[p + g.nx]));
    }
  return edge == 0 ? 0.0 : static_cast<double>(on_border) / static_cast<double>(edge);
}

std::size_t deepest_pixel(const Pixels& region, const PixelGrid& g) {
  constexpr int kFar = 1 << 28;
  std::vector<int> d(region.size());
  for (std::size_t p = 0; p < region.size(); ++p)
    d[p] = region[p] ? kFar : 0;
  auto at = [&](int a, int b) {
    return a < 0 || b < 0 || a >= g.nx || b >= g.ny ? 0 : d[static_cast<std::size_t>(b) * g.nx + a];
  };
  for (int b = 0; b < g.ny; ++b)
    for (int a = 0; a < g.nx; ++a)
      if (int& x = d[static_cast<std::size_t>(b) * g.nx + a]; x)
        x = std::min(
            {x, at(a - 1, b) + 3, at(a, b - 1) + 3, at(a - 1, b - 1) + 4, at(a + 1, b - 1) + 4});
  std::size_t best = 0;
  int depth = -1;
  for (int b = g.ny - 1; b >= 0; --b)
    for (int a = g.nx - 1; a >= 0; --a) {
      const std::size_t p = static_cast<std::size_t>(b) * g.nx + a;
      if (int& x = d[p]; x) {
        x = std::min(
            {x, at(a + 1, b) + 3, at(a, b + 1) + 3, at(a + 1, b + 1) + 4, at(a - 1, b + 1) + 4});
        if (x >= depth)
          depth = x, best = p;
      }
    }
  return best;
}

} // namespace tearflow::mri
