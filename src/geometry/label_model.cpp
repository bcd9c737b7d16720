// A dissection model from a label map (label_model.hpp): fields, tears, ends and caps,
// centreline and landmarks, mesh.
#include "geometry/label_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/implicit_mesher.hpp"
#include "geometry/import.hpp"
#include "geometry/vessel_paths.hpp"

namespace tearflow::geometry {

namespace fs = std::filesystem;

namespace {

double norm(const Vec3& v) {
  return std::sqrt(dot(v, v));
}
Vec3 unit(const Vec3& v) {
  return (1 / norm(v)) * v;
}
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A plane's section: the samples of a square grid of `step` on the plane within `radius` of
// `origin` for which `inside` holds, in the 4-connected component nearest the origin.
struct Section {
  std::vector<Vec3> points, rim; ///< rim: samples with a neighbour not in the section
  Vec3 centroid{};
  double area = 0;
  bool touches_border = false; ///< reaches the disc's edge: the plane runs along the vessel
  bool empty() const { return points.empty(); }
};

Section section(const std::function<bool(const Vec3&)>& inside, const Vec3& origin,
                const Vec3& normal, double radius, double step) {
  const Vec3 n = unit(normal);
  const Vec3 any = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = unit(cross(n, any)), e2 = cross(n, e1);
  const int m = static_cast<int>(std::ceil(radius / step)), side = 2 * m + 1;
  auto at = [&](int a, int b) { return origin + ((a - m) * step) * e1 + ((b - m) * step) * e2; };
  auto in_disc = [&](int a, int b) { return std::hypot(a - m, b - m) * step <= radius; };
  std::vector<std::uint8_t> in(side * side, 0), taken(side * side, 0);
  int start = -1;
  double best = 0;
  for (int b = 0; b < side; ++b)
    for (int a = 0; a < side; ++a)
      if (in_disc(a, b) && inside(at(a, b))) {
        in[a + side * b] = 1;
        const double d = std::hypot(a - m, b - m);
        if (start < 0 || d < best)
          start = a + side * b, best = d;
      }
  Section s;
  if (start < 0)
    return s;
  std::deque<int> queue{start};
  taken[start] = 1;
  Vec3 sum{0, 0, 0};
  while (!queue.empty()) {
    const int c = queue.front();
    queue.pop_front();
    const int a = c % side, b = c / side;
    const Vec3 p = at(a, b);
    s.points.push_back(p);
    sum = sum + p;
    if (std::hypot(a - m, b - m) * step > radius - 1.5 * step)
      s.touches_border = true;
    bool rim = false;
    for (auto [da, db] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int u = a + da, v = b + db;
      if (u < 0 || v < 0 || u >= side || v >= side || !in[u + side * v]) {
        rim = true;
        continue;
      }
      if (!taken[u + side * v]) {
        taken[u + side * v] = 1;
        queue.push_back(u + side * v);
      }
    }
    if (rim)
      s.rim.push_back(p);
  }
  s.area = s.points.size() * step * step;
  s.centroid = (1.0 / s.points.size()) * sum;
  return s;
}

// A polyline with its arclength.
struct Centreline {
  std::vector<Vec3> p;
  std::vector<double> s;
  explicit Centreline(std::vector<Vec3> points) : p(std::move(points)), s(p.size(), 0.0) {
    for (std::size_t i = 1; i < p.size(); ++i)
      s[i] = s[i - 1] + norm(p[i] - p[i - 1]);
  }
  double length() const { return s.back(); }
  Vec3 at(double t) const {
    t = std::clamp(t, 0.0, length());
    const std::size_t i =
        std::min<std::size_t>(std::upper_bound(s.begin(), s.end(), t) - s.begin(), p.size() - 1);
    if (i == 0)
      return p[0];
    const double f = (t - s[i - 1]) / std::max(s[i] - s[i - 1], 1e-12);
    return p[i - 1] + f * (p[i] - p[i - 1]);
  }
  /// Downstream unit tangent: a central difference over +-3 mm.
  Vec3 tangent(double t) const { return unit(at(t + 3e-3) - at(t - 3e-3)); }
  /// Arclength of the point nearest x.
  double project(const Vec3& x) const {
    std::size_t best = 0;
    for (std::size_t i = 1; i < p.size(); ++i)
      if (norm(p[i] - x) < norm(p[best] - x))
        best = i;
    return s[best];
  }
};

Vec3 gradient(const std::function<double(const Vec3&)>& f, const Vec3& x, double h) {
  Vec3 g{};
  for (int a = 0; a < 3; ++a) {
    Vec3 e{0, 0, 0};
    e[a] = h;
    g[a] = (f(x + e) - f(x - e)) / (2 * h);
  }
  return g;
}

// The cap of a vessel end: walking in from the tip along `path` (tip first), the first
// plane perpendicular to the path whose section of the aorta is whole (its rim's normals
// perpendicular to the plane's: no part of the end face in it, nor running along the
// vessel), moved two voxels further in.
LabelCap find_cap(const LabelledDissection& d, const std::vector<Vec3>& path, double radius,
                  const std::string& name) {
  const double spacing = std::max({d.grid().spacing[0], d.grid().spacing[1], d.grid().spacing[2]});
  const Centreline line(path);
  auto aorta = [&](const Vec3& x) { return d.aorta(x); };
  auto inside = [&](const Vec3& x) { return d.aorta(x) < 0; };
  const double ahead = std::max(2 * radius, 5e-3), reach = 2.5 * radius + d.wall_thickness();
  // The vessel's axis at t: the medial path starts at a corner of the end face, so its
  // tangent near the tip is off; the line through the centroids of the sections one radius
  // apart is not (twice: the second with the first's normal).
  auto axis_at = [&](double t) {
    Vec3 n = unit(line.at(t + radius) - line.at(t + radius + ahead));
    for (int it = 0; it < 2; ++it) {
      const Section near = section(inside, line.at(t), n, reach, 0.5 * spacing);
      const Section far = section(inside, line.at(t + radius), n, reach, 0.5 * spacing);
      if (near.empty() || far.empty())
        break;
      n = unit(near.centroid - far.centroid);
    }
    return n;
  };
  for (double t = spacing; t + radius + ahead < line.length(); t += 0.5 * spacing) {
    const Vec3 normal = axis_at(t); // out of the domain
    const Section s = section(inside, line.at(t), normal, reach, 0.5 * spacing);
    if (s.empty() || s.touches_border)
      continue;
    const bool whole = std::all_of(s.rim.begin(), s.rim.end(), [&](const Vec3& q) {
      const Vec3 g = gradient(aorta, q, 0.5 * spacing);
      return std::abs(dot(g, normal)) < 0.5 * norm(g);
    });
    if (!whole)
      continue;
    const double t2 = t + 2 * spacing;
    const Vec3 n2 = axis_at(t2);
    const Section c = section(inside, line.at(t2), n2, reach, 0.5 * spacing);
    LabelCap cap{name, c.centroid, n2, c.area, 0};
    for (const Vec3& q : c.points)
      cap.reach = std::max(cap.reach, norm(q - c.centroid));
    cap.reach += d.wall_thickness() + 2e-3;
    return cap;
  }
  const Vec3 tip = path.front();
  input_error("label map: cannot cap the vessel end near ({:.1f}, {:.1f}, {:.1f}) mm: no plane "
              "across the vessel within its length gives a whole section (a branch shorter "
              "than two radii, or an end that is not tubular)",
              tip[0] * 1e3, tip[1] * 1e3, tip[2] * 1e3);
}

} // namespace

LabelModel build_label_model(const LabelMap& map, const LabelModelOptions& o) {
  const std::string src = "label map '" + map.file.string() + "'";
  auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& what) {
    if (o.verbose)
      fmt::print("labels: {} ({:.1f} s)\n", what, seconds_since(t0)), std::fflush(stdout);
  };
  LabelledDissection d(map, o.dissection);
  LabelModel out;
  out.flap_gap = d.flap_gap();
  say(fmt::format("fields on {}x{}x{} voxels, flap gap {:.2f} mm, {} tear(s)", d.grid().size[0],
                  d.grid().size[1], d.grid().size[2], d.flap_gap() * 1e3, d.tears().size()));
  out.seconds_fields = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();

