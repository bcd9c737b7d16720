// `geometry voxelize`: the parametric dissection as a label map, the input `geometry labels`
// is tested with. Checked against the mesh itself (lumen and thrombus volumes), the image's
// geometry as ITK reads it back, the labels present, and bad input.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <unistd.h>

#include <gtest/gtest.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkMetaImageIO.h>
#include <itkNiftiImageIO.h>
#include <itkNrrdImageIO.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "geometry/sections.hpp"
#include "geometry/voxelize.hpp"
#include "test_geometry_support.hpp"

namespace tearflow::geometry {
namespace {

using namespace testing;
using Image = itk::Image<unsigned char, 3>;
constexpr double mm = 1e-3, mL = 1e-6;

/// The mesh's own volumes [m^3]: fluid tets split by the voxelizer's rule applied to their
/// centroids (fluid components without the tear regions; those by their side of the flap).
/// Away from the holes both rules say "which side of the flap", so the split differs from
/// the voxels' only by the holes' tets, tens of mm^3. Thrombus: the false lumen's tets past
/// the exit tear's rim + 2 mm.
struct MeshVolumes {
  double fluid = 0, tl = 0, fl = 0, thrombus = 0;
  double aligned_area = 0; ///< interface area whose normal is within 1 degree of x, y or z
};

MeshVolumes mesh_volumes(const CachedModel& m) {
  const mesh::Mesh& mesh = m.mesh;
  const int fluid = region_index(mesh, "fluid");
  const std::size_t n = mesh.tets.size();
  std::vector<char> in_tear(n, 0);
  std::vector<Vec3> centroid(n);
  std::vector<double> side(n, 0);
  for (std::size_t t = 0; t < n; ++t) {
    const Tet& e = mesh.tets[t];
    centroid[t] =
        0.25 * (mesh.points[e[0]] + mesh.points[e[1]] + mesh.points[e[2]] + mesh.points[e[3]]);
    for (const TearLandmark& tear : m.landmarks.tears) {
      const Vec3 d = centroid[t] - tear.centroid, across = cross(tear.normal, tear.axis);
      const double s = dot(d, tear.axis) / (tear.axial + 1 * mm),
                   c = dot(d, across) / (tear.across + 1 * mm);
      if (mesh.tet_region[t] == fluid && std::abs(dot(d, tear.normal)) <= 3 * mm &&
          s * s + c * c <= 1)
        in_tear[t] = 1, side[t] = dot(d, tear.normal);
    }
  }
  const std::vector<int> comp = fluid_components(mesh, in_tear);
  const int tl = comp[locate(mesh, m.landmarks.plane("AAo").origin, fluid)];
  const int fl = comp[locate(mesh, *m.landmarks.plane("FL3").point, fluid)];
  EXPECT_NE(tl, fl);
  const TearLandmark& exit = m.landmarks.tear("exit");
  MeshVolumes out;
  for (std::size_t t = 0; t < n; ++t) {
    if (mesh.tet_region[t] != fluid)
      continue;
    const Tet& e = mesh.tets[t];
    const double v = mesh::signed_volume(mesh.points[e[0]], mesh.points[e[1]], mesh.points[e[2]],
                                         mesh.points[e[3]]);
    out.fluid += v;
    const bool is_tl = in_tear[t] ? side[t] > 0 : comp[t] == tl;
    const bool is_fl = in_tear[t] ? side[t] <= 0 : comp[t] == fl;
    out.tl += is_tl ? v : 0;
    out.fl += is_fl ? v : 0;
    // The exit tear's axis points downstream in the parametric model (towards -z).
    if (is_fl && dot(centroid[t] - exit.centroid, exit.axis) > exit.axial + 2 * mm)
      out.thrombus += v;
  }
  EXPECT_NEAR(out.tl + out.fl, out.fluid, 1e-9) << "fluid in neither lumen";
  for (const Tri& t : mesh.face("interface").triangles) {
    const Vec3 a = mesh.points[t[0]], nrm = cross(mesh.points[t[1]] - a, mesh.points[t[2]] - a);
    const double area = 0.5 * std::sqrt(dot(nrm, nrm));
    for (int d = 0; d < 3; ++d)
      if (std::abs(nrm[d]) > std::cos(std::numbers::pi / 180) * 2 * area)
        out.aligned_area += area;
  }
  return out;
}

/// Expected error of a voxel count as a volume, h the spacing. Each voxel the surface (area
/// A) crosses is counted whole or not at all by its centre: an error uniform in +-h^3/2
/// (sd h^3/sqrt(12)) over A/h^2 voxels. Where the surface is curved against the grid these
/// errors are independent and average out to sd h^2 sqrt(A/12) (about 60 mm^3 for the
/// model's ~4e4 mm^2, 0.03 %). On a flat patch of side L they share one offset: L/h times
/// more, and the flap is flat over ~20 mm. Allowed: 0.5 % of the volume, above that.
double random_tolerance(double volume) {
  return 5e-3 * volume;
}

/// Faces parallel to the voxel layers (the flat flap in an axis-aligned image) share one
/// offset from the layers, so their error adds up instead: up to h/2 per unit area of one
/// flap face. The flap's thickness is 2 h, so its two faces' errors cancel in the total but
/// not in the lumens' split.
double aligned_tolerance(const MeshVolumes& mv, double h) {
  return 0.5 * h * 0.5 * mv.aligned_area;
}

Image::Pointer read_image(const fs::path& file) {
  const std::string name = file.filename().string();
  itk::ImageIOBase::Pointer io;
  if (name.ends_with(".mha"))
    io = itk::MetaImageIO::New().GetPointer();
  else if (name.ends_with(".nrrd"))
    io = itk::NrrdImageIO::New().GetPointer();
  else
    io = itk::NiftiImageIO::New().GetPointer();
  auto reader = itk::ImageFileReader<Image>::New();
  reader->SetImageIO(io);
  reader->SetFileName(file.string());
  reader->Update();
  return reader->GetOutput();
}

std::map<int, std::size_t> histogram(const Image* img) {
  std::map<int, std::size_t> h;
  const std::size_t n = img->GetLargestPossibleRegion().GetNumberOfPixels();
  for (std::size_t v = 0; v < n; ++v)
    ++h[img->GetBufferPointer()[v]];
  return h;
}

/// Direction columns Rz Ry Rx e_a, written out independently of the library's.
std::array<Vec3, 3> expected_axes(const Vec3& deg) {
  const double a = deg[0] * std::numbers::pi / 180, b = deg[1] * std::numbers::pi / 180,
               c = deg[2] * std::numbers::pi / 180;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b),
               cc = std::cos(c), sc = std::sin(c);
  return {Vec3{cc * cb, sc * cb, -sb},
          Vec3{cc * sb * sa - sc * ca, sc * sb * sa + cc * ca, cb * sa},
          Vec3{cc * sb * ca + sc * sa, sc * sb * ca - cc * sa, cb * ca}};
}

/// The label at a model point [m] of an image read back (physical space in mm).
int label_at(const Image* img, const Vec3& p) {
  Image::PointType x;
  for (int r = 0; r < 3; ++r)
    x[r] = p[r] / mm;
  Image::IndexType idx;
  EXPECT_TRUE(img->TransformPhysicalPointToIndex(x, idx));
  return img->GetPixel(idx);
}

/// Checks what ITK reads back: spacing, direction, origin (the image centred on the model,
/// `margin` around it), labels only 0..max_label, and the landmarks' lumens.
void check_image(const fs::path& file, const CachedModel& m, const VoxelizeOptions& o,
                 const VoxelizeResult& r, int max_label) {
  SCOPED_TRACE(file.string());
  const Image::Pointer img = read_image(file);
  const auto size = img->GetLargestPossibleRegion().GetSize();
  const std::array<Vec3, 3> axis = expected_axes(o.rotation);
  Vec3 origin{};
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(int(size[a]), r.size[a]);
    EXPECT_NEAR(img->GetSpacing()[a], o.spacing / mm, 1e-6);
    for (int row = 0; row < 3; ++row)
      EXPECT_NEAR(img->GetDirection()(row, a), axis[a][row], 1e-6) << row << "," << a;
    double lo = 1e9, hi = -1e9;
    for (const Vec3& p : m.mesh.points)
      lo = std::min(lo, dot(axis[a], p)), hi = std::max(hi, dot(axis[a], p));
    // The first centre; the image spans at least the model plus the margin either side.
    const double first = 0.5 * (lo + hi) - 0.5 * (r.size[a] - 1) * o.spacing;
    EXPECT_LE(first, lo - o.margin + 1e-9);
    EXPECT_GT(first, lo - o.margin - o.spacing);
    origin = origin + first * axis[a];
  }
  for (int row = 0; row < 3; ++row)
    EXPECT_NEAR(img->GetOrigin()[row], origin[row] / mm, 1e-4) << row;
  const std::map<int, std::size_t> h = histogram(img);
  for (const auto& [label, count] : h)
    EXPECT_LE(label, max_label) << count << " voxels";
  EXPECT_EQ(h.count(1) ? h.at(1) : 0, r.tl_voxels);
  EXPECT_EQ(h.count(2) ? h.at(2) : 0, r.fl_voxels);
  EXPECT_EQ(label_at(img, m.landmarks.plane("AAo").origin), 1);
  for (int k = 1; k <= 5; ++k) {
    EXPECT_EQ(label_at(img, *m.landmarks.plane(fmt::format("TL{}", k)).point), 1) << k;
    EXPECT_EQ(label_at(img, *m.landmarks.plane(fmt::format("FL{}", k)).point), 2) << k;
  }
}

