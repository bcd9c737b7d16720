// Straight pipe: an OpenCASCADE cylinder meshed by Gmsh, read back from memory.
#include "mesh/pipe_generator.hpp"

#include <cmath>
#include <numbers>
#include <system_error>

#include <gmsh.h>

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
  const double volume = std::numbers::pi * s.radius * s.radius * s.length;
  const double estimate = kTetsPerSizeCubed * volume / std::pow(s.element_size, 3);
  if (!(estimate <= kMaxTets))
    input_error("pipe: element_size {} m for radius {} m and length {} m would give about {:.3g} "
                "tetrahedra, more than the {:.0f} M allowed; use a larger element_size",
                s.element_size, s.radius, s.length, estimate, kMaxTets / 1e6);
}

// Builds and meshes the pipe in the current Gmsh model.
void mesh_pipe_model(const PipeSpec& s) {
  gmsh::clear();
  gmsh::model::add("pipe");
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
  gmsh::model::mesh::generate(3);
}

} // namespace

Mesh make_pipe(const PipeSpec& spec) {
  return make_pipe(spec, {});
}

Mesh make_pipe(const PipeSpec& spec, const std::filesystem::path& msh_file) {
  check_spec(spec);
  const std::string source = fmt::format("pipe (radius {} m, length {} m, element size {} m)",
                                         spec.radius, spec.length, spec.element_size);
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