  // The vessel's ends and the medial paths between them.
  VesselVoxels vessel{&d.grid(), d.aorta_mask(), {}};
  {
    std::vector<float> sd = signed_distance(d.grid(), vessel.inside, 0.0);
    for (float& v : sd)
      v = std::max(0.0f, -v);
    vessel.depth = std::move(sd);
  }
  const std::vector<std::size_t> ends = vessel_ends(vessel, o.min_branch);
  if (ends.size() < 2)
    input_error("{}: the aorta has fewer than two ends", src);
  const std::vector<std::int64_t> from_root = medial_paths(vessel, ends[0]);
  // Each end's radius: the deepest point within 20 mm of its tip.
  std::vector<double> radius(ends.size(), 0.0);
  std::vector<std::vector<std::size_t>> to_root(ends.size());
  for (std::size_t e = 1; e < ends.size(); ++e)
    to_root[e] = trace_voxels(from_root, ends[e]);
  to_root[0] = to_root[1];
  std::reverse(to_root[0].begin(), to_root[0].end());
  for (std::size_t e = 0; e < ends.size(); ++e) {
    const std::vector<Vec3> pts = path_points(vessel, to_root[e]);
    double along = 0;
    for (std::size_t i = 0; i < pts.size() && along < 20e-3; ++i) {
      radius[e] = std::max(radius[e], double(vessel.depth[to_root[e][i]]));
      if (i > 0)
        along += norm(pts[i] - pts[i - 1]);
    }
  }
  if (o.verbose)
    for (std::size_t e = 0; e < ends.size(); ++e) {
      const Vec3 p = path_points(vessel, to_root[e]).front();
      fmt::print(
          "labels: end {} at ({:.1f}, {:.1f}, {:.1f}) mm, radius {:.1f} mm, path {} voxels\n", e,
          p[0] * 1e3, p[1] * 1e3, p[2] * 1e3, radius[e] * 1e3, to_root[e].size());
    }
  // The aorta's two ends are its widest; the inlet is the one farther from the false lumen.
  std::vector<std::size_t> order(ends.size());
  for (std::size_t e = 0; e < ends.size(); ++e)
    order[e] = e;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return radius[a] > radius[b]; });
  std::size_t inlet = order[0], outlet = order[1];
  std::vector<std::int64_t> from_inlet = medial_paths(vessel, ends[inlet]);
  std::vector<std::size_t> main_voxels = trace_voxels(from_inlet, ends[outlet]);
  std::reverse(main_voxels.begin(), main_voxels.end()); // inlet first
  auto fl_present = [&](const Centreline& line, double s) {
    const Vec3 c = line.at(s);
    const Section sec = section([&](const Vec3& x) { return d.aorta(x) < 0; }, c, line.tangent(s),
                                2.5 * std::max(-d.aorta(c), 5e-3), 0.5e-3);
    return std::any_of(sec.points.begin(), sec.points.end(),
                       [&](const Vec3& x) { return d.false_lumen(x) < 0; });
  };
  double fl_first = 0, fl_last = 0;
  auto fl_extent = [&](const Centreline& line) {
    fl_first = -1;
    for (double s = 0; s < line.length(); s += 2e-3)
      if (fl_present(line, s)) {
        if (fl_first < 0)
          fl_first = s;
        fl_last = s;
      }
  };
  bool swapped = false;
  {
    const Centreline line(path_points(vessel, main_voxels));
    fl_extent(line);
    if (fl_first < 0)
      input_error("{}: no false lumen along the aorta's centreline", src);
    if (fl_first < line.length() - fl_last) { // the false lumen is nearer this end: the outlet
      std::swap(inlet, outlet);
      from_inlet = medial_paths(vessel, ends[inlet]);
      main_voxels = trace_voxels(from_inlet, ends[outlet]);
      std::reverse(main_voxels.begin(), main_voxels.end());
      swapped = true;
    }
  }
  const Centreline line(path_points(vessel, main_voxels));
  if (swapped) // (else the centreline is the one just sampled)
    fl_extent(line);
  out.centreline = line.p;
  say(fmt::format("centreline {:.0f} mm, {} ends, false lumen from {:.0f} to {:.0f} mm",
                  line.length() * 1e3, ends.size(), fl_first * 1e3, fl_last * 1e3));

  // Branches: where each leaves the aorta's centreline, in order from the inlet.
  std::vector<std::uint8_t> on_main(vessel.inside.size(), 0);
  std::map<std::size_t, double> main_s;
  for (std::size_t i = 0; i < main_voxels.size(); ++i) {
    on_main[main_voxels[i]] = 1;
    main_s[main_voxels[i]] = line.s[i];
  }
  struct Branch {
    std::size_t end;
    double join_s;
    std::vector<std::size_t> voxels;
  };
  std::vector<Branch> branches;
  // A branch joins where its medial path (from its tip) first comes within the aorta's
  // radius of the aorta's centreline (its medial path may run on inside the aorta).
  for (std::size_t e = 0; e < ends.size(); ++e) {
    if (e == inlet || e == outlet)
      continue;
    std::vector<std::size_t> v = trace_voxels(from_inlet, ends[e]);
    std::size_t k = 0;
    while (k < v.size() && !on_main[v[k]])
      ++k;
    v.resize(k);
    const std::vector<Vec3> pts = path_points(vessel, v);
    double s_join = k < v.size() + 1 && !pts.empty() ? line.project(pts.back()) : 0.0;
    for (const Vec3& p : pts) {
      const double s = line.project(p);
      if (norm(p - line.at(s)) < -d.aorta(line.at(s)) + 1e-3) {
        s_join = s;
        break;
      }
    }
    branches.push_back({e, s_join, std::move(v)});
  }
  std::sort(branches.begin(), branches.end(),
            [](const Branch& a, const Branch& b) { return a.join_s < b.join_s; });
  auto cap_name = [&](std::size_t k) {
    std::string name = branches.size() == 3 ? std::vector<std::string>{"BCT", "LCC", "LSA"}[k]
                                            : fmt::format("branch_{}", k + 1);
    return name;
  };
  std::vector<Vec3> inlet_path = line.p, outlet_path(line.p.rbegin(), line.p.rend());
  out.caps.push_back(find_cap(d, inlet_path, radius[inlet], "inlet"));
  for (std::size_t k = 0; k < branches.size(); ++k)
    out.caps.push_back(
        find_cap(d, path_points(vessel, branches[k].voxels), radius[branches[k].end], cap_name(k)));
  out.caps.push_back(find_cap(d, outlet_path, radius[outlet], "outlet"));
  for (const auto& [from, to] : o.rename_faces) {
    auto it = std::find_if(out.caps.begin(), out.caps.end(),
                           [&](const LabelCap& c) { return c.name == from; });
    if (it == out.caps.end()) {
      std::string known;
      for (const LabelCap& c : out.caps)
        known += (known.empty() ? "" : ", ") + c.name;
      input_error("--face {}={}: no cap is called '{}' (the caps: {})", from, to, from, known);
    }
    it->name = to;
  }
  const double s_in = line.project(out.caps.front().centre);
  const double s_out = line.project(out.caps.back().centre);

  // Tears by position: entry (most proximal), exit (most distal), then tear_2, ...
  std::vector<LabelTear>& tears = d.tears();
  std::sort(tears.begin(), tears.end(), [&](const LabelTear& a, const LabelTear& b) {
    return line.project(a.centroid) < line.project(b.centroid);
  });
  for (std::size_t k = 0; k < tears.size(); ++k)
    tears[k].name = k == 0                  ? "entry"
                    : k + 1 == tears.size() ? "exit"
                                            : fmt::format("tear_{}", k + 1);
  for (const auto& [name, area] : o.tear_areas) {
    auto it = std::find_if(tears.begin(), tears.end(),
                           [&](const LabelTear& t) { return t.name == name; });
    if (it == tears.end()) {
      std::string known;
      for (const LabelTear& t : tears)
        known += (known.empty() ? "" : ", ") + t.name;
      input_error("{}: no tear '{}' to resize (the tears found: {})", src, name, known);
    }
    d.resize_tear(static_cast<std::size_t>(it - tears.begin()), area);
  }
  out.tears = tears;

  // Landmarks.
  const double h = d.wall_thickness();
  auto fluid_point = [&](const Section& sec, const std::function<double(const Vec3&)>& depth) {
    const Vec3* best = nullptr;
    double best_d = 0;
    for (const Vec3& x : sec.points)
      if (d.label(x) == LabelledDissection::fluid && (!best || depth(x) > best_d))
        best = &x, best_d = depth(x);
    return best ? std::optional<Vec3>(*best) : std::nullopt;
  };
  auto plane_section = [&](const Vec3& c, const Vec3& normal) {
    return section([&](const Vec3& x) { return d.aorta(x) < 0; }, c, normal,
                   2.5 * std::max(-d.aorta(c), 5e-3), 0.25e-3);
  };
  auto aorta_plane = [&](const std::string& name, const Vec3& origin, const Vec3& normal) {
    const Section sec = plane_section(origin, normal);
    const auto p = fluid_point(
        sec, [&](const Vec3& x) { return -std::min(d.true_lumen(x), d.false_lumen(x)); });
    if (!p)
      input_error("{}: landmark {} at ({:.1f}, {:.1f}, {:.1f}) mm crosses no fluid", src, name,
                  origin[0] * 1e3, origin[1] * 1e3, origin[2] * 1e3);
    out.landmarks.planes.push_back({name, origin, normal, "aorta", *p});
  };
  auto centreline_plane = [&](const std::string& name, double s) {
    aorta_plane(name, line.at(s), line.tangent(s));
  };
  if (!o.landmarks.empty()) {
    Landmarks given = read_landmarks(o.landmarks);
    out.landmarks.planes = given.planes;
    out.landmarks.tears = given.tears;
  } else {
    // The inlet and outlet planes: the caps' planes 1 mm inside (on a cap a section is
    // undefined), downstream.
    const LabelCap &in_cap = out.caps.front(), &out_cap = out.caps.back();
    aorta_plane("inlet", in_cap.centre - 1e-3 * in_cap.normal, -1.0 * in_cap.normal);
    const double first_join = branches.empty() ? 0.5 * (s_in + fl_first) : branches[0].join_s;
    centreline_plane("AAo", 0.5 * (s_in + first_join - radius[inlet]));
    const double s_entry = line.project(tears.front().centroid);
    const double s_exit = tears.size() > 1 ? line.project(tears.back().centroid) : fl_last;
    centreline_plane("DAo_prox", s_entry);
    double offset = o.station_offset;
    if (s_exit - s_entry - 2 * offset < 20e-3)
      offset = std::max(0.5 * (s_exit - s_entry - 20e-3), 0.0);
    if (offset < 5e-3)
      input_error("{}: the tears are {:.0f} mm apart along the centreline: no room for the five "
                  "TL/FL stations between them",
                  src, (s_exit - s_entry) * 1e3);
    const double first = s_entry + offset, last = s_exit - offset;
    for (int k = 0; k < 5; ++k) {
      const double s = first + k * (last - first) / 4;
      const Section sec = plane_section(line.at(s), line.tangent(s));
      const auto tl = fluid_point(sec, [&](const Vec3& x) { return -d.true_lumen(x); });
      const auto fl = fluid_point(sec, [&](const Vec3& x) { return -d.false_lumen(x); });
      if (!tl || !fl || d.true_lumen(*tl) >= 0 || d.false_lumen(*fl) >= 0)
        input_error("{}: station {} ({:.0f} mm along the centreline) does not cross both lumina; "
                    "give the landmarks with --landmarks",
                    src, k + 1, s * 1e3);
      out.landmarks.planes.push_back(
          {fmt::format("TL{}", k + 1), line.at(s), line.tangent(s), "TL", *tl});
      out.landmarks.planes.push_back(
          {fmt::format("FL{}", k + 1), line.at(s), line.tangent(s), "FL", *fl});
    }
    // Below the false lumen's end; else below the exit tear; in a scan cropped across the
    // dissection (no exit tear, the false lumen reaching the outlet's cap) between the last
    // station and the outlet, inside the capped domain.
    const double fl_end_wall = fl_last + h;
    centreline_plane("DAo_dist", fl_end_wall + 10e-3 < s_out - 1e-3
                                     ? 0.5 * (fl_end_wall + s_out) + 2e-3
                                 : s_exit < s_out ? 0.5 * (s_exit + s_out)
                                                  : 0.5 * (last + s_out));
    aorta_plane("outlet", out_cap.centre - 1e-3 * out_cap.normal, out_cap.normal);
  }
  if (out.landmarks.tears.empty())
    for (const LabelTear& t : tears)
      out.landmarks.tears.push_back(
          {t.name, t.centroid, t.normal, t.axis, t.area, t.axial, t.across});
  out.seconds_landmarks = seconds_since(t1);
  say("caps and landmarks");

  // The mesh.
  const auto t2 = std::chrono::steady_clock::now();
  ImplicitDomain domain;
  domain.label = [&d](const Vec3& x) { return d.label(x); };
  const ImageGrid& g = d.grid();
  const Vec3 far = g.point({double(g.size[0] - 1), double(g.size[1] - 1), double(g.size[2] - 1)});
  domain.centre = 0.5 * (g.origin + far);
  domain.radius = 0.5 * norm(far - g.origin);
  for (const LabelCap& c : out.caps)
    domain.caps.push_back({c.name, c.centre, c.normal, c.reach});
  domain.source = src;
  ImplicitMeshOptions mo;
  mo.element_size = o.element_size;
  // As the built-in model (lumen_sizing.hpp): at least three elements across each lumen's
  // thickness, so that the narrow true lumen has interior nodes.
  d.prepare_sizing(o.element_size);
  const double smallest = std::max(0.5e-3, 0.5 * d.wall_thickness());
  // And as the built-in model's tears (tbad_builder.cpp): at most a 24th of the perimeter
  // within a semi-axis of the rim (24 edges keep 98.9 % of an ellipse's area).
  mo.size = [&d, smallest, &o](const Vec3& x) {
    double size = std::clamp(2 * d.lumen_half_thickness(x) / 3, smallest, o.element_size);
    for (const LabelTear& t : d.tears())
      if (norm(x - t.centroid) < 2 * t.axial + d.wall_thickness())
        size = std::min(size, std::max(std::numbers::pi * (t.axial + t.across) / 24, smallest));
    return size;
  };
  mo.min_feature = std::min(0.5 * h, 0.5e-3);
  mo.verbose = o.verbose;
  out.mesh = mesh_implicit(domain, mo);
  out.mesh.source = src;
  out.seconds_mesh = seconds_since(t2);
  say(fmt::format("mesh: {} nodes, {} tets", out.mesh.points.size(), out.mesh.tets.size()));
  return out;
}

