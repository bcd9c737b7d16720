// Straight pipe: an OpenCASCADE cylinder meshed by Gmsh, read back from memory.
#include "mesh/pipe_generator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <system_error>

#include <gmsh.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"

namespace tearflow::mesh {

namespace {

// Tets per element_size^3 of volume. A packing of regular tets of edge h would give
// 6 sqrt(2) = 8.5, but Gmsh's tets come out larger than edge h on average: its Delaunay
// mesher gives 4.5 to 4.9 on our pipes. 5 errs on the high side.
constexpr double kTetsPerSizeCubed = 5.0;
constexpr double kMaxTets = 20e6;

void check_spec(const PipeSpec& s) {
  auto bad = [](double x) { return !(x > 0) || !std::isfinite(x); };
  if (bad(s.radius) || bad(s.length) || bad(s.element_size))
    input_error("pipe: radius ({} m), length ({} m) and element_size ({} m) must be positive",
                s.radius, s.length, s.element_size);
  if (s.wall_thickness < 0.0 || !std::isfinite(s.wall_thickness))
    input_error("pipe: wall_thickness must be >= 0 m, got {} m", s.wall_thickness);
  // An element above the diameter is not one across the lumen (the probe's case meshed and
  // ran without a word); above the radius, about two across: too few for any flow.
  if (s.element_size > 2.0 * s.radius)
    input_error("pipe: element_size {} m exceeds the diameter {} m, not one element across the "
                "lumen; use at most the radius, a quarter of it or less to resolve the flow",
                s.element_size, 2.0 * s.radius);
  if (s.element_size > s.radius)
    spdlog::warn("pipe: element_size {} m exceeds the radius {} m: about two elements across the "
                 "lumen, too few to resolve its flow",
                 s.element_size, s.radius);
  const double outer = s.radius + s.wall_thickness;
  const double volume = std::numbers::pi * outer * outer * s.length;
  const double estimate = kTetsPerSizeCubed * volume / std::pow(s.element_size, 3);
  if (!(estimate <= kMaxTets))
    input_error("pipe: element_size {} m for radius {} m and length {} m would give about {:.3g} "
                "tetrahedra, more than the {:.0f} M allowed; use a larger element_size",
                s.element_size, s.radius, s.length, estimate, kMaxTets / 1e6);
}

void set_mesh_options(const PipeSpec& s);

// Surfaces of the volume `tag`.
std::vector<int> boundary_surfaces(int tag) {
  gmsh::vectorpair out;
  gmsh::model::getBoundary({{3, tag}}, out, false, false, false);
  std::vector<int> tags;
  for (const auto& [dim, t] : out)
    tags.push_back(std::abs(t));
  return tags;
}

// The lumen and its wall: two cylinders fragmented into the lumen and the annulus, which
// then share the interface surface (and its mesh nodes).
void define_pipe_with_wall(const PipeSpec& s) {
  const int outer =
      gmsh::model::occ::addCylinder(0, 0, 0, 0, 0, s.length, s.radius + s.wall_thickness);
  const int inner = gmsh::model::occ::addCylinder(0, 0, 0, 0, 0, s.length, s.radius);
  gmsh::vectorpair pieces;
  std::vector<gmsh::vectorpair> map;
  gmsh::model::occ::fragment({{3, outer}}, {{3, inner}}, pieces, map);
  gmsh::model::occ::synchronize();
  // The lumen has three surfaces (two disks and its side), the annulus four.
  int lumen = -1, annulus = -1;
  for (const auto& [dim, tag] : pieces)
    (boundary_surfaces(tag).size() == 3 ? lumen : annulus) = tag;
  if (lumen < 0 || annulus < 0)
    input_error("pipe: unexpected OpenCASCADE fragments for the pipe with a wall");
  const std::vector<int> lumen_faces = boundary_surfaces(lumen);
  std::map<std::string, std::vector<int>> faces;
  for (int tag : boundary_surfaces(annulus)) {
    double x, y, z;
    gmsh::model::occ::getCenterOfMass(2, tag, x, y, z);
    const bool shared = std::find(lumen_faces.begin(), lumen_faces.end(), tag) != lumen_faces.end();
    faces[z < 0.25 * s.length   ? "wall_inlet"
          : z > 0.75 * s.length ? "wall_outlet"
          : shared              ? "interface"
                                : "outer_wall"]
        .push_back(tag);
  }
  for (int tag : lumen_faces) {
    double x, y, z;
    gmsh::model::occ::getCenterOfMass(2, tag, x, y, z);
    if (z < 0.25 * s.length)
      faces["inlet"].push_back(tag);
    else if (z > 0.75 * s.length)
      faces["outlet"].push_back(tag);
  }
  for (const char* name :
       {"inlet", "outlet", "interface", "wall_inlet", "wall_outlet", "outer_wall"})
    if (faces[name].size() != 1)
      input_error("pipe: unexpected OpenCASCADE fragments ({} surfaces for '{}')",
                  faces[name].size(), name);
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {lumen}), "fluid");
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {annulus}), "wall");
  for (const auto& [name, tags] : faces)
    gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, tags), name);
}

