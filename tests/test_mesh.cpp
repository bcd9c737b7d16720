// Mesh module: the real SimVascular meshes, the pipe generator, the Gmsh reader, and the
// errors that bad meshes must give (never a crash).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include <gmock/gmock.h>
#include <gmsh.h>
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"
#include "mesh/pipe_generator.hpp"
#include "mesh/readers.hpp"
#include "mesh/region.hpp"

namespace tearflow::mesh {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kMeshes = fs::path(TEARFLOW_SHARED_DIR) / "meshes";
constexpr double pi = std::numbers::pi;

double total_volume(const Mesh& m) {
  double v = 0;
  for (const Tet& t : m.tets)
    v += signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
  return v;
}

double area(const Mesh& m, const std::string& face) {
  double a = 0;
  for (const Tri& t : m.face(face).triangles) {
    const Vec3 n = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    a += 0.5 * std::sqrt(dot(n, n));
  }
  return a;
}

std::vector<std::string> face_names(const Mesh& m) {
  std::vector<std::string> names;
  for (const Face& f : m.faces)
    names.push_back(f.name);
  return names;
}

// Independent of check_mesh: the boundary (tet faces seen once) by a plain global sort. Checks
// that every face triangle is on it and the named faces cover it exactly once.
void expect_faces_tile_boundary(const Mesh& m) {
  std::vector<Tri> all;
  for (const Tet& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) {
      Tri f{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip)
          f[j++] = t[k];
      std::sort(f.begin(), f.end());
      all.push_back(f);
    }
  std::sort(all.begin(), all.end());
  std::vector<Tri> boundary;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    while (j < all.size() && all[j] == all[i])
      ++j;
    if (j - i == 1)
      boundary.push_back(all[i]);
    i = j;
  }
  std::vector<Tri> named;
  for (const Face& f : m.faces)
    for (Tri t : f.triangles) {
      std::sort(t.begin(), t.end());
      named.push_back(t);
    }
  std::sort(named.begin(), named.end());
  EXPECT_EQ(named, boundary) << m.source;
}

