#include "rom/dissection_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "bc/face_geometry.hpp"
#include "core/digest.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/sections.hpp"
#include "io/durable_file.hpp"

namespace tearflow::rom {

using nlohmann::json;

int DissectionGeometry::node(const std::string& name) const {
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].name == name)
      return static_cast<int>(i);
  return -1;
}

namespace {

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}
double norm(const Vec3& v) {
  return std::sqrt(dot(v, v));
}
Vec3 lerp(const Vec3& a, const Vec3& b, double f) {
  return a + f * (b - a);
}

/// A plane across a lumen: where the path crosses it and the point that picks the lumen.
struct Cut {
  Vec3 origin{}, normal{}, point{};
};

struct Piece {
  double area = 0.0;
  Vec3 centroid{};
  bool found = false;
};

/// The piece of the fluid section by `cut` containing its point, else the one whose centroid
/// is nearest the point (within `reach`); `other`, when given, must not be in it.
Piece section_piece(const mesh::Mesh& mesh, int fluid, const Cut& cut, double reach,
                    const Vec3* other = nullptr) {
  const geometry::Section s = geometry::cut_region(mesh, fluid, cut.origin, cut.normal);
  if (s.areas.empty())
    return {};
  int piece = s.piece_containing(cut.point);
  if (piece < 0) {
    double best = reach;
    for (size_t k = 0; k < s.areas.size(); ++k)
      if (norm(s.centroids[k] - cut.point) < best)
        best = norm(s.centroids[k] - cut.point), piece = static_cast<int>(k);
  }
  if (piece < 0)
    return {};
  if (other) {
    const Vec3 q = cut.origin + (*other - cut.origin) -
                   dot(*other - cut.origin, cut.normal) * cut.normal; // onto the plane
    if (s.piece_containing(q) == piece)
      return {};
  }
  return {s.areas[piece], s.centroids[piece], true};
}

/// The part within `reach` of the cut's point of the section's piece containing that point:
/// its area and centroid (per cut tet polygon, by the polygons' centroids).
Piece local_piece(const mesh::Mesh& mesh, int fluid, const Cut& cut, double reach) {
  const geometry::Section s = geometry::cut_region(mesh, fluid, cut.origin, cut.normal);
  const int piece = s.piece_containing(cut.point);
  if (piece < 0)
    return {};
  Piece out;
  for (size_t t = 0; t < s.polygons.size(); ++t) {
    const std::vector<Vec3>& poly = s.polygons[t];
    if (s.piece_of[t] != piece || poly.size() < 3)
      continue;
    Vec3 c{0, 0, 0};
    double a = 0.0;
    for (size_t i = 1; i + 1 < poly.size(); ++i) { // fan triangles
      const double ai =
          0.5 * std::abs(dot(cross(poly[i] - poly[0], poly[i + 1] - poly[0]), cut.normal));
      c = c + (ai / 3.0) * (poly[0] + poly[i] + poly[i + 1]);
      a += ai;
    }
    if (a <= 0.0 || norm((1.0 / a) * c - cut.point) > reach)
      continue;
    out.area += a;
    out.centroid = out.centroid + c;
  }
  if (out.area <= 0.0)
    return {};
  out.centroid = (1.0 / out.area) * out.centroid;
  out.found = true;
  return out;
}

/// Trapezoidal integrals of a segment over its samples (s, A).
void integrate(GeometrySegment& seg, std::vector<std::pair<double, double>> samples) {
  std::sort(samples.begin(), samples.end());
  seg.samples = static_cast<int>(samples.size());
  for (size_t k = 1; k < samples.size(); ++k) {
    const double ds = samples[k].first - samples[k - 1].first;
    const double a0 = samples[k - 1].second, a1 = samples[k].second;
    seg.inverse_area_squared += 0.5 * ds * (1.0 / (a0 * a0) + 1.0 / (a1 * a1));
    seg.inverse_area += 0.5 * ds * (1.0 / a0 + 1.0 / a1);
    auto friction = [](double a) { return 1.0 / (2.0 * std::sqrt(a / M_PI) * a * a); };
    seg.friction_integral += 0.5 * ds * (friction(a0) + friction(a1));
    seg.volume += 0.5 * ds * (a0 + a1);
  }
}