TEST(GeometryVoxelize, AxisAlignedImageHoldsTheMeshsLumens) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  const MeshVolumes mv = mesh_volumes(m);
  TempDir tmp("geometry-voxelize");
  const VoxelizeOptions o; // 1 mm
  const VoxelizeResult r = voxelize_geometry(m.dir, o, tmp.path / "labels.nii.gz");
  const double fluid = r.tl_volume + r.fl_volume;
  fmt::print("mesh: fluid {:.3f} TL {:.3f} FL {:.3f} mL, grid-aligned interface {:.0f} mm^2\n"
             "voxels: {} x {} x {}, TL {:.3f} FL {:.3f} mL, {} in pockets\n",
             mv.fluid / mL, mv.tl / mL, mv.fl / mL, mv.aligned_area / (mm * mm), r.size[0],
             r.size[1], r.size[2], r.tl_volume / mL, r.fl_volume / mL, r.pocket_voxels);
  EXPECT_NEAR(fluid, mv.fluid, random_tolerance(mv.fluid));
  const double split = random_tolerance(mv.fl) + aligned_tolerance(mv, o.spacing);
  EXPECT_NEAR(r.fl_volume, mv.fl, split);
  EXPECT_NEAR(r.tl_volume, mv.tl, split);
  EXPECT_EQ(r.thrombus_voxels, 0u);
  check_image(tmp.path / "labels.nii.gz", m, o, r, 2);
}

