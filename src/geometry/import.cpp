// Import of a user's model: a finished mesh (Gmsh or SimVascular) or lumen and wall
// surfaces given face by face (STL or VTP, meshed by geometry/surface_mesher), with a
// landmarks file; checked, then written in the same layout as `geometry tbad` (mesh.msh in
// mm, landmarks.json in mm).
#include "geometry/import.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <system_error>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/landmarks.hpp"
#include "geometry/sections.hpp"
#include "geometry/surface_mesher.hpp"
#include "geometry/tbad_builder.hpp"
#include "mesh/point_grid.hpp"
#include "mesh/readers.hpp"

namespace tearflow::geometry {

namespace fs = std::filesystem;

void write_msh(const mesh::Mesh& m, const fs::path& file) {
  std::ofstream out(file);
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n"
      << m.regions.size() + m.faces.size() << "\n";
  int tag = 1;
  for (const std::string& r : m.regions)
    out << "3 " << tag++ << " \"" << r << "\"\n";
  for (const mesh::Face& f : m.faces)
    out << "2 " << tag++ << " \"" << f.name << "\"\n";
  out << "$EndPhysicalNames\n$Nodes\n" << m.points.size() << "\n";
  for (std::size_t i = 0; i < m.points.size(); ++i)
    out << fmt::format("{} {:.17g} {:.17g} {:.17g}\n", i + 1, m.points[i][0] * 1e3,
                       m.points[i][1] * 1e3, m.points[i][2] * 1e3);
  std::size_t count = m.tets.size();
  for (const mesh::Face& f : m.faces)
    count += f.triangles.size();
  out << "$EndNodes\n$Elements\n" << count << "\n";
  std::size_t id = 1;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const int physical = m.tet_region[t] + 1;
    const Tet& k = m.tets[t];
    out << id++ << " 4 2 " << physical << " " << physical << " " << k[0] + 1 << " " << k[1] + 1
        << " " << k[2] + 1 << " " << k[3] + 1 << "\n";
  }
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const int physical = static_cast<int>(m.regions.size() + f) + 1;
    for (const Tri& t : m.faces[f].triangles)
      out << id++ << " 2 2 " << physical << " " << physical << " " << t[0] + 1 << " " << t[1] + 1
          << " " << t[2] + 1 << "\n";
  }
  out << "$EndElements\n";
  if (!out)
    input_error("could not write '{}'", file.string());
}

namespace {

// The fluid's boundary must be closed by named faces: every boundary triangle of the fluid
// region is in a named face (a cap, the wall or the interface).
void check_fluid_boundary_named(const mesh::Mesh& m) {
  const int fluid = region_index(m, "fluid");
  std::map<Tri, int> count;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    if (m.tet_region[t] == fluid)
      for (int skip = 0; skip < 4; ++skip) {
        Tri f = face_opposite(m.tets[t], skip);
        std::sort(f.begin(), f.end());
        ++count[f];
      }
  std::set<Tri> named;
  for (const mesh::Face& f : m.faces)
    for (Tri t : f.triangles) {
      std::sort(t.begin(), t.end());
      named.insert(t);
    }
  std::size_t unnamed = 0;
  for (const auto& [f, n] : count)
    unnamed += n == 1 && !named.count(f);
  if (unnamed > 0)
    input_error("{}: {} boundary triangles of the fluid belong to no named face: the named faces "
                "do not close the fluid (name every cap, the wall or the interface)",
                m.source, unnamed);
  for (const char* cap : {"inlet", "outlet"})
    if (!m.has_face(cap))
      input_error("{}: no face '{}' (faces must include inlet and outlet)", m.source, cap);
}

// Every landmark must lie in the fluid: its point inside, its plane cutting it.
void check_landmarks(const mesh::Mesh& m, const Landmarks& l) {
  for (const Landmark& p : l.planes)
    landmark_area(m, p); // InputError naming the landmark when its point is not in the fluid
  for (const TearLandmark& t : l.tears)
    if (locate(m, t.centroid, region_index(m, "fluid")) < 0)
      input_error("{}: tear '{}': its centroid is not inside the fluid", m.source, t.name);
}

mesh::Mesh read_volume_mesh(const fs::path& path, double scale, const std::string& region) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return mesh::read_simvascular(path, scale, region);
  if (path.extension() == ".msh")
    return read_fsi_mesh(path, scale);
  input_error("import: '{}' is neither a .msh file nor a SimVascular mesh-complete directory",
              path.string());
}

