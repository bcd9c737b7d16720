// Three-outlet junction: OpenCASCADE cylinders fused with a sphere, meshed by Gmsh.
#include "mesh/junction_generator.hpp"

#include <array>
#include <cmath>
#include <numbers>

#include <gmsh.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"

namespace tearflow::mesh {

namespace {

void check_spec(const JunctionSpec& s) {
  for (double x : {s.trunk_radius, s.trunk_length, s.straight_radius, s.straight_length,
                   s.side_radius, s.side_length, s.element_size})
    if (!(x > 0.0) || !std::isfinite(x))
      input_error("junction: every dimension must be positive");
  if (s.straight_radius > s.trunk_radius || s.side_radius > s.trunk_radius)
    input_error("junction: branches ({} m, {} m) must not be wider than the trunk ({} m)",
                s.straight_radius, s.side_radius, s.trunk_radius);
  if (!(s.side_angle_deg > 20.0 && s.side_angle_deg < 90.0))
    input_error("junction: side_angle_deg {} must be in (20, 90)", s.side_angle_deg);
}

void mesh_junction_model(const JunctionSpec& s) {
  namespace occ = gmsh::model::occ;
  gmsh::clear();
  gmsh::model::add("junction");
  const double zj = s.trunk_length, a = s.side_angle_deg * std::numbers::pi / 180.0;
  // Branch end points: where the outlet caps are.
  const std::array<std::array<double, 3>, 4> caps = {{
      {0.0, 0.0, 0.0},
      {0.0, 0.0, zj + s.straight_length},
      {s.side_length * std::sin(a), 0.0, zj + s.side_length * std::cos(a)},
      {-s.side_length * std::sin(a), 0.0, zj + s.side_length * std::cos(a)},
  }};
  const int trunk = occ::addCylinder(0, 0, 0, 0, 0, zj, s.trunk_radius);
  const int straight = occ::addCylinder(0, 0, zj, 0, 0, s.straight_length, s.straight_radius);
  const int side_p = occ::addCylinder(0, 0, zj, caps[2][0], 0, caps[2][2] - zj, s.side_radius);
  const int side_m = occ::addCylinder(0, 0, zj, caps[3][0], 0, caps[3][2] - zj, s.side_radius);
  const int ball = occ::addSphere(0, 0, zj, s.trunk_radius);
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::fuse({{3, trunk}}, {{3, straight}, {3, side_p}, {3, side_m}, {3, ball}}, out, map);
  occ::synchronize();
  if (out.size() != 1)
    input_error("junction: the fused geometry has {} volumes, expected 1", out.size());

  // Caps are the planar surfaces whose centre of mass is a branch end; the rest is wall.
  std::array<std::vector<int>, 4> cap_tags;
  std::vector<int> wall;
  gmsh::vectorpair surfaces;
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    double x, y, z;
    occ::getCenterOfMass(dim, tag, x, y, z);
    bool is_cap = false;
    for (size_t i = 0; i < caps.size(); ++i)
      if (std::hypot(x - caps[i][0], y - caps[i][1], z - caps[i][2]) < 0.25 * s.side_radius) {
        cap_tags[i].push_back(tag);
        is_cap = true;
      }
    if (!is_cap)
      wall.push_back(tag);
  }
  const std::array<const char*, 4> names = {"inlet", "outlet_1", "outlet_2", "outlet_3"};
  for (size_t i = 0; i < caps.size(); ++i) {
    if (cap_tags[i].size() != 1)
      input_error("junction: found {} surfaces for {}, expected 1", cap_tags[i].size(), names[i]);
    gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, cap_tags[i]), names[i]);
  }
  gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, wall), "wall");
  gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {out[0].second}), "fluid");

  // As the pipe generator: uniform size, Frontal-Delaunay surfaces, deterministic Delaunay
  // volumes (every rank builds the same mesh).
  gmsh::option::setNumber("Mesh.MeshSizeMin", s.element_size);
  gmsh::option::setNumber("Mesh.MeshSizeMax", s.element_size);
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  gmsh::option::setNumber("Mesh.Algorithm", 6);
  gmsh::option::setNumber("Mesh.Algorithm3D", 1);
  gmsh::model::mesh::generate(3);
}

} // namespace

Mesh make_junction(const JunctionSpec& spec) {
  check_spec(spec);
  const std::string source = fmt::format("junction (trunk radius {} m, element size {} m)",
                                         spec.trunk_radius, spec.element_size);
  Mesh mesh;
  {
    GmshSession session;
    mesh = with_gmsh(source, [&] {
      mesh_junction_model(spec);
      return mesh_from_gmsh_model(1.0, source);
    });
  }
  drop_unused_nodes(mesh);
  check_mesh(mesh);
  return mesh;
}

} // namespace tearflow::mesh
