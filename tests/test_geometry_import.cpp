// `geometry import` and `geometry report` through the library and the program: a finished
// mesh goes through unchanged, bad surfaces and landmarks are refused with clear messages,
// and the report draws its picture under a virtual X server.
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "geometry/geometry_report.hpp"
#include "geometry/import.hpp"
#include "mesh/pipe_generator.hpp"
#include "mesh/readers.hpp"
#include "test_geometry_support.hpp"

namespace tearflow::geometry {
namespace {

using namespace testing;
using ::testing::HasSubstr;

struct TempDir {
  fs::path path =
      fs::temp_directory_path() / fmt::format("tearflow-geometry-import-{}", ::getpid());
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};

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

TEST(GeometryImport, NonWatertightSurfaceIsAClearError) {
  TempDir dir;
  const CachedModel m = cached_tbad("OR", kCoarse);
  write_cube_stl(dir.path / "open.stl", 1);
  write_cube_stl(dir.path / "closed.stl", 0);
  ImportOptions o;
  o.landmarks = m.dir / kLandmarksFile;
  o.lumen = dir.path / "open.stl";
  o.wall = dir.path / "closed.stl";
  const std::string e = import_error(o, dir.path / "out");
  EXPECT_THAT(e, HasSubstr("lumen surface '" + o.lumen.string() + "' is not watertight"));
  EXPECT_THAT(e, HasSubstr("3 edges are not shared by exactly two triangles"));
  o.lumen = dir.path / "closed.stl";
  o.wall = dir.path / "open.stl";
  EXPECT_THAT(import_error(o, dir.path / "out"), HasSubstr("wall surface"));
  EXPECT_FALSE(fs::exists(dir.path / "out" / kMeshFile));
}

TEST(GeometryImport, FinishedMeshKeepsRegionsFacesAndLandmarks) {
  TempDir dir;
  const CachedModel m = cached_tbad("OR", kCoarse);
  ImportOptions o;
  o.mesh = m.dir / kMeshFile;
  o.landmarks = m.dir / kLandmarksFile;
  import_geometry(o, dir.path / "out");
  const mesh::Mesh back = read_fsi_mesh(dir.path / "out" / kMeshFile, 1e-3);
  EXPECT_EQ(back.num_nodes(), m.mesh.num_nodes());
  EXPECT_EQ(back.num_tets(), m.mesh.num_tets());
  EXPECT_EQ(back.regions, m.mesh.regions);
  ASSERT_EQ(back.faces.size(), m.mesh.faces.size());
  for (const mesh::Face& f : m.mesh.faces)
    EXPECT_EQ(back.face(f.name).triangles.size(), f.triangles.size()) << f.name;
  const Landmarks l = read_landmarks(dir.path / "out" / kLandmarksFile);
  EXPECT_EQ(l.planes.size(), m.landmarks.planes.size());
}

TEST(GeometryImport, LandmarkOutsideTheFluidIsAnError) {
  TempDir dir;
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
  TempDir dir;
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
  const mesh::Mesh m = read_fsi_mesh(dir.path / "out" / kMeshFile, 1e-3);
  EXPECT_EQ(m.num_tets(), lumen.num_tets() + wall.num_tets());
  const MeshReport r = check_fsi_mesh(m);
  EXPECT_EQ(r.interface_triangles, lumen.face("lumen_wall").triangles.size());
  // Shared nodes: the merged mesh has fewer nodes than the two apart by the interface's.
  EXPECT_EQ(m.num_nodes() + static_cast<Index>(r.interface_nodes),
            lumen.num_nodes() + wall.num_nodes());
  EXPECT_FALSE(m.has_face("wall_inner")) << "the wall's copy of the interface is dropped";
  EXPECT_TRUE(m.has_face("wall_outer"));
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(GeometryCli, NegativeThicknessExitsWithInputError) {
  TempDir dir;
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
  TempDir dir;
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
