// The TBAD in OpenCASCADE, following what works in Gmsh 4.8 for a dissected aorta
// (../shared/reference/geometry-notes.md): sweep the lumen and the outer wall, shell = outer
// minus lumen; the flap (with the false lumen's end caps) is cut from a box swept along the
// vessel and intersected with a copy of the lumen, so it spans the lumen exactly; the tears
// are elliptic cylinders cut out of it; occ::fragment(shell, lumen, flap) then gives one
// fluid volume whose two lumina meet only through the tears, and conforming interfaces.
//
// The CAD is built in millimetres: OpenCASCADE's tolerances are absolute (1e-7), and
// coordinates of order 0.1 would make them relatively 1000 times coarser than in mm.
#include "geometry/tbad_builder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <system_error>

#include <gmsh.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/lumen_sizing.hpp"
#include "geometry/tbad_model.hpp"
#include "mesh/gmsh_session.hpp"

namespace tearflow::geometry {

namespace {

namespace occ = gmsh::model::occ;
constexpr double kMm = 1e3; // CAD units per metre
constexpr double pi = std::numbers::pi;
// Spacing of the swept sections [m]. The loft interpolates them with a smooth surface; at
// 6 mm it follows the radius profile (which changes by up to 4 mm over 13 mm past the LSA)
// without visible wiggles, and 70-odd sections keep OpenCASCADE's lofting fast.
constexpr double kSectionSpacing = 6e-3;
// The lofts run this far past the inlet and outlet and are cut there: OpenCASCADE's loft
// bulges between its last sections (by 6 % in radius at the outlet), so the ends must lie
// outside the domain. (Three sections' overrun made occ::fragment fail; two work.)
constexpr double kLoftOverrun = 2 * kSectionSpacing;

using DimTags = gmsh::vectorpair;

// The 3x4 affine map taking local (x, y, z) to origin + x ex + y ey + z ez, in mm.
std::vector<double> placement(const Vec3& origin, const Vec3& ex, const Vec3& ey, const Vec3& ez) {
  std::vector<double> a(12);
  for (int r = 0; r < 3; ++r) {
    a[4 * r + 0] = ex[r];
    a[4 * r + 1] = ey[r];
    a[4 * r + 2] = ez[r];
    a[4 * r + 3] = origin[r] * kMm;
  }
  return a;
}

// A circle in the cross-section at `f`. It starts (its seam, and the lofted surface's seam
// line) on the flap's normal, at the true lumen's far wall, where the flap never reaches:
// started across the flap, the seam met the flap's edge wherever the flap crosses the
// centre (beside the exit tear) and Delaunay left wall slivers there (radius ratio 0.006).
int circle_wire(const Frame& f, double radius) {
  const int c = occ::addCircle(0, 0, 0, radius * kMm);
  occ::affineTransform({{1, c}}, placement(f.origin, f.normal, -1.0 * f.across, f.tangent));
  return occ::addWire({c});
}

// A rectangle in the cross-section at `f`: across in [-w, w], along the flap normal in
// [lo, hi] [m].
int rectangle_wire(const Frame& f, double w, double lo, double hi) {
  std::vector<int> pts, lines;
  for (const auto& [x, y] : {std::pair{-w, lo}, {w, lo}, {w, hi}, {-w, hi}}) {
    const Vec3 p = kMm * (f.origin + x * f.across + y * f.normal);
    pts.push_back(occ::addPoint(p[0], p[1], p[2]));
  }
  for (int i = 0; i < 4; ++i)
    lines.push_back(occ::addLine(pts[i], pts[(i + 1) % 4]));
  return occ::addWire(lines);
}

int single_volume(const DimTags& out, const char* what) {
  int tag = -1, count = 0;
  for (const auto& [dim, t] : out)
    if (dim == 3)
      tag = t, ++count;
  if (count != 1)
    input_error("tbad: OpenCASCADE made {} volumes for the {}, expected one", count, what);
  return tag;
}

// A smooth solid through the section wires. (Capping the surface degree with maxDegree = 3
// to damp the loft's end bulge made the later booleans fail; the overrun above is the cure.)
int loft(const std::vector<int>& wires, const char* what) {
  DimTags out;
  occ::addThruSections(wires, out, -1, true, false);
  return single_volume(out, what);
}

std::vector<double> section_positions(double s0, double s1) {
  const int n = std::max(2, static_cast<int>(std::ceil((s1 - s0) / kSectionSpacing)) + 1);
  std::vector<double> s;
  for (int i = 0; i < n; ++i)
    s.push_back(s0 + (s1 - s0) * i / (n - 1));
  return s;
}

// A box just beyond the cross-section at `f` (along its tangent), wide enough for the
// vessel of radius `r` and deep enough for the loft's overrun, and no more: the inlet's
// box must not reach the descending aorta. Cuts the lofted vessel's end off at a cap.
int end_cutter(const Frame& f, double r) {
  const double w = 2 * (r + 3e-3) * kMm, depth = 2 * kLoftOverrun * kMm;
  const int box = occ::addBox(-w / 2, -w / 2, 0, w, w, depth);
  occ::affineTransform({{3, box}}, placement(f.origin, f.across, f.normal, f.tangent));
  return box;
}

// Lumen (offset 0) or outer wall (offset h): the swept aorta, cut at the caps, fused with
// the branch tubes.
int vessel(const TbadModel& m, double offset, const char* what) {
  auto lofted = [&](double s0, double s1) {
    std::vector<int> wires;
    for (double s : section_positions(s0, s1))
      wires.push_back(circle_wire(m.frame(s), m.radius(s) + offset));
    return loft(wires, what);
  };
  DimTags out;
  std::vector<DimTags> map;
  // Two lofts joined on the straight centreline above the exit tear: one loft through all
  // the sections (the domain lengthened by the flap's distal taper) came out with parts of
  // the lumen left in the wall or in pieces after the booleans.
  const double split = m.paired_station(5) - kSectionSpacing;
  occ::fuse({{3, lofted(-kLoftOverrun, split)}}, {{3, lofted(split, m.length() + kLoftOverrun)}},
            out, map);
  const int aorta = single_volume(out, what);
  Frame in = m.frame(0);
  in.tangent = -1.0 * in.tangent;
  in.across = -1.0 * in.across; // keep the frame right-handed
  occ::cut({{3, aorta}},
           {{3, end_cutter(in, m.radius(0) + offset)},
            {3, end_cutter(m.frame(m.length()), m.radius(m.length()) + offset)}},
           out, map);
  const int trimmed = single_volume(out, what);
  DimTags tubes;
  for (const BranchGeometry& b : m.branches()) {
    const Vec3 p = kMm * b.base, d = (b.length * kMm) * b.direction;
    tubes.push_back(
        {3, occ::addCylinder(p[0], p[1], p[2], d[0], d[1], d[2], (b.radius + offset) * kMm)});
  }
  occ::fuse({{3, trimmed}}, tubes, out, map);
  return single_volume(out, what);
}

// A box along the flap over [s0, s1]: its sections span the lumen across (radius + `wide`)
// and reach along the flap's normal from beyond the wall on the FL's side to the flap's TL
// face (side +1) or FL face (side -1). The flap's faces sit flap_half_thickness from its
// mid-surface along the section's normal, so the flap is h thick where it slopes.
// Two lofts, fused: every kSectionSpacing to `dense`, and from there (on the straight
// centreline above the exit tear) every kTaperSpacing, where the flap crosses the vessel
// within 12-25 mm (TL5 to the exit tear, and the distal taper); a loft through 6 mm
// sections would cut those curves short, and one loft through both spacings (or dense
// sections over the arch) overshoots and came out inverted or in pieces.
constexpr double kTaperSpacing = 1.5e-3;
constexpr double kBoxMargin = 4e-3; // the boxes' reach beyond the lumen [m]

int flap_box(const TbadModel& m, double s0, double s1, double dense, double wide, int side,
             const char* what) {
  auto wires = [&](double a, double b, double spacing) {
    const int n = std::max(2, static_cast<int>(std::ceil((b - a) / spacing)) + 1);
    std::vector<int> w;
    for (int i = 0; i < n; ++i) {
      const double s = a + (b - a) * i / (n - 1);
      const double r = m.radius(s) + wide,
                   face = m.flap_offset(s) + side * m.flap_half_thickness(s);
      w.push_back(rectangle_wire(m.frame(s), r, -m.radius(s) - wide - kBoxMargin, face));
    }
    return w;
  };
  if (!(dense > s0 + kSectionSpacing && dense < s1))
    return loft(wires(s0, s1, kSectionSpacing), what);
  const int proximal = loft(wires(s0, dense, kSectionSpacing), what);
  const int distal = loft(wires(dense, s1, kTaperSpacing), what);
  DimTags out;
  std::vector<DimTags> map;
  occ::fuse({{3, proximal}}, {{3, distal}}, out, map);
  return single_volume(out, what);
}

// The flap with the false lumen's end caps: a box over [s0 - h, s1 + h] reaching from the
// flap's TL face through the FL and beyond the wall, minus a box over [s0, s1] reaching from
// the flap's FL face; then intersected with the lumen.
int flap_with_caps(const TbadModel& m, int lumen) {
  const double h = m.spec().wall_thickness;
  const double dense = m.paired_station(5) - kSectionSpacing;
  const int outer_box =
      flap_box(m, m.flap_start() - h, m.flap_end() + h, dense, kBoxMargin, +1, "flap box");
  const int inner_box =
      flap_box(m, m.flap_start(), m.flap_end(), dense, 2 * kBoxMargin, -1, "false lumen box");
  DimTags out, lumen_copy;
  std::vector<DimTags> map;
  occ::cut({{3, outer_box}}, {{3, inner_box}}, out, map);
  const int slab = single_volume(out, "flap slab");
  occ::copy({{3, lumen}}, lumen_copy);
  occ::intersect({{3, slab}}, lumen_copy, out, map);
  return single_volume(out, "flap");
}

// An elliptic cylinder through the flap around the tear, three flap thicknesses long.
int tear_cutter(const TearGeometry& t, double h) {
  const double len = 3 * h * kMm;
  const int disk = occ::addDisk(0, 0, -0.5 * len, t.axial * kMm, t.across * kMm);
  DimTags out;
  occ::extrude({{2, disk}}, 0, 0, len, out);
  const int vol = single_volume(out, "tear");
  occ::affineTransform({{3, vol}}, placement(t.centre, t.axis, cross(t.normal, t.axis), t.normal));
  return vol;
}

struct Cap {
  std::string name;
  Vec3 centre, axis; // [m]
  double radius = 0; // lumen radius [m]
};

std::vector<Cap> caps(const TbadModel& m) {
  const Frame in = m.frame(0), out = m.frame(m.length());
  std::vector<Cap> c{{"inlet", in.origin, in.tangent, m.radius(0)}};
  for (const BranchGeometry& b : m.branches())
    c.push_back({b.name, b.cap_centre(), b.direction, b.radius});
  c.push_back({"outlet", out.origin, out.tangent, m.radius(m.length())});
  return c;
}

// Names the volumes and the boundary surfaces by their adjacent volumes: fluid and wall on
// either side is the interface; fluid only is a cap; wall only is a cap's ring when it lies
// in a cap's plane, else the outer wall.
void add_physical_groups(const TbadModel& m, const std::vector<int>& fluid,
                         const std::vector<int>& wall) {
  auto in = [](const std::vector<int>& v, int t) {
    return std::find(v.begin(), v.end(), t) != v.end();
  };
  const std::vector<Cap> cap_list = caps(m);
  const double h = m.spec().wall_thickness;
  std::map<std::string, std::vector<int>> groups;
  DimTags surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    std::vector<int> up, down;
    gmsh::model::getAdjacencies(2, tag, up, down);
    bool f = false, w = false;
    for (int v : up)
      (in(fluid, v) ? f : w) = true;
    if (f && w) {
      groups["interface"].push_back(tag);
      continue;
    }
    if (up.size() == 2)
      continue; // between the shell and the flap: inside the wall
    double x, y, z;
    occ::getCenterOfMass(2, tag, x, y, z);
    const Vec3 c = (1.0 / kMm) * Vec3{x, y, z};
    const Cap* on = nullptr;
    for (const Cap& cap : cap_list) {
      const Vec3 d = c - cap.centre;
      // On the cap's plane to 1 um (the end cuts are B-spline surfaces after the affine
      // placement, so the surface type cannot tell).
      if (std::abs(dot(d, cap.axis)) < 1e-6 && std::sqrt(dot(d, d)) < cap.radius + h)
        on = &cap;
    }
    if (f && !on) {
      input_error("tbad: a fluid boundary surface (tag {}) at ({:.1f}, {:.1f}, {:.1f}) mm is on "
                  "no cap",
                  tag, x, y, z);
    }
    if (f)
      groups[on->name].push_back(tag);
    else
      groups[on ? "wall_" + on->name : "outer_wall"].push_back(tag);
  }
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, fluid), "fluid");
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, wall), "wall");
  for (const Cap& cap : cap_list)
    for (const std::string& name : {cap.name, "wall_" + cap.name})
      if (groups[name].empty())
        input_error("tbad: no surface found for face '{}'", name);
  for (const auto& [name, tags] : groups)
    gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, tags), name);
}