/// A station of a lumen's chain: a landmark (or a tear's node) with its plane.
struct ChainPoint {
  std::string name;
  Cut cut;
  double area = 0.0;
  std::string lumen;
};

ChainPoint station(const mesh::Mesh& mesh, const geometry::Landmarks& lm, const std::string& name) {
  const geometry::Landmark& l = lm.plane(name);
  ChainPoint c{name, {l.origin, unit(l.normal), l.point.value_or(l.origin)}, 0.0, l.lumen};
  c.area = geometry::landmark_area(mesh, l);
  return c;
}

/// Where `p` lies along a chain: the index k with p between planes k and k + 1 and its
/// fraction there; -1 before the first plane, size - 1 after the last.
std::pair<int, double> locate_on_chain(const std::vector<ChainPoint>& chain, const Vec3& p) {
  for (size_t k = 0; k + 1 < chain.size(); ++k) {
    const double da = dot(p - chain[k].cut.origin, chain[k].cut.normal);
    const double db = dot(p - chain[k + 1].cut.origin, chain[k + 1].cut.normal);
    if (k == 0 && da < 0.0)
      return {-1, da};
    if (da >= 0.0 && db < 0.0)
      return {static_cast<int>(k), da / (da - db)};
  }
  return {static_cast<int>(chain.size()) - 1,
          dot(p - chain.back().cut.origin, chain.back().cut.normal)};
}

/// Inserts a tear's node into a chain (on a station within `snap` of it); returns its name.
std::string insert_tear_node(std::vector<ChainPoint>& chain, const geometry::TearLandmark& t,
                             const std::string& lumen, double snap) {
  const auto [k, f] = locate_on_chain(chain, t.centroid);
  ChainPoint node;
  node.name = lumen + "_" + t.name;
  node.lumen = lumen;
  if (k < 0 || k == static_cast<int>(chain.size()) - 1) { // beyond an end: f is the distance
    const ChainPoint& end = k < 0 ? chain.front() : chain.back();
    if (std::abs(f) <= snap)
      return end.name;
    node.cut = {end.cut.origin + f * end.cut.normal, end.cut.normal,
                end.cut.point + f * end.cut.normal};
    node.area = end.area;
    chain.insert(k < 0 ? chain.begin() : chain.end(), node);
    return node.name;
  }
  const ChainPoint &a = chain[k], &b = chain[k + 1];
  const double length = norm(b.cut.point - a.cut.point);
  if (f * length <= snap) // on a station (of either lumen or the undivided aorta)
    return a.name;
  if ((1.0 - f) * length <= snap)
    return b.name;
  node.cut = {lerp(a.cut.origin, b.cut.origin, f), unit(lerp(a.cut.normal, b.cut.normal, f)),
              lerp(a.cut.point, b.cut.point, f)};
  // A tear's own section merges the lumina: its area is its lumen's stations'.
  if (a.lumen == lumen && b.lumen == lumen)
    node.area = (1.0 - f) * a.area + f * b.area;
  else
    node.area = a.lumen == lumen ? a.area : b.area;
  chain.insert(chain.begin() + k + 1, node);
  return node.name;
}

/// A tear's node's area, measured where its lumen is whole: the mean of its sections at the
/// tear's two rims (the planes `margin` beyond its ends along its axis). The stations'
/// interpolation it replaces misses how the lumina change toward a tear: in the parametric
/// model the flap moves from a 57 mm^2 TL at station 5 to a 240 mm^2 one at the exit tear, which
/// the merged flow leaving the tear passes. A rim's section must not hold the other lumen's
/// point `other` (when that node is a lumen's, not the undivided aorta's), else must lie within
/// half and 1.5 times the interpolated area; the node keeps that area where no rim qualifies.
void measure_tear_node(const mesh::Mesh& mesh, int fluid, const geometry::TearLandmark& t,
                       ChainPoint& node, const ChainPoint& other, double margin) {
  const bool separate = other.lumen == "TL" || other.lumen == "FL";
  double sum = 0.0;
  int found = 0;
  for (const double side : {-1.0, 1.0}) {
    const Vec3 shift = (side * (t.axial + margin)) * unit(t.axis);
    const Cut cut{node.cut.origin + shift, node.cut.normal, node.cut.point + shift};
    const Vec3 away = other.cut.point + shift;
    const Piece p = section_piece(mesh, fluid, cut, 0.0, separate ? &away : nullptr);
    if (p.found && (separate || (p.area > 0.5 * node.area && p.area < 1.5 * node.area)))
      sum += p.area, ++found;
  }
  if (found > 0)
    node.area = sum / found;
}

