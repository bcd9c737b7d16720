// The dissection's fields from a label map (labelled_dissection.hpp has the definitions).
// Distances come from ITK's exact transform, smoothed by half a voxel; tears are measured
// by the level-set integrals  A = int delta(w) H(sigma + growth) dV  with smoothed delta
// and Heaviside functions one to one and a half voxels wide, on a grid twice as fine as the
// voxels (trilinear), which are second-order accurate in the voxel size.
#include "geometry/labelled_dissection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <map>
#include <numbers>

#include <Eigen/Dense>

#include "core/error.hpp"

namespace tearflow::geometry {

namespace {

constexpr double kPi = std::numbers::pi;

// Smoothed Dirac delta and Heaviside step of half-width eps (Osher and Fedkiw, eq. 1.22-1.23).
double smooth_delta(double x, double eps) {
  return std::abs(x) >= eps ? 0.0 : (1 + std::cos(kPi * x / eps)) / (2 * eps);
}
double smooth_step(double x, double eps) {
  if (x <= -eps)
    return 0.0;
  if (x >= eps)
    return 1.0;
  return 0.5 * (1 + x / eps + std::sin(kPi * x / eps) / kPi);
}

double norm(const Vec3& v) {
  return std::sqrt(dot(v, v));
}

// Polynomial smooth minimum and maximum: within k of each other, a blend rounding the
// edge where the two surfaces meet with a radius of about k.
double smooth_min(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}
double smooth_max(double a, double b, double k) {
  return -smooth_min(-a, -b, k);
}

} // namespace

double GridField::at(const Vec3& x) const {
  const Vec3 c = grid->index(x);
  std::array<int, 3> i0{};
  std::array<double, 3> f{};
  for (int a = 0; a < 3; ++a) {
    if (!(c[a] >= 0) || c[a] > grid->size[a] - 1)
      return outside;
    i0[a] = std::min(static_cast<int>(c[a]), grid->size[a] - 2);
    f[a] = c[a] - i0[a];
  }
  const std::size_t nx = grid->size[0], nxy = nx * grid->size[1];
  const float* v = values.data() + grid->linear(i0[0], i0[1], i0[2]);
  const double c00 = v[0] + f[0] * (v[1] - v[0]), c10 = v[nx] + f[0] * (v[nx + 1] - v[nx]);
  const double c01 = v[nxy] + f[0] * (v[nxy + 1] - v[nxy]);
  const double c11 = v[nxy + nx] + f[0] * (v[nxy + nx + 1] - v[nxy + nx]);
  const double c0 = c00 + f[1] * (c10 - c00), c1 = c01 + f[1] * (c11 - c01);
  return c0 + f[2] * (c1 - c0);
}

LabelledDissection::LabelledDissection(const LabelMap& map, const DissectionOptions& o)
    : file_(map.file), h_(o.wall_thickness), round_(0.25 * o.wall_thickness),
      min_tear_area_(o.min_tear_area) {
  const std::string src = "label map '" + map.file.string() + "'";
  const LabelRoles& r = o.roles;
  if (!(h_ > 0))
    input_error("{}: wall thickness {} mm, expected a positive number", src, h_ * 1e3);
  // Which voxels carry which role, and the box they fill.
  std::array<int, 3> lo{map.grid.size}, hi{-1, -1, -1};
  std::size_t counts[3] = {0, 0, 0};
  for (int k = 0; k < map.grid.size[2]; ++k)
    for (int j = 0; j < map.grid.size[1]; ++j)
      for (int i = 0; i < map.grid.size[0]; ++i) {
        const int l = map.labels[map.grid.linear(i, j, k)];
        const int role = l == r.true_lumen ? 0 : l == r.false_lumen ? 1 : l == r.thrombus ? 2 : -1;
        if (role < 0)
          continue;
        ++counts[role];
        const std::array<int, 3> ijk{i, j, k};
        for (int a = 0; a < 3; ++a)
          lo[a] = std::min(lo[a], ijk[a]), hi[a] = std::max(hi[a], ijk[a]);
      }
  const char* names[3] = {"true lumen", "false lumen", "thrombus"};
  const int labels[3] = {r.true_lumen, r.false_lumen, r.thrombus};
  for (int role = 0; role < 3; ++role)
    if (counts[role] == 0 && (role < 2 || r.thrombus >= 0)) {
      std::map<int, std::size_t> present;
      for (std::int16_t l : map.labels)
        ++present[l];
      std::string list;
      for (const auto& [l, c] : present)
        list += fmt::format("{}{} ({} voxels)", list.empty() ? "" : ", ", l, c);
      input_error("{}: no voxel carries the {} label {}; the labels present are {}: give the "
                  "right one with --{}",
                  src, names[role], labels[role], list,
                  role == 0   ? "true-lumen"
                  : role == 1 ? "false-lumen"
                              : "thrombus");
    }
  spacing_ = std::max({map.grid.spacing[0], map.grid.spacing[1], map.grid.spacing[2]});
  if (spacing_ > h_)
    input_error("{}: voxels of {:.2f} mm cannot resolve a flap {:.2f} mm thick (the flap is the "
                "unlabelled layer between the lumina); resample the segmentation to voxels of "
                "at most the wall thickness",
                src, spacing_ * 1e3, h_ * 1e3);

  // The fields' grid: the labelled box, padded by the wall and room for the caps' rims.
  const double min_spacing =
      std::min({map.grid.spacing[0], map.grid.spacing[1], map.grid.spacing[2]});
  const int pad = static_cast<int>(std::ceil((2 * h_ + 3e-3) / min_spacing)) + 2;
  grid_ = map.grid;
  for (int a = 0; a < 3; ++a)
    grid_.size[a] = hi[a] - lo[a] + 1 + 2 * pad;
  grid_.origin = map.grid.point({double(lo[0] - pad), double(lo[1] - pad), double(lo[2] - pad)});
  const std::size_t n = grid_.count();
  std::vector<std::uint8_t> tl(n, 0), flt(n, 0), th(n, 0), other(n, 1);
  fl_mask_.assign(n, 0);
  for (int k = 0; k < grid_.size[2]; ++k)
    for (int j = 0; j < grid_.size[1]; ++j)
      for (int i = 0; i < grid_.size[0]; ++i) {
        const int mi = i + lo[0] - pad, mj = j + lo[1] - pad, mk = k + lo[2] - pad;
        if (mi < 0 || mj < 0 || mk < 0 || mi >= map.grid.size[0] || mj >= map.grid.size[1] ||
            mk >= map.grid.size[2])
          continue;
        const int l = map.labels[map.grid.linear(mi, mj, mk)];
        const std::size_t v = grid_.linear(i, j, k);
        tl[v] = l == r.true_lumen;
        fl_mask_[v] = l == r.false_lumen;
        th[v] = r.thrombus >= 0 && l == r.thrombus;
        flt[v] = fl_mask_[v] || th[v];
        other[v] = !(tl[v] || flt[v]);
      }
  const double sigma =
      o.smoothing * (map.grid.spacing[0] + map.grid.spacing[1] + map.grid.spacing[2]) / 3;
  const float far = static_cast<float>(1.0);
  tl_ = {&grid_, signed_distance(grid_, tl, sigma, true), far};
  fl_ = {&grid_, signed_distance(grid_, flt, sigma, true), far};
  if (r.thrombus >= 0)
    thrombus_ = {&grid_, signed_distance(grid_, th, sigma, true), far};

  // The gap read as flap: label-free voxels on the lumina's mid-surface within 3 h of both;
  // its 90th percentile, widened by a voxel, and at least h plus a voxel.
  // Between the lumina (not outside the aorta where the flap meets the wall) the nearest
  // points of the two lie on opposite sides: their distances' gradients are opposed.
  std::vector<float> gaps;
  w_ = {&grid_, std::vector<float>(n), far};
  for (std::size_t v = 0; v < n; ++v)
    w_.values[v] = 0.5f * (tl_.values[v] - fl_.values[v]);
  const std::size_t step[3] = {1, std::size_t(grid_.size[0]),
                               std::size_t(grid_.size[0]) * grid_.size[1]};
  for (int k = 1; k + 1 < grid_.size[2]; ++k)
    for (int j = 1; j + 1 < grid_.size[1]; ++j)
      for (int i = 1; i + 1 < grid_.size[0]; ++i) {
        const std::size_t v = grid_.linear(i, j, k);
        const float ut = tl_.values[v], uf = fl_.values[v];
        if (!(other[v] && ut > 0 && uf > 0 && std::abs(ut - uf) < spacing_ && ut + uf < 3 * h_))
          continue;
        double gt = 0, gf = 0, gtf = 0;
        for (int a = 0; a < 3; ++a) {
          const double dt = tl_.values[v + step[a]] - tl_.values[v - step[a]];
          const double df = fl_.values[v + step[a]] - fl_.values[v - step[a]];
          gt += dt * dt, gf += df * df, gtf += dt * df;
        }
        if (gtf < -0.7 * std::sqrt(gt * gf))
          gaps.push_back(ut + uf);
      }
  if (gaps.empty())
    input_error("{}: the true lumen (label {}) and the false lumen (label {}) never come within "
                "{:.1f} mm of each other: there is no flap between them to rebuild",
                src, r.true_lumen, r.false_lumen, 3 * h_ * 1e3);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() * 9 / 10, gaps.end());
  gap_ = std::max(gaps[gaps.size() * 9 / 10] + spacing_, h_ + spacing_);

