// `geometry labels`: a dissection rebuilt from a label map. No patient data ships, so the
// built-in model is voxelized (geometry/voxelize.hpp) and rebuilt, and the rebuilt model is
// compared with the built one on the same planes: lumen volume, the lumen's area at every
// landmark, the tears' areas and places, the landmarks' places.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/import.hpp"
#include "geometry/label_map.hpp"
#include "geometry/label_model.hpp"
#include "geometry/sections.hpp"
#include "geometry/voxelize.hpp"
#include "test_geometry_support.hpp"

namespace tearflow::geometry {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;
constexpr double mm = 1e-3, mm2 = 1e-6;

double region_volume(const mesh::Mesh& m, const std::string& region, const LabelModel* clip) {
  const int r = region_index(m, region);
  double v = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (m.tet_region[t] != r)
      continue;
    const Tet& k = m.tets[t];
    const Vec3 c = 0.25 * (m.points[k[0]] + m.points[k[1]] + m.points[k[2]] + m.points[k[3]]);
    bool kept = true;
    if (clip)
      for (const LabelCap& cap : clip->caps) {
        const Vec3 d = c - cap.centre;
        const double along = dot(d, cap.normal);
        kept = kept && !(along > 0 && dot(d, d) - along * along < cap.reach * cap.reach);
      }
    if (kept)
      v += mesh::signed_volume(m.points[k[0]], m.points[k[1]], m.points[k[2]], m.points[k[3]]);
  }
  return v;
}

// The area of the landmark's plane within 30 mm of its origin where `inside(x)`, sampled
// every 0.1 mm.
template <typename Inside> double plane_area(const Landmark& l, Inside&& inside) {
  const Vec3 n = l.normal, any = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 e1 = cross(n, any);
  e1 = (1 / std::sqrt(dot(e1, e1))) * e1;
  const Vec3 e2 = cross(n, e1);
  const double step = 0.1e-3;
  double area = 0;
  for (int a = -300; a <= 300; ++a)
    for (int b = -300; b <= 300; ++b)
      if (inside(l.origin + (a * step) * e1 + (b * step) * e2))
        area += step * step;
  return area;
}

// The lumen's area at a landmark as the fields say (before meshing): in the fluid, on the
// landmark's side of the flap.
double field_area(const LabelledDissection& d, const Landmark& l) {
  return plane_area(l, [&](const Vec3& x) {
    if (d.label(x) != LabelledDissection::fluid)
      return false;
    const double w = d.true_lumen(x) - d.false_lumen(x);
    return l.lumen == "aorta" || (l.lumen == "TL") == (w < 0);
  });
}

// The lumen's area at a landmark as the label map holds it: each sample takes its nearest
// voxel's label (what the segmentation says, before any reconstruction; in an axis-aligned
// map its flap sits up to half a voxel off the built one).
double label_map_area(const LabelMap& map, const LabelRoles& roles, const Landmark& l) {
  return plane_area(l, [&](const Vec3& x) {
    const Vec3 c = map.grid.index(x);
    std::array<int, 3> i{};
    for (int k = 0; k < 3; ++k) {
      i[k] = static_cast<int>(std::lround(c[k]));
      if (i[k] < 0 || i[k] >= map.grid.size[k])
        return false;
    }
    const int label = map.labels[map.grid.linear(i[0], i[1], i[2])];
    const bool tl = label == roles.true_lumen, fl = label == roles.false_lumen;
    return l.lumen == "aorta" ? (tl || fl) : l.lumen == "TL" ? tl : fl;
  });
}

struct RoundTrip {
  testing::CachedModel built;
  LabelModel rebuilt;
  std::map<std::string, double> field_areas, label_areas;
  double volume_built = 0, volume_rebuilt = 0; // fluid between the rebuilt model's caps
};