/// The true lumen's area beside a tear (GeometryTear::channel_area): its TL node's rims, the
/// lumen picked by a TL point. When that node is the undivided aorta's (an entry on DAo_prox),
/// its own point may lie in the false lumen, so the point is the neighbouring TL station's,
/// projected onto the node's plane, and that station's area is kept where no rim is found.
double tear_channel(const mesh::Mesh& mesh, int fluid, const geometry::TearLandmark& t,
                    const std::vector<ChainPoint>& tl, const ChainPoint* node,
                    const ChainPoint& fl_node, double margin) {
  if (node->lumen == "TL")
    return node->area;
  ChainPoint channel = *node;
  const auto at = tl.begin() + (node - tl.data());
  const auto next = std::find_if(at, tl.end(), [](const ChainPoint& c) { return c.lumen == "TL"; });
  const auto prev = std::find_if(std::make_reverse_iterator(at), tl.rend(),
                                 [](const ChainPoint& c) { return c.lumen == "TL"; });
  const ChainPoint* station = next != tl.end() ? &*next : prev != tl.rend() ? &*prev : nullptr;
  if (!station)
    return node->area;
  const Vec3 p = station->cut.point;
  channel.cut.point = p - dot(p - node->cut.origin, node->cut.normal) * node->cut.normal;
  channel.area = station->area;
  measure_tear_node(mesh, fluid, t, channel, fl_node, margin);
  return channel.area;
}

/// The segments of a chain, each sampled at its ends and three interior sections.
void chain_segments(const mesh::Mesh& mesh, int fluid, const std::vector<ChainPoint>& chain,
                    const std::vector<ChainPoint>* partner, const std::string& lumen,
                    std::vector<GeometrySegment>& out) {
  for (size_t k = 0; k + 1 < chain.size(); ++k) {
    const ChainPoint &a = chain[k], &b = chain[k + 1];
    GeometrySegment seg{a.name, b.name, lumen};
    seg.length = norm(b.cut.point - a.cut.point);
    std::vector<std::pair<double, double>> samples{{0.0, a.area}, {seg.length, b.area}};
    // The partner lumen's points at the same stations, when both ends are paired stations.
    const ChainPoint *pa = nullptr, *pb = nullptr;
    if (partner)
      for (const ChainPoint& p : *partner) {
        if (norm(p.cut.origin - a.cut.origin) < 1e-9 && p.name != a.name)
          pa = &p;
        if (norm(p.cut.origin - b.cut.origin) < 1e-9 && p.name != b.name)
          pb = &p;
      }
    const double lo = std::min(a.area, b.area), hi = std::max(a.area, b.area);
    for (double f : {0.25, 0.5, 0.75}) {
      const Cut cut{lerp(a.cut.origin, b.cut.origin, f), unit(lerp(a.cut.normal, b.cut.normal, f)),
                    lerp(a.cut.point, b.cut.point, f)};
      Vec3 other{};
      if (pa && pb)
        other = lerp(pa->cut.point, pb->cut.point, f);
      const Piece p =
          section_piece(mesh, fluid, cut, 0.5 * seg.length + 0.01, pa && pb ? &other : nullptr);
      // Without a partner to check, a section far outside its ends' areas crossed into the
      // other lumen or a branch: left out.
      if (p.found && p.area > 0.5 * lo && p.area < 1.5 * hi)
        samples.emplace_back(f * seg.length, p.area);
    }
    integrate(seg, samples);
    out.push_back(seg);
  }
}

struct ArchSample {
  double s = 0.0, area = 0.0;
  Vec3 point{};
};

