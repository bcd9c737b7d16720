// `geometry import` and `geometry report` through the library and the program: a finished
// mesh goes through unchanged, bad surfaces and landmarks are refused with clear messages,
// and the report draws its picture under a virtual X server.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/geometry_report.hpp"
#include "geometry/import.hpp"
#include "geometry/sections.hpp"
#include "mesh/pipe_generator.hpp"
#include "mesh/readers.hpp"
#include "test_geometry_support.hpp"

namespace tearflow::geometry {
namespace {

using namespace testing;
using ::testing::HasSubstr;

std::string import_error(const ImportOptions& o, const fs::path& out) {
  try {
    import_geometry(o, out);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// An ASCII STL of the unit cube (in mm), leaving out the last `missing` of its 12 triangles.
void write_cube_stl(const fs::path& file, int missing) {
  const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int t[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::ofstream out(file);
  out << "solid cube\n";
  for (int i = 0; i < 12 - missing; ++i) {
    out << " facet normal 0 0 0\n  outer loop\n";
    for (int k : t[i])
      out << fmt::format("   vertex {} {} {}\n", v[k][0], v[k][1], v[k][2]);
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid cube\n";
}

// A face's triangles written on their own points, coordinates in mm: ASCII STL (every
// triangle repeats its corners) or ASCII VTP (shared points), as a user's tool writes them.
void write_face(const mesh::Mesh& m, const mesh::Face& f, const fs::path& file) {
  std::ofstream out(file);
  if (file.extension() == ".stl") {
    out << "solid " << f.name << "\n";
    for (const Tri& t : f.triangles) {
      out << " facet normal 0 0 0\n  outer loop\n";
      for (Index n : t)
        out << fmt::format("   vertex {:.17g} {:.17g} {:.17g}\n", m.points[n][0] * 1e3,
                           m.points[n][1] * 1e3, m.points[n][2] * 1e3);
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid " << f.name << "\n";
    return;
  }
  std::map<Index, Index> local;
  std::vector<Index> nodes;
  for (const Tri& t : f.triangles)
    for (Index n : t)
      if (local.emplace(n, static_cast<Index>(nodes.size())).second)
        nodes.push_back(n);
  out << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
      << fmt::format("<Piece NumberOfPoints=\"{}\" NumberOfPolys=\"{}\">\n", nodes.size(),
                     f.triangles.size())
      << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Index n : nodes)
    out << fmt::format("{:.17g} {:.17g} {:.17g}\n", m.points[n][0] * 1e3, m.points[n][1] * 1e3,
                       m.points[n][2] * 1e3);
  out << "</DataArray></Points>\n<Polys><DataArray type=\"Int64\" Name=\"connectivity\" "
         "format=\"ascii\">\n";
  for (const Tri& t : f.triangles)
    out << local[t[0]] << " " << local[t[1]] << " " << local[t[2]] << "\n";
  out << "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= f.triangles.size(); ++i)
    out << 3 * i << "\n";
  out << "</DataArray></Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
}

double region_volume(const MeshReport& r, const std::string& name) {
  for (const RegionQuality& q : r.regions)
    if (q.name == name)
      return q.volume;
  return 0;
}

TEST(GeometryImport, NonWatertightSurfaceIsAClearError) {
  TempDir dir("geometry-import");
  const CachedModel m = cached_tbad("OR", kCoarse);
  write_cube_stl(dir.path / "open.stl", 1);
  write_cube_stl(dir.path / "closed.stl", 0);
  ImportOptions o;
  o.landmarks = m.dir / GeometryFiles::kLandmarks;
  o.lumen = dir.path / "open.stl";
  o.wall = dir.path / "closed.stl";
  const std::string e = import_error(o, dir.path / "out");
  EXPECT_THAT(e, HasSubstr("lumen surface '" + o.lumen.string() + "' is not watertight"));
  EXPECT_THAT(e, HasSubstr("3 edges are not shared by exactly two triangles"));
  o.lumen = dir.path / "closed.stl";
  o.wall = dir.path / "open.stl";
  EXPECT_THAT(import_error(o, dir.path / "out"), HasSubstr("wall surface"));
  EXPECT_FALSE(fs::exists(dir.path / "out" / GeometryFiles::kMesh));
}

TEST(GeometryImport, FinishedMeshKeepsRegionsFacesAndLandmarks) {
  TempDir dir("geometry-import");
  const CachedModel m = cached_tbad("OR", kCoarse);
  ImportOptions o;
  o.mesh = m.dir / GeometryFiles::kMesh;
  o.landmarks = m.dir / GeometryFiles::kLandmarks;
  import_geometry(o, dir.path / "out");
  const mesh::Mesh back = read_fsi_mesh(dir.path / "out" / GeometryFiles::kMesh, 1e-3);
  EXPECT_EQ(back.num_nodes(), m.mesh.num_nodes());
  EXPECT_EQ(back.num_tets(), m.mesh.num_tets());
  EXPECT_EQ(back.regions, m.mesh.regions);
  ASSERT_EQ(back.faces.size(), m.mesh.faces.size());
  for (const mesh::Face& f : m.mesh.faces)
    EXPECT_EQ(back.face(f.name).triangles.size(), f.triangles.size()) << f.name;
  const Landmarks l = read_landmarks(dir.path / "out" / GeometryFiles::kLandmarks);
  EXPECT_EQ(l.planes.size(), m.landmarks.planes.size());
}

TEST(GeometryImport, LandmarkOutsideTheFluidIsAnError) {
  TempDir dir("geometry-import");
  const fs::path msh = dir.path / "pipe.msh";
  mesh::make_pipe({0.01, 0.05, 0.004}, msh); // metres: import with --units m
  Landmarks l;
  l.planes.push_back({"inlet", {0, 0, 0.001}, {0, 0, 1}, "aorta", std::nullopt});
  l.planes.push_back({"AAo", {0.02, 0, 0.025}, {0, 0, 1}, "aorta", std::nullopt}); // outside
  write_landmarks(l, dir.path / "landmarks.json", "m");
  ImportOptions o;
  o.mesh = msh;
  o.landmarks = dir.path / "landmarks.json";
  o.length_scale = 1.0;
  EXPECT_THAT(import_error(o, dir.path / "out"),
              HasSubstr("landmark 'AAo': its point (0.02, 0, 0.025) m is not inside the fluid"));
  l.planes.pop_back();
  write_landmarks(l, dir.path / "landmarks.json", "m");
  EXPECT_EQ(import_error(o, dir.path / "out"), "(no error)");
}

// SimVascular's FSI layout: separate fluid and wall meshes sharing the wall's nodes
// (../shared/meshes/pipe-fsi, cm). Merged, they must form one mesh whose interface nodes are
// shared, with the wall's copy of the interface dropped.
TEST(GeometryImport, SeparateFluidAndWallMeshesAreMergedAtTheirSharedNodes) {
  TempDir dir("geometry-import");
  const fs::path fsi = fs::path(TEARFLOW_SHARED_DIR) / "meshes" / "pipe-fsi";
  const mesh::Mesh lumen = mesh::read_simvascular(fsi / "lumen", 1e-2);
  const mesh::Mesh wall = mesh::read_simvascular(fsi / "wall", 1e-2, "wall");
  Vec3 lo = lumen.points[0], hi = lo;
  for (const Vec3& p : lumen.points)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  const Vec3 mid = 0.5 * (lo + hi);
  Landmarks l; // a plane across the middle of the pipe (axis z)
  l.planes.push_back({"mid", mid, {0, 0, 1}, "aorta", std::nullopt});
  write_landmarks(l, dir.path / "landmarks.json", "cm");
  ImportOptions o;
  o.mesh = fsi / "lumen";
  o.wall_mesh = fsi / "wall";
  o.landmarks = dir.path / "landmarks.json";
  o.length_scale = 1e-2;
  EXPECT_THAT(import_error(o, dir.path / "out"),
              HasSubstr("face 'lumen_wall' lies between the fluid and the wall"));
  o.rename_faces = {
      {"lumen_inlet", "inlet"}, {"lumen_outlet", "outlet"}, {"lumen_wall", "interface"}};
  import_geometry(o, dir.path / "out");
  const mesh::Mesh m = read_fsi_mesh(dir.path / "out" / GeometryFiles::kMesh, 1e-3);
  EXPECT_EQ(m.num_tets(), lumen.num_tets() + wall.num_tets());
  const MeshReport r = check_fsi_mesh(m);
  EXPECT_EQ(r.interface_triangles, lumen.face("lumen_wall").triangles.size());
  // Shared nodes: the merged mesh has fewer nodes than the two apart by the interface's.
  EXPECT_EQ(m.num_nodes() + static_cast<Index>(r.interface_nodes),
            lumen.num_nodes() + wall.num_nodes());
  EXPECT_FALSE(m.has_face("wall_inner")) << "the wall's copy of the interface is dropped";
  EXPECT_TRUE(m.has_face("wall_outer"));
}

// The parametric TBAD's boundary exported face by face into `dir`/lumen (caps and
// interface as VTP) and `dir`/wall (rings and outer wall as STL), as a user's tool would.
void export_tbad_faces(const CachedModel& m, const fs::path& dir) {
  fs::create_directories(dir / "lumen");
  fs::create_directories(dir / "wall");
  for (const mesh::Face& f : m.mesh.faces) {
    const bool wall_face = f.name == "outer_wall" || f.name.rfind("wall_", 0) == 0;
    write_face(m.mesh, f,
               wall_face ? dir / "wall" / (f.name + ".stl") : dir / "lumen" / (f.name + ".vtp"));
  }
}

std::vector<std::string> face_names(const mesh::Mesh& m) {
  std::vector<std::string> names;
  for (const mesh::Face& f : m.faces)
    names.push_back(f.name);
  std::sort(names.begin(), names.end());
  return names;
}

// The built model's faces exported into `dir` and imported again (its triangles kept, or
// remeshed at its element size): the mesh read back, checked to have the model's regions and
// named faces.
mesh::Mesh reimport_faces(const CachedModel& m, const fs::path& dir, bool remesh) {
  export_tbad_faces(m, dir);
  ImportOptions o;
  o.lumen = dir / "lumen";
  o.wall = dir / "wall";
  o.landmarks = m.dir / GeometryFiles::kLandmarks;
  o.element_size = kCoarse;
  o.remesh_surfaces = remesh;
  import_geometry(o, dir / "out");
  mesh::Mesh back = read_fsi_mesh(dir / "out" / GeometryFiles::kMesh, 1e-3);
  EXPECT_EQ(back.regions, (std::vector<std::string>{"fluid", "wall"}));
  EXPECT_EQ(face_names(back), face_names(m.mesh));
  return back;
}

// Imported again on its own triangles, the TBAD must be the same model: regions fluid and
// wall, the same named faces, shared interface nodes, the same volumes and tear areas,
// every landmark in the fluid (import checks it), usable tets.
TEST(GeometryImport, FaceSurfacesOfTheTbadKeptGiveTheSameModel) {
  TempDir dir("geometry-import");
  const CachedModel m = cached_tbad("OR", kCoarse);
  const mesh::Mesh back = reimport_faces(m, dir.path, false);
  const MeshReport before = check_fsi_mesh(m.mesh), after = check_fsi_mesh(back);
  EXPECT_EQ(after.interface_triangles, before.interface_triangles);
  EXPECT_EQ(after.interface_nodes, before.interface_nodes);
  // Same closed boundary, so the same enclosed volume, up to VTK's STL reader, which keeps
  // Float32 coordinates: nodes move by 6e-8 of 150 mm, 1e-5 mm, over the outer wall's
  // 4e4 mm^2: 0.4 mm^3 of the wall's 8.4e4 mm^3, 5e-6. Tolerance 1e-5.
  for (const char* region : {"fluid", "wall"})
    EXPECT_NEAR(region_volume(after, region) / region_volume(before, region), 1.0, 1e-5) << region;
  // Quality: on the same surfaces the tets are like the built model's (min radius ratio
  // 0.14 at 3 mm), so the built model's bound holds (test_geometry_tbad.cpp, 0.05).
  for (const RegionQuality& q : after.regions) {
    fmt::print("{}: {} tets, {:.1f} mm^3, min radius ratio {:.3f}\n", q.name, q.tets,
               q.volume * 1e9, q.min_quality);
    EXPECT_GT(q.min_quality, 0.05) << q.name;
  }
  // The tears are the holes of the flap, part of the interface given in Float64 VTP: their
  // measured areas (the fluid's section in the flap's mid-plane) equal the built model's
  // up to the rounding of the sums over the cut tets.
  const Landmarks l = read_landmarks(dir.path / "out" / GeometryFiles::kLandmarks);
  for (const TearLandmark& t : l.tears)
    EXPECT_NEAR(tear_area(back, t), tear_area(m.mesh, t), 1e-9 * t.area) << t.name;
}

// The same faces remeshed at the target size: a valid two-region mesh with the same named
// faces, volumes and tears within what re-chording the surfaces can change.
TEST(GeometryImport, FaceSurfacesOfTheTbadAreRemeshedAtTheTargetSize) {
  TempDir dir("geometry-import");
  // The model at one uniform size (no true-lumen sizing, --lumen-elements 0): remeshing
  // imported surfaces knows only the target size, and re-chording the finer true-lumen
  // triangles at 3 mm leaves slivers (radius ratio 0.007) where they meet the coarse rest.
  const CachedModel m = cached_tbad("OR", kCoarse, 0);
  const mesh::Mesh back = reimport_faces(m, dir.path, true);
  const MeshReport before = check_fsi_mesh(m.mesh), after = check_fsi_mesh(back);
  EXPECT_GT(after.interface_nodes, 0u);
  // The remeshed surfaces' nodes lie on the input triangles, so the new surface re-chords
  // the old one: a vessel of radius R re-chorded with edges h loses at most a fraction
  // h^2 / (6 R^2) of its section (an inscribed polygon); with h = 3 mm and R = 10 mm (the
  // smallest aortic radius; branches hold little volume) that is 1.5 %. The wall (thickness
  // t = 2 mm) loses or gains at its inner and outer surface the same order of area,
  // pi h^2 / 6 per unit length, against its section 2 pi R t: h^2 / (12 R t) = 3.75 %.
  const double h = kCoarse, r = 10e-3, t = 2e-3;
  for (const auto& [region, tol] :
       {std::pair{"fluid", h * h / (6 * r * r)}, {"wall", h * h / (12 * r * t)}}) {
    const double v0 = region_volume(before, region), v1 = region_volume(after, region);
    fmt::print("{}: {:.1f} mm^3 remeshed, {:.1f} mm^3 built\n", region, v1 * 1e9, v0 * 1e9);
    EXPECT_NEAR(v1 / v0, 1.0, tol) << region;
  }
  // Quality 0.01: below it a tet is a sliver that would ruin the solid's conditioning
  // (test_geometry_tbad.cpp). The built model's 0.05 is not reached at 3 mm, where the
  // remeshed tear and flap rims are coarser than the built model's refined ones (0.04 in
  // the wall; 0.18 at 2 mm).
  for (const RegionQuality& q : after.regions) {
    fmt::print("{}: {} tets, min radius ratio {:.3f}\n", q.name, q.tets, q.min_quality);
    EXPECT_GT(q.min_quality, 0.01) << q.name;
  }
  // Tears: the acceptance bound, 3 % (the rims' polygons are remeshed too).
  for (const TearLandmark& tear : m.landmarks.tears)
    EXPECT_NEAR(tear_area(back, tear), tear.area, 0.03 * tear.area) << tear.name;
}

// SimVascular's mesh-surfaces as they come (../shared/meshes/pipe-fsi, cm): the lumen's
// faces renamed, the wall's copy of the lumen wall (wall_inner) dropped.
TEST(GeometryImport, SimVascularMeshSurfacesAreMeshedWithAWall) {
  TempDir dir("geometry-import");
  const fs::path fsi = fs::path(TEARFLOW_SHARED_DIR) / "meshes" / "pipe-fsi";
  Landmarks l;
  l.planes.push_back({"mid", {0, 0, 0.05}, {0, 0, 1}, "aorta", std::nullopt}); // [m]
  write_landmarks(l, dir.path / "landmarks.json", "cm");
  ImportOptions o;
  o.lumen = fsi / "lumen"; // its mesh-surfaces/
  o.wall = fsi / "wall";
  o.landmarks = dir.path / "landmarks.json";
  o.length_scale = 1e-2;
  o.element_size = 2e-3;
  EXPECT_THAT(import_error(o, dir.path / "out"), HasSubstr("no lumen face is called 'interface'"));
  o.rename_faces = {
      {"lumen_inlet", "inlet"}, {"lumen_outlet", "outlet"}, {"lumen_wall", "interface"}};
  import_geometry(o, dir.path / "out");
  const mesh::Mesh m = read_fsi_mesh(dir.path / "out" / GeometryFiles::kMesh, 1e-3);
  EXPECT_FALSE(m.has_face("wall_inner"));
  for (const char* face :
       {"inlet", "outlet", "interface", "wall_inlet", "wall_outlet", "wall_outer"})
    EXPECT_TRUE(m.has_face(face)) << face;
  const MeshReport r = check_fsi_mesh(m);
  // Against the volumes of SimVascular's own meshes of these surfaces: the remeshed
  // surfaces' nodes lie on the input triangles, so they re-chord them; with h = 2 mm on the
  // lumen radius R = 1 cm a section loses at most h^2 / (6 R^2) = 0.67 % (an inscribed
  // polygon); the wall (t = 2 mm) loses about as much area at its outer surface as at its
  // inner one, pi h^2 / 6 each per unit length, of its section 2 pi R t: h^2 / (12 R t).
  const double R = 0.01, t = 0.002, h = 2e-3;
  auto volume = [](const mesh::Mesh& v) {
    double sum = 0;
    for (const Tet& k : v.tets)
      sum += mesh::signed_volume(v.points[k[0]], v.points[k[1]], v.points[k[2]], v.points[k[3]]);
    return sum;
  };
  const double fluid0 = volume(mesh::read_simvascular(fsi / "lumen", 1e-2));
  const double wall0 = volume(mesh::read_simvascular(fsi / "wall", 1e-2, "wall"));
  EXPECT_NEAR(region_volume(r, "fluid") / fluid0, 1.0, h * h / (6 * R * R));
  EXPECT_NEAR(region_volume(r, "wall") / wall0, 1.0, h * h / (12 * R * t));
  fmt::print("fluid {:.1f} mm^3 (SimVascular's {:.1f}), wall {:.1f} mm^3 ({:.1f})\n",
             region_volume(r, "fluid") * 1e9, fluid0 * 1e9, region_volume(r, "wall") * 1e9,
             wall0 * 1e9);
  for (const RegionQuality& q : r.regions) // no slivers, as above
    EXPECT_GT(q.min_quality, 0.05) << q.name;
}

// Two tets sharing a face have 9 distinct edges, not 12: three of length 1 and six of
// sqrt(2) here, so the mean is (3 + 6 sqrt 2) / 9 exactly.
TEST(GeometryReport, EdgeLengthsCountSharedEdgesOnce) {
  mesh::Mesh m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.tet_region = {0, 0};
  m.regions = {"fluid"};
  const std::vector<EdgeLengths> e = edge_lengths(m);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].edges, 9u);
  const double s2 = std::sqrt(2.0);
  EXPECT_DOUBLE_EQ(e[0].mean, (3 + 6 * s2) / 9);
  EXPECT_DOUBLE_EQ(e[0].median, s2);
  EXPECT_DOUBLE_EQ(e[0].max, s2);
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(GeometryCli, NegativeThicknessExitsWithInputError) {
  TempDir dir("geometry-import");
  const std::string log = (dir.path / "log").string();
  EXPECT_EQ(run(fmt::format("{} geometry tbad --wall-thickness -2 -o {} 2> {}", TEARFLOW_BINARY,
                            (dir.path / "out").string(), log)),
            2);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_THAT(text, HasSubstr("wall thickness (h) is -2 mm, expected a positive number"));
}

TEST(GeometryCli, ReportWritesPictureUnderVirtualX) {
  if (run("command -v xvfb-run > /dev/null") != 0)
    GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const CachedModel m = cached_tbad("OR", kCoarse);
  TempDir dir("geometry-import");
  const fs::path png = dir.path / "model.png";
  ASSERT_EQ(run(fmt::format("xvfb-run -a {} geometry report {} --png {} > {}", TEARFLOW_BINARY,
                            m.dir.string(), png.string(), (dir.path / "out").string())),
            0);
  std::ifstream in(png, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  // A blank 900 x 1400 picture compresses to about 5 kB; the model is far more.
  EXPECT_GT(fs::file_size(png), 50'000u);
  std::ifstream out(dir.path / "out");
  const std::string text((std::istreambuf_iterator<char>(out)), {});
  EXPECT_THAT(text, HasSubstr("tears (mm^2)"));
}

} // namespace
} // namespace tearflow::geometry
