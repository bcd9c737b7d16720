// The meshed parametric TBAD against the acceptance: tear areas, landmark lumen
// areas against the reference study, lumina that communicate only through the tears, and a
// valid two-region mesh at two sizes. Models are built at CI's coarse size and cached per
// test executable (test_geometry_support.hpp).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/sections.hpp"
#include "geometry/tbad_model.hpp"
#include "test_geometry_support.hpp"

namespace tearflow::geometry {
namespace {

using namespace testing;
using ::testing::HasSubstr;

// Reference study, unloaded original model, mm^2 (../shared/reference/tbad-study.md).
const std::map<std::string, double> kReferenceAreas{
    {"AAo", 492.6}, {"TL1", 235.6}, {"TL2", 149.2}, {"TL3", 67.6},
    {"TL4", 58.4},  {"TL5", 56.6},  {"FL1", 476.3}, {"FL2", 436.3},
    {"FL3", 475.0}, {"FL4", 458.7}, {"FL5", 429.3}, {"DAo_dist", 365.5}};

struct TearCase {
  std::string variant;
  double entry, exit; // requested areas [mm^2], from the study
};

void PrintTo(const TearCase& c, std::ostream* os) {
  *os << c.variant;
}

class TearAreas : public ::testing::TestWithParam<TearCase> {};

// 3 %: the acceptance bound. What the mesh loses is the polygonal rim: with at least 24
// edges around each tear (the builder's refinement) a polygon inscribed in the ellipse holds
// 98.9 % of its area, so a correct build lands between -1.1 % and 0 (-0.2 % measured at
// 3 mm); a hole cut in the wrong place or of the wrong size is off by far more.
TEST_P(TearAreas, MeasuredOnTheMeshWithin3Percent) {
  const TearCase& c = GetParam();
  const CachedModel m = cached_tbad(c.variant, kCoarse);
  for (const auto& [name, requested] : {std::pair{"entry", c.entry}, {"exit", c.exit}}) {
    const TearLandmark& t = m.landmarks.tear(name);
    EXPECT_NEAR(t.area * 1e6, requested, 1e-9); // the landmarks file states the request
    const double measured = tear_area(m.mesh, t) * 1e6;
    fmt::print("{} {} tear: requested {:.1f} mm^2, measured {:.1f} mm^2 ({:+.2f} %)\n", c.variant,
               name, requested, measured, 100 * (measured / requested - 1));
    EXPECT_NEAR(measured, requested, 0.03 * requested) << c.variant << " " << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Variants, TearAreas,
                         ::testing::Values(TearCase{"OR", 228, 227}, TearCase{"EN", 62, 227},
                                           TearCase{"EX", 228, 61}),
                         [](const auto& info) { return info.param.variant; });

// 10 %: the acceptance bound. The model is laid out to reproduce the table exactly; what
// remains is the loft between sections (up to 3 % where the radius changes) and the
// polygonal boundary of the coarse mesh (about -1 % at 3 mm).
TEST(TbadGeometry, LandmarkAreasFollowTheReferenceTable) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  fmt::print("{:<10} {:>12} {:>12} {:>9}\n", "landmark", "reference", "model", "diff");
  for (const std::string& name : area_landmark_names()) {
    const double ref = kReferenceAreas.at(name);
    const double area = landmark_area(m.mesh, m.landmarks.plane(name)) * 1e6;
    fmt::print("{:<10} {:>8.1f} mm2 {:>8.1f} mm2 {:>+8.2f} %\n", name, ref, area,
               100 * (area / ref - 1));
    EXPECT_NEAR(area, ref, 0.10 * ref) << name;
  }
}

// Pieces of a landmark plane's fluid section near the vessel: the plane is infinite and may
// also cut other parts of the aorta far away.
std::vector<int> nearby_pieces(const Section& s, const Landmark& l, double radius) {
  std::vector<int> near;
  for (std::size_t p = 0; p < s.areas.size(); ++p) {
    const Vec3 d = s.centroids[p] - l.origin;
    if (std::sqrt(dot(d, d)) < radius)
      near.push_back(static_cast<int>(p));
  }
  return near;
}

TEST(TbadGeometry, EveryTlFlPlaneCutsTheFluidIntoTwoLumina) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  const int fluid = region_index(m.mesh, "fluid");
  for (int k = 1; k <= 5; ++k) {
    const Landmark &tl = m.landmarks.plane(fmt::format("TL{}", k)),
                   &fl = m.landmarks.plane(fmt::format("FL{}", k));
    const Section s = cut_region(m.mesh, fluid, tl.origin, tl.normal);
    // 40 mm: twice the largest lumen radius; the other aortic segments are farther.
    const std::vector<int> near = nearby_pieces(s, tl, 40e-3);
    EXPECT_EQ(near.size(), 2u) << "station " << k;
    const int tl_piece = s.piece_containing(*tl.point), fl_piece = s.piece_containing(*fl.point);
    EXPECT_GE(tl_piece, 0);
    EXPECT_GE(fl_piece, 0);
    EXPECT_NE(tl_piece, fl_piece) << "station " << k;
  }
  // And the plane through the entry tear (DAo_prox) finds them joined: one piece.
  const Landmark& prox = m.landmarks.plane("DAo_prox");
  const Section s = cut_region(m.mesh, fluid, prox.origin, prox.normal);
  EXPECT_EQ(nearby_pieces(s, prox, 40e-3).size(), 1u);
}

TEST(TbadGeometry, LuminaCommunicateOnlyThroughTheTears) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  const int fluid = region_index(m.mesh, "fluid");
  const Index tl = locate(m.mesh, *m.landmarks.plane("TL3").point, fluid);
  const Index fl = locate(m.mesh, *m.landmarks.plane("FL3").point, fluid);
  ASSERT_GE(tl, 0);
  ASSERT_GE(fl, 0);
  // 1.2: the tets crossing the flap's mid-plane inside the hole have their section centroid
  // within the ellipse; 20 % covers the rim's polygonal approximation and keeps well inside
  // the flap (the ligament is at least one wall thickness, over 25 % of any semi-axis here).
  const std::vector<char> entry = tear_region(m.mesh, m.landmarks.tear("entry"), 1.2);
  const std::vector<char> exit = tear_region(m.mesh, m.landmarks.tear("exit"), 1.2);
  std::vector<char> both(entry.size());
  for (std::size_t t = 0; t < both.size(); ++t)
    both[t] = entry[t] || exit[t];
  EXPECT_GT(std::count(entry.begin(), entry.end(), 1), 0);
  EXPECT_GT(std::count(exit.begin(), exit.end(), 1), 0);