/// The arch's centreline from AAo to DAo_prox, tracked: a step of a fifth of the lumen's
/// radius along the tangent, the section there normal to the tangent, its piece containing
/// the step's end; the piece's centroid is the next point and the tangent turns halfway
/// toward it. Only the section within 1.3 radii of the step's end counts, so that a section
/// through a branch's ostium or across both limbs of the arch stays centred on the aorta.
/// Stops on reaching DAo_prox's plane near its origin. Sections through an ostium (area above 1.3
/// times the median) keep their place but not their area, which is interpolated.
std::vector<ArchSample> march_arch(const mesh::Mesh& mesh, int fluid, const ChainPoint& aao,
                                   const ChainPoint& prox) {
  const double radius = std::sqrt(std::min(aao.area, prox.area) / M_PI);
  const double step = 0.2 * radius;
  const double chord = norm(prox.cut.origin - aao.cut.origin);
  std::vector<ArchSample> arch{{0.0, aao.area, aao.cut.origin}};
  Vec3 c = aao.cut.origin, t = aao.cut.normal;
  bool reached = false;
  for (int k = 0; k < static_cast<int>(8.0 * chord / step) + 20 && !reached; ++k) {
    const Vec3 guess = c + step * t;
    const Piece p = local_piece(mesh, fluid, {guess, t, guess}, 1.3 * radius);
    if (!p.found)
      break;
    t = unit(t + unit(p.centroid - c));
    const double s = arch.back().s + norm(p.centroid - c);
    c = p.centroid;
    reached = dot(c - prox.cut.origin, prox.cut.normal) >= 0.0 &&
              norm(c - prox.cut.origin) < 2.0 * radius;
    if (!reached)
      arch.push_back({s, p.area, c});
    else
      arch.push_back(
          {arch.back().s + norm(prox.cut.origin - arch.back().point), prox.area, prox.cut.origin});
  }
  if (!reached)
    input_error("the reduced-order model could not follow the aorta from AAo to DAo_prox "
                "through the arch (lost after {:.0f} mm)",
                arch.back().s * 1e3);
  std::vector<double> areas;
  for (const ArchSample& a : arch)
    areas.push_back(a.area);
  std::nth_element(areas.begin(), areas.begin() + areas.size() / 2, areas.end());
  const double median = areas[areas.size() / 2];
  for (size_t k = 1; k + 1 < arch.size(); ++k)
    if (arch[k].area > 1.3 * median)
      arch[k].area = 0.0; // an ostium: interpolated below
  for (size_t k = 1; k + 1 < arch.size(); ++k)
    if (arch[k].area == 0.0) {
      size_t next = k + 1;
      while (arch[next].area == 0.0)
        ++next;
      const double f = (arch[k].s - arch[k - 1].s) / (arch[next].s - arch[k - 1].s);
      arch[k].area = (1.0 - f) * arch[k - 1].area + f * arch[next].area;
    }
  return arch;
}

/// Whether a face bounds the fluid region: its first triangle is a face of a fluid tet.
bool bounds_fluid(const mesh::Face& face, const std::set<std::array<Index, 3>>& fluid_faces) {
  if (face.triangles.empty())
    return false;
  std::array<Index, 3> t = face.triangles.front();
  std::sort(t.begin(), t.end());
  return fluid_faces.count(t) > 0;
}

double region_volume(const mesh::Mesh& mesh, int region) {
  double v = 0.0;
  for (Index t = 0; t < mesh.num_tets(); ++t)
    if (mesh.tet_region[t] == region) {
      const Tet& k = mesh.tets[t];
      v += mesh::signed_volume(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]],
                               mesh.points[k[3]]);
    }
  return v;
}

} // namespace

