// A 4D-flow scan pictured beside the run (issue 30): a synthetic scan of the two-lumen run of
// tests/pictures_support.hpp (mri::synthesize_run, axis-aligned 1 mm voxels, SNR 40) goes
// through `tearflow pictures RUN --mri SCAN`, and the scan's plane maps are compared with the
// run's on the rendered PNGs: each pixel's colour is turned back into u.n through the
// pictures' colour table, and the pixel's position on the plane comes from the view recorded
// in pictures.json.
//
// The bound at an interior pixel (its plane point p at least the scan's reach, below, from the
// lumen's rim). The run's field is u = c (R^2 - rho^2) e_z, c = U a / R^2 (Poiseuille), given
// at the mesh's nodes and interpolated P1; the scan's voxel v holds the mean of that P1 field
// over 2 x 2 x 2 points of the voxel (synthesize_run, one instant per frame), plus noise.
//   - Decoding: a pixel's value is the table's colour of its value; the nearest of the 256
//     table colours is within one entry, 2 speed_max / 256, on each picture.
//   - P1 error: for a quadratic field with Hessian -2c in the plane, the interpolant in a
//     tetrahedron of circumradius r_c differs from it by c (r_c^2 - |x - o|^2) <= c r_c^2 (o
//     the circumcentre); both pictures carry it once: 2 c r_c^2, r_c the mesh's largest.
//   - Partial volume: the scan's value at p is a convex combination of voxel means that
//     reproduces linear fields (the section's vertices and values are interpolated alike), so
//     only the quadratic part remains: c (sum_v w_v |x_v - p|^2_xy + mean_s |y_s - x_v|^2_xy)
//     <= c (h^2 / 2 + h^2 / 8) (the linear interpolation of |x|^2 on the voxel squares: at
//     most half the squared diagonal, h^2 / 2; the sample points at -h/4 and h/4 per axis).
//   - Noise: the phase noise of synthetic.hpp, sigma = sqrt(2) venc / (pi SNR) at blood's
//     magnitude 1, per voxel; a convex combination of voxels has at most that. 4.5 sigma at
//     every one of the ~2000 interior pixels: the noise is drawn once (a fixed seed), and a
//     Gaussian exceeds 4.5 sigma with probability 7e-6.
// The scan's reach from p: the voxels around p lie within h per axis, their samples h/4
// further, so every value enters from within sqrt(2) 5h/4 in the plane; a pixel is interior
// when that plus one pixel lies inside its lumen.
#include <cmath>
#include <fstream>
#include <limits>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkTetra.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>

#include "analysis/flow_features.hpp"
#include "cli_support.hpp"
#include "core/virtual_display.hpp"
#include "mri/alignment.hpp"
#include "mri/image_io.hpp"
#include "mri/synthetic_run.hpp"
#include "mri_support.hpp"
#include "pictures_support.hpp"
#include "report/flow_pictures.hpp"
#include "report/flow_section.hpp"