LabelModel geometry_from_labels(const fs::path& scan, const LabelModelOptions& options,
                                const fs::path& dir) {
  const LabelMap map = read_label_map(scan);
  LabelModel m = build_label_model(map, options);
  write_geometry(m.mesh, m.landmarks, dir);
  using nlohmann::json;
  auto mm = [](const Vec3& v) { return json::array({v[0] * 1e3, v[1] * 1e3, v[2] * 1e3}); };
  json caps = json::array(), tears = json::array();
  for (const LabelCap& c : m.caps)
    caps.push_back({{"name", c.name},
                    {"centre_mm", mm(c.centre)},
                    {"normal", json::array({c.normal[0], c.normal[1], c.normal[2]})},
                    {"area_mm2", c.area * 1e6}});
  for (const LabelTear& t : m.tears)
    tears.push_back({{"name", t.name},
                     {"centroid_mm", mm(t.centroid)},
                     {"area_in_labels_mm2", t.found_area * 1e6},
                     {"area_mm2", t.area * 1e6},
                     {"rim_moved_mm", t.growth * 1e3}});
  json line = json::array();
  for (std::size_t i = 0; i < m.centreline.size(); i += 4)
    line.push_back(mm(m.centreline[i]));
  const json j{{"label_map", fs::absolute(scan).string()},
               {"wall_thickness_mm", options.dissection.wall_thickness * 1e3},
               {"flap_gap_mm", m.flap_gap * 1e3},
               {"element_size_mm", options.element_size * 1e3},
               {"caps", caps},
               {"tears", tears},
               {"centreline_mm", line},
               {"seconds",
                {{"fields", m.seconds_fields},
                 {"landmarks", m.seconds_landmarks},
                 {"mesh", m.seconds_mesh}}}};
  std::ofstream f(dir / "labels.json");
  f << j.dump(2) << "\n";
  if (!f)
    input_error("could not write '{}'", (dir / "labels.json").string());
  return m;
}

} // namespace tearflow::geometry
