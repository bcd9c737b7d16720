// Imported face surfaces into a fluid(-wall) tet mesh through Gmsh, following Gmsh's
// remeshing of STL surfaces (tutorial t13): the triangles become discrete surfaces, one per
// face file; classifySurfaces splits them into patches that can be parametrized, keeping
// sharp edges and, as discrete curves given beforehand, every border between two faces;
// createGeometry parametrizes the patches, so they can be remeshed at the requested size
// (or, keeping the surfaces, they stay discrete and keep their triangles); surface loops of
// the patches bound the fluid and the wall volumes, which share the interface patches and
// so their nodes.
//
// Built in millimetres, as the parametric TBAD: Gmsh's geometric tolerances are absolute.
#include "geometry/surface_mesher.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <system_error>

#include <gmsh.h>
#include <vtkCellArray.h>
#include <vtkCleanPolyData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"
#include "mesh/point_grid.hpp"

namespace tearflow::geometry {

namespace fs = std::filesystem;

namespace {

constexpr double kMm = 1e3; // Gmsh units per metre
constexpr const char* kInterface = "interface";
// Edges sharper than this (dihedral angle between the triangles' normals) stay edges of the
// remeshed surface: the flap's and tears' rims (90 degrees) and the caps' rims. Gmsh's
// tutorial uses 40 degrees; on the parametric dissection's surfaces that left a patch of
// the lumen wall near the false lumen's distal end which Gmsh could not remesh ("overlapping
// facets", at 1.5 and 3 mm), and 60 degrees failed alike; 25 degrees remeshes it at 2, 3
// and 4.5 mm. A branch triangulated with fewer than 15 edges around (24 degrees per edge)
// gets extra patch borders along it, which costs nothing but patches.
constexpr double kFeatureAngle = 25 * std::numbers::pi / 180;

std::string lower_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

// One face file, triangulated, its coincident points merged (an STL repeats them per
// triangle), coordinates times `scale`.
FaceSurface read_face(const fs::path& file, double scale, const std::string& src) {
  vtkSmartPointer<vtkPolyData> raw;
  const std::string ext = lower_extension(file);
  if (ext == ".stl") {
    vtkNew<vtkSTLReader> r;
    r->SetFileName(file.c_str());
    r->Update();
    raw = r->GetOutput();
  } else if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(file.c_str());
    r->Update();
    raw = r->GetOutput();
  } else {
    input_error("{}: unknown format '{}', expected .stl or .vtp", src, ext);
  }
  vtkNew<vtkTriangleFilter> tri;
  tri->SetInputData(raw);
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(tri->GetOutputPort());
  clean->SetTolerance(0.0);
  clean->Update();
  vtkPolyData* pd = clean->GetOutput();
  if (pd->GetNumberOfPolys() == 0)
    input_error("{}: no triangles (unreadable or empty file)", src);
  FaceSurface s;
  s.name = file.stem().string();
  s.file = file;
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i) {
    double p[3];
    pd->GetPoint(i, p);
    s.points.push_back({p[0] * scale, p[1] * scale, p[2] * scale});
  }
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = pd->GetPolys();
  polys->InitTraversal();
  while (polys->GetNextCell(ids))
    if (ids->GetNumberOfIds() == 3)
      s.triangles.push_back({static_cast<Index>(ids->GetId(0)), static_cast<Index>(ids->GetId(1)),
                             static_cast<Index>(ids->GetId(2))});
  return s;
}

// All faces' points merged into one list: points closer than 1e-7 of the model's size are
// one (files written by one tool repeat the shared rims' points exactly, up to Float32).
struct MergedFaces {
  std::vector<Vec3> points;
  std::vector<std::vector<Tri>> triangles; ///< per face, on `points`
};