  const std::vector<int> whole = fluid_components(m.mesh, {});
  EXPECT_EQ(*std::max_element(whole.begin(), whole.end()), 0) << "the fluid is one volume";
  for (const auto* removed : {&entry, &exit}) {
    const std::vector<int> c = fluid_components(m.mesh, *removed);
    EXPECT_EQ(c[tl], c[fl]) << "one tear closed: still connected through the other";
  }
  const std::vector<int> c = fluid_components(m.mesh, both);
  EXPECT_NE(c[tl], c[fl]) << "both tears closed: the lumina must be disconnected";
}

// How well the fluid mesh resolves the true lumen across its thickness near a paired
// station: the fraction of a laminar profile's flux that the P1 velocity space, zero at
// every boundary node (no-slip), can carry. The profile is u = (y - f)(w(x) - y) in the
// station's frame (y along the flap normal, x across), zero on the flap's TL face y = f and
// on the lumen wall y = w(x) = sqrt(R^2 - x^2): the shape of slot flow. Over the fluid tets
// whose centroid lies in the TL within `half_slab` of the plane, the fraction is
// sum |T| mean(nodal u) / sum |T| mean(u), the latter by a 4-point rule exact for quadratics.
struct LumenResolution {
  double captured = 0; // fraction of the profile's integral the interpolant keeps
  int tets = 0, interior_nodes = 0;
};

