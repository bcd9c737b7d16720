// Geometry directory -> label map (voxelize.hpp). Point location is a scan over each fluid
// tet's bounding box in index space rather than a locator query per voxel: no tree to
// search, the background never visited, and each fluid voxel tested by the few tets whose
// boxes hold it. Reading the mesh costs more than labelling (1 s in all for the 3 mm model
// at 1 mm, 4 s at 0.3 mm: 1.4e8 voxels).
#include "geometry/voxelize.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/label_map.hpp"
#include "geometry/landmarks.hpp"
#include "mesh/region.hpp"

namespace tearflow::geometry {

namespace fs = std::filesystem;

namespace {

constexpr double mm = 1e-3;
// A tear region reaches this far either side of the flap's mid-surface: past the half
// thickness of any flap we build or import (the study's 2 mm, up to 4 mm) plus a voxel, so
// that no voxel in the hole is left to join the lumens.
constexpr double kTearHalfHeight = 3 * mm;
// Thrombus starts this far past the exit tear's distal rim: the flow through the tear keeps
// the false lumen beside it patent.
constexpr double kThrombusGap = 2 * mm;
// Voxel classes while labelling; the lumens' codes are swapped for the user's at the end.
enum Class : std::uint8_t { kOutside = 0, kTL = 1, kFL = 2, kThrombus = 3, kFluid, kTearRegion };
// Images are bounded before memory is spent: 4e8 voxels is 0.4 GB of labels (twice: ours
// and ITK's copy to write), more than a 0.25 mm image of the whole model (2.4e8).
constexpr double kMaxVoxels = 4e8;
// Pockets reached by neither lumen that are larger than this share of the fluid are not
// slivers but fluid the landmarks do not account for: an error, not a guess.
constexpr double kMaxPocketShare = 0.01;
// Nearest labelled voxel for a pocket with no labelled neighbour: searched this far [voxels].
constexpr int kPocketReach = 4;

/// The image (isotropic voxels of `voxel`), with the voxelizer's own walks over it.
struct Grid : ImageGrid {
  double voxel = 0; ///< the voxels' size [m]

  Vec3 centre(int i, int j, int k) const { return point({double(i), double(j), double(k)}); }
  Vec3 centre(std::size_t v) const {
    const auto [i, j, k] = ijk(v);
    return centre(i, j, k);
  }
  /// Calls f(w) for each 6-neighbour w of voxel v inside the image.
  template <typename F> void neighbours(std::size_t v, F&& f) const {
    const auto [i, j, k] = ijk(v);
    const std::size_t nx = size[0], nxy = nx * size[1];
    if (i > 0)
      f(v - 1);
    if (i + 1 < size[0])
      f(v + 1);
    if (j > 0)
      f(v - nx);
    if (j + 1 < size[1])
      f(v + nx);
    if (k > 0)
      f(v - nxy);
    if (k + 1 < size[2])
      f(v + nxy);
  }
  /// Integer index ranges [lo, hi] covering the continuous box [a, b], clipped to the image.
  bool range(const Vec3& a, const Vec3& b, std::array<int, 3>& lo, std::array<int, 3>& hi) const {
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::max(0, int(std::ceil(a[d])));
      hi[d] = std::min(size[d] - 1, int(std::floor(b[d])));
      if (lo[d] > hi[d])
        return false;
    }
    return true;
  }
};

/// The image axes Rz Ry Rx e_a for angles in degrees (rows, as ImageGrid::direction).
Mat3 rotated_axes(const Vec3& degrees) {
  const Mat3 rx = rotation({1, 0, 0}, degrees[0]), ry = rotation({0, 1, 0}, degrees[1]),
             rz = rotation({0, 0, 1}, degrees[2]);
  auto apply = [](const Mat3& rows, const Vec3& v) { // R v, R's rows being R e_b
    return v[0] * rows[0] + v[1] * rows[1] + v[2] * rows[2];
  };
  Mat3 axes{};
  for (int a = 0; a < 3; ++a)
    axes[a] = apply(rz, apply(ry, rx[a]));
  return axes;
}

void check_options(const VoxelizeOptions& o) {
  if (!(o.spacing > 0) || !std::isfinite(o.spacing))
    input_error("voxelize: the voxel spacing (--spacing) must be a positive length, got {} mm",
                o.spacing / mm);
  if (!(o.margin >= 0) || !std::isfinite(o.margin))
    input_error("voxelize: the margin must be a length >= 0, got {} mm", o.margin / mm);
  for (double a : o.rotation)
    if (!std::isfinite(a))
      input_error("voxelize: the rotation (--rotate) must be three finite angles in degrees");
  const int labels[3] = {o.true_lumen, o.false_lumen, o.thrombus_label};
  for (int l : labels)
    if (l < 1 || l > 255)
      input_error("voxelize: labels must lie in 1..255 (one byte per voxel), got {}", l);
  if (o.true_lumen == o.false_lumen ||
      (o.thrombus && (o.thrombus_label == o.true_lumen || o.thrombus_label == o.false_lumen)))
    input_error("voxelize: the labels must differ: true lumen {}, false lumen {}, thrombus {}",
                o.true_lumen, o.false_lumen, o.thrombus_label);
}

Grid make_grid(const mesh::Mesh& mesh, const VoxelizeOptions& o, const fs::path& dir) {
  Grid g;
  g.direction = rotated_axes(o.rotation);
  g.voxel = o.spacing;
  g.spacing = {o.spacing, o.spacing, o.spacing};
  Vec3 lo, hi;
  lo.fill(std::numeric_limits<double>::max());
  hi.fill(std::numeric_limits<double>::lowest());
  for (const Vec3& p : mesh.points)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], dot(g.direction[a], p));
      hi[a] = std::max(hi[a], dot(g.direction[a], p));
    }
  double voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double n = std::ceil((hi[a] - lo[a] + 2 * o.margin) / o.spacing) + 1;
    voxels *= n;
    g.size[a] = n < 1e9 ? int(n) : 0;
    // Centred on the model: the margin is the same on both sides of each axis.
    g.origin = g.origin + (0.5 * (lo[a] + hi[a]) - 0.5 * (n - 1) * o.spacing) * g.direction[a];
  }
  if (voxels > kMaxVoxels)
    input_error("voxelize '{}': a {} mm spacing makes {:.3g} voxels ({:.0f} x {:.0f} x {:.0f} "
                "mm), more than the {:.0g} allowed; choose a coarser --spacing",
                dir.string(), o.spacing / mm, voxels, (hi[0] - lo[0]) / mm, (hi[1] - lo[1]) / mm,
                (hi[2] - lo[2]) / mm, kMaxVoxels);
  return g;
}