RoundTrip round_trip(const std::string& variant, double spacing, const Vec3& rotation,
                     bool thrombus = false, double element_size = 3e-3) {
  testing::TempDir dir("geometry-labels");
  RoundTrip r{testing::cached_tbad(variant, testing::kCoarse), {}};
  VoxelizeOptions vo;
  vo.spacing = spacing;
  vo.rotation = rotation;
  vo.thrombus = thrombus;
  voxelize_geometry(r.built.dir, vo, dir.path / "labels.nii.gz");
  LabelModelOptions o;
  o.element_size = element_size;
  if (thrombus)
    o.dissection.roles.thrombus = 3;
  const LabelMap map = read_label_map(dir.path / "labels.nii.gz");
  r.rebuilt = build_label_model(map, o);
  const LabelledDissection fields(map, o.dissection);
  for (const std::string& name : area_landmark_names()) {
    r.field_areas[name] = field_area(fields, r.built.landmarks.plane(name));
    r.label_areas[name] = label_map_area(map, o.dissection.roles, r.built.landmarks.plane(name));
  }
  write_geometry(r.rebuilt.mesh, r.rebuilt.landmarks, dir.path / "model"); // checks it
  r.volume_built = region_volume(r.built.mesh, "fluid", &r.rebuilt);
  r.volume_rebuilt = region_volume(r.rebuilt.mesh, "fluid", nullptr);
  return r;
}

// The checks every round trip makes; `area_tol` and `tear_tol` relative. Prints the table.
// `aligned_spacing`: the voxel size of a map whose axes are the built model's (0 for an
// oblique one). The built flap is a plane x = const; sampled by voxel centres on the same
// axes its faces land anywhere within half a voxel of where they are, the same way along the
// whole flap, so a lumen's area at a station moves by up to s/2 times the flap's width (at
// most the vessel's diameter): what the labels hold, before any reconstruction. That is
// added to the tolerance of the TL and FL planes.
void expect_same_model(const RoundTrip& r, double area_tol, double tear_tol,
                       double aligned_spacing = 0) {
  const mesh::Mesh &a = r.built.mesh, &b = r.rebuilt.mesh;
  fmt::print("fluid volume between the caps: built {:.1f} mL, rebuilt {:.1f} mL ({:+.2f} %)\n",
             r.volume_built * 1e6, r.volume_rebuilt * 1e6,
             100 * (r.volume_rebuilt / r.volume_built - 1));
  // Lumen volume: the 3 %.
  EXPECT_NEAR(r.volume_rebuilt / r.volume_built, 1.0, 0.03);
  fmt::print("{:>9} {:>9} {:>9} {:>8} {:>9} {:>8} {:>9} {:>8} {:>12}\n", "landmark", "built",
             "rebuilt", "diff", "fields", "diff", "labels", "diff", "placed [mm]");
  for (const std::string& name : area_landmark_names()) {
    const Landmark& l = r.built.landmarks.plane(name);
    const double a0 = landmark_area(a, l), a1 = landmark_area(b, l);
    const Vec3 moved = r.rebuilt.landmarks.plane(name).origin - l.origin;
    const double af = r.field_areas.at(name), al = r.label_areas.at(name);
    fmt::print("{:>9} {:9.1f} {:9.1f} {:+7.2f}% {:9.1f} {:+7.2f}% {:9.1f} {:+7.2f}% {:12.1f}\n",
               name, a0 / mm2, a1 / mm2, 100 * (a1 / a0 - 1), af / mm2, 100 * (af / a0 - 1),
               al / mm2, 100 * (al / a0 - 1), std::sqrt(dot(moved, moved)) / mm);
    double tol = area_tol * a0;
    if (l.lumen != "aorta") {
      const std::string k = name.substr(2);
      const double both = landmark_area(a, r.built.landmarks.plane("TL" + k)) +
                          landmark_area(a, r.built.landmarks.plane("FL" + k));
      tol += 0.5 * aligned_spacing * 2 * std::sqrt(both / std::numbers::pi);
    }
    EXPECT_NEAR(a1, a0, tol) << name;
    // Against what the map holds: the 5 % whatever the map's axes. (Nearest-voxel
    // sampling moves an outline by up to half a voxel either way; along a curved outline the
    // two signs alternate and cancel, along an aligned flap they do not, and that is the map.)
    EXPECT_NEAR(a1, al, area_tol * al) << name << " against the label map's own area";
  }
  for (const TearLandmark& t : r.built.landmarks.tears) {
    const TearLandmark& u = r.rebuilt.landmarks.tear(t.name);
    const Vec3 moved = u.centroid - t.centroid;
    const double on_mesh = tear_area(b, u);
    fmt::print("tear {}: built {:.1f} mm^2, rebuilt {:.1f} mm^2 on the mesh ({:+.2f} %), {:.1f} "
               "in the fields; centroid {:.2f} mm apart\n",
               t.name, t.area / mm2, on_mesh / mm2, 100 * (on_mesh / t.area - 1), u.area / mm2,
               std::sqrt(dot(moved, moved)) / mm);
    fmt::print(
        "  normal ({:.3f} {:.3f} {:.3f}) vs ({:.3f} {:.3f} {:.3f}); semi-axes {:.2f} x {:.2f} "
        "vs {:.2f} x {:.2f} mm\n",
        u.normal[0], u.normal[1], u.normal[2], t.normal[0], t.normal[1], t.normal[2], u.axial / mm,
        u.across / mm, t.axial / mm, t.across / mm);
    EXPECT_NEAR(on_mesh / t.area, 1.0, tear_tol) << t.name;
    // The same tear at the same place: within a third of its short semi-axis.
    EXPECT_LT(std::sqrt(dot(moved, moved)), t.across / 3) << t.name;
  }
  EXPECT_EQ(r.rebuilt.landmarks.tears.size(), r.built.landmarks.tears.size());
  for (const RegionQuality& q : check_fsi_mesh(b).regions) {
    fmt::print("{}: {} tets, min radius ratio {:.3f}\n", q.name, q.tets, q.min_quality);
    // As for imported surfaces (test_geometry_import.cpp): below 0.01 a tet is a sliver that
    // would ruin the solid's conditioning.
    EXPECT_GT(q.min_quality, 0.01) << q.name;
  }
  std::fflush(stdout); // the full table runs for many minutes: show each case as it ends
}