// Appends `wall` to `fluid`, merging wall nodes that coincide with fluid nodes (to 1e-7 of
// the model's size: the meshes share those nodes, up to Float32 storage in .vtu files). Wall faces
// whose triangles are all fluid faces too (the wall's copy of the interface) are dropped.
mesh::Mesh merge_fluid_and_wall(mesh::Mesh fluid, const mesh::Mesh& wall) {
  Vec3 lo = fluid.points[0], hi = lo;
  for (const Vec3& p : fluid.points)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const double tol = 1e-7 * std::sqrt(dot(hi - lo, hi - lo));
  const mesh::PointGrid grid(fluid.points, 1000 * tol);
  std::vector<Index> map(wall.points.size());
  std::size_t shared = 0;
  for (std::size_t i = 0; i < wall.points.size(); ++i) {
    const Vec3& p = wall.points[i];
    const Index twin = grid.find(p, tol);
    if (twin >= 0) {
      map[i] = twin;
      ++shared;
    } else {
      map[i] = fluid.num_nodes();
      fluid.points.push_back(p);
    }
  }
  if (shared == 0)
    input_error("{} and {}: the wall shares no node with the fluid; expected its inner face to "
                "coincide node for node with the fluid's wall",
                fluid.source, wall.source);
  std::vector<int> region_of(wall.regions.size());
  for (std::size_t r = 0; r < wall.regions.size(); ++r) {
    const auto it = std::find(fluid.regions.begin(), fluid.regions.end(), wall.regions[r]);
    region_of[r] = static_cast<int>(it - fluid.regions.begin());
    if (it == fluid.regions.end())
      fluid.regions.push_back(wall.regions[r]);
  }
  for (std::size_t t = 0; t < wall.tets.size(); ++t) {
    Tet k = wall.tets[t];
    for (Index& n : k)
      n = map[n];
    fluid.tets.push_back(k);
    fluid.tet_region.push_back(region_of[wall.tet_region[t]]);
  }
  std::set<Tri> fluid_faces;
  for (const mesh::Face& f : fluid.faces)
    for (Tri t : f.triangles) {
      std::sort(t.begin(), t.end());
      fluid_faces.insert(t);
    }
  for (const mesh::Face& f : wall.faces) {
    mesh::Face merged{f.name, {}};
    bool duplicate = true;
    for (const Tri& t : f.triangles) {
      Tri m{map[t[0]], map[t[1]], map[t[2]]};
      merged.triangles.push_back(m);
      std::sort(m.begin(), m.end());
      duplicate = duplicate && fluid_faces.count(m);
    }
    if (!duplicate)
      fluid.faces.push_back(std::move(merged));
  }
  fluid.source = fluid.source + " + " + wall.source;
  return fluid;
}

void rename_faces(mesh::Mesh& m, const std::vector<std::pair<std::string, std::string>>& renames) {
  for (const auto& [from, to] : renames) {
    bool found = false;
    for (mesh::Face& f : m.faces)
      if (f.name == from) {
        f.name = to;
        found = true;
      }
    if (!found)
      m.face(from); // InputError listing the faces
  }
}

} // namespace

void import_geometry(const ImportOptions& o, const fs::path& dir) {
  if (o.landmarks.empty())
    input_error("import: --landmarks is required");
  const bool surfaces = !o.lumen.empty() || !o.wall.empty();
  if (surfaces == !o.mesh.empty())
    input_error("import: give either --mesh or --lumen (with --wall for a wall)");
  if (surfaces && o.lumen.empty())
    input_error("import: --wall needs --lumen");
  const Landmarks landmarks = read_landmarks(o.landmarks);
  mesh::Mesh m;
  if (surfaces) {
    const FaceSet lumen = read_face_set(o.lumen, "lumen", o.length_scale, o.rename_faces);
    FaceSet wall{"wall", o.wall, {}};
    if (!o.wall.empty())
      wall = read_face_set(o.wall, "wall", o.length_scale, o.rename_faces);
    for (const auto& [from, to] : o.rename_faces) {
      bool found = false;
      for (const FaceSet* set : {&lumen, static_cast<const FaceSet*>(&wall)})
        for (const FaceSurface& f : set->faces)
          found = found || f.file.stem() == from;
      if (!found)
        input_error("import: --face {}={}: no face file is called '{}'", from, to, from);
    }
    m = mesh_face_sets(lumen, wall, o.element_size, o.remesh_surfaces, o.verbose);
  } else {
    m = read_volume_mesh(o.mesh, o.length_scale, "fluid");
    if (!o.wall_mesh.empty())
      m = merge_fluid_and_wall(std::move(m), read_volume_mesh(o.wall_mesh, o.length_scale, "wall"));
    rename_faces(m, o.rename_faces);
  }
  write_geometry(m, landmarks, dir);
}

void write_geometry(const mesh::Mesh& m, const Landmarks& landmarks, const fs::path& dir) {
  check_fsi_mesh(m);
  check_fluid_boundary_named(m);
  check_landmarks(m, landmarks);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    input_error("cannot create '{}': {}", dir.string(), ec.message());
  write_msh(m, GeometryFiles{dir}.mesh());
  write_landmarks(landmarks, GeometryFiles{dir}.landmarks(), "mm");
}

} // namespace tearflow::geometry