DissectionGeometry measure_dissection(const mesh::Mesh& mesh, const geometry::Landmarks& lm) {
  const int fluid = geometry::region_index(mesh, "fluid");
  DissectionGeometry g;
  auto add_node = [&](const ChainPoint& c) {
    if (g.node(c.name) < 0)
      g.nodes.push_back({c.name, c.lumen, c.cut.point, c.area, "", c.area});
  };

  // The aorta to DAo_prox: the arch's centreline tracked from AAo (march_arch).
  const ChainPoint inlet = station(mesh, lm, "inlet"), aao = station(mesh, lm, "AAo"),
                   prox = station(mesh, lm, "DAo_prox");
  const std::vector<ArchSample> arch = march_arch(mesh, fluid, aao, prox);

  // Branches: planar faces of the fluid other than inlet and outlet, from the nearest sample.
  std::set<std::array<Index, 3>> fluid_faces;
  for (Index t = 0; t < mesh.num_tets(); ++t)
    if (mesh.tet_region[t] == fluid) {
      const Tet& k = mesh.tets[t];
      for (int skip = 0; skip < 4; ++skip) {
        Tri f = face_opposite(k, skip);
        std::sort(f.begin(), f.end());
        fluid_faces.insert(f);
      }
    }
  struct Branch {
    std::string face;
    size_t sample = 0;
    double area = 0.0, length = 0.0;
    Vec3 centroid{};
  };
  std::vector<Branch> branches;
  for (const mesh::Face& f : mesh.faces) {
    if (f.name == "inlet" || f.name == "outlet" || !bounds_fluid(f, fluid_faces))
      continue;
    const bc::FaceGeometry fg = bc::face_geometry(mesh, f);
    if (fg.max_normal_deviation > 0.05)
      continue; // not a cap
    Branch b{f.name, 0, fg.area, 0.0, fg.centroid};
    double best = 1e30;
    for (size_t k = 0; k < arch.size(); ++k)
      if (norm(arch[k].point - fg.centroid) < best)
        best = norm(arch[k].point - fg.centroid), b.sample = k;
    b.length = std::max(best - std::sqrt(arch[b.sample].area / M_PI), 0.2 * best);
    branches.push_back(b);
  }
  std::sort(branches.begin(), branches.end(),
            [](const Branch& a, const Branch& b) { return a.sample < b.sample; });

  // The aorta's chain: inlet, AAo, a node per branch sample, DAo_prox.
  add_node(inlet);
  add_node(aao);
  {
    GeometrySegment seg{"inlet", "AAo", "aorta"};
    seg.length = norm(aao.cut.origin - inlet.cut.origin);
    integrate(seg, {{0.0, inlet.area}, {seg.length, aao.area}});
    g.segments.push_back(seg);
  }
  size_t last = 0;
  std::string last_name = "AAo";
  auto arch_segment = [&](size_t to, const std::string& name) {
    GeometrySegment seg{last_name, name, "aorta"};
    std::vector<std::pair<double, double>> samples;
    for (size_t k = last; k <= to; ++k)
      samples.emplace_back(arch[k].s - arch[last].s, arch[k].area);
    seg.length = arch[to].s - arch[last].s;
    integrate(seg, samples);
    g.segments.push_back(seg);
    last = to, last_name = name;
  };
  for (const Branch& b : branches) {
    const size_t k = std::clamp<size_t>(b.sample, 1, arch.size() - 2);
    const std::string node = k == last ? last_name : "arch_" + b.face;
    if (k != last) {
      g.nodes.push_back({node, "aorta", arch[k].point, arch[k].area, "", arch[k].area});
      arch_segment(k, node);
    }
    g.nodes.push_back({b.face, "branch", b.centroid, b.area, "", b.area});
    GeometrySegment seg{node, b.face, "branch"};
    seg.length = b.length;
    integrate(seg, {{0.0, b.area}, {b.length, b.area}});
    g.segments.push_back(seg);
  }
  add_node(prox);
  arch_segment(arch.size() - 1, "DAo_prox");

  // The lumina's chains, the tears' nodes inserted.
  std::vector<ChainPoint> tl{prox}, fl;
  for (int k = 1;; ++k) {
    const std::string t = fmt::format("TL{}", k), f = fmt::format("FL{}", k);
    if (std::none_of(lm.planes.begin(), lm.planes.end(),
                     [&](const geometry::Landmark& l) { return l.name == t; }))
      break;
    tl.push_back(station(mesh, lm, t));
    fl.push_back(station(mesh, lm, f));
  }
  if (fl.empty())
    input_error("the model's landmarks have no paired stations TL1/FL1: the reduced-order model "
                "needs them (docs/geometry.md)");
  tl.push_back(station(mesh, lm, "DAo_dist"));
  tl.push_back(station(mesh, lm, "outlet"));
  if (lm.tears.empty())
    input_error("the model's landmarks have no tears: the reduced-order model connects the "
                "lumina through them");
  const double snap = 2e-3;
  for (const geometry::TearLandmark& t : lm.tears) {
    const std::string tn = insert_tear_node(tl, t, "TL", snap);
    const std::string fn = insert_tear_node(fl, t, "FL", snap);
    // A node inserted for the tear (not a station it lies on) is measured at the tear's rims.
    auto point = [](std::vector<ChainPoint>& chain, const std::string& name) {
      return &*std::find_if(chain.begin(), chain.end(),
                            [&](const ChainPoint& c) { return c.name == name; });
    };
    ChainPoint *tp = point(tl, tn), *fp = point(fl, fn); // `other` is read for its point only
    if (tn == "TL_" + t.name)
      measure_tear_node(mesh, fluid, t, *tp, *fp, snap);
    if (fn == "FL_" + t.name)
      measure_tear_node(mesh, fluid, t, *fp, *tp, snap);
    g.tears.push_back({t.name, tn, fn, t.area, tear_channel(mesh, fluid, t, tl, tp, *fp, snap)});
  }
  for (const ChainPoint& c : tl)
    add_node(c);
  for (const ChainPoint& c : fl)
    add_node(c);
  chain_segments(mesh, fluid, tl, &fl, "TL", g.segments);
  chain_segments(mesh, fluid, fl, &tl, "FL", g.segments);
  for (GeometrySegment& s : g.segments) // the chain's ends outside the dissection are aorta
    if (s.lumen == "TL" &&
        (g.nodes[g.node(s.from)].lumen == "aorta" && g.nodes[g.node(s.to)].lumen == "aorta"))
      s.lumen = "aorta";
  // Pair the stations: TLk with FLk, and each tear's two nodes.
  auto pair = [&](const std::string& a, const std::string& b) {
    GeometryNode &na = g.nodes[g.node(a)], &nb = g.nodes[g.node(b)];
    if (na.lumen != "TL" || nb.lumen != "FL")
      return;
    na.partner = b, nb.partner = a;
    na.total_area = nb.total_area = na.area + nb.area;
  };
  for (size_t k = 1; k <= fl.size(); ++k)
    if (g.node(fmt::format("TL{}", k)) >= 0 && g.node(fmt::format("FL{}", k)) >= 0)
      pair(fmt::format("TL{}", k), fmt::format("FL{}", k));
  for (const GeometryTear& t : g.tears)
    pair(t.tl_node, t.fl_node);

  // The wall's thickness from its volume and its two surfaces.
  const auto wall = std::find(mesh.regions.begin(), mesh.regions.end(), "wall");
  if (wall != mesh.regions.end() && mesh.has_face("outer_wall") && mesh.has_face("interface")) {
    const double v = region_volume(mesh, static_cast<int>(wall - mesh.regions.begin()));
    const double a = bc::face_geometry(mesh, mesh.face("outer_wall")).area +
                     bc::face_geometry(mesh, mesh.face("interface")).area;
    g.wall_thickness = 2.0 * v / a;
  }
  return g;
}