  // sigma: the signed distance, in the flap's mid-surface, from the tears' rims (> 0 in a
  // tear), read at x - w n, n the unit gradient of w. In a tear it is the distance to the
  // label-free gap between the lumina (G); in the flap, minus the distance to where the
  // lumina touch (C: lumen voxels on the mid-surface). One distance alone would be bounded
  // by the thin sheets' half-thickness on the other side.
  std::vector<std::uint8_t> gap_mask(n, 0), contact_mask(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    gap_mask[v] = other[v] && tl_.values[v] < gap_ && fl_.values[v] < gap_;
    contact_mask[v] = !other[v] && std::abs(w_.values[v]) < 0.75 * spacing_;
  }
  const GridField to_gap{&grid_, signed_distance(grid_, gap_mask, sigma), far};
  const GridField to_contact{&grid_, signed_distance(grid_, contact_mask, sigma), far};
  // Off the flap's band sigma is not needed: there, and beyond 30 mm, it reads -30 mm.
  const double band = std::max(h_, 3 * spacing_), none = 30e-3;
  mid_sigma_ = {&grid_, std::vector<float>(n, static_cast<float>(-none)),
                static_cast<float>(-none)};
  for (int k = 1; k + 1 < grid_.size[2]; ++k)
    for (int j = 1; j + 1 < grid_.size[1]; ++j)
      for (int i = 1; i + 1 < grid_.size[0]; ++i) {
        const std::size_t v = grid_.linear(i, j, k);
        const double w = w_.values[v];
        if (std::abs(w) >= band)
          continue;
        Vec3 g{0, 0, 0};
        for (int a = 0; a < 3; ++a)
          g = g + ((w_.values[v + step[a]] - w_.values[v - step[a]]) / (2 * grid_.spacing[a])) *
                      grid_.direction[a];
        const double gn = norm(g);
        if (gn < 1e-6)
          continue;
        const Vec3 p = grid_.point({double(i), double(j), double(k)}) - (w / gn) * g;
        const double a = to_gap.at(p);
        mid_sigma_.values[v] = static_cast<float>(std::max(a > 0 ? a : -to_contact.at(p), -none));
      }
  find_tears();
}

