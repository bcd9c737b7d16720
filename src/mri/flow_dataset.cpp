// The 4D-flow dataset's geometry: index <-> patient point, grids, trilinear weights.
#include "mri/flow_dataset.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tearflow::mri {

const char* encoding_name(Encoding e) {
  switch (e) {
  case Encoding::velocity_3d:
    return "4D flow";
  case Encoding::through_plane:
    return "2D phase contrast (through-plane)";
  case Encoding::magnitude:
    return "cine (magnitude only)";
  }
  return "?";
}

void Flow4D::require(Encoding e, const std::string& where) const {
  if (encoding != e)
    input_error("{}: a {} scan is needed, this is {}", where, encoding_name(e),
                encoding_name(encoding));
}

double Flow4D::cycle(const std::string& where) const {
  const std::size_t nf = frames.size();
  if (nf == 0)
    input_error("{}: no frames", where);
  const double span = frames.back().time - frames.front().time;
  if (period > 0) {
    if (!(span < period))
      input_error("{}: its frames span {:.1f} ms, not less than the R-R interval {:.1f} ms", where,
                  span * 1e3, period * 1e3);
    return period;
  }
  if (nf < 2)
    input_error("{}: one frame and no R-R interval (NominalInterval); a cycle cannot be formed",
                where);
  return span * nf / (nf - 1);
}

void Flow4D::check_in_slice(const Vec3& p, const std::string& what) const {
  const double off = dot(p - grid.origin, grid.direction[2]);
  const double reach = slice_reach(grid);
  if (std::abs(off) > reach)
    input_error("{} ({:.1f}, {:.1f}, {:.1f}) mm lies {:.1f} mm off the slice (at most {:.1f} mm: "
                "the slice's thickness or 5 mm); is it this slice's point?",
                what, p[0] * 1e3, p[1] * 1e3, p[2] * 1e3, off * 1e3, reach * 1e3);
}

void Flow4D::check(const std::string& where) const {
  const std::size_t n = grid.count();
  if (n == 0)
    input_error("{}: empty image grid", where);
  if (encoding != Encoding::velocity_3d && grid.size[2] != 1)
    input_error("{}: a {} scan has one slice, this one {}", where, encoding_name(encoding),
                grid.size[2]);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Frame& fr = frames[f];
    if (fr.magnitude.size() != n || fr.velocity[0].size() != n || fr.velocity[1].size() != n ||
        fr.velocity[2].size() != n)
      input_error("{}: frame {} does not hold {} voxels in each image", where, f, n);
    if (f > 0 && !(fr.time > frames[f - 1].time))
      input_error("{}: frame times must increase (frame {} at {} s after {} s)", where, f, fr.time,
                  frames[f - 1].time);
  }
}

bool Trilinear::locate(const ImageGrid& grid, const Vec3& index) {
  std::array<int, 3> i0{};
  std::array<double, 3> f{};
  for (int a = 0; a < 3; ++a) {
    const double x = index[a];
    if (grid.size[a] == 1) {
      if (std::abs(x) > 0.5)
        return false;
      i0[a] = 0, f[a] = 0.0;
      continue;
    }
    if (!(x >= 0.0 && x <= grid.size[a] - 1))
      return false;
    i0[a] = std::min(static_cast<int>(x), grid.size[a] - 2);
    f[a] = x - i0[a];
  }
  const std::array<int, 3> step{grid.size[0] > 1 ? 1 : 0, grid.size[1] > 1 ? 1 : 0,
                                grid.size[2] > 1 ? 1 : 0};
  int c = 0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di, ++c) {
        voxel[c] = grid.linear(i0[0] + di * step[0], i0[1] + dj * step[1], i0[2] + dk * step[2]);
        weight[c] = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
      }
  return true;
}

double wrap_velocity(double v, double venc) {
  return v - 2.0 * venc * std::floor((v + venc) / (2.0 * venc));
}

} // namespace tearflow::mri
