// The CGAL-free half of the implicit mesher: labels, cap rims, surface seeds.
#include "geometry/implicit_sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "core/error.hpp"

namespace tearflow::geometry::implicit {

namespace {

constexpr double kMm = 1e3; // for messages
// Fine samples per coarse cell along each axis (see sample()).
constexpr int kBlock = 4;

// The ends of the last interval when bisecting [a, b], where `side` holds at a and not at b,
// down to `tol`.
template <typename Side>
std::pair<Vec3, Vec3> bisect(Vec3 a, Vec3 b, double tol, const Side& side) {
  while (dot(b - a, b - a) > tol * tol) {
    const Vec3 m = 0.5 * (a + b);
    (side(m) ? a : b) = m;
  }
  return {a, b};
}

// Marching squares on an n x n grid of nodes (index j n + i) whose border nodes are out: the
// loops around the in-nodes, as sequences of crossed grid edges (2 (j n + i) for the edge
// from node (i, j) to (i + 1, j), that + 1 for the edge to (i, j + 1)). `centre_in(i, j)`
// decides the saddle cells (two in-corners facing each other).
template <typename CentreIn>
std::vector<std::vector<int>> march(int n, const std::vector<char>& in, const CentreIn& centre_in) {
  std::map<int, std::array<int, 2>> next; // each crossed edge's neighbours along its loop
  auto link = [&](int a, int b) {
    for (auto [e, f] : {std::pair{a, b}, std::pair{b, a}}) {
      auto [it, fresh] = next.try_emplace(e, std::array<int, 2>{-1, -1});
      it->second[it->second[0] < 0 ? 0 : 1] = f;
    }
  };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int k = j * n + i;
      // Corners counter-clockwise from (i, j); edge c joins corners c and c + 1.
      const bool c[4] = {in[k] != 0, in[k + 1] != 0, in[k + n + 1] != 0, in[k + n] != 0};
      const int e[4] = {2 * k, 2 * (k + 1) + 1, 2 * (k + n), 2 * k + 1};
      std::vector<int> crossed;
      for (int s = 0; s < 4; ++s)
        if (c[s] != c[(s + 1) % 4])
          crossed.push_back(e[s]);
      if (crossed.size() == 2) {
        link(crossed[0], crossed[1]);
      } else if (crossed.size() == 4) {
        // Corner s lies between edges s - 1 and s: cut off corners 1 and 3 when the centre
        // joins corners 0 and 2, else corners 0 and 2.
        const int s = centre_in(i, j) == c[0] ? 1 : 0;
        link(e[(s + 3) % 4], e[s]);
        link(e[(s + 1) % 4], e[(s + 2) % 4]);
      }
    }
  std::vector<std::vector<int>> loops;
  std::set<int> done;
  for (const auto& [start, unused] : next) {
    if (done.count(start))
      continue;
    std::vector<int> loop;
    int prev = -1, cur = start;
    do {
      loop.push_back(cur);
      done.insert(cur);
      const std::array<int, 2>& nb = next.at(cur);
      const int to = nb[0] != prev ? nb[0] : nb[1];
      prev = cur;
      cur = to;
    } while (cur != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Unit vectors u, v making (u, v, n) orthonormal.
std::pair<Vec3, Vec3> plane_basis(const Vec3& n) {
  const Vec3 t = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 u = cross(n, t);
  u = (1 / std::sqrt(dot(u, u))) * u;
  return {u, cross(n, u)};
}

} // namespace

int Labels::eval(const Vec3& x, bool check) const {
  const Vec3 r = x - d_.centre;
  if (dot(r, r) > d_.radius * d_.radius)
    return kOutside;
  for (std::size_t i = 0; i < d_.caps.size(); ++i) {
    const ImplicitCap& c = d_.caps[i];
    const Vec3 y = x - c.centre;
    const double beyond = dot(y, c.normal);
    const Vec3 radial = y - beyond * c.normal;
    if (beyond > 0 && dot(radial, radial) < c.radius * c.radius)
      return kFirstCap + static_cast<int>(i);
  }
  const int l = d_.label(x);
  if (l == kFluid || l == kWall)
    return l;
  if (check && l != kOutside)
    input_error("{}: label {} at ({:.2f}, {:.2f}, {:.2f}) mm, expected 0 (outside), 1 (fluid) "
                "or 2 (wall)",
                src_, l, x[0] * kMm, x[1] * kMm, x[2] * kMm);
  return kOutside;
}

std::vector<Polyline> cap_rims(const Labels& labels, const ImplicitCap& cap, double h, double tol,
                               const std::string& src) {
  const auto [u, v] = plane_basis(cap.normal);
  auto at = [&](double a, double b) { return cap.centre + a * u + b * v; };
  // Sampled a tolerance inside: on the plane itself, rounding decides the side of the cap.
  const Vec3 inward = -tol * cap.normal;
  auto label_at = [&](const Vec3& x) { return labels(x + inward); };
  const double r = cap.radius;
  const int rim_points = static_cast<int>(std::ceil(2 * std::numbers::pi * r / h));
  for (int k = 0; k < rim_points; ++k) {
    const double phi = 2 * std::numbers::pi * k / rim_points;
    const Vec3 x = at(r * std::cos(phi), r * std::sin(phi));
    if (const int l = label_at(x); l != kOutside)
      input_error("{}: cap '{}' does not reach past the vessel: label {} at ({:.2f}, {:.2f}, "
                  "{:.2f}) mm on the rim of its disc (radius {:.2f} mm); make its radius larger",
                  src, cap.name, l, x[0] * kMm, x[1] * kMm, x[2] * kMm, r * kMm);
  }
  const int m = static_cast<int>(std::ceil(r / h)) + 1, n = 2 * m + 1;
  std::vector<int> label(static_cast<std::size_t>(n) * n, kOutside);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = (i - m) * h, b = (j - m) * h;
      if (a * a + b * b <= r * r)
        label[j * n + i] = label_at(at(a, b));
    }
  std::vector<Polyline> loops;
  for (const bool with_wall : {false, true}) {
    auto in_set = [with_wall](int l) { return l == kFluid || (with_wall && l == kWall); };
    std::vector<char> in(label.size());
    std::transform(label.begin(), label.end(), in.begin(), in_set);
    if (!with_wall && std::find(in.begin(), in.end(), 1) == in.end())
      input_error("{}: cap '{}' cuts no fluid (sampled every {:.3g} mm on its disc of radius "
                  "{:.2f} mm around ({:.2f}, {:.2f}, {:.2f}) mm)",
                  src, cap.name, h * kMm, r * kMm, cap.centre[0] * kMm, cap.centre[1] * kMm,
                  cap.centre[2] * kMm);
    auto centre_in = [&](int i, int j) {
      return in_set(label_at(at((i - m + 0.5) * h, (j - m + 0.5) * h)));
    };
    for (const std::vector<int>& edges : march(n, in, centre_in)) {
      Polyline loop;
      for (const int e : edges) {
        const int k = e / 2, i = k % n, j = k / n;
        Vec3 a = at((i - m) * h, (j - m) * h);
        Vec3 b = e % 2 == 0 ? at((i + 1 - m) * h, (j - m) * h) : at((i - m) * h, (j + 1 - m) * h);
        if (!in[k])
          std::swap(a, b);
        const auto [p, q] = bisect(a, b, tol, [&](const Vec3& x) { return in_set(label_at(x)); });
        const Vec3 pt = 0.5 * (p + q);
        // Points a thousandth of the spacing apart (the curve passing by a node) are one.
        if (loop.empty() || dot(pt - loop.back(), pt - loop.back()) > 1e-6 * h * h)
          loop.push_back(pt);
      }
      while (loop.size() > 1 &&
             dot(loop.front() - loop.back(), loop.front() - loop.back()) <= 1e-6 * h * h)
        loop.pop_back();
      if (loop.size() < 3)
        continue;
      loop.push_back(loop.front());
      loops.push_back(std::move(loop));
    }
  }
  return loops;
}

// One seed per element cube and surface: a thin layer gets seeds on both of its sides, and
// CGAL's Delaunay facets between them have their dual Voronoi edges cross it. Sparser seeds
// (three elements apart) missed a free-floating plate in the test pipe; denser ones only
// constrain the refinement (seeds closer than half an element would make small elements).
// Coarse to fine, to spend time and memory on the domain rather than its sphere (an aorta
// fills a few percent of it): every kBlock h, then every h in the cells within two coarse
// cells of a coarse node inside the domain. So only a piece thinner than kBlock h everywhere
// and farther than that from the rest can be missed; the wall, on the fluid, cannot.
Sampling sample(const Labels& labels, const ImplicitDomain& d,
                const std::function<double(const Vec3&)>& size, double element_size, double h,
                double tol, const std::string& src) {
  const double coarse = kBlock * h;
  const int nc = static_cast<int>(std::ceil(2 * d.radius / coarse)) + 1;
  const double nodes = std::pow(static_cast<double>(nc), 3);
  if (nodes > 4e8) // a byte each
    input_error("{}: sampling the bounding sphere (radius {:.1f} mm) every {:.3g} mm takes "
                "{:.3g} coarse samples, too many: give a tighter sphere or a larger min_feature",
                src, d.radius * kMm, h * kMm, nodes);
  const Vec3 origin = d.centre - Vec3{d.radius, d.radius, d.radius};
  const auto at = [&](long i, long j, long k) {
    return origin +
           Vec3{static_cast<double>(i) * h, static_cast<double>(j) * h, static_cast<double>(k) * h};
  };
  const auto node = [nc](long i, long j, long k) { return (k * nc + j) * nc + i; };
  std::vector<char> active(static_cast<std::size_t>(nodes));
  for (long k = 0; k < nc; ++k)
    for (long j = 0; j < nc; ++j)
      for (long i = 0; i < nc; ++i)
        active[node(i, j, k)] = !is_outside(labels.checked(at(kBlock * i, kBlock * j, kBlock * k)));
  // Grown by two coarse cells, axis by axis.
  for (int axis = 0; axis < 3; ++axis) {
    const std::vector<char> was = active;
    const long stride = axis == 0 ? 1 : axis == 1 ? nc : static_cast<long>(nc) * nc;
    for (long q = 0; q < static_cast<long>(was.size()); ++q) {
      const long pos = q / stride % nc;
      for (long s = -2; s <= 2 && !active[q]; ++s)
        if (pos + s >= 0 && pos + s < nc && was[q + s * stride])
          active[q] = 1;
    }
  }

  const int num_labels = kFirstCap + static_cast<int>(d.caps.size());
  const long bins = static_cast<long>(std::ceil(2 * d.radius / element_size)) + 1;
  const auto bin_key = [&](const Vec3& x, int a, int b, long di = 0, long dj = 0, long dk = 0) {
    std::array<long, 3> c{};
    for (int t = 0; t < 3; ++t)
      c[t] = std::clamp(static_cast<long>((x[t] - origin[t]) / element_size), 0L, bins - 1);
    const long pair = std::min(a, b) * num_labels + std::max(a, b);
    return static_cast<std::uint64_t>(((c[2] + dk) * bins + c[1] + dj) * bins + c[0] + di) *
               (num_labels * num_labels) +
           pair;
  };
  std::unordered_set<std::uint64_t> tried;
  std::unordered_map<std::uint64_t, std::vector<Vec3>> seeds_in;
  Sampling out;
  const auto cross = [&](int la, int lb, Vec3 a, Vec3 b) {
    if (la == lb || (is_outside(la) && is_outside(lb)))
      return;
    if (!tried.insert(bin_key(0.5 * (a + b), la, lb)).second)
      return;
    if (is_outside(la)) // bisect from the inside: the seed then lies on its region's boundary
      std::swap(a, b), std::swap(la, lb);
    const auto [p, q] = bisect(a, b, tol, [&](const Vec3& x) { return labels(x) == la; });
    const Vec3 s = 0.5 * (p + q);
    lb = labels(q);
    if (is_outside(la) && is_outside(lb))
      return;
    for (long dk = -1; dk <= 1; ++dk)
      for (long dj = -1; dj <= 1; ++dj)
        for (long di = -1; di <= 1; ++di)
          if (const auto it = seeds_in.find(bin_key(s, la, lb, di, dj, dk)); it != seeds_in.end())
            for (const Vec3& t : it->second)
              if (dot(t - s, t - s) < 0.25 * element_size * element_size)
                return;
    seeds_in[bin_key(s, la, lb)].push_back(s);
    out.seeds.push_back({s, std::min(la, lb), std::max(la, lb)});
  };

  constexpr int kN = kBlock + 1;
  std::array<int, kN * kN * kN> fine{};
  const auto f = [](int a, int b, int c) { return (c * kN + b) * kN + a; };
  for (long k = 0; k + 1 < nc; ++k)
    for (long j = 0; j + 1 < nc; ++j)
      for (long i = 0; i + 1 < nc; ++i) {
        if (!active[node(i, j, k)])
          continue;
        const long i0 = kBlock * i, j0 = kBlock * j, k0 = kBlock * k;
        int fluid = 0, wall = 0;
        for (int c = 0; c < kN; ++c)
          for (int b = 0; b < kN; ++b)
            for (int a = 0; a < kN; ++a) {
              const int l = fine[f(a, b, c)] = labels.checked(at(i0 + a, j0 + b, k0 + c));
              if (a < kBlock && b < kBlock && c < kBlock) // each node counted by one cell
                fluid += l == kFluid, wall += l == kWall;
              if (a > 0)
                cross(fine[f(a - 1, b, c)], l, at(i0 + a - 1, j0 + b, k0 + c),
                      at(i0 + a, j0 + b, k0 + c));
              if (b > 0)
                cross(fine[f(a, b - 1, c)], l, at(i0 + a, j0 + b - 1, k0 + c),
                      at(i0 + a, j0 + b, k0 + c));
              if (c > 0)
                cross(fine[f(a, b, c - 1)], l, at(i0 + a, j0 + b, k0 + c - 1),
                      at(i0 + a, j0 + b, k0 + c));
            }
        const double cell = h * h * h;
        out.fluid_volume += fluid * cell;
        out.wall_volume += wall * cell;
        if (fluid + wall > 0)
          out.vertices += (fluid + wall) * cell /
                          std::pow(size(at(i0 + kBlock / 2, j0 + kBlock / 2, k0 + kBlock / 2)), 3);
      }
  return out;
}

} // namespace tearflow::geometry::implicit