double LabelledDissection::aorta(const Vec3& x) const {
  return aorta_of(tl_.at(x), fl_.at(x));
}

// E of the header; the gap's fill kept within 3h/4 of a lumen, so that the wall (h beyond
// the lumina) encloses it where the flap meets the wall. (The fluid in the fill lies off the
// flap, |w| > h/2, so within (g - h)/2, about a voxel, of a lumen.)
double LabelledDissection::aorta_of(double ut, double uf) const {
  return std::min({ut, uf, std::max(0.5 * (ut + uf - gap_), std::min(ut, uf) - 0.75 * h_)});
}

std::vector<std::uint8_t> LabelledDissection::aorta_mask() const {
  std::vector<std::uint8_t> m(grid_.count());
  for (std::size_t v = 0; v < m.size(); ++v) {
    m[v] = aorta_of(tl_.values[v], fl_.values[v]) < 0;
  }
  return m;
}

int LabelledDissection::tear_at(const Vec3& x) const {
  int best = -1;
  double best_d = 0;
  for (std::size_t k = 0; k < tears_.size(); ++k) {
    const LabelTear& t = tears_[k];
    const double d = norm(x - t.centroid);
    if (d < t.reach + std::max(t.growth, 0.0) && (best < 0 || d < best_d))
      best = static_cast<int>(k), best_d = d;
  }
  return best;
}