MergedFaces merge_points(const std::vector<const FaceSurface*>& faces) {
  Vec3 lo = faces[0]->points[0], hi = lo;
  for (const FaceSurface* f : faces)
    for (const Vec3& p : f->points)
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const double tol = 1e-7 * std::sqrt(dot(hi - lo, hi - lo));
  MergedFaces m;
  mesh::PointGrid grid(m.points, 1000 * tol);
  for (const FaceSurface* f : faces) {
    std::vector<Index> map(f->points.size());
    for (std::size_t i = 0; i < f->points.size(); ++i) {
      const Vec3& p = f->points[i];
      Index twin = grid.find(p, tol);
      if (twin < 0) {
        twin = static_cast<Index>(m.points.size());
        m.points.push_back(p);
        grid.insert(twin);
      }
      map[i] = twin;
    }
    std::vector<Tri> tris;
    for (const Tri& t : f->triangles)
      tris.push_back({map[t[0]], map[t[1]], map[t[2]]});
    m.triangles.push_back(std::move(tris));
  }
  return m;
}

std::pair<Index, Index> edge(Index a, Index b) {
  return {std::min(a, b), std::max(a, b)};
}

// The faces `members` (indices into m.triangles) must close a volume: every edge used by
// exactly two of their triangles.
void check_closed(const MergedFaces& m, const std::vector<std::size_t>& members,
                  const std::string& src) {
  std::map<std::pair<Index, Index>, int> count;
  for (std::size_t f : members)
    for (const Tri& t : m.triangles[f])
      for (int i = 0; i < 3; ++i)
        ++count[edge(t[i], t[(i + 1) % 3])];
  std::size_t open = 0;
  Index first = -1;

  for (const auto& [e, n] : count)
    if (n != 2 && open++ == 0)
      first = e.first;
  if (open > 0) {
    const Vec3 p = m.points[first];
    input_error("{} is not watertight: {} edges are not shared by exactly two triangles (holes "
                "or non-manifold edges), e.g. at ({:.2f}, {:.2f}, {:.2f}) mm; close the surface "
                "(a face file for every cap, and for a wall its outer surface and the rings "
                "at the caps)",
                src, open, p[0] * kMm, p[1] * kMm, p[2] * kMm);
  }
}

std::set<Tri> sorted_triangles(const std::vector<Tri>& tris) {
  std::set<Tri> s;
  for (Tri t : tris) {
    std::sort(t.begin(), t.end());
    s.insert(t);
  }
  return s;
}

// The faces as discrete surfaces 1..n (nodes in mm), and their borders (edges whose
// triangles belong to different faces) as the lines of discrete curve 1, which
// classifySurfaces keeps as cuts.
void add_discrete_faces(const MergedFaces& m) {
  std::vector<std::size_t> node_tags(m.points.size());
  std::vector<double> coord;
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    node_tags[i] = i + 1;
    for (int k = 0; k < 3; ++k)
      coord.push_back(m.points[i][k] * kMm);
  }
  std::map<std::pair<Index, Index>, std::set<std::size_t>> faces_of_edge;
  for (std::size_t f = 0; f < m.triangles.size(); ++f) {
    const int tag = gmsh::model::addDiscreteEntity(2, static_cast<int>(f) + 1);
    if (f == 0)
      gmsh::model::mesh::addNodes(2, tag, node_tags, coord);
    std::vector<std::size_t> nodes;
    for (const Tri& t : m.triangles[f])
      for (int i = 0; i < 3; ++i) {
        nodes.push_back(static_cast<std::size_t>(t[i]) + 1);
        faces_of_edge[edge(t[i], t[(i + 1) % 3])].insert(f);
      }
    gmsh::model::mesh::addElementsByType(tag, 2, {}, nodes);
  }
  std::vector<std::size_t> lines;
  for (const auto& [e, faces] : faces_of_edge)
    if (faces.size() > 1) {
      lines.push_back(static_cast<std::size_t>(e.first) + 1);
      lines.push_back(static_cast<std::size_t>(e.second) + 1);
    }
  if (!lines.empty()) {
    const int curve = gmsh::model::addDiscreteEntity(1);
    gmsh::model::mesh::addElementsByType(curve, 1, {}, lines);
  }
}