/// 4: each tear's channel area (the entry's dividing junction). A file of another version was
/// measured for another network and is measured again.
constexpr int kGeometryVersion = 4;

json to_json(const DissectionGeometry& g) {
  json j{{"format", "tearflow-rom-geometry"},
         {"version", kGeometryVersion},
         {"mesh_digest", g.mesh_digest},
         {"wall_thickness_m", g.wall_thickness}};
  for (const GeometryNode& n : g.nodes)
    j["nodes"].push_back({{"name", n.name},
                          {"lumen", n.lumen},
                          {"position_m", n.position},
                          {"area_m2", n.area},
                          {"partner", n.partner},
                          {"total_area_m2", n.total_area}});
  for (const GeometrySegment& s : g.segments)
    j["segments"].push_back({{"from", s.from},
                             {"to", s.to},
                             {"lumen", s.lumen},
                             {"length_m", s.length},
                             {"int_ds_over_A2_per_m3", s.inverse_area_squared},
                             {"int_ds_over_A_per_m", s.inverse_area},
                             {"int_ds_over_D_A2_per_m4", s.friction_integral},
                             {"volume_m3", s.volume},
                             {"samples", s.samples}});
  for (const GeometryTear& t : g.tears)
    j["tears"].push_back({{"name", t.name},
                          {"TL_node", t.tl_node},
                          {"FL_node", t.fl_node},
                          {"area_m2", t.area},
                          {"channel_area_m2", t.channel_area}});
  return j;
}