int LabelledDissection::label(const Vec3& x) const {
  const double ut = tl_.at(x), uf = fl_.at(x);
  const double e = aorta_of(ut, uf);
  if (e >= 0)
    return std::min(ut, uf) < h_ ? wall : outside;
  // The fluid is E minus the flap (and thrombus). The tears' rims are rounded by `round_`
  // (sharp edges there the mesher would refine without end); E and the flap share the
  // flap's faces (E < 0 is the lumina up to them), so they meet with a plain maximum: a
  // rounded one would thicken the flap by round_/4 all along.
  double flap = 0.5 * h_ - std::abs(0.5 * (ut - uf)); // > 0 in the flap's slab
  if (flap > -round_) {
    const int k = tear_at(x);
    if (k >= 0)
      flap = smooth_min(flap, -(mid_sigma_.at(x) + tears_[k].growth), round_);
  }
  double f = std::max(e, flap);
  if (!thrombus_.values.empty())
    f = smooth_max(f, -thrombus_.at(x), round_);
  return f < 0 ? fluid : wall;
}

void LabelledDissection::measure_tear(LabelTear& t) const {
  const double eps_w = 1.5 * spacing_, eps_s = spacing_;
  const double reach = t.reach + std::max(t.growth, 0.0);
  // The index box of the ball around the centroid.
  std::array<int, 3> lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    const double c = grid_.index(t.centroid)[a], r = reach / grid_.spacing[a];
    lo[a] = std::max(0, static_cast<int>(std::floor(c - r)));
    hi[a] = std::min(grid_.size[a] - 1, static_cast<int>(std::ceil(c + r)));
  }
  // (Rotated grids: the box in index space holds the ball since the axes are orthonormal.)
  const double dv = grid_.spacing[0] * grid_.spacing[1] * grid_.spacing[2] / 8;
  double area = 0, band = 0;
  Vec3 first{0, 0, 0}, band_first{0, 0, 0};
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero(), band_second = Eigen::Matrix3d::Zero();
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        if (std::abs(w_.values[grid_.linear(i, j, k)]) > eps_w + spacing_)
          continue;
        for (int s = 0; s < 8; ++s) {
          const Vec3 x = grid_.point({i + 0.25 * ((s & 1) ? 1 : -1), j + 0.25 * ((s & 2) ? 1 : -1),
                                      k + 0.25 * ((s & 4) ? 1 : -1)});
          if (norm(x - t.centroid) > reach)
            continue;
          // In the aorta only: a grown rim stops at the wall.
          const double on_band = smooth_delta(w_.at(x), eps_w) * smooth_step(-aorta(x), eps_s) * dv;
          if (on_band <= 0)
            continue;
          const Eigen::Vector3d e(x[0], x[1], x[2]);
          band += on_band;
          band_first = band_first + on_band * x;
          band_second += on_band * e * e.transpose();
          const double weight = on_band * smooth_step(mid_sigma_.at(x) + t.growth, eps_s);
          if (weight <= 0)
            continue;
          area += weight;
          first = first + weight * x;
          second += weight * e * e.transpose();
        }
      }
  t.area = area;
  if (area <= 0)
    return;
  t.centroid = (1 / area) * first;
  // The flap's normal: the least-variance direction of the mid-surface band around the tear
  // (flap and hole, a disc of the reach's radius: robust where a gradient at one point is
  // not, on the labels' staircase), pointing into the true lumen (against w's gradient).
  const Eigen::Vector3d bc(band_first[0] / band, band_first[1] / band, band_first[2] / band);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> plane(band_second / band - bc * bc.transpose());
  Vec3 nrm{plane.eigenvectors()(0, 0), plane.eigenvectors()(1, 0), plane.eigenvectors()(2, 0)};
  Vec3 g{0, 0, 0};
  for (int a = 0; a < 3; ++a)
    g = g + ((w_.at(t.centroid + spacing_ * grid_.direction[a]) -
              w_.at(t.centroid - spacing_ * grid_.direction[a])) /
             (2 * spacing_)) *
                grid_.direction[a];
  t.normal = dot(nrm, g) > 0 ? -1.0 * nrm : nrm;
  const Eigen::Vector3d c(t.centroid[0], t.centroid[1], t.centroid[2]);
  const Eigen::Matrix3d cov = second / area - c * c.transpose();
  const Eigen::Vector3d nn(t.normal[0], t.normal[1], t.normal[2]);
  const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - nn * nn.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(proj * cov * proj);
  // Ascending eigenvalues: [0] ~ 0 (the normal), [1] across, [2] along the long axis. An
  // ellipse of semi-axis a has the second moment a^2 / 4 along it.
  const Eigen::Vector3d axis = eig.eigenvectors().col(2);
  t.axis = {axis[0], axis[1], axis[2]};
  t.axial = 2 * std::sqrt(std::max(eig.eigenvalues()[2], 0.0));
  t.across = 2 * std::sqrt(std::max(eig.eigenvalues()[1], 0.0));
}