// Element sizes: uniform, finer near each tear. At the hole's rim the size is at most
// perimeter / 24 (the inscribed polygon then holds 98.9 % of the ellipse's area) and half
// a wall thickness: with one element across the hole's 2 mm wall, Delaunay left flat tets
// whose four nodes all lie on it (radius ratio 0.02 to 0.03). The size grows back to the
// target size over one semi-axis. Curvature sizing gives small branches about 12 edges
// around. In the dissected segment LumenSizing, a size callback (Gmsh takes the smallest of
// callback, fields and curvature), puts `lumen_elements` elements across the true lumen.
void set_mesh_sizes(const TbadModel& m) {
  const TbadSpec& s = m.spec();
  std::vector<double> fields;
  DimTags surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const TearGeometry& t : m.tears()) {
    // Ramanujan's approximation of the ellipse perimeter.
    const double a = t.axial, b = t.across;
    const double perimeter = pi * (3 * (a + b) - std::sqrt((3 * a + b) * (a + 3 * b)));
    const double size = s.tear_element_size > 0
                            ? s.tear_element_size
                            : std::min({s.element_size, perimeter / 24, 0.5 * s.wall_thickness});
    // The hole's wall: the surfaces whose centre of mass is the tear's centre.
    std::vector<double> wall;
    for (const auto& [dim, tag] : surfaces) {
      double x, y, z;
      occ::getCenterOfMass(2, tag, x, y, z);
      const Vec3 d = (1.0 / kMm) * Vec3{x, y, z} - t.centre;
      if (std::sqrt(dot(d, d)) < 0.1 * b)
        wall.push_back(tag);
    }
    if (wall.empty())
      input_error("tbad: the {} tear's hole is missing from the model", t.name);
    const int distance = gmsh::model::mesh::field::add("Distance");
    gmsh::model::mesh::field::setNumbers(distance, "SurfacesList", wall);
    const int threshold = gmsh::model::mesh::field::add("Threshold");
    gmsh::model::mesh::field::setNumber(threshold, "InField", distance);
    gmsh::model::mesh::field::setNumber(threshold, "SizeMin", size * kMm);
    gmsh::model::mesh::field::setNumber(threshold, "SizeMax", s.element_size * kMm);
    gmsh::model::mesh::field::setNumber(threshold, "DistMin", 0.5 * s.wall_thickness * kMm);
    gmsh::model::mesh::field::setNumber(threshold, "DistMax", a * kMm);
    fields.push_back(threshold);
  }
  const int min = gmsh::model::mesh::field::add("Min");
  gmsh::model::mesh::field::setNumbers(min, "FieldsList", fields);
  gmsh::model::mesh::field::setAsBackgroundMesh(min);
  auto lumen = std::make_shared<const LumenSizing>(m);
  if (lumen->enabled())
    gmsh::model::mesh::setSizeCallback([lumen](int, int, double x, double y, double z) {
      return lumen->size((1.0 / kMm) * Vec3{x, y, z}) * kMm;
    });
  gmsh::option::setNumber("Mesh.MeshSizeMax", s.element_size * kMm);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 12);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  // As for the pipe (mesh/pipe_generator.cpp): Frontal-Delaunay surfaces and the
  // deterministic Delaunay volume mesher, since every MPI rank may rebuild the same mesh.
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.Algorithm3D", 1);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