LumenResolution true_lumen_resolution(const mesh::Mesh& mesh, const TbadModel& model, double s,
                                      double half_slab) {
  const int fluid = region_index(mesh, "fluid");
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const mesh::Face& f : mesh.faces)
    for (const Tri& t : f.triangles)
      for (Index n : t)
        on_boundary[n] = 1;
  const Frame f = model.frame(s);
  const double h = model.spec().wall_thickness;
  auto profile = [&](const Vec3& p) {
    const Vec3 d = p - f.origin;
    const double a = dot(d, f.tangent), y = dot(d, f.normal), x = dot(d, f.across);
    const double r = model.radius(s + a), face = model.flap_offset(s + a) + 0.5 * h;
    const double wall = std::sqrt(std::max(0.0, r * r - x * x));
    return std::max(0.0, (y - face) * (wall - y));
  };
  LumenResolution res;
  double exact = 0, interpolated = 0;
  std::set<Index> interior;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_region[t] != fluid)
      continue;
    const Tet& tet = mesh.tets[t];
    const Vec3 c = 0.25 * (mesh.points[tet[0]] + mesh.points[tet[1]] + mesh.points[tet[2]] +
                           mesh.points[tet[3]]);
    const Vec3 d = c - f.origin;
    if (std::abs(dot(d, f.tangent)) > half_slab ||
        dot(d, f.normal) < model.flap_offset(s) + 0.5 * h)
      continue;
    const double vol = mesh::signed_volume(mesh.points[tet[0]], mesh.points[tet[1]],
                                           mesh.points[tet[2]], mesh.points[tet[3]]);
    // 4-point rule, degree 2: points at 0.5854 towards each node from 0.1382 of the others.
    constexpr double a = 0.5854101966249685, b = 0.1381966011250105;
    double q = 0, nodal = 0;
    for (int i = 0; i < 4; ++i) {
      Vec3 p{0, 0, 0};
      for (int j = 0; j < 4; ++j)
        p = p + (i == j ? a : b) * mesh.points[tet[j]];
      q += 0.25 * profile(p);
      if (!on_boundary[tet[i]]) {
        nodal += 0.25 * profile(mesh.points[tet[i]]);
        interior.insert(tet[i]);
      }
    }
    exact += vol * q;
    interpolated += vol * nodal;
    ++res.tets;
  }
  res.captured = exact > 0 ? interpolated / exact : 0.0;
  res.interior_nodes = static_cast<int>(interior.size());
  return res;
}

std::vector<LumenResolution> print_true_lumen_resolution(const CachedModel& m, int elements) {
  const TbadModel model(variant_spec("OR", kCoarse, elements));
  std::vector<LumenResolution> out;
  for (int k = 1; k <= 5; ++k) {
    const double s = model.paired_station(k);
    // Half slab 3 mm: one global element size each side of the plane.
    const LumenResolution r = true_lumen_resolution(m.mesh, model, s, 3e-3);
    fmt::print("TL{} (thickness {:.2f} mm, {} elements across): {} tets, {} interior nodes, "
               "captured {:.3f} of the slot profile\n",
               k, model.true_lumen_thickness(s) * 1e3, elements, r.tets, r.interior_nodes,
               r.captured);
    out.push_back(r);
  }
  return out;
}

// The bound, from P1 interpolation error. On a tet T, for a quadratic q with Hessian H,
// int_T (I q - q) = |T|/40 sum over its 6 edges of e^T H e. Here d2u/dy2 = -2; a tet of edge
// l has sum e_y^2 = 2 l^2 when regular, so the interpolant loses l^2/10 of u per volume.
// The mean of u over a circular segment of height t is about 0.34 t^2/6 (its thickness
// falls off sideways), so the relative loss is 1.75 (l/t)^2; Gmsh's Delaunay tets have
// l = 1.2 times the target size (5 tets per size^3), and the size here is t/n: a loss of
// 2.5/n^2. We require at least 1 - 2.5/n^2 (0.72 for the default n = 3) and measure 0.77 at
// n = 3 and 0.88 at n = 4 (printed). Sizes of t/(n-1) would keep 1 - 2.5/(n-1)^2 (0.38 at
// n = 3), and a lumen one element thick has every node on the interface and keeps nothing.
TEST(TbadGeometry, TrueLumenIsResolvedAcrossItsThickness) {
  const int n = TbadSpec{}.lumen_elements;
  ASSERT_GE(n, 3);
  const double bound = 1.0 - 2.5 / (n * n);
  const std::vector<LumenResolution> r = print_true_lumen_resolution(cached_tbad("OR", kCoarse), n);
  for (int k = 0; k < 5; ++k) {
    EXPECT_GT(r[k].tets, 10) << "TL" << k + 1;
    EXPECT_GE(r[k].captured, bound) << "TL" << k + 1;
  }
}