TEST(GeometryVoxelize, ObliqueImageHoldsTheSameLumens) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  const MeshVolumes mv = mesh_volumes(m);
  TempDir tmp("geometry-voxelize");
  VoxelizeOptions o;
  o.rotation = {20, -15, 30};
  const VoxelizeResult r = voxelize_geometry(m.dir, o, tmp.path / "oblique.nii.gz");
  const VoxelizeResult aligned = voxelize_geometry(m.dir, {}, tmp.path / "aligned.nii");
  fmt::print("oblique: {} x {} x {}, TL {:.3f} FL {:.3f} mL (mesh {:.3f}, {:.3f}), {} in "
             "pockets\n",
             r.size[0], r.size[1], r.size[2], r.tl_volume / mL, r.fl_volume / mL, mv.tl / mL,
             mv.fl / mL, r.pocket_voxels);
  // No face is parallel to the layers: the split's error averages out as the total's does.
  EXPECT_NEAR(r.tl_volume + r.fl_volume, mv.fluid, random_tolerance(mv.fluid));
  EXPECT_NEAR(r.fl_volume, mv.fl, random_tolerance(mv.fl));
  EXPECT_NEAR(r.tl_volume, mv.tl, random_tolerance(mv.tl));
  EXPECT_NEAR(r.fl_volume, aligned.fl_volume,
              2 * random_tolerance(mv.fl) + aligned_tolerance(mv, o.spacing));
  check_image(tmp.path / "oblique.nii.gz", m, o, r, 2);
}