// After classification, the input face of every surface patch (by its triangles' nodes).
std::map<int, std::size_t> patch_faces(const MergedFaces& m, const std::vector<std::string>& names,
                                       const std::string& src) {
  std::map<Tri, std::size_t> face_of;
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (Tri t : m.triangles[f]) {
      std::sort(t.begin(), t.end());
      face_of[t] = f;
    }
  std::map<int, std::size_t> out;
  gmsh::vectorpair patches;
  gmsh::model::getEntities(patches, 2);
  for (const auto& [dim, tag] : patches) {
    std::vector<std::size_t> element_tags, nodes;
    gmsh::model::mesh::getElementsByType(2, element_tags, nodes, tag);
    std::set<std::size_t> faces;
    for (std::size_t i = 0; i + 2 < nodes.size(); i += 3) {
      Tri t{static_cast<Index>(nodes[i] - 1), static_cast<Index>(nodes[i + 1] - 1),
            static_cast<Index>(nodes[i + 2] - 1)};
      std::sort(t.begin(), t.end());
      const auto it = face_of.find(t);
      if (it != face_of.end())
        faces.insert(it->second);
    }
    if (faces.size() != 1)
      input_error("{}: Gmsh's surface patch {} spans {} input faces (expected one){}", src, tag,
                  faces.size(), faces.size() > 1 ? ": " + names[*faces.begin()] + ", ..." : "");
    out[tag] = *faces.begin();
  }
  return out;
}

} // namespace

FaceSet read_face_set(const fs::path& path, const std::string& what, double length_scale,
                      const std::vector<std::pair<std::string, std::string>>& renames) {
  FaceSet set{what, path, {}};
  const std::string src = fmt::format("{} surface '{}'", what, path.string());
  std::error_code ec;
  std::vector<fs::path> files;
  if (fs::is_directory(path, ec)) {
    fs::path dir = path;
    if (fs::is_directory(dir / "mesh-surfaces", ec))
      dir /= "mesh-surfaces"; // a SimVascular mesh-complete directory
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (const std::string ext = lower_extension(entry.path());
          entry.is_regular_file() && (ext == ".stl" || ext == ".vtp"))
        files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    if (files.empty())
      input_error("{}: the directory holds no .stl or .vtp face files", src);
  } else if (fs::is_regular_file(path, ec)) {
    files.push_back(path);
  } else {
    input_error("{}: no such file or directory", src);
  }
  for (const fs::path& file : files) {
    const std::string file_src = fmt::format("{} surface '{}'", what, file.string());
    FaceSurface face = read_face(file, length_scale, file_src);
    for (const auto& [from, to] : renames)
      if (face.name == from)
        face.name = to;
    set.faces.push_back(std::move(face));
  }
  return set;
}