DissectionGeometry geometry_from_json(const json& j, const std::string& source) {
  DissectionGeometry g;
  try {
    if (j.at("format") != "tearflow-rom-geometry" || j.at("version") != kGeometryVersion)
      input_error("{}: not a tearflow-rom-geometry file of version {}", source, kGeometryVersion);
    g.mesh_digest = j.at("mesh_digest").get<std::string>();
    g.wall_thickness = j.at("wall_thickness_m").get<double>();
    for (const json& n : j.at("nodes"))
      g.nodes.push_back({n.at("name"), n.at("lumen"), n.at("position_m").get<Vec3>(),
                         n.at("area_m2"), n.at("partner"), n.at("total_area_m2")});
    for (const json& s : j.at("segments"))
      g.segments.push_back({s.at("from"), s.at("to"), s.at("lumen"), s.at("length_m"),
                            s.at("int_ds_over_A2_per_m3"), s.at("int_ds_over_A_per_m"),
                            s.at("int_ds_over_D_A2_per_m4"), s.at("volume_m3"), s.at("samples")});
    for (const json& t : j.at("tears"))
      g.tears.push_back({t.at("name"), t.at("TL_node"), t.at("FL_node"), t.at("area_m2"),
                         t.at("channel_area_m2")});
  } catch (const json::exception& e) {
    input_error("{}: malformed reduced-order geometry ({})", source, e.what());
  }
  for (const GeometrySegment& s : g.segments)
    if (g.node(s.from) < 0 || g.node(s.to) < 0)
      input_error("{}: segment {} -> {} names an unknown node", source, s.from, s.to);
  for (const GeometryTear& t : g.tears)
    if (!(t.channel_area > 0.0)) // NaN too: the entry's junction would be left out silently
      input_error("{}: tear {} has channel_area_m2 {} (expected > 0)", source, t.name,
                  t.channel_area);
  return g;
}

std::string model_digest(const std::filesystem::path& model_dir) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const GeometryFiles files{model_dir};
  for (const auto& file : {files.mesh(), files.landmarks()}) {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      input_error("{}: cannot read (a model directory holds mesh.msh and landmarks.json)",
                  file.string());
    std::ostringstream bytes;
    bytes << in.rdbuf();
    const std::string s = bytes.str();
    h = fnv1a(s.data(), s.size(), h);
  }
  return fmt::format("{:016x}", h);
}

DissectionGeometry model_geometry(const std::filesystem::path& model_dir, bool progress) {
  const std::filesystem::path file = model_dir / "rom" / "geometry.json";
  const std::string digest = model_digest(model_dir);
  if (std::filesystem::exists(file)) {
    std::ifstream in(file);
    json j = json::parse(in, nullptr, false);
    if (!j.is_discarded() && j.value("mesh_digest", "") == digest &&
        j.value("version", 0) == kGeometryVersion)
      return geometry_from_json(j, file.string());
  }
  if (progress)
    fmt::print("reduced-order model: measuring {} (segments, areas, tears)\n", model_dir.string());
  const GeometryFiles files{model_dir};
  const mesh::Mesh mesh = geometry::read_fsi_mesh(files.mesh(), 1e-3);
  DissectionGeometry g = measure_dissection(mesh, geometry::read_landmarks(files.landmarks()));
  g.mesh_digest = digest;
  std::filesystem::create_directories(file.parent_path());
  io::write_file_atomically(file, to_json(g).dump(1) + "\n");
  return g;
}

} // namespace tearflow::rom