namespace tearflow {
namespace {

using testing::SyntheticLumen;
using testing::SyntheticRun;

constexpr double kVoxel = 1e-3, kVenc = 1.0, kSnr = 40.0, kSpeedMax = 1.0;

/// The run and (`scan`) its scan, in a folder of the test's own (ctest runs the tests of this
/// file side by side).
struct ScannedRun {
  SyntheticRun run;
  std::filesystem::path dir =
      testing::fresh_dir(std::string("scan-pictures-") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
  double circumradius = 0.0; ///< the mesh's largest tetrahedron circumradius [m]

  explicit ScannedRun(bool with_scan = true) {
    run = testing::two_lumen_run();
    testing::write_synthetic_run(run, dir / "run");
    std::filesystem::create_directories(dir / "run" / "geometry");
    geometry::write_landmarks(testing::two_lumen_landmarks(run),
                              dir / "run" / "geometry" / "landmarks.json");
    if (!with_scan)
      return;
    mri::RunScan scan;
    scan.run_dir = dir / "run";
    scan.voxel = kVoxel;
    scan.frames = run.frames - 1; // frame k at t = k T / 8: the saved frames themselves
    scan.time_samples = 1;        // the instant: no time window to bound
    scan.voxel_samples = 2;
    scan.effects.venc = kVenc;
    scan.effects.snr = kSnr;
    const mri::Flow4D data = mri::synthesize_run(scan);
    mri::write_volumes(data, dir / "scan", ".mha");
    write_moved_scan(data);

    const auto frame = analysis::read_flow_frame(dir / "run" / "flow_000000.vtu");
    for (vtkIdType c = 0; c < frame->GetNumberOfCells(); ++c) {
      double x[4][3], centre[3];
      for (int k = 0; k < 4; ++k)
        frame->GetPoint(frame->GetCell(c)->GetPointId(k), x[k]);
      circumradius =
          std::max(circumradius, std::sqrt(vtkTetra::Circumsphere(x[0], x[1], x[2], x[3], centre)));
    }
  }

  /// The same scan placed in a patient frame rotated by 20 degrees and shifted by
  /// (30, -20, 40) mm (x_mri = R x_model + t, its velocities rotated too), and the paired
  /// points that place it (alignment.hpp's JSON).
  void write_moved_scan(const mri::Flow4D& data) const {
    mri::RigidTransform t;
    t.rotation = mri::rotation({1 / std::sqrt(3.0), 1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}, 20);
    t.translation = {0.03, -0.02, 0.04};
    mri::write_volumes(testing::moved_scan(data, t), dir / "scan-moved", ".mha");
    nlohmann::json pairs = {
        {"units", "mm"}, {"model", nlohmann::json::array()}, {"mri", nlohmann::json::array()}};
    for (const Vec3& x : {Vec3{0, 0, 0}, Vec3{0.02, 0, 0}, Vec3{0, 0.01, 0}, Vec3{0, 0, 0.03}}) {
      pairs["model"].push_back({1e3 * x[0], 1e3 * x[1], 1e3 * x[2]});
      const Vec3 y = t.apply(x);
      pairs["mri"].push_back({1e3 * y[0], 1e3 * y[1], 1e3 * y[2]});
    }
    std::ofstream(dir / "scan-moved.json") << pairs.dump(2);
  }
};

const ScannedRun& scanned_run() {
  static const ScannedRun r;
  return r;
}

/// A plane map's PNG turned back into values: u.n per pixel of the map's part, NaN where the
/// colour is none of the table's (background, rim, arrows, caption).
struct DecodedMap {
  int width = 0, height = 0;
  std::vector<double> value;
  report::PlaneView view;
  Vec3 point(int i, int j) const { // flow_pictures.hpp, PlaneView
    const double s = 2 * view.half_height / height;
    return view.centre + ((i + 0.5 - width / 2.0) * s) * view.right +
           ((j + 0.5 - height / 2.0) * s) * view.up;
  }
  double pixel() const { return 2 * view.half_height / height; }
};

Vec3 vec(const nlohmann::json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

DecodedMap decode(const std::filesystem::path& png, const nlohmann::json& picture) {
  DecodedMap m;
  const nlohmann::json& v = picture.at("plane_view");
  m.view.centre = vec(v["centre_m"]);
  m.view.right = vec(v["right"]);
  m.view.up = vec(v["up"]);
  m.view.half_height = v["half_height_m"];
  m.width = v["map_pixels"][0];
  m.height = v["map_pixels"][1];
  const auto table = report::through_plane_table({"", -kSpeedMax, kSpeedMax});
  auto reader = vtkSmartPointer<vtkPNGReader>::New();
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  vtkDataArray* rgb = image->GetPointData()->GetScalars();
  const int nx = image->GetDimensions()[0];
  m.value.assign(static_cast<std::size_t>(m.width) * m.height, std::nan(""));
  for (int j = 0; j < m.height; ++j)
    for (int i = 0; i < m.width; ++i) {
      double c[3];
      for (int k = 0; k < 3; ++k)
        c[k] = rgb->GetComponent(i + static_cast<vtkIdType>(nx) * j, k) / 255.0;
      double best = 1e300;
      int entry = -1;
      for (int t = 0; t < table->GetNumberOfTableValues(); ++t) {
        const double* e = table->GetTableValue(t);
        const double d = std::abs(e[0] - c[0]) + std::abs(e[1] - c[1]) + std::abs(e[2] - c[2]);
        if (d < best) {
          best = d;
          entry = t;
        }
      }
      if (best <= 3 * 2.5 / 255) // the table's own colour, rounded to 8 bits
        m.value[i + static_cast<std::size_t>(m.width) * j] =
            -kSpeedMax + (entry + 0.5) * 2 * kSpeedMax / table->GetNumberOfTableValues();
    }
  return m;
}

const nlohmann::json& picture_named(const nlohmann::json& pictures, const std::string& file) {
  for (const nlohmann::json& p : pictures)
    if (p["file"] == file)
      return p;
  throw std::runtime_error("no picture " + file);
}

struct Agreement {
  int interior = 0, beyond = 0;  ///< interior pixels decoded in both, and those off the bound
  double worst_excess = -1e300;  ///< largest |difference| - bound [m/s]
  double worst = 0.0, rms = 0.0; ///< largest and RMS |difference| [m/s]
};

/// The scan's map against the run's at peak amplitude `a` on every plane picture.
Agreement compare(const std::filesystem::path& run_folder, const nlohmann::json& run_pictures,
                  const std::filesystem::path& scan_folder, const nlohmann::json& scan_pictures,
                  double a) {
  const ScannedRun& s = scanned_run();
  Agreement result;
  const double sigma = std::sqrt(2.0) * kVenc / (M_PI * kSnr);
  const double entry = 2 * kSpeedMax / 256;
  const double reach = std::sqrt(2.0) * 5 * kVoxel / 4;
  // The lumina each picture shows: inlet and outlet are the true lumen's planes.
  const std::vector<std::pair<std::string, std::vector<std::size_t>>> planes = {
      {"inlet", {0}}, {"station1", {0, 1}}, {"outlet", {0}}};
  for (const auto& [plane, lumina] : planes) {
    const std::string file = "plane_" + plane + ".png";
    const DecodedMap sim = decode(run_folder / file, picture_named(run_pictures, file));
    const DecodedMap mri =
        decode(scan_folder / ("mri_" + file), picture_named(scan_pictures, "mri_" + file));
    EXPECT_EQ(sim.width, mri.width);
    EXPECT_NEAR(sim.view.half_height, mri.view.half_height, 1e-12) << "not one view";
    for (int j = 0; j < sim.height; ++j)
      for (int i = 0; i < sim.width; ++i) {
        const std::size_t k = i + static_cast<std::size_t>(sim.width) * j;
        const Vec3 p = sim.point(i, j);
        for (const std::size_t lumen : lumina) {
          const SyntheticLumen& l = s.run.lumina[lumen];
          const double rho = std::hypot(p[0] - l.x, p[1]);
          if (rho + reach + sim.pixel() > l.radius || std::isnan(sim.value[k]) ||
              std::isnan(mri.value[k]))
            continue;
          const double c = l.u_peak * a / (l.radius * l.radius);
          const double bound = c * (0.5 + 1.0 / 8) * kVoxel * kVoxel +
                               2 * c * s.circumradius * s.circumradius + 2 * entry + 4.5 * sigma;
          const double excess = std::abs(mri.value[k] - sim.value[k]) - bound;
          ++result.interior;
          result.beyond += excess > 0;
          result.worst_excess = std::max(result.worst_excess, excess);
          result.worst = std::max(result.worst, std::abs(mri.value[k] - sim.value[k]));
          result.rms += (mri.value[k] - sim.value[k]) * (mri.value[k] - sim.value[k]);
        }
      }
  }
  result.rms = std::sqrt(result.rms / std::max(result.interior, 1));
  return result;
}

TEST(ScanPictures, PlaneMapsAgreeWithTheRunWithinNoiseAndPartialVolume) {
  const ScannedRun& s = scanned_run();
  const auto out = report::flow_pictures_dir(s.dir / "run"); // where the report looks
  const testing::Result r = testing::run_tearflow(
      fmt::format("pictures {} --mri {} --mri-venc {} --speed-max {}", (s.dir / "run").string(),
                  (s.dir / "scan").string(), kVenc, kSpeedMax));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json record = testing::read_json(out / "pictures.json");
  // The scan's peak systole is its frame 2 (t = T / 4, a = 1.5), found from its own flow.
  ASSERT_TRUE(record.contains("scan")) << record.dump(2);
  EXPECT_EQ(record["scan"]["peak_systole_frame"], 2);
  // The .mha volumes carry no venc: --mri-venc supplies it, and the scan is unwrapped as `mri
  // flow --venc` unwraps it (the scan has no wraps: venc 1 m/s above its 0.9 m/s peak).
  EXPECT_EQ(record["scan"]["corrections"]["grid"]["venc_m_per_s"], kVenc);
  EXPECT_TRUE(record["scan"]["corrections"]["unwrap"].is_object())
      << record["scan"]["corrections"]["unwrap"];
  const nlohmann::json& frame = record["frames"][0];
  EXPECT_EQ(frame["event"], "peak systole");
  EXPECT_EQ(frame["scan"]["frame"], 2);
  EXPECT_NEAR(frame["scan"]["time_after_trigger_s"].get<double>(), s.run.period / 4, 1e-6);

  const auto folder = out / "peak-systole";
  const Agreement agree =
      compare(folder, frame["pictures"], folder, frame["scan"]["pictures"], 1.5);
  std::printf("interior pixels %d, beyond the bound %d, worst excess %.4f m/s, largest "
              "difference %.4f m/s, RMS %.4f m/s (largest circumradius %.3f mm)\n",
              agree.interior, agree.beyond, agree.worst_excess, agree.worst, agree.rms,
              1e3 * s.circumradius);
  EXPECT_GT(agree.interior, 1000) << "too few interior pixels to compare";
  EXPECT_EQ(agree.beyond, 0) << "worst excess " << agree.worst_excess << " m/s";

  // The report's section: the scan's column beside the run's, picture by picture.
  const std::string section = report::flow_patterns_section({s.dir / "run"}, {"OR"});
  EXPECT_NE(section.find("OR: 4D-flow MRI, scan frame 2"), std::string::npos)
      << section.substr(0, 2000);
  EXPECT_NE(section.find("alt='mri_plane_station1.png'"), std::string::npos);
  EXPECT_NE(section.find("alt='mri_streamlines_anterior.png'"), std::string::npos);

  // The comparison can fail: the run's frame at t = 3T/4 (a = 0.5) against the scan's peak.
  const auto late = s.dir / "pictures-late";
  const testing::Result r2 = testing::run_tearflow(
      fmt::format("pictures {} --time {} --speed-max {} -o {}", (s.dir / "run").string(),
                  0.75 * s.run.period, kSpeedMax, late.string()));
  ASSERT_EQ(r2.code, 0) << r2.output;
  const nlohmann::json late_record = testing::read_json(late / "pictures.json");
  const Agreement wrong =
      compare(late / late_record["frames"][0]["folder"].get<std::string>(),
              late_record["frames"][0]["pictures"], folder, frame["scan"]["pictures"], 1.5);
  EXPECT_GT(wrong.beyond, wrong.interior / 4) << "a third of the amplitude went unnoticed";
}

TEST(ScanPictures, StreamlinesStartFromTheRunsSeedsAndStayInTheLumen) {
  const ScannedRun& s = scanned_run();
  const auto out = s.dir / "pictures-lines";
  const testing::Result r = testing::run_tearflow(
      fmt::format("pictures {} --mri {} --no-png -o {}", (s.dir / "run").string(),
                  (s.dir / "scan").string(), out.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto read = [](const std::filesystem::path& f) {
    auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    reader->SetFileName(f.c_str());
    reader->Update();
    return vtkSmartPointer<vtkPolyData>(reader->GetOutput());
  };
  const auto run_lines = read(out / "peak-systole" / "streamlines.vtp");
  const auto scan_lines = read(out / "peak-systole" / "mri_streamlines.vtp");
  ASSERT_GT(scan_lines->GetNumberOfLines(), 20);
  // Each scan line starts at one of the run's seeds (the first points of the run's lines),
  // to the VTP's float precision.
  std::vector<Vec3> seeds;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  for (run_lines->GetLines()->InitTraversal(); run_lines->GetLines()->GetNextCell(n, ids);) {
    Vec3 x;
    run_lines->GetPoint(ids[0], x.data());
    seeds.push_back(x);
  }
  const double tol = 1e-7; // float rounding of coordinates of a few cm
  const double inlet = 0.004;
  for (scan_lines->GetLines()->InitTraversal(); scan_lines->GetLines()->GetNextCell(n, ids);) {
    Vec3 first;
    scan_lines->GetPoint(ids[0], first.data());
    double nearest = 1e300;
    for (const Vec3& q : seeds)
      nearest = std::min(nearest, std::sqrt(dot(first - q, first - q)));
    EXPECT_LT(nearest, tol) << "a scan streamline starts off the run's seeds";
    EXPECT_NEAR(first[2], inlet, tol);
    // The scan's axial flow keeps a trace in its lumen: within the true lumen's radius
    // (partial volume and noise bend it by far less than a voxel over 3 cm).
    for (vtkIdType k = 0; k < n; ++k) {
      double x[3];
      scan_lines->GetPoint(ids[k], x);
      EXPECT_LE(std::hypot(x[0] - s.run.lumina[0].x, x[1]), s.run.lumina[0].radius + kVoxel);
    }
  }
}

TEST(ScanPictures, TheScansAnimationPlaysBesideTheRunsFromItsSeeds) {
  // `--animate --mri`: the scan's streamlines of each of its frames, from the run's seeds in
  // the run's camera (scan_frame's tracing, checked above), as an animation of the same view
  // and the same pace as the run's, on the same row of the report.
  const ScannedRun s;
  const testing::Result r = testing::run_tearflow(
      fmt::format("pictures {} --mri {} --mri-venc {} --speed-max {} --animate",
                  (s.dir / "run").string(), (s.dir / "scan").string(), kVenc, kSpeedMax));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto out = report::flow_pictures_dir(s.dir / "run");
  const nlohmann::json record = testing::read_json(out / "pictures.json");
  ASSERT_TRUE(record.contains("scan_animation")) << record.dump(2).substr(0, 2000);
  const nlohmann::json &run = record["animation"], &scan = record["scan_animation"];
  const unsigned frames = static_cast<unsigned>(s.run.frames - 1); // the scan's (fixture)
  EXPECT_EQ(scan["frames"], frames);
  EXPECT_EQ(testing::apng_frame_count(out / scan["file"].get<std::string>()), frames);
  EXPECT_EQ(scan["file"], "mri_" + run["file"].get<std::string>());
  EXPECT_EQ(scan["view"], run["view"]);
  // The scan's frame k is the run's saved frame k (t = k T / 8).
  for (unsigned k = 0; k < frames; ++k)
    EXPECT_NEAR(scan["frame_times_s"][k].get<double>(), run["frame_times_s"][k].get<double>(), 1e-9)
        << "frame " << k;
  // One pace: each cycle lasts the same within one frame's delay (integer milliseconds).
  const int run_ms = run["frames"].get<int>() * run["frame_delay_ms"].get<int>(),
            scan_ms = scan["frames"].get<int>() * scan["frame_delay_ms"].get<int>();
  EXPECT_LE(std::abs(run_ms - scan_ms),
            std::max(run["frame_delay_ms"].get<int>(), scan["frame_delay_ms"].get<int>()));
  // Every frame shows streamlines: pixels in the colour map's hues left of the colour bar
  // (which lies right of 80 % of the width), where only they are coloured (the grey lumen is
  // not: none in the part without streamlines). The caption and colour bar alone would pass a
  // "something drawn" check.
  for (unsigned k = 0; k < frames; ++k) {
    const std::string name =
        fmt::format("mri_streamlines_{:03d}_{}.png", k, scan["view"].get<std::string>());
    std::printf("%s: %.4f of the picture coloured\n", name.c_str(),
                testing::coloured_fraction(out / "animation" / name, 0.8));
    EXPECT_GT(testing::coloured_fraction(out / "animation" / name, 0.8), 0.0) << name;
  }

  // The report: the scan's animation in the scan's column, on the run's animation's row.
  const std::string section = report::flow_patterns_section({s.dir / "run"}, {"OR"});
  const std::size_t at = section.find("alt='../" + run["file"].get<std::string>() + "'");
  ASSERT_NE(at, std::string::npos);
  const std::size_t row_end = section.find("</tr>", at);
  EXPECT_NE(section.substr(at, row_end - at).find("alt='../" + scan["file"].get<std::string>()),
            std::string::npos);
}

TEST(ScanPictures, BadScanInputIsAClearError) {
  const ScannedRun s(false); // both errors come before the scan is read
  const auto run = (s.dir / "run").string();
  const auto missing = testing::run_tearflow(
      fmt::format("pictures {} --mri {} --no-png", run, (s.dir / "nothing").string()));
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.output.find("nothing"), std::string::npos) << missing.output;
  const auto timed = testing::run_tearflow(
      fmt::format("pictures {} --mri {} --time 0.2 --no-png", run, (s.dir / "scan").string()));
  EXPECT_NE(timed.code, 0);
  EXPECT_NE(timed.output.find("--time"), std::string::npos) << timed.output;
}

} // namespace
} // namespace tearflow

namespace tearflow {
namespace {

TEST(ScanPictures, AScanInAnotherFrameIsPlacedByItsAlignment) {
  // The scan moved into a rotated, shifted patient frame and placed back by the paired points
  // gives the scan's own sections: the same voxels at the same model points (to the rounding
  // of the fit and of the .mha's geometry). What differs is the background correction, fitted
  // to each scan's static tissue on its own: 10 coefficients over ~12 k voxels of noise rms
  // 0.02 m/s put each fit within sqrt(10 / 12e3) 0.02 = 6e-4 m/s of the truth, so the mean
  // u.n of a section within 2e-3 m/s (about 3 of these) of the other's.
  const ScannedRun& s = scanned_run();
  const auto out = s.dir / "pictures-moved", own = s.dir / "pictures-own";
  for (const auto& [scan, folder, align] :
       {std::tuple{s.dir / "scan-moved", out,
                   " --mri-align " + (s.dir / "scan-moved.json").string()},
        std::tuple{s.dir / "scan", own, std::string()}}) {
    const testing::Result r = testing::run_tearflow(
        fmt::format("pictures {} --mri {}{} --no-png -o {}", (s.dir / "run").string(),
                    scan.string(), align, folder.string()));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const nlohmann::json moved = testing::read_json(out / "pictures.json")["frames"][0]["scan"],
                       unmoved = testing::read_json(own / "pictures.json")["frames"][0]["scan"];
  for (const char* plane : {"inlet", "TL1", "FL1", "outlet"}) {
    const double q = unmoved["planes"][plane]["flow_m3_per_s"],
                 area = unmoved["planes"][plane]["area_m2"];
    EXPECT_NEAR(moved["planes"][plane]["area_m2"].get<double>(), area, 1e-6 * area) << plane;
    EXPECT_NEAR(moved["planes"][plane]["flow_m3_per_s"].get<double>(), q, 2e-3 * area) << plane;
  }
}

} // namespace
} // namespace tearflow