void LabelledDissection::find_tears() {
  const std::string src = "label map '" + file_.string() + "'";
  const std::size_t n = grid_.count();
  // Candidates: on the mid-surface (|w| < 3/4 voxel: a digital surface without holes), in
  // the aorta, where the lumina touch (sigma > 0).
  std::vector<std::uint8_t> cand(n, 0);
  double flap_area = 0;
  const double dv = grid_.spacing[0] * grid_.spacing[1] * grid_.spacing[2];
  for (std::size_t v = 0; v < n; ++v) {
    const double w = w_.values[v];
    const bool inside = aorta_of(tl_.values[v], fl_.values[v]) < 0;
    if (inside)
      flap_area += smooth_delta(w, 1.5 * spacing_) * dv;
    cand[v] = inside && std::abs(w) < 0.75 * spacing_ && mid_sigma_.values[v] > 0;
  }
  std::vector<int> comp(n, -1);
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (!cand[seed] || comp[seed] >= 0)
      continue;
    const int id = static_cast<int>(members.size());
    members.emplace_back();
    std::deque<std::size_t> queue{seed};
    comp[seed] = id;
    while (!queue.empty()) {
      const std::size_t v = queue.front();
      queue.pop_front();
      members[id].push_back(v);
      grid_.for_each_neighbour(v, [&](std::size_t u, int, int, int) {
        if (cand[u] && comp[u] < 0) {
          comp[u] = id;
          queue.push_back(u);
        }
      });
    }
  }
  double total = 0;
  for (const std::vector<std::size_t>& voxels : members) {
    LabelTear t;
    Vec3 c{0, 0, 0};
    std::vector<Vec3> points;
    for (std::size_t v : voxels) {
      const auto [i, j, k] = grid_.ijk(v);
      points.push_back(grid_.point({double(i), double(j), double(k)}));
      c = c + points.back();
      t.inscribed = std::max(t.inscribed, double(mid_sigma_.values[v]));
    }
    t.centroid = (1.0 / points.size()) * c;
    for (const Vec3& p : points)
      t.reach = std::max(t.reach, norm(p - t.centroid));
    t.reach += 2 * spacing_ + 1e-3;
    measure_tear(t);
    if (t.area < min_tear_area_)
      continue;
    t.found_area = t.area;
    total += t.area;
    tears_.push_back(t);
  }
  if (tears_.empty())
    input_error("{}: the true and the false lumen never touch through the flap: no tear (a tear "
                "is where the two labels meet with no unlabelled voxel between them; contacts "
                "below {:.0f} mm^2 are ignored)",
                src, min_tear_area_ * 1e6);
  if (total > 0.5 * flap_area)
    input_error("{}: the true and the false lumen touch over {:.0f} of the flap's {:.0f} mm^2: "
                "the flap must be an unlabelled layer between the lumina (tears are where they "
                "touch); a segmentation whose lumina share their boundary has no flap to read",
                src, total * 1e6, flap_area * 1e6);
  std::sort(tears_.begin(), tears_.end(),
            [](const LabelTear& a, const LabelTear& b) { return a.area > b.area; });
}