// The same measure on the uniform 3 mm mesh (sizing off), the mesh that gave no TL flow:
// TL3 and TL4 (4.7 and 4.3 mm thick) have no interior node and keep nothing, below the
// 0.375 that even 2 elements across would keep (bound above with n = 2). (TL5, as thin,
// now keeps 0.45: distal to it the TL widens towards the exit tear, 6.5 mm thick at the
// slab's distal end 3 mm away, and the slab reaches interior nodes there.)
TEST(TbadGeometry, UniformMeshLeavesTheNarrowTrueLumenUnresolved) {
  const std::vector<LumenResolution> r =
      print_true_lumen_resolution(cached_tbad("OR", kCoarse, 0), 0);
  for (int k = 2; k < 4; ++k)
    EXPECT_LT(r[k].captured, 1.0 - 2.5 / 4) << "TL" << k + 1;
}

// Radius-ratio bound 0.05: Gmsh's optimizer leaves the worst tets of these meshes at 0.1 to
// 0.25 (in the thin flap ligaments beside the tears); a sliver that would ruin the solid's
// conditioning is below 0.01.
constexpr double kMinQuality = 0.05;

void expect_valid_two_region_mesh(const CachedModel& m) {
  const MeshReport r = check_fsi_mesh(m.mesh); // throws on inverted elements or bad faces
  ASSERT_EQ(r.regions.size(), 2u);
  for (const RegionQuality& q : r.regions) {
    fmt::print("{}: {} tets, radius ratio min {:.3f} mean {:.3f}\n", q.name, q.tets, q.min_quality,
               q.mean_quality);
    EXPECT_GT(q.min_quality, kMinQuality) << q.name;
    EXPECT_GT(q.tets, 1000u);
  }
  const std::set<std::string> expected{"inlet",    "BCT",         "LCC",        "LSA",
                                       "outlet",   "wall_inlet",  "wall_BCT",   "wall_LCC",
                                       "wall_LSA", "wall_outlet", "outer_wall", "interface"};
  std::set<std::string> names;
  for (const mesh::Face& f : m.mesh.faces)
    names.insert(f.name);
  EXPECT_EQ(names, expected);
  // Interface nodes are shared: the fluid's own boundary (faces of one fluid tet) is exactly
  // its caps plus the interface, so no fluid face meets the wall through duplicated nodes.
  const int fluid = region_index(m.mesh, "fluid");
  std::map<Tri, int> count;
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t)
    if (m.mesh.tet_region[t] == fluid)
      for (int skip = 0; skip < 4; ++skip) {
        Tri f{};
        for (int i = 0, j = 0; i < 4; ++i)
          if (i != skip)
            f[j++] = m.mesh.tets[t][i];
        std::sort(f.begin(), f.end());
        ++count[f];
      }
  std::set<Tri> boundary, named;
  for (const auto& [f, n] : count)
    if (n == 1)
      boundary.insert(f);
  for (const std::string name : {"inlet", "BCT", "LCC", "LSA", "outlet", "interface"})
    for (Tri f : m.mesh.face(name).triangles) {
      std::sort(f.begin(), f.end());
      named.insert(f);
    }
  EXPECT_EQ(boundary.size(), named.size());
  EXPECT_TRUE(boundary == named) << "the fluid's boundary is not its caps plus the interface";
}