// The pipe with boundary layers (PipeSpec::layers), in the built-in kernel: the cross-section
// at z = 0 as an unstructured core disk of radius r_c, a ring [r_c, a] of structured layers
// thinning towards the wall, and (with a wall) a structured annulus [a, b]; four quarter
// patches each, so that the ring and the annulus are transfinite. Extruding the section along
// z in layers of element_size extrudes its mesh too, so lumen and wall share the interface
// nodes as in the uniform pipe.
void define_layered_pipe(const PipeSpec& s) {
  namespace geo = gmsh::model::geo;
  const BoundaryLayers& bl = s.layers;
  const double a = s.radius, b = a + s.wall_thickness;
  const double ring = bl.thickness();
  const double rc = a - ring;
  if (!(bl.first > 0.0) || !(bl.growth >= 1.0 + 1e-9) || bl.wall_layers < 1 || !(rc > 0.3 * a))
    input_error("pipe: boundary layers need first > 0 m, growth > 1, wall_layers >= 1 and a ring "
                "({} layers from {} m at growth {}: {} m) thinner than 0.7 of the radius {} m",
                bl.count, bl.first, bl.growth, ring, a);
  const bool wall = s.wall_thickness > 0.0;
  const int quarter =
      std::max(2, static_cast<int>(std::ceil(0.5 * std::numbers::pi * a / s.element_size)));
  const int centre = geo::addPoint(0, 0, 0);
  std::vector<double> radii{rc, a};
  if (wall)
    radii.push_back(b);
  // points[r][q]: radius r, angle q pi / 2; arcs[r][q] from q to q + 1; spokes[r][q] from
  // radius r to r + 1 at angle q.
  std::vector<std::array<int, 4>> points(radii.size()), arcs(radii.size()), spokes;
  for (size_t r = 0; r < radii.size(); ++r)
    for (int q = 0; q < 4; ++q)
      points[r][q] = geo::addPoint(radii[r] * std::cos(0.5 * std::numbers::pi * q),
                                   radii[r] * std::sin(0.5 * std::numbers::pi * q), 0);
  for (size_t r = 0; r < radii.size(); ++r)
    for (int q = 0; q < 4; ++q) {
      arcs[r][q] = geo::addCircleArc(points[r][q], centre, points[r][(q + 1) % 4]);
      geo::mesh::setTransfiniteCurve(arcs[r][q], quarter + 1);
    }
  for (size_t r = 0; r + 1 < radii.size(); ++r) {
    auto& spoke = spokes.emplace_back();
    for (int q = 0; q < 4; ++q) {
      spoke[q] = geo::addLine(points[r][q], points[r + 1][q]);
      // The ring's layers thin outwards by 1 / growth; the wall's are uniform.
      if (r == 0)
        geo::mesh::setTransfiniteCurve(spoke[q], bl.count + 1, "Progression", 1.0 / bl.growth);
      else
        geo::mesh::setTransfiniteCurve(spoke[q], bl.wall_layers + 1);
    }
  }
  // Sections and, per lateral curve, the face its extrusion belongs to ("" = inside).
  struct Section {
    int surface;
    bool lumen;
    std::vector<std::string> lateral;
  };
  std::vector<Section> sections;
  const int core_loop = geo::addCurveLoop({arcs[0][0], arcs[0][1], arcs[0][2], arcs[0][3]});
  sections.push_back({geo::addPlaneSurface({core_loop}), true, {"", "", "", ""}});
  for (size_t r = 0; r + 1 < radii.size(); ++r)
    for (int q = 0; q < 4; ++q) {
      const int loop =
          geo::addCurveLoop({spokes[r][q], arcs[r + 1][q], -spokes[r][(q + 1) % 4], -arcs[r][q]});
      const int patch = geo::addPlaneSurface({loop});
      geo::mesh::setTransfiniteSurface(patch, "AlternateLeft");
      const std::string outer = r == 0 ? (wall ? "interface" : "wall") : "outer_wall";
      sections.push_back({patch, r == 0, {"", outer, "", r == 0 ? "" : "interface"}});
    }
  gmsh::vectorpair sources, out;
  for (const Section& sec : sections)
    sources.push_back({2, sec.surface});
  const int layers_z = std::max(1, static_cast<int>(std::lround(s.length / s.element_size)));
  geo::extrude(sources, 0, 0, s.length, out, {layers_z}, {}, false);
  geo::synchronize();

  // extrude's output per source surface: its top, its volume, then one surface per curve of
  // its boundary loop, in the loop's order.
  std::map<std::string, std::vector<int>> faces;
  std::vector<int> lumen, annulus;
  size_t at = 0;
  for (const Section& sec : sections) {
    if (at + 2 + sec.lateral.size() > out.size() || out[at].first != 2 || out[at + 1].first != 3)
      input_error("pipe: unexpected output of the built-in kernel's extrusion");
    faces[sec.lumen ? "inlet" : "wall_inlet"].push_back(sec.surface);
    faces[sec.lumen ? "outlet" : "wall_outlet"].push_back(out[at].second);
    (sec.lumen ? lumen : annulus).push_back(out[at + 1].second);
    for (size_t j = 0; j < sec.lateral.size(); ++j)
      if (!sec.lateral[j].empty())
        faces[sec.lateral[j]].push_back(out[at + 2 + j].second);
    at += 2 + sec.lateral.size();
  }
  for (auto& [name, tags] : faces) { // the ring and the annulus share the interface's surfaces
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
  }
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, lumen), "fluid");
  if (wall)
    gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, annulus), "wall");
  for (const auto& [name, tags] : faces)
    gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, tags), name);
}