namespace {

// Grey-level dilation: the largest value within `r` voxels along each axis (a box), by
// running maxima axis after axis.
std::vector<float> box_maximum(const ImageGrid& g, std::vector<float> v, std::array<int, 3> r) {
  std::vector<float> line;
  const std::size_t step[3] = {1, std::size_t(g.size[0]), std::size_t(g.size[0]) * g.size[1]};
  for (int a = 0; a < 3; ++a) {
    const int n = g.size[a];
    line.resize(n);
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int j = 0; j < g.size[b]; ++j)
      for (int k = 0; k < g.size[c]; ++k) {
        const std::size_t base = j * step[b] + k * step[c];
        for (int i = 0; i < n; ++i)
          line[i] = v[base + i * step[a]];
        for (int i = 0; i < n; ++i) {
          float m = line[i];
          for (int d = std::max(0, i - r[a]); d <= std::min(n - 1, i + r[a]); ++d)
            m = std::max(m, line[d]);
          v[base + i * step[a]] = m;
        }
      }
  }
  return v;
}

} // namespace

void LabelledDissection::prepare_sizing(double radius) {
  std::array<int, 3> r{};
  for (int a = 0; a < 3; ++a)
    r[a] = static_cast<int>(std::ceil(radius / grid_.spacing[a]));
  std::vector<float> tl(tl_.values.size()), fl(fl_.values.size());
  for (std::size_t v = 0; v < tl.size(); ++v) {
    tl[v] = std::max(0.0f, -tl_.values[v]);
    fl[v] = std::max(0.0f, -fl_.values[v]);
  }
  tl_depth_ = {&grid_, box_maximum(grid_, std::move(tl), r), 0.0f};
  fl_depth_ = {&grid_, box_maximum(grid_, std::move(fl), r), 0.0f};
}

double LabelledDissection::lumen_half_thickness(const Vec3& x) const {
  const double ut = tl_.at(x), uf = fl_.at(x);
  const double t = tl_depth_.at(x), f = fl_depth_.at(x);
  if (ut < 0 && ut < uf)
    return t;
  if (uf < 0)
    return f;
  // In the wall: the thinner lumen beside it (a lumen that is not near reads 0: ignore it).
  if (t > 0 && f > 0)
    return std::min(t, f);
  return std::max(t, f);
}

double LabelledDissection::tear_area(std::size_t k, double growth) const {
  LabelTear t = tears_.at(k);
  t.growth = growth;
  measure_tear(t);
  return t.area;
}

void LabelledDissection::resize_tear(std::size_t k, double area) {
  LabelTear& t = tears_.at(k);
  if (!(area > 0))
    input_error("tear '{}': area {} mm^2, expected a positive number", t.name, area * 1e6);
  // The area grows monotonically with the rim's offset: bisection between closing the tear
  // (offset -inscribed) and growing it by its own size.
  double lo = -t.inscribed, hi = 2 * std::sqrt(t.found_area / kPi) + 5e-3;
  if (tear_area(k, hi) < area)
    input_error("tear '{}' ({:.0f} mm^2 in the label map) cannot grow to {:.0f} mm^2: its rim "
                "would run off the flap; the largest it grows to is about {:.0f} mm^2",
                t.name, t.found_area * 1e6, area * 1e6, tear_area(k, hi) * 1e6);
  for (int it = 0; it < 40 && hi - lo > 1e-3 * spacing_; ++it) {
    const double mid = 0.5 * (lo + hi);
    (tear_area(k, mid) < area ? lo : hi) = mid;
  }
  t.growth = 0.5 * (lo + hi);
  measure_tear(t);
}

} // namespace tearflow::geometry