TEST(TbadGeometry, MeshIsValidAtTheCoarseSize) {
  expect_valid_two_region_mesh(cached_tbad("OR", kCoarse));
}

TEST(TbadGeometry, MeshIsValidAtACoarserSize) {
  expect_valid_two_region_mesh(cached_tbad("OR", 4.5e-3));
}

TEST(TbadGeometry, TearTooLargeForTheFlapIsAnInputError) {
  TbadSpec s = variant_spec("OR", kCoarse);
  s.entry_tear.area = 600e-6;
  try {
    build_tbad(s, fs::temp_directory_path() / "tearflow-test-never-built");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("entry tear area 600.0 mm^2 is larger than the flap can hold"));
  }
  EXPECT_FALSE(
      fs::exists(fs::temp_directory_path() / "tearflow-test-never-built" / GeometryFiles::kMesh));
}

// Issue 28: `--element-size nan` meshed at the default 3 mm without a word; a size below 1.5
// mm starts minutes of meshing without saying how much. Through the program: nan and inf are
// refused before anything is built; a small size prints its tet estimate first (here the
// tear's bad area then stops the build at once: 1.0 mm, the measured 1.52 M tets).
TEST(TbadGeometry, CommandLineSizesAreFiniteAndLongWorkIsAnnounced) {
  const fs::path out = tearflow::testing::fresh_dir("geometry-cli-sizes");
  for (const char* bad : {"nan", "inf"}) {
    const auto r = tearflow::testing::run_tearflow(
        fmt::format("geometry tbad --element-size {} -o {}", bad, out.string()));
    EXPECT_NE(r.code, 0) << r.output;
    EXPECT_THAT(r.output, HasSubstr(fmt::format("--element-size: a finite number is expected, "
                                                "got '{}'",
                                                bad)));
    EXPECT_FALSE(fs::exists(out));
  }
  const auto r = tearflow::testing::run_tearflow(
      fmt::format("geometry tbad --element-size 1.0 --entry-tear-area 600 -o {}", out.string()));
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("element size 1 mm gives about 1.5 M tets (estimate)"));
  EXPECT_THAT(r.output, HasSubstr("larger than the flap can hold"));
}

// The study's resolution, 1.3 mm: a valid mesh with the tears and landmark areas within the
// acceptance bounds (as at 3 mm; the rims are refined alike, so the tears come out the same,
// and the lumen areas move closer to the table as the polygonal boundary refines). Minutes
// of meshing: only under `ctest -L verification-full` (geometry.tbad.full), which sets
// TEARFLOW_GEOMETRY_FULL; skipped otherwise.
TEST(TbadGeometryFull, StudyResolutionMeshIsValidWithTearsAndLandmarks) {
  if (!std::getenv("TEARFLOW_GEOMETRY_FULL"))
    GTEST_SKIP() << "set TEARFLOW_GEOMETRY_FULL=1 (ctest -L verification-full) to build 1.3 mm";
  const CachedModel m = cached_tbad("OR", 1.3e-3);
  expect_valid_two_region_mesh(m);
  for (const auto& [name, requested] : {std::pair{"entry", 228.0}, {"exit", 227.0}}) {
    const double measured = tear_area(m.mesh, m.landmarks.tear(name)) * 1e6;
    fmt::print("{} tear: requested {:.1f} mm^2, measured {:.1f} mm^2 ({:+.2f} %)\n", name,
               requested, measured, 100 * (measured / requested - 1));
    EXPECT_NEAR(measured, requested, 0.03 * requested) << name; // as TearAreas
  }
  for (const std::string& name : area_landmark_names()) {
    const double ref = kReferenceAreas.at(name);
    const double area = landmark_area(m.mesh, m.landmarks.plane(name)) * 1e6;
    fmt::print("{:<10} {:>8.1f} mm2 {:>8.1f} mm2 {:>+8.2f} %\n", name, ref, area,
               100 * (area / ref - 1));
    EXPECT_NEAR(area, ref, 0.10 * ref) << name; // as LandmarkAreasFollowTheReferenceTable
  }
}

} // namespace
} // namespace tearflow::geometry