// CI: the OR model at 1 mm in an oblique image.
TEST(GeometryLabels, ObliqueOneMillimetreMapRebuildsTheModel) {
  const RoundTrip r = round_trip("OR", 1e-3, {20, -15, 30});
  expect_same_model(r, 0.05, 0.15);
  std::vector<std::string> caps;
  for (const LabelCap& c : r.rebuilt.caps)
    caps.push_back(c.name);
  EXPECT_THAT(caps, ::testing::ElementsAre("inlet", "BCT", "LCC", "LSA", "outlet"));
}

fs::path test_data_dir() {
  return tearflow::testing::test_data;
}

// The round-trip table (docs/geometry.md): every variant at 1 and 0.7 mm, axis-aligned and
// oblique, and OR with thrombus (axis-aligned maps: the sampling's own error added to the
// TL/FL planes' tolerance, expect_same_model). Minutes: `ctest -L verification-full`
// (geometry.labels.full, which sets TEARFLOW_GEOMETRY_FULL); skipped otherwise. Tolerances: the
// issue's (volume 3 %, areas 5 %, tears 10 % at 0.7 mm); at 1 mm the tears 15 % (the rim's voxels
// are 1.4 times larger; measured within 3 % at both).
TEST(GeometryLabelsFull, EveryVariantRoundTripsAtBothSpacingsAndOrientations) {
  if (!std::getenv("TEARFLOW_GEOMETRY_FULL"))
    GTEST_SKIP() << "set TEARFLOW_GEOMETRY_FULL=1 (ctest -L verification-full) for the table";
  for (const char* variant : {"OR", "EN", "EX"})
    for (double spacing : {1e-3, 0.7e-3})
      for (const Vec3& rotation : {Vec3{0, 0, 0}, Vec3{20, -15, 30}}) {
        fmt::print("\n== {} at {} mm, rotated ({}, {}, {}) degrees\n", variant, spacing / mm,
                   rotation[0], rotation[1], rotation[2]);
        SCOPED_TRACE(fmt::format("{} {} mm ({}, {}, {})", variant, spacing / mm, rotation[0],
                                 rotation[1], rotation[2]));
        expect_same_model(round_trip(variant, spacing, rotation), 0.05,
                          spacing < 0.8e-3 ? 0.10 : 0.15, rotation[0] == 0 ? spacing : 0.0);
      }
  fmt::print("\n== OR with thrombus at 1 mm, rotated\n");
  const RoundTrip r = round_trip("OR", 1e-3, {20, -15, 30}, true);
  expect_same_model(r, 0.05, 0.15);
}

// The CI model's label map at 1 mm, written once per test process.
fs::path ci_label_map(const fs::path& dir) {
  const fs::path file = dir / "labels.nii.gz";
  if (!fs::exists(file)) {
    VoxelizeOptions vo;
    vo.rotation = {20, -15, 30};
    voxelize_geometry(testing::cached_tbad("OR", testing::kCoarse).dir, vo, file);
  }
  return file;
}