TbadBuild build_tbad(const TbadSpec& spec, const std::filesystem::path& dir, bool verbose) {
  const TbadModel model(spec);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    input_error("tbad: cannot create output directory '{}': {}", dir.string(), ec.message());
  const std::filesystem::path msh = GeometryFiles{dir}.mesh();
  const std::string source =
      fmt::format("parametric TBAD (element size {} mm)", spec.element_size * kMm);
  TbadBuild build;
  {
    mesh::GmshSession session(verbose);
    build.mesh = mesh::with_gmsh(source, [&] {
      const auto t0 = std::chrono::steady_clock::now();
      gmsh::clear();
      gmsh::model::add("tbad");
      const int lumen = vessel(model, 0.0, "lumen");
      const int outer = vessel(model, spec.wall_thickness, "outer wall");
      DimTags out, lumen_copy;
      std::vector<DimTags> map;
      occ::copy({{3, lumen}}, lumen_copy);
      occ::cut({{3, outer}}, lumen_copy, out, map);
      const int shell = single_volume(out, "wall shell");
      int flap = flap_with_caps(model, lumen);
      DimTags cutters;
      for (const TearGeometry& t : model.tears())
        cutters.push_back({3, tear_cutter(t, spec.wall_thickness)});
      occ::cut({{3, flap}}, cutters, out, map);
      flap = single_volume(out, "flap with tears");
      occ::fragment({{3, shell}, {3, lumen}, {3, flap}}, {}, out, map);
      occ::synchronize();
      // map[i]: the pieces of input i. Pieces of the lumen that are not flap are fluid.
      std::vector<int> wall, fluid;
      for (int i : {0, 2})
        for (const auto& [d, t] : map[i])
          wall.push_back(t);
      for (const auto& [d, t] : map[1])
        if (std::find(wall.begin(), wall.end(), t) == wall.end())
          fluid.push_back(t);
      if (fluid.size() != 1) {
        std::string pieces;
        for (int v : fluid) {
          double mass = 0, x = 0, y = 0, z = 0;
          occ::getMass(3, v, mass);
          occ::getCenterOfMass(3, v, x, y, z);
          pieces += fmt::format(" {:.0f} mm^3 at ({:.0f}, {:.0f}, {:.0f});", mass, x, y, z);
        }
        input_error("tbad: the fluid came out as {} volumes, expected one (the two lumina "
                    "joined by the tears):{}",
                    fluid.size(), pieces);
      }
      add_physical_groups(model, fluid, wall);
      build.cad_seconds = seconds_since(t0);
      const auto t1 = std::chrono::steady_clock::now();
      set_mesh_sizes(model);
      gmsh::model::mesh::generate(3);
      gmsh::model::mesh::removeSizeCallback();
      build.mesh_seconds = seconds_since(t1);
      std::filesystem::remove(msh, ec);
      gmsh::write(msh.string());
      if (!std::filesystem::is_regular_file(msh, ec))
        input_error("{}: could not write '{}'", source, msh.string());
      return mesh::mesh_from_gmsh_model(1.0 / kMm, source);
    });
  }
  mesh::drop_unused_nodes(build.mesh);
  check_fsi_mesh(build.mesh);
  build.landmarks = tbad_landmarks(model);
  write_landmarks(build.landmarks, GeometryFiles{dir}.landmarks(), "mm");
  return build;
}

} // namespace tearflow::geometry