mesh::Mesh mesh_face_sets(const FaceSet& lumen, const FaceSet& wall, double element_size,
                          bool remesh, bool verbose) {
  if (!(element_size > 0))
    input_error("import: element size {} mm, expected a positive number", element_size * kMm);
  const std::string lumen_src = fmt::format("lumen surface '{}'", lumen.path.string());
  const std::string wall_src = fmt::format("wall surface '{}'", wall.path.string());
  const bool has_wall = !wall.faces.empty();
  // Faces: the lumen's, then the wall's that are not copies of lumen faces.
  std::vector<const FaceSurface*> faces;
  for (const FaceSurface& f : lumen.faces)
    faces.push_back(&f);
  const std::size_t num_lumen = faces.size();
  for (const FaceSurface& f : wall.faces)
    faces.push_back(&f);
  MergedFaces m = merge_points(faces);
  std::set<Tri> interface_tris;
  for (std::size_t f = 0; f < num_lumen; ++f)
    if (faces[f]->name == kInterface)
      interface_tris = sorted_triangles(m.triangles[f]);
  std::vector<std::string> names;
  std::vector<std::size_t> fluid_faces, wall_faces;
  for (std::size_t f = 0, kept = 0; f < faces.size(); ++f) {
    if (f >= num_lumen) {
      const std::set<Tri> tris = sorted_triangles(m.triangles[f]);
      if (!interface_tris.empty() &&
          std::includes(interface_tris.begin(), interface_tris.end(), tris.begin(), tris.end()))
        continue; // the wall's copy of the interface (SimVascular's wall_inner)
    }
    if (std::find(names.begin(), names.end(), faces[f]->name) != names.end())
      input_error("import: two face files are called '{}' ({}); rename one with --face",
                  faces[f]->name, faces[f]->file.string());
    names.push_back(faces[f]->name);
    if (kept != f)
      m.triangles[kept] = std::move(m.triangles[f]);
    (f < num_lumen ? fluid_faces : wall_faces).push_back(kept);
    if (f < num_lumen && faces[f]->name == kInterface)
      wall_faces.push_back(kept);
    ++kept;
  }
  m.triangles.resize(names.size());
  check_closed(m, fluid_faces, lumen_src);
  if (has_wall) {
    check_closed(m, wall_faces, wall_src);
    if (std::find(names.begin(), names.end(), kInterface) == names.end())
      input_error("{}: no lumen face is called '{}': name the face the fluid shares with the "
                  "wall so (its file interface.vtp, or --face lumen_wall=interface)",
                  lumen_src, kInterface);
  }

  const std::string source = fmt::format("{}{} (element size {} mm)", lumen_src,
                                         has_wall ? " + " + wall_src : "", element_size * kMm);
  mesh::Mesh out;
  try {
    mesh::GmshSession session(verbose);
    out = mesh::with_gmsh(source, [&] {
      gmsh::clear();
      gmsh::model::add("import");
      add_discrete_faces(m);
      gmsh::model::mesh::classifySurfaces(kFeatureAngle, true, remesh, std::numbers::pi);
      const std::map<int, std::size_t> face_of = patch_faces(m, names, source);
      if (remesh)
        gmsh::model::mesh::createGeometry();
      std::vector<int> fluid_patches, wall_patches;
      std::map<std::string, std::vector<int>> groups;
      for (const auto& [patch, f] : face_of) {
        groups[names[f]].push_back(patch);
        if (std::find(fluid_faces.begin(), fluid_faces.end(), f) != fluid_faces.end())
          fluid_patches.push_back(patch);
        if (std::find(wall_faces.begin(), wall_faces.end(), f) != wall_faces.end())
          wall_patches.push_back(patch);
      }
      const int fluid =
          gmsh::model::geo::addVolume({gmsh::model::geo::addSurfaceLoop(fluid_patches)});
      int solid = -1;
      if (has_wall)
        solid = gmsh::model::geo::addVolume({gmsh::model::geo::addSurfaceLoop(wall_patches)});
      gmsh::model::geo::synchronize();
      gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {fluid}), "fluid");
      if (has_wall)
        gmsh::model::setPhysicalName(3, gmsh::model::addPhysicalGroup(3, {solid}), "wall");
      for (const auto& [name, patches] : groups)
        gmsh::model::setPhysicalName(2, gmsh::model::addPhysicalGroup(2, patches), name);
      // Uniform size, curvature sizing (12 edges around a small branch), as for the
      // parametric TBAD; MeshAdapt on the reparametrized patches (Frontal-Delaunay left
      // slivers of radius ratio 0.001 to 0.004 on SimVascular's pipe-fsi surfaces, MeshAdapt
      // none below 0.27) and the deterministic Delaunay volume mesher. Kept surfaces are
      // not remeshed; the size then caps the volumes' elements.
      gmsh::option::setNumber("Mesh.MeshSizeMax", element_size * kMm);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 12);
      gmsh::option::setNumber("Mesh.ElementOrder", 1);
      gmsh::option::setNumber("Mesh.Algorithm", 1);
      gmsh::option::setNumber("Mesh.Algorithm3D", 1);
      gmsh::model::mesh::generate(3);
      return mesh::mesh_from_gmsh_model(1.0 / kMm, source);
    });
  } catch (const InputError& e) {
    if (!remesh)
      throw;
    // Gmsh's reparametrization fails on some thin features (a flap with its tears' rims):
    // the given triangles may still make a good boundary.
    input_error("{}\n  (remeshing the surfaces failed; --keep-surfaces meshes the volumes on "
                "the given triangles)",
                e.what());
  }
  mesh::drop_unused_nodes(out);
  return out;
}

} // namespace tearflow::geometry