/// Marks kFluid every voxel whose centre lies in a tet of region `fluid`.
void rasterize_fluid(const mesh::Mesh& mesh, int fluid, const Grid& g,
                     std::vector<std::uint8_t>& cls) {
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_region[t] != fluid)
      continue;
    std::array<Vec3, 4> q;
    Vec3 a, b;
    a.fill(std::numeric_limits<double>::max());
    b.fill(std::numeric_limits<double>::lowest());
    for (int n = 0; n < 4; ++n) {
      q[n] = g.index(mesh.points[mesh.tets[t][n]]);
      for (int d = 0; d < 3; ++d)
        a[d] = std::min(a[d], q[n][d]), b[d] = std::max(b[d], q[n][d]);
    }
    std::array<int, 3> lo, hi;
    if (!g.range(a, b, lo, hi))
      continue;
    // Barycentric coordinates are affine, so they are the same in index space: l_a =
    // grad[a] . (x - q0) with grad[a] the rows of the inverse of the edge matrix.
    const Vec3 e1 = q[1] - q[0], e2 = q[2] - q[0], e3 = q[3] - q[0];
    const double det = dot(e1, cross(e2, e3));
    if (det == 0)
      continue;
    const std::array<Vec3, 4> grad{Vec3{}, (1 / det) * cross(e2, e3), (1 / det) * cross(e3, e1),
                                   (1 / det) * cross(e1, e2)};
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const Vec3 r = Vec3{double(i), double(j), double(k)} - q[0];
          const double l1 = dot(grad[1], r), l2 = dot(grad[2], r), l3 = dot(grad[3], r);
          // A centre on a face shared with the wall counts as fluid: which side takes a tie
          // changes nothing measurable, and rounding must not drop centres between two
          // fluid tets.
          constexpr double eps = -1e-12;
          if (l1 >= eps && l2 >= eps && l3 >= eps && 1 - l1 - l2 - l3 >= eps)
            cls[g.linear(i, j, k)] = kFluid;
        }
  }
}

Vec3 unit(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? (1 / n) * v : v;
}

/// A tear's region (see voxelize.hpp) in its own frame.
struct TearRegion {
  std::string name;
  Vec3 centroid, normal, axis, across; ///< normal into the TL; axis, across in the flap
  double axial = 0, lateral = 0;       ///< the tear's own semi-axes along `axis`, `across`
  double a = 0, b = 0;                 ///< the region's semi-axes: the tear's plus a voxel