TEST(GeometryVoxelize, ThrombusFillsTheFalseLumenPastTheExitTear) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  const MeshVolumes mv = mesh_volumes(m);
  TempDir tmp("geometry-voxelize");
  VoxelizeOptions o;
  o.thrombus = true;
  const VoxelizeResult plain = voxelize_geometry(m.dir, {}, tmp.path / "plain.nii.gz");
  const VoxelizeResult r = voxelize_geometry(m.dir, o, tmp.path / "thrombus.nrrd");
  fmt::print("thrombus {:.3f} mL (mesh {:.3f}); FL {:.3f} -> {:.3f} mL\n", r.thrombus_volume / mL,
             mv.thrombus / mL, plain.fl_volume / mL, r.fl_volume / mL);
  EXPECT_EQ(r.tl_voxels, plain.tl_voxels);
  EXPECT_EQ(r.fl_voxels + r.thrombus_voxels, plain.fl_voxels) << "taken from the FL alone";
  // 10 %: the thrombus is a thin lumen (4 mm deep at its cap) along a flap parallel to the
  // voxel layers here, whose shared offset (above) moves up to h/2 over the flap's ~500 mm^2
  // there, 0.25 mL (7 %); the mesh's cut by tet centroids adds ~50 mm^3. Measured: -3.9 %
  // here, -0.8 % in oblique images.
  EXPECT_NEAR(r.thrombus_volume, mv.thrombus, 0.1 * mv.thrombus);
  EXPECT_GT(r.thrombus_volume, 1 * mL);
  check_image(tmp.path / "thrombus.nrrd", m, o, r, 3);
  const std::map<int, std::size_t> h = histogram(read_image(tmp.path / "thrombus.nrrd"));
  EXPECT_EQ(h.count(3) ? h.at(3) : 0, r.thrombus_voxels);
}

TEST(GeometryVoxelize, MetaImageThroughTheProgram) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  TempDir tmp("geometry-voxelize");
  const fs::path out = tmp.path / "sub" / "labels.mha";
  // 1.2 mm: the false lumen's proximal end cap is only ~1.35 mm thick on the arch's inner
  // side (the model's cap is h thick along the centreline, less inside the bend), and at
  // 1.5 mm the lumens meet through it (BadInputIsAClearError has that error, at 3 mm).
  const tearflow::testing::Result run = tearflow::testing::run_tearflow(fmt::format(
      "geometry voxelize {} -o {} --spacing 1.2 --rotate 5,0,-10", m.dir.string(), out.string()));
  EXPECT_EQ(run.code, 0) << run.output;
  EXPECT_NE(run.output.find("true lumen"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(" mL"), std::string::npos) << run.output;
  VoxelizeOptions o;
  o.spacing = 1.2 * mm;
  o.rotation = {5, 0, -10};
  const VoxelizeResult r = voxelize_geometry(m.dir, o, tmp.path / "same.nii.gz");
  check_image(out, m, o, r, 2);
}

std::string voxelize_error(const fs::path& dir, const VoxelizeOptions& o, const fs::path& out) {
  try {
    voxelize_geometry(dir, o, out);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GeometryVoxelize, BadInputIsAClearError) {
  const CachedModel m = cached_tbad("OR", kCoarse);
  TempDir tmp("geometry-voxelize");
  const fs::path out = tmp.path / "x.nii.gz";
  EXPECT_NE(voxelize_error(tmp.path, {}, out).find("not a geometry directory"), std::string::npos);
  EXPECT_NE(voxelize_error(m.dir, {}, tmp.path / "x.png").find("expected a .nii"),
            std::string::npos);
  VoxelizeOptions o;
  o.spacing = 0;
  EXPECT_NE(voxelize_error(m.dir, o, out).find("--spacing"), std::string::npos);
  o.spacing = 1e-5; // 10 um: 10^11 voxels, refused before any is allocated
  EXPECT_NE(voxelize_error(m.dir, o, out).find("coarser --spacing"), std::string::npos);
  // Voxels thicker than the flap (2 mm): the lumens meet through it.
  o.spacing = 3 * mm;
  EXPECT_NE(voxelize_error(m.dir, o, out).find("finer --spacing"), std::string::npos)
      << voxelize_error(m.dir, o, out);
  o = {};
  o.false_lumen = o.true_lumen;
  EXPECT_NE(voxelize_error(m.dir, o, out).find("labels must differ"), std::string::npos);
  const tearflow::testing::Result run = tearflow::testing::run_tearflow(
      fmt::format("geometry voxelize {} -o {} --rotate 1,2", m.dir.string(), out.string()));
  EXPECT_NE(run.code, 0) << run.output;
}

} // namespace
} // namespace tearflow::geometry