// A tear resized (the option `--entry-tear-area`): the reference study's EN entry tear,
// 62 mm^2, cut from the OR map's 228, measured on the mesh within the 10 % the round trip
// allows a tear.
TEST(GeometryLabels, EntryTearIsResizedToTheStudysEnArea) {
  testing::TempDir dir("geometry-labels-resize");
  LabelModelOptions o;
  o.element_size = 4.5e-3;
  o.tear_areas = {{"entry", 62e-6}};
  const LabelModel m = build_label_model(read_label_map(ci_label_map(dir.path)), o);
  const TearLandmark& entry = m.landmarks.tear("entry");
  const double on_mesh = tear_area(m.mesh, entry);
  fmt::print("entry tear resized to {:.1f} mm^2 (fields), {:.1f} mm^2 on the mesh; exit {:.1f}\n",
             entry.area / mm2, on_mesh / mm2, tear_area(m.mesh, m.landmarks.tear("exit")) / mm2);
  EXPECT_NEAR(entry.area / 62e-6, 1.0, 0.01); // the bisection's own tolerance
  EXPECT_NEAR(on_mesh / 62e-6, 1.0, 0.10);
  EXPECT_NEAR(tear_area(m.mesh, m.landmarks.tear("exit")) / 227e-6, 1.0, 0.10);
}