  /// Landmarks may give a tear by its area alone (no axis, no semi-axes): then a circle of
  /// that area; an axis not in the flap's plane is projected onto it.
  TearRegion(const TearLandmark& t, double pad)
      : name(t.name), centroid(t.centroid), normal(unit(t.normal)) {
    axis = unit(t.axis - dot(t.axis, normal) * normal);
    double p = t.axial, q = t.across;
    if (!(p > 0 && q > 0))
      p = q = std::sqrt(t.area / std::numbers::pi);
    if (!(dot(axis, axis) > 0.5)) { // none given: any direction, the ellipse's circumcircle
      const Vec3 e = std::abs(normal[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      axis = unit(e - dot(e, normal) * normal);
      p = q = std::max(p, q);
    }
    across = unit(cross(normal, axis));
    axial = p;
    lateral = q;
    a = p + pad;
    b = q + pad;
  }
  template <typename F> void for_each_voxel(const Grid& g, F&& f) const {
    Vec3 lo, hi;
    lo.fill(std::numeric_limits<double>::max());
    hi.fill(std::numeric_limits<double>::lowest());
    for (int c = 0; c < 8; ++c) {
      const Vec3 x = centroid + ((c & 1) ? a : -a) * axis + ((c & 2) ? b : -b) * across +
                     ((c & 4) ? kTearHalfHeight : -kTearHalfHeight) * normal;
      const Vec3 q = g.index(x);
      for (int d = 0; d < 3; ++d)
        lo[d] = std::min(lo[d], q[d]), hi[d] = std::max(hi[d], q[d]);
    }
    std::array<int, 3> l, h;
    if (!g.range(lo, hi, l, h))
      return;
    for (int k = l[2]; k <= h[2]; ++k)
      for (int j = l[1]; j <= h[1]; ++j)
        for (int i = l[0]; i <= h[0]; ++i) {
          const Vec3 d = g.centre(i, j, k) - centroid;
          const double s = dot(d, axis) / a, t = dot(d, across) / b;
          if (std::abs(dot(d, normal)) <= kTearHalfHeight && s * s + t * t <= 1)
            f(g.linear(i, j, k), dot(d, normal));
        }
  }
};

/// 6-connected flood over kFluid voxels from `seeds`, labelling them `to`; returns the count.
std::size_t flood(std::vector<std::uint8_t>& cls, const Grid& g,
                  const std::vector<std::size_t>& seeds, std::uint8_t to) {
  std::vector<std::size_t> queue;
  for (std::size_t s : seeds)
    if (cls[s] == kFluid) {
      cls[s] = to;
      queue.push_back(s);
    }
  for (std::size_t head = 0; head < queue.size(); ++head)
    g.neighbours(queue[head], [&](std::size_t w) {
      if (cls[w] == kFluid) {
        cls[w] = to;
        queue.push_back(w);
      }
    });
  return queue.size();
}

/// The voxel nearest to `p` among those of class `a` or `b` within two voxels (landmark
/// points sit on caps and near walls, where the nearest centre may lie outside the fluid).
std::optional<std::size_t> nearest_of(const std::vector<std::uint8_t>& cls, const Grid& g,
                                      const Vec3& p, std::uint8_t a, std::uint8_t b) {
  const Vec3 q = g.index(p);
  std::optional<std::size_t> best;
  double best_d2 = std::numeric_limits<double>::max();
  std::array<int, 3> lo, hi;
  if (!g.range(q - Vec3{2, 2, 2}, q + Vec3{2, 2, 2}, lo, hi))
    return best;
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const Vec3 r = Vec3{double(i), double(j), double(k)} - q;
        const std::uint8_t c = cls[g.linear(i, j, k)];
        if ((c == a || c == b) && dot(r, r) < best_d2)
          best_d2 = dot(r, r), best = g.linear(i, j, k);
      }
  return best;
}

/// Labels the fluid voxels that neither flood reached: small pockets take the label of the
/// lumen they touch most, else of the nearest labelled voxel. Returns their voxel count.
std::size_t label_pockets(std::vector<std::uint8_t>& cls, const Grid& g, std::size_t fluid,
                          const fs::path& dir) {
  std::size_t total = 0;
  std::vector<std::size_t> pocket;
  for (std::size_t v = 0; v < cls.size(); ++v) {
    if (cls[v] != kFluid)
      continue;
    pocket.assign(1, v);
    cls[v] = kOutside; // taken: relabelled below
    std::size_t touch[3] = {0, 0, 0};
    for (std::size_t head = 0; head < pocket.size(); ++head)
      g.neighbours(pocket[head], [&](std::size_t w) {
        if (cls[w] == kFluid) {
          cls[w] = kOutside;
          pocket.push_back(w);
        } else if (cls[w] == kTL || cls[w] == kFL) {
          ++touch[cls[w]];
        }
      });
    if (pocket.size() > kMaxPocketShare * fluid)
      input_error("voxelize '{}': {:.1f} mL of fluid around ({:.1f}, {:.1f}, {:.1f}) mm is "
                  "reached neither from the true lumen's plane (AAo or inlet) nor from the "
                  "FL planes' points; is it part of the model?",
                  dir.string(), pocket.size() * std::pow(g.voxel, 3) / 1e-6,
                  g.centre(pocket[0])[0] / mm, g.centre(pocket[0])[1] / mm,
                  g.centre(pocket[0])[2] / mm);
    std::uint8_t label = touch[kTL] + touch[kFL] == 0 ? kOutside
                         : touch[kTL] >= touch[kFL]   ? kTL
                                                      : kFL;
    // Touching neither (kept apart by a corner or a voxel of wall): the nearest lumen.
    double best = std::numeric_limits<double>::max();
    for (std::size_t p = 0; p < pocket.size() && touch[kTL] + touch[kFL] == 0; ++p) {
      const auto c = g.ijk(pocket[p]);
      for (int dk = -kPocketReach; dk <= kPocketReach; ++dk)
        for (int dj = -kPocketReach; dj <= kPocketReach; ++dj)
          for (int di = -kPocketReach; di <= kPocketReach; ++di) {
            const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
            if (i < 0 || j < 0 || k < 0 || i >= g.size[0] || j >= g.size[1] || k >= g.size[2])
              continue;
            const std::uint8_t l = cls[g.linear(i, j, k)];
            const double d2 = di * di + dj * dj + dk * dk;
            if ((l == kTL || l == kFL) && d2 < best)
              best = d2, label = l;
          }
    }
    if (label == kOutside)
      input_error("voxelize '{}': a fluid pocket of {} voxel(s) at ({:.1f}, {:.1f}, {:.1f}) mm "
                  "lies more than {} voxels from either lumen",
                  dir.string(), pocket.size(), g.centre(pocket[0])[0] / mm,
                  g.centre(pocket[0])[1] / mm, g.centre(pocket[0])[2] / mm, kPocketReach);
    for (std::size_t w : pocket)
      cls[w] = label;
    total += pocket.size();
  }
  return total;
}

} // namespace