// A fresh empty temporary directory, removed at the end of the test.
class TempDir {
public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("tearflow_test_mesh_" + std::to_string(std::random_device{}()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

private:
  fs::path path_;
};

// Error messages must say what is wrong and where.
template <typename F> void expect_input_error(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no InputError; expected one mentioning '" << parts.front() << "'";
  } catch (const InputError& e) {
    for (const std::string& p : parts)
      EXPECT_THAT(e.what(), HasSubstr(p));
  }
}

TEST(MeshSimVascular, PipeRcrWithGlobalNodeIds) {
  const Mesh m = read_simvascular(kMeshes / "pipe-rcr", 0.01);
  EXPECT_EQ(m.num_nodes(), 30211);
  EXPECT_EQ(m.num_tets(), 170694);
  EXPECT_THAT(face_names(m), ::testing::ElementsAre("lumen_inlet", "lumen_outlet", "lumen_wall"));
  EXPECT_EQ(m.regions, std::vector<std::string>{"fluid"});
  expect_faces_tile_boundary(m);
  // 1%: the mesh's polygonal circle loses 0.6% of the disk's area.
  EXPECT_NEAR(area(m, "lumen_inlet"), pi * 0.02 * 0.02, 0.01 * pi * 0.02 * 0.02);
  EXPECT_NEAR(total_volume(m), pi * 0.02 * 0.02 * 0.3, 0.01 * pi * 0.02 * 0.02 * 0.3);
}

TEST(MeshSimVascular, PipeFsiMatchedByCoordinates) {
  const Mesh lumen = read_simvascular(kMeshes / "pipe-fsi" / "lumen", 0.01);
  EXPECT_EQ(lumen.num_nodes(), 38214);
  EXPECT_EQ(lumen.num_tets(), 204705);
  EXPECT_THAT(face_names(lumen),
              ::testing::ElementsAre("lumen_inlet", "lumen_outlet", "lumen_wall"));
  expect_faces_tile_boundary(lumen);
  EXPECT_NEAR(total_volume(lumen), pi * 1e-4 * 0.1, 0.01 * pi * 1e-4 * 0.1);

  const Mesh wall = read_simvascular(kMeshes / "pipe-fsi" / "wall", 0.01, "wall");
  EXPECT_EQ(wall.num_nodes(), 22377);
  EXPECT_EQ(wall.num_tets(), 85220);
  // Faces come in file-name order (directory order is unspecified).
  EXPECT_THAT(face_names(wall),
              ::testing::ElementsAre("wall_inlet", "wall_inner", "wall_outer", "wall_outlet"));
  EXPECT_EQ(wall.regions, std::vector<std::string>{"wall"});
  expect_faces_tile_boundary(wall);
  const double wall_volume = pi * (0.012 * 0.012 - 0.01 * 0.01) * 0.1;
  EXPECT_NEAR(total_volume(wall), wall_volume, 0.01 * wall_volume);
  // The README says wall_inner coincides node for node with lumen_wall.
  EXPECT_EQ(wall.face("wall_inner").triangles.size(), lumen.face("lumen_wall").triangles.size());
  EXPECT_NEAR(area(wall, "wall_inner"), area(lumen, "lumen_wall"), 1e-9);
}

TEST(MeshSimVascular, DispatchAndUnits) {
  const Mesh cm = read_mesh(kMeshes / "pipe-fsi" / "wall", 1.0); // kept in file units
  const Mesh m = read_mesh(kMeshes / "pipe-fsi" / "wall", 0.01);
  EXPECT_NEAR(total_volume(cm) * 1e-6, total_volume(m), 1e-12);
}

// Tolerance for the pipe: Gmsh puts about n = 2 pi R / h nodes on the circle, and the
// inscribed polygon has (h/R)^2 / 6 less area than the disk: 0.7% at h = R/5. Volume and cap
// areas get 1%; the wall (perimeter error (h/R)^2 / 24) gets 1% too.
TEST(MeshPipe, VolumeAndFaceAreas) {
  const PipeSpec spec{0.01, 0.1, 0.002};
  const Mesh m = make_pipe(spec);
  EXPECT_GT(m.num_tets(), 10000);
  EXPECT_EQ(m.regions, std::vector<std::string>{"fluid"});
  EXPECT_THAT(face_names(m), ::testing::ElementsAre("inlet", "outlet", "wall"));
  const double disk = pi * spec.radius * spec.radius;
  EXPECT_NEAR(total_volume(m), disk * spec.length, 0.01 * disk * spec.length);
  EXPECT_NEAR(area(m, "inlet"), disk, 0.01 * disk);
  EXPECT_NEAR(area(m, "outlet"), disk, 0.01 * disk);
  const double lateral = 2 * pi * spec.radius * spec.length;
  EXPECT_NEAR(area(m, "wall"), lateral, 0.01 * lateral);
  for (const Tri& t : m.face("inlet").triangles)
    for (Index n : t)
      EXPECT_NEAR(m.points[n][2], 0.0, 1e-12);
  for (const Tri& t : m.face("outlet").triangles)
    for (Index n : t)
      EXPECT_NEAR(m.points[n][2], spec.length, 1e-12);
  expect_faces_tile_boundary(m);
  std::vector<bool> used(m.points.size(), false); // every node belongs to a tet
  for (const Tet& t : m.tets)
    for (Index n : t)
      used[n] = true;
  EXPECT_TRUE(std::all_of(used.begin(), used.end(), [](bool u) { return u; }));
}

// The pipe with boundary layers is an extruded polygonal section, so its volumes and the
// interface's area are those of the n-gon prisms exactly (n = 4 quarter arcs of
// ceil(pi a / (2 h)) segments each; rounding only), and the layer at the wall has the
// requested thickness at the section's nodes, which lie on the spokes of the transfinite ring.
TEST(MeshPipe, BoundaryLayersAtTheWall) {
  PipeSpec spec{0.005, 0.02, 0.0015, 0.001};
  spec.layers = {6, 1.5e-4, 1.5, 3};
  const Mesh m = make_pipe(spec);
  EXPECT_THAT(m.regions, ::testing::ElementsAre("fluid", "wall"));
  EXPECT_THAT(face_names(m), ::testing::ElementsAre("inlet", "interface", "outer_wall", "outlet",
                                                    "wall_inlet", "wall_outlet"));
  const int n = 4 * static_cast<int>(std::ceil(0.5 * pi * spec.radius / spec.element_size));
  auto polygon = [n](double r) { return 0.5 * n * r * r * std::sin(2 * pi / n); };
  const double a = spec.radius, b = a + spec.wall_thickness, L = spec.length;
  double volume[2] = {0.0, 0.0};
  for (size_t e = 0; e < m.tets.size(); ++e) {
    const Tet& t = m.tets[e];
    volume[m.tet_region[e]] +=
        signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
  }
  EXPECT_NEAR(volume[0], polygon(a) * L, 1e-9 * polygon(a) * L);
  EXPECT_NEAR(volume[1], (polygon(b) - polygon(a)) * L, 1e-9 * polygon(b) * L);
  const double perimeter = 2 * n * a * std::sin(pi / n);
  EXPECT_NEAR(area(m, "interface"), perimeter * L, 1e-9 * perimeter * L);
  // Thinnest gap between the wall and a lumen node inside it: the first layer.
  std::vector<bool> in_wall(m.points.size(), false);
  for (size_t e = 0; e < m.tets.size(); ++e)
    for (Index v : m.tets[e])
      if (m.tet_region[e] == 1)
        in_wall[v] = true;
  double gap = 1.0;
  for (size_t v = 0; v < m.points.size(); ++v)
    if (!in_wall[v])
      gap = std::min(gap, a - std::hypot(m.points[v][0], m.points[v][1]));
  EXPECT_NEAR(gap, spec.layers.first, 1e-6 * spec.layers.first);
  // The interface's nodes are shared: each is a node of a lumen tet and of a wall tet.
  std::vector<bool> in_fluid(m.points.size(), false);
  for (size_t e = 0; e < m.tets.size(); ++e)
    for (Index v : m.tets[e])
      if (m.tet_region[e] == 0)
        in_fluid[v] = true;
  for (const Tri& t : m.face("interface").triangles)
    for (Index v : t)
      EXPECT_TRUE(in_fluid[v] && in_wall[v]);

  PipeSpec thick = spec;
  thick.layers = {12, 5e-4, 1.5, 3}; // a ring of 0.13 m in a 5 mm lumen
  expect_input_error([&] { make_pipe(thick); }, {"boundary layers", "thinner than 0.7"});
}

TEST(MeshPipe, RejectsBadSpecs) {
  expect_input_error([] { make_pipe({-0.01, 0.1, 0.002}); }, {"radius (-0.01 m)", "positive"});
  expect_input_error([] { make_pipe({0.01, 0.0, 0.002}); }, {"length (0 m)", "positive"});
  expect_input_error([] { make_pipe({0.01, 0.1, std::nan("")}); }, {"must be positive"});
  expect_input_error([] { make_pipe({0.01, 0.1, 1e-5}); }, {"1e-05 m", "more than the 20 M"});
  // Larger than the pipe (the probe's case ran without a word).
  expect_input_error([] { make_pipe({0.005, 0.1, 0.011}); },
                     {"element_size 0.011 m exceeds the diameter 0.01 m"});
}

TEST(MeshGmsh, RoundTripThroughMshFile) {
  TempDir tmp;
  const fs::path file = tmp.path() / "pipe.msh";
  const Mesh made = make_pipe({0.01, 0.05, 0.004}, file);
  const Mesh read = read_gmsh(file, 1.0);
  EXPECT_EQ(read.num_nodes(), made.num_nodes());
  EXPECT_EQ(read.num_tets(), made.num_tets());
  EXPECT_EQ(read.regions, made.regions);
  ASSERT_EQ(face_names(read), face_names(made));
  for (const Face& f : made.faces)
    EXPECT_EQ(read.face(f.name).triangles.size(), f.triangles.size());
  EXPECT_NEAR(total_volume(read), total_volume(made), 1e-12);
  expect_faces_tile_boundary(read);
  // Units and dispatch: the same file read as millimetres.
  const Mesh mm = read_mesh(file, 1e-3);
  EXPECT_NEAR(total_volume(mm), 1e-9 * total_volume(made), 1e-18);
}

TEST(MeshErrors, MissingFilesAndDirectories) {
  TempDir tmp;
  expect_input_error([&] { read_gmsh(tmp.path() / "nope.msh", 1.0); }, {"nope.msh", "not found"});
  expect_input_error([&] { read_mesh(tmp.path() / "nope.msh", 1.0); }, {"nope.msh", "not found"});
  expect_input_error([&] { read_mesh(tmp.path() / "nope", 1.0); }, {"nope", "not found"});
  expect_input_error([&] { read_simvascular(tmp.path(), 1.0); },
                     {tmp.path().string(), "mesh-complete.mesh.vtu"});
  fs::create_symlink(kMeshes / "pipe-rcr" / "mesh-complete.mesh.vtu",
                     tmp.path() / "mesh-complete.mesh.vtu");
  expect_input_error([&] { read_simvascular(tmp.path(), 1.0); }, {"mesh-surfaces"});
  std::ofstream(tmp.path() / "mesh.txt") << "hello\n";
  expect_input_error([&] { read_mesh(tmp.path() / "mesh.txt", 1.0); },
                     {"mesh.txt", "unknown format"});
}

TEST(MeshErrors, CorruptFiles) {
  TempDir tmp;
  std::ofstream(tmp.path() / "bad.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\nxx\n";
  expect_input_error([&] { read_gmsh(tmp.path() / "bad.msh", 1.0); }, {"bad.msh", "Gmsh"});
  // Gmsh stays usable after an error inside gmsh::open.
  make_pipe({0.01, 0.05, 0.005}, tmp.path() / "ok.msh");
  EXPECT_GT(read_gmsh(tmp.path() / "ok.msh", 1.0).num_tets(), 0);
  // A negative node tag in an element crashes Gmsh 4.8 itself; the reader must catch it first.
  std::ifstream in(tmp.path() / "ok.msh");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::size_t end = text.find("\n$EndElements");
  ASSERT_NE(end, std::string::npos);
  text.replace(text.rfind(' ', end - 2) + 1, 1, "-"); // the last node tag becomes negative
  std::ofstream(tmp.path() / "negative.msh") << text;
  expect_input_error([&] { read_gmsh(tmp.path() / "negative.msh", 1.0); },
                     {"negative.msh", "unexpected '-'"});

  const fs::path dir = tmp.path() / "svmesh";
  fs::create_directories(dir / "mesh-surfaces");
  {
    std::ifstream in(kMeshes / "pipe-rcr" / "mesh-complete.mesh.vtu", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "mesh-complete.mesh.vtu", std::ios::binary)
        << bytes.substr(0, bytes.size() / 2);
  }
  fs::copy(kMeshes / "pipe-rcr" / "mesh-surfaces" / "lumen_inlet.vtp", dir / "mesh-surfaces");
  expect_input_error([&] { read_simvascular(dir, 1.0); },
                     {"mesh-complete.mesh.vtu", "could not be read"});
}

TEST(MeshErrors, HigherOrderGmshElements) {
  TempDir tmp;
  const fs::path file = tmp.path() / "p2.msh";
  {
    GmshSession session;
    gmsh::model::add("p2");
    gmsh::model::occ::addBox(0, 0, 0, 1, 1, 1);
    gmsh::model::occ::synchronize();
    gmsh::option::setNumber("Mesh.MeshSizeMax", 0.5);
    gmsh::option::setNumber("Mesh.ElementOrder", 2);
    gmsh::option::setNumber("Mesh.SaveAll", 1);
    gmsh::model::mesh::generate(3);
    gmsh::write(file.string());
  }
  expect_input_error([&] { read_gmsh(file, 1.0); }, {"p2.msh", "Tetrahedron 10", "only linear"});
}

class MeshBrokenPipe : public ::testing::Test {
protected:
  static void SetUpTestSuite() { pipe_ = new Mesh(make_pipe({0.01, 0.04, 0.004})); }
  static void TearDownTestSuite() { delete pipe_; }
  static Mesh* pipe_;
  Mesh m = *pipe_;
};
Mesh* MeshBrokenPipe::pipe_ = nullptr;

TEST_F(MeshBrokenPipe, InvertedElement) {
  std::swap(m.tets[7][0], m.tets[7][1]);
  expect_input_error([&] { check_mesh(m); }, {"inverted element", "tet 7", m.source});
}

TEST_F(MeshBrokenPipe, DegenerateElement) {
  m.tets[3][3] = m.tets[3][0]; // a repeated node: zero volume
  expect_input_error([&] { check_mesh(m); }, {"degenerate element", "tet 3"});
}

TEST_F(MeshBrokenPipe, FaceTriangleNotOnBoundary) {
  std::vector<bool> on_boundary(m.points.size(), false);
  for (const Face& f : m.faces)
    for (const Tri& t : f.triangles)
      for (Index n : t)
        on_boundary[n] = true;
  const auto inner = std::find_if(m.tets.begin(), m.tets.end(), [&](const Tet& t) {
    return std::none_of(t.begin(), t.end(), [&](Index n) { return on_boundary[n]; });
  });
  ASSERT_NE(inner, m.tets.end());
  m.faces[0].triangles[2] = {(*inner)[0], (*inner)[1], (*inner)[2]};
  expect_input_error([&] { check_mesh(m); },
                     {"face 'inlet'", "triangle 2", "inside a region", "boundary"});
  // The same triangle between two regions is an interface (the fluid-wall face of an FSI
  // mesh) and may carry a name.
  m.regions.push_back("wall");
  m.tet_region[static_cast<size_t>(inner - m.tets.begin())] = 1;
  EXPECT_NO_THROW(check_mesh(m));
  m.tet_region[static_cast<size_t>(inner - m.tets.begin())] = 0;
  m.faces[0].triangles[2] = {0, 1, 2};
  expect_input_error([&] { check_mesh(m); }, {"face 'inlet'", "not a face of any tet"});
}

TEST_F(MeshBrokenPipe, NamesAndIndices) {
  expect_input_error([&] { (void)m.face("outflow"); },
                     {"no face 'outflow'", "'inlet'", "'outlet'", "'wall'"});
  EXPECT_TRUE(m.has_face("wall"));
  EXPECT_FALSE(m.has_face("outflow"));
  m.faces[1].name = "inlet";
  expect_input_error([&] { check_mesh(m); }, {"'inlet'", "used twice"});
  m.faces[1].name = "";
  expect_input_error([&] { check_mesh(m); }, {"empty name"});
  m = *pipe_;
  m.tets[11][2] = m.num_nodes();
  expect_input_error([&] { check_mesh(m); }, {"tet 11", "node indices"});
  m = *pipe_;
  m.tet_region[4] = 1;
  expect_input_error([&] { check_mesh(m); }, {"tet 4", "region index 1"});
}

TEST_F(MeshBrokenPipe, OverlappingTets) {
  m.tets.push_back(m.tets[20]); // its interior faces are now shared by three tets
  m.tet_region.push_back(0);
  expect_input_error([&] { check_mesh(m); }, {"shared by more than two tets"});
}

// A mesh-complete directory written from a Mesh, to test the SimVascular reader's handling
// of orientation, node matching and non-triangle faces.
void write_mesh_complete(const Mesh& m, const fs::path& dir, bool with_ids,
                         const std::vector<Tet>& tets) {
  fs::create_directories(dir / "mesh-surfaces");
  vtkNew<vtkPoints> points;
  for (const Vec3& p : m.points)
    points->InsertNextPoint(p.data());
  vtkNew<vtkIntArray> ids;
  ids->SetName("GlobalNodeID");
  for (Index i = 0; i < m.num_nodes(); ++i)
    ids->InsertNextValue(i + 1);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  for (const Tet& t : tets) {
    const vtkIdType c[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, c);
  }
  if (with_ids)
    grid->GetPointData()->AddArray(ids);
  vtkNew<vtkXMLUnstructuredGridWriter> w;
  w->SetInputData(grid);
  w->SetFileName((dir / "mesh-complete.mesh.vtu").c_str());
  w->Write();
  for (const Face& f : m.faces) { // faces share all volume points: simple, and valid
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    vtkNew<vtkCellArray> tris;
    for (const Tri& t : f.triangles) {
      const vtkIdType c[3] = {t[0], t[1], t[2]};
      tris->InsertNextCell(3, c);
    }
    poly->SetPolys(tris);
    if (with_ids)
      poly->GetPointData()->AddArray(ids);
    vtkNew<vtkXMLPolyDataWriter> pw;
    pw->SetInputData(poly);
    pw->SetFileName((dir / "mesh-surfaces" / (f.name + ".vtp")).c_str());
    pw->Write();
  }
}

TEST_F(MeshBrokenPipe, SimVascularOrientation) {
  TempDir tmp;
  std::vector<Tet> flipped = m.tets;
  for (Tet& t : flipped)
    std::swap(t[0], t[1]);
  write_mesh_complete(m, tmp.path() / "all_negative", true, flipped);
  const Mesh fixed = read_simvascular(tmp.path() / "all_negative", 1.0);
  // All flipped back (positive total); 1e-6 as VTK stored the points as Float32.
  EXPECT_NEAR(total_volume(fixed), total_volume(m), 1e-6 * total_volume(m));
  std::vector<Tet> mixed = m.tets;
  std::swap(mixed[9][0], mixed[9][1]);
  write_mesh_complete(m, tmp.path() / "mixed", false, mixed);
  expect_input_error([&] { read_simvascular(tmp.path() / "mixed", 1.0); },
                     {"inverted element", "tet 9"});
}

TEST_F(MeshBrokenPipe, SimVascularFaceNodeMatchesNothing) {
  TempDir tmp;
  for (Vec3& p : m.points)
    p = 100.0 * p; // centimetres, like the real files
  write_mesh_complete(m, tmp.path(), false, m.tets);
  auto write_stray = [&](std::vector<Vec3> xs) {
    vtkNew<vtkPoints> points;
    for (const Vec3& x : xs)
      points->InsertNextPoint(x.data());
    vtkNew<vtkCellArray> polys;
    std::vector<vtkIdType> ids(xs.size());
    for (std::size_t i = 0; i < ids.size(); ++i)
      ids[i] = static_cast<vtkIdType>(i);
    polys->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetPolys(polys);
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(poly);
    w->SetFileName((tmp.path() / "mesh-surfaces" / "stray.vtp").c_str());
    w->Write();
  };
  write_stray({m.points[0], {50, 0, 0}, m.points[1]}); // point 1 is far outside the pipe
  expect_input_error([&] { read_simvascular(tmp.path(), 0.01); },
                     {"face 'stray'", "point 1", "matches no node"});
  write_stray({m.points[0], m.points[1], m.points[2], m.points[3]}); // a quadrangle
  expect_input_error([&] { read_simvascular(tmp.path(), 0.01); },
                     {"face 'stray'", "polygon 0", "triangles only"});
}

TEST_F(MeshBrokenPipe, ExtractRegionKeepsTheFacesThatBoundIt) {
  // Two regions split at mid-length: "fluid" below, "wall" above.
  m.regions = {"fluid", "wall"};
  int fluid_tets = 0;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    double z = 0.0;
    for (Index n : m.tets[t])
      z += 0.25 * m.points[n][2];
    m.tet_region[t] = z < 0.02 ? 0 : 1;
    fluid_tets += z < 0.02;
  }
  const Mesh f = extract_region(m, "fluid");
  EXPECT_EQ(f.num_tets(), fluid_tets);
  EXPECT_EQ(f.regions, std::vector<std::string>{"fluid"});
  EXPECT_NO_THROW(check_mesh(f));
  // The inlet (z = 0) is all fluid; the outlet (z = L) bounds only the other region.
  EXPECT_EQ(f.face("inlet").triangles.size(), m.face("inlet").triangles.size());
  EXPECT_FALSE(f.has_face("outlet"));
  EXPECT_TRUE(f.has_face("wall"));
  EXPECT_LT(f.face("wall").triangles.size(), m.face("wall").triangles.size());
  expect_input_error([&] { (void)extract_region(m, "lumen"); },
                     {"no volume region 'lumen'", "'fluid'", "'wall'"});
}

} // namespace
} // namespace tearflow::mesh