std::string build_error(const LabelMap& map, const LabelModelOptions& o = {}) {
  try {
    build_label_model(map, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string read_error(const fs::path& file) {
  try {
    read_label_map(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GeometryLabels, BadLabelMapsAreClearErrors) {
  testing::TempDir dir("geometry-labels-bad");
  const fs::path good = ci_label_map(dir.path);
  EXPECT_THAT(read_error(dir.path / "none.nii.gz"), HasSubstr("no such file"));
  {
    std::ofstream(dir.path / "text.nii") << "not an image\n";
    EXPECT_THAT(read_error(dir.path / "text.nii"), HasSubstr("cannot be read"));
    std::ofstream(dir.path / "labels.png") << "x";
    EXPECT_THAT(read_error(dir.path / "labels.png"), HasSubstr("not an image ITK can read"));
  }
  { // cut short: the first half of the uncompressed file
    const LabelMap map = read_label_map(good);
    write_label_map(map, dir.path / "whole.nii");
    const auto size = fs::file_size(dir.path / "whole.nii");
    fs::copy_file(dir.path / "whole.nii", dir.path / "cut.nii");
    fs::resize_file(dir.path / "cut.nii", size / 2);
    EXPECT_THAT(read_error(dir.path / "cut.nii"), HasSubstr("cut short"));
  }
  const LabelMap map = read_label_map(good);
  { // a label that is not there: the message lists the labels present
    LabelModelOptions o;
    o.dissection.roles.false_lumen = 5;
    const std::string e = build_error(map, o);
    EXPECT_THAT(e, HasSubstr("no voxel carries the false lumen label 5"));
    EXPECT_THAT(e, HasSubstr("the labels present are 0 ("));
    EXPECT_THAT(e, HasSubstr("--false-lumen"));
  }
  { // voxels coarser than the flap
    LabelMap coarse = map;
    coarse.grid.spacing = {2.5e-3, 2.5e-3, 2.5e-3};
    EXPECT_THAT(build_error(coarse), HasSubstr("cannot resolve a flap 2.00 mm thick"));
  }
  { // no tear: the false lumen's voxels beside the true lumen's unlabelled
    LabelMap closed = map;
    const ImageGrid& g = map.grid;
    for (int k = 1; k + 1 < g.size[2]; ++k)
      for (int j = 1; j + 1 < g.size[1]; ++j)
        for (int i = 1; i + 1 < g.size[0]; ++i) {
          if (map.labels[g.linear(i, j, k)] != 2)
            continue;
          bool beside = false;
          for (int d = -1; d <= 1; ++d)
            for (int e = -1; e <= 1; ++e)
              for (int f = -1; f <= 1; ++f)
                beside = beside || map.labels[g.linear(i + d, j + e, k + f)] == 1;
          if (beside)
            closed.labels[g.linear(i, j, k)] = 0;
        }
    EXPECT_THAT(build_error(closed), HasSubstr("never touch through the flap: no tear"));
  }
}

// A segmentation cropped across the dissection (as scans ending above the diaphragm are): the
// outlet's cap crosses both lumina and the flap, and the exit tear is gone. The model still
// builds: one tear, the stations between it and the false lumen's end, the outlet cap's
// section both lumina and the flap.
TEST(GeometryLabels, ScanCroppedAcrossTheDissectionIsCappedAcrossBothLumina) {
  testing::TempDir dir("geometry-labels-crop");
  LabelMap map = read_label_map(ci_label_map(dir.path));
  const ImageGrid& g = map.grid;
  std::size_t cut = 0;
  for (int k = 0; k < g.size[2]; ++k)
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i)
        if (g.point({double(i), double(j), double(k)})[2] < -70e-3 && map.labels[g.linear(i, j, k)])
          map.labels[g.linear(i, j, k)] = 0, ++cut;
  ASSERT_GT(cut, 0u);
  LabelModelOptions o;
  o.element_size = 4.5e-3;
  const LabelModel m = build_label_model(map, o);
  write_geometry(m.mesh, m.landmarks, dir.path / "model"); // checks it
  ASSERT_EQ(m.tears.size(), 1u);
  EXPECT_EQ(m.tears[0].name, "entry");
  const LabelCap& outlet = m.caps.back();
  EXPECT_EQ(outlet.name, "outlet");
  // Both lumina and the flap: the built model's TL5 + FL5 (56.7 + 427.4 mm^2) at least.
  fmt::print("outlet cap across the dissection: {:.1f} mm^2\n", outlet.area / mm2);
  EXPECT_GT(outlet.area, 484e-6);
  EXPECT_GT(tear_area(m.mesh, m.landmarks.tear("entry")), 0.9 * 228e-6);
  for (const char* name : {"TL5", "FL5", "DAo_dist"})
    EXPECT_GT(landmark_area(m.mesh, m.landmarks.plane(name)), 0) << name;
}

// CI, end to end through the program: a label map to a model (`geometry labels`), then
// `geometry report` and a few rigid-wall steps of the study's case on it.
TEST(GeometryLabels, CommandLineBuildsAModelThatRuns) {
  testing::TempDir dir("geometry-labels-cli");
  const fs::path map = ci_label_map(dir.path), model = dir.path / "model";
  tearflow::testing::Result r = tearflow::testing::run_tearflow(
      "geometry labels " + map.string() + " --element-size 4.5 -o " + model.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("caps: inlet"));
  EXPECT_THAT(r.output, HasSubstr("tears: entry"));
  EXPECT_TRUE(fs::exists(model / GeometryFiles::kMesh));
  EXPECT_TRUE(fs::exists(model / "labels.json"));
  r = tearflow::testing::run_tearflow("geometry report --no-png " + model.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("entry"));
  // The rigid-wall case of the built-in model on this mesh: its faces have the same names.
  std::ifstream in(fs::path(TEARFLOW_SOURCE_DIR) / "examples/tbad-rigid/case.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "geometry/mesh.msh";
  text.replace(text.find(from), from.size(), (model / GeometryFiles::kMesh).string());
  std::ofstream(dir.path / "case.yaml") << text;
  r = tearflow::testing::run_tearflow("run " + (dir.path / "case.yaml").string() +
                                      " --steps 3 -q -o " + (dir.path / "run").string());
  EXPECT_EQ(r.code, 0) << r.output;
  // And with its wall and flap: the CI study's FSI case, two steps, each converging (the run
  // stops with an error when Newton does not).
  std::ifstream fin(test_data_dir() / "study/case-fsi.yaml");
  text.assign((std::istreambuf_iterator<char>(fin)), std::istreambuf_iterator<char>());
  const std::string unused = "unused.msh";
  text.replace(text.find(unused), unused.size(), (model / GeometryFiles::kMesh).string());
  std::ofstream(dir.path / "case-fsi.yaml") << text;
  r = tearflow::testing::run_tearflow("run " + (dir.path / "case-fsi.yaml").string() +
                                      " --steps 2 -o " + (dir.path / "fsi").string());
  EXPECT_EQ(r.code, 0) << r.output;
  fmt::print("{}\n", r.output.substr(r.output.size() > 1500 ? r.output.size() - 1500 : 0));
  // A bad option: a tear that is not there.
  r = tearflow::testing::run_tearflow("geometry labels " + map.string() +
                                      " --tear-area tear_9=50 -o " + (dir.path / "x").string());
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.output, HasSubstr("no tear 'tear_9' to resize (the tears found: entry, exit)"));
  // Sizes checked before any work.
  r = tearflow::testing::run_tearflow("geometry labels " + map.string() + " --element-size 0 -o " +
                                      (dir.path / "x").string());
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.output, HasSubstr("--element-size 0 mm: expected a positive length"));
}

} // namespace
} // namespace tearflow::geometry