VoxelizeResult voxelize_geometry(const fs::path& geometry_dir, const VoxelizeOptions& options,
                                 const fs::path& out) {
  check_options(options);
  check_label_map_name(out, "voxelize: output");
  const GeometryFiles files{geometry_dir};
  if (!fs::is_regular_file(files.mesh()) || !fs::is_regular_file(files.landmarks()))
    input_error("voxelize: '{}' is not a geometry directory: expected {} and {} in it",
                geometry_dir.string(), GeometryFiles::kMesh, GeometryFiles::kLandmarks);
  const Landmarks landmarks = read_landmarks(files.landmarks());
  const mesh::Mesh mesh = read_fsi_mesh(files.mesh(), 1e-3);
  const Grid g = make_grid(mesh, options, geometry_dir);

  std::vector<std::uint8_t> cls(g.count(), kOutside);
  rasterize_fluid(mesh, mesh::region_index(mesh, "fluid"), g, cls);
  const std::size_t fluid = std::size_t(std::count(cls.begin(), cls.end(), kFluid));

  const std::string lm = files.landmarks().string();
  if (landmarks.tears.empty())
    input_error("voxelize: '{}' has no tears: the lumens are told apart at them", lm);
  std::vector<TearRegion> regions;
  for (const TearLandmark& t : landmarks.tears) {
    const TearRegion r(t, g.voxel);
    r.for_each_voxel(g, [&](std::size_t v, double) {
      if (cls[v] == kFluid)
        cls[v] = kTearRegion;
    });
    regions.push_back(r);
  }

  // The true lumen from its landmark: AAo's origin lies inside; the inlet's, on its cap.
  const Landmark* tl_mark = nullptr;
  for (const char* name : {"AAo", "inlet"})
    for (const Landmark& l : landmarks.planes)
      if (!tl_mark && l.name == name)
        tl_mark = &l;
  if (!tl_mark)
    input_error("voxelize: '{}' has neither an 'AAo' nor an 'inlet' plane to find the true "
                "lumen by",
                lm);
  const auto tl_seed = nearest_of(cls, g, tl_mark->origin, kFluid, kFluid);
  if (!tl_seed)
    input_error("voxelize: plane '{}' of '{}': its origin ({:.1f}, {:.1f}, {:.1f}) mm is not in "
                "the fluid (outside the tear regions) at {} mm voxels",
                tl_mark->name, lm, tl_mark->origin[0] / mm, tl_mark->origin[1] / mm,
                tl_mark->origin[2] / mm, g.voxel / mm);
  flood(cls, g, {*tl_seed}, kTL);

  std::vector<std::size_t> fl_seeds;
  for (const Landmark& l : landmarks.planes) {
    if (l.lumen != "FL" || !l.point)
      continue;
    const auto v = nearest_of(cls, g, *l.point, kFluid, kTL);
    if (v && cls[*v] == kFluid) {
      fl_seeds.push_back(*v);
      continue;
    }
    if (v)
      input_error("voxelize '{}': the point of plane '{}' lies in the true lumen's piece: the "
                  "lumens meet outside the tear regions, where the wall between them (flap or "
                  "false-lumen end cap) is thinner than a voxel ({} mm); choose a finer "
                  "--spacing",
                  geometry_dir.string(), l.name, g.voxel / mm);
    input_error("voxelize: plane '{}' of '{}': its point ({:.1f}, {:.1f}, {:.1f}) mm is not in "
                "the fluid at {} mm voxels",
                l.name, lm, (*l.point)[0] / mm, (*l.point)[1] / mm, (*l.point)[2] / mm,
                g.voxel / mm);
  }
  if (fl_seeds.empty())
    input_error("voxelize: '{}' has no false-lumen plane (lumen \"FL\" with a point) to find "
                "the false lumen by",
                lm);
  flood(cls, g, fl_seeds, kFL);

  // Tear regions by their side of the flap: the normal points into the true lumen.
  for (const TearRegion& r : regions)
    r.for_each_voxel(g, [&](std::size_t v, double height) {
      if (cls[v] == kTearRegion)
        cls[v] = height > 0 ? kTL : kFL;
    });
  VoxelizeResult result;
  result.pocket_voxels = label_pockets(cls, g, fluid, geometry_dir);

  if (options.thrombus) {
    const TearRegion* exit = nullptr;
    for (const TearRegion& r : regions)
      if (r.name == "exit")
        exit = &r;
    const Landmark* outlet = nullptr;
    for (const Landmark& l : landmarks.planes)
      if (l.name == "outlet")
        outlet = &l;
    if (!exit || !outlet)
      input_error("voxelize --thrombus: '{}' needs an 'exit' tear and an 'outlet' plane (the "
                  "thrombus fills the false lumen past the exit tear, towards the outlet)",
                  lm);
    // Downstream: the tear's axis (along the vessel in our models) oriented towards the
    // outlet; an axis across the vessel (or an arbitrary one, none given) gives way to the
    // outlet's direction in the flap's plane.
    const Vec3 to_outlet = outlet->origin - exit->centroid;
    Vec3 d = exit->axis;
    double from = exit->axial + kThrombusGap;
    if (!(std::abs(dot(d, unit(to_outlet))) > 0.5)) {
      d = unit(to_outlet - dot(to_outlet, exit->normal) * exit->normal);
      from = std::max(exit->axial, exit->lateral) + kThrombusGap;
    }
    if (dot(to_outlet, d) < 0)
      d = -1.0 * d;
    for (std::size_t v = 0; v < cls.size(); ++v)
      if (cls[v] == kFL && dot(g.centre(v) - exit->centroid, d) > from)
        cls[v] = kThrombus;
  }

  const std::uint8_t code[4] = {0, std::uint8_t(options.true_lumen),
                                std::uint8_t(options.false_lumen),
                                std::uint8_t(options.thrombus_label)};
  for (std::uint8_t& c : cls) {
    switch (c) {
    case kTL:
      ++result.tl_voxels;
      break;
    case kFL:
      ++result.fl_voxels;
      break;
    case kThrombus:
      ++result.thrombus_voxels;
      break;
    default:
      break;
    }
    c = c < 4 ? code[c] : 0; // every voxel is outside or labelled by now
  }
  const double voxel = std::pow(g.voxel, 3);
  result.tl_volume = result.tl_voxels * voxel;
  result.fl_volume = result.fl_voxels * voxel;
  result.thrombus_volume = result.thrombus_voxels * voxel;
  result.size = g.size;
  LabelMap map;
  map.grid = g;
  map.labels.assign(cls.begin(), cls.end());
  if (out.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(out.parent_path(), ec); // a failure shows as the writer's error
  }
  write_label_map(map, out);
  return result;
}

} // namespace tearflow::geometry