// The lumen alone: one OpenCASCADE cylinder.
void define_pipe(const PipeSpec& s) {
  const int volume = gmsh::model::occ::addCylinder(0, 0, 0, 0, 0, s.length, s.radius);
  gmsh::model::occ::synchronize();

  // The cylinder's surfaces: the two disks and the lateral wall, told apart by the z of
  // their centre of mass (0, length, length / 2). OpenCASCADE bounding boxes are padded by
  // its tolerance, so they are not reliable for this.
  std::vector<int> inlet, outlet, wall;
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    double x, y, z;
    gmsh::model::occ::getCenterOfMass(dim, tag, x, y, z);
    if (z < 0.25 * s.length)
      inlet.push_back(tag);
    else if (z > 0.75 * s.length)
      outlet.push_back(tag);
    else
      wall.push_back(tag);
  }
  if (inlet.size() != 1 || outlet.size() != 1 || wall.empty())
    input_error("pipe: unexpected OpenCASCADE cylinder ({} inlet, {} outlet, {} wall surfaces)",
                inlet.size(), outlet.size(), wall.size());
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {volume}), "fluid");
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, inlet), "inlet");
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, outlet), "outlet");
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, wall), "wall");
}

// Builds and meshes the pipe in the current Gmsh model.
void mesh_pipe_model(const PipeSpec& s) {
  gmsh::clear();
  gmsh::model::add("pipe");
  if (s.layers.count > 0)
    define_layered_pipe(s);
  else if (s.wall_thickness > 0.0)
    define_pipe_with_wall(s);
  else
    define_pipe(s);
  set_mesh_options(s);
  gmsh::model::mesh::generate(3);
}

void set_mesh_options(const PipeSpec& s) {
  // Uniform size: min = max = element_size, none from geometry points or curvature.
  // MeshSizeExtendFromBoundary stays at its default 1: at 0 the Delaunay 3D mesher takes 8x
  // longer for the same mesh (115 s instead of 14.5 s for 415 k tets).
  gmsh::option::setNumber("Mesh.MeshSizeMin", s.element_size);
  gmsh::option::setNumber("Mesh.MeshSizeMax", s.element_size);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  // Frontal-Delaunay surfaces (regular triangles; plain Delaunay 2D left slivers of
  // V / l^3 = 6e-4) and Delaunay volumes. HXT (Algorithm3D = 10) meshes 5-10x faster, but in
  // Gmsh 4.8 its result depends on the process's heap layout: the same call gives different
  // meshes after different earlier allocations. Every MPI rank builds the pipe itself and
  // must get the same mesh, so we take the deterministic Delaunay mesher.
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.Algorithm3D", 1);
}

} // namespace

Mesh make_pipe(const PipeSpec& spec) {
  return make_pipe(spec, {});
}

Mesh make_pipe(const PipeSpec& spec, const std::filesystem::path& msh_file) {
  check_spec(spec);
  const std::string source =
      fmt::format("pipe (radius {} m, length {} m, element size {} m{})", spec.radius, spec.length,
                  spec.element_size,
                  spec.wall_thickness > 0.0 ? fmt::format(", wall {} m", spec.wall_thickness) : "");
  Mesh mesh;
  {
    GmshSession session;
    mesh = with_gmsh(source, [&] {
      mesh_pipe_model(spec);
      if (!msh_file.empty()) {
        std::error_code ec;
        std::filesystem::remove(msh_file, ec);
        gmsh::write(msh_file.string());
        if (!std::filesystem::is_regular_file(msh_file, ec))
          input_error("{}: could not write '{}'", source, msh_file.string());
      }
      return mesh_from_gmsh_model(1.0, source);
    });
  }
  drop_unused_nodes(mesh); // Gmsh keeps nodes of geometry points even if no tet uses them
  check_mesh(mesh);
  return mesh;
}

} // namespace tearflow::mesh
