// The study's 2D scans (issue 29): 2D through-plane phase contrast of the analytic pipe read
// back from DICOM and measured against the exact flow; `mri inflow` turning such scans into a
// case that `tune` and `run` take; 2D cine of a run with moving walls tracked into true and
// false lumen areas against the run's own; and the errors of bad 2D input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>

#include <gtest/gtest.h>

#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "mri/corrected_scan.hpp"
#include "mri/corrections.hpp"
#include "mri/image_io.hpp"
#include "mri/lumen_tracking.hpp"
#include "mri/measured_case.hpp"
#include "mri/synthetic_run.hpp"
#include "mri/vessel_flow.hpp"
#include "mri_support.hpp"

using namespace tearflow;
using namespace tearflow::testing;

namespace {

/// A 2D phase-contrast slice of the test pipe (radius 6 mm, pixels 1.5 mm, slice 6 mm)
/// through its axis point, its normal tilted by `degrees` about (1, 1, 0) from the axis; the
/// field of view `fov` radii across (static tissue out to 0.45 fov, air beyond).
mri::PipeScan pc_slice(double degrees, double snr = 0.0, double radius = 6e-3, double fov = 5) {
  mri::PipeScan s = test_pipe_scan(degrees, snr, radius);
  const int n = static_cast<int>(std::ceil(fov * radius / 1.5e-3)) + 1;
  s.tissue_radius = 0.45 * fov * radius;
  s.grid = mri::centred_grid(s.axis_point, mri::rotation({1, 1, 0}, degrees), {n, n, 1},
                             {1.5e-3, 1.5e-3, 6e-3});
  s.encoding = mri::Encoding::through_plane;
  return s;
}

/// Largest |Q - Q_exact| / Q_exact over the frames.
double worst_error(const mri::PipeScan& scan, const mri::VesselFlow& v) {
  double worst = 0.0;
  for (int k = 0; k < scan.frames; ++k) {
    const double exact = mri::exact_frame_flow(scan, k);
    worst = std::max(worst, std::abs(v.flow[k] - exact) / exact);
  }
  return worst;
}

} // namespace

TEST(Mri2d, PhaseContrastFlowOfAnObliquePipeThroughDicom) {
  for (double degrees : {0.0, 25.0}) {
    for (auto convention : {mri::PhaseConvention::classic, mri::PhaseConvention::rescaled}) {
      const mri::PipeScan scan = pc_slice(degrees);
      const auto dir = fresh_dir("mri2d-pc");
      mri::write_dicom(mri::synthesize_pipe(scan), dir, {convention});
      const mri::Flow4D data = mri::read_dicom(dir);
      ASSERT_EQ(data.encoding, mri::Encoding::through_plane);
      EXPECT_EQ(data.grid.size[2], 1);
      EXPECT_NEAR(data.period, 0.8, 1e-3); // NominalInterval, written in whole ms
      const mri::VesselFlow v = mri::measure_vessel(data, "AAo", {});
      EXPECT_EQ(v.seed_from, "slice centre");
      // The bound, 2 % noise-free; through an oblique slice the flux of the
      // divergence-free pipe flow is Q itself, and what remains is partial volume, the flow
      // margin and the 12-bit phase quantization (venc / 2048 per pixel): measured ~0.2 %.
      const double worst = worst_error(scan, v);
      std::printf("%g degrees, %s: worst frame %.3f %%\n", degrees,
                  convention == mri::PhaseConvention::classic ? "classic" : "rescaled",
                  100 * worst);
      EXPECT_LT(worst, 0.02);
    }
  }
}

TEST(Mri2d, FlowSignFollowsTheVesselOrTheLandmark) {
  // The slice's normal turned against the flow: the scanner reads negative through-plane
  // velocity; the vessel's flow is still positive (its cycle mean), or follows the landmark.
  mri::PipeScan scan = pc_slice(180.0);
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  const mri::VesselFlow v = mri::measure_vessel(data, "AAo", {});
  EXPECT_EQ(v.sign, -1);
  EXPECT_GT(v.mean_flow(), 0.0);
  EXPECT_LT(worst_error(scan, v), 0.02);
  // A landmark whose normal points against the flow (upstream) gives negative flow: the
  // landmark decides, not the mean.
  geometry::Landmarks landmarks = test_pipe_landmarks(scan);
  landmarks.planes[0].normal = Vec3{0, 0, -1};
  landmarks.planes[0].point = scan.axis_point + Vec3{1e-3, 0, 0};
  const mri::VesselFlow w = mri::measure_vessel(data, "AAo", {std::nullopt, &landmarks});
  EXPECT_EQ(w.seed_from, "landmark AAo");
  EXPECT_LT(w.mean_flow(), 0.0);
  // A seed outside the slice's field of view is an error naming the scan.
  expect_input_error(
      [&] {
        mri::measure_vessel(data, "AAo", {Vec3{0.5, 0.0, 0.05}, nullptr});
      },
      "outside the slice");
}

TEST(Mri2d, PhaseOffsetIsRemovedOnASlice) {
  // SNR 20 and a linear + quadratic offset of up to ~5 % of venc, on a slice of 90 mm with
  // tissue to 40 mm (a 2D scan's field of view holds far more static tissue than the vessel).
  // Bounds: the fitted offset within 1 % of venc of the applied one over the lumen (the 4D
  // criterion, issue 29); the cycle-mean flow within 1 % of that of the same scan (the same
  // noise) without the offset and uncorrected: the correction's own error, apart from the
  // noise's (the flow region's tissue rim alone gives the cycle mean ~0.5 % of noise here).
  // Expected: the fit's noise, time-mean phase noise on tissue (0.45 venc / SNR / 0.2 /
  // sqrt(20) = 0.025 m/s) over ~1,200 static pixels and 6 in-plane terms: ~0.002 m/s, 0.5 %
  // of the mean velocity at most.
  for (unsigned seed : {1u, 2u, 3u}) {
    mri::PipeScan scan = pc_slice(25.0, 20.0, 6e-3, 15);
    scan.seed = seed;
    mri::Flow4D data = mri::synthesize_pipe(scan);
    const auto clean_dir = fresh_dir("mri2d-no-offset");
    mri::write_dicom(data, clean_dir);
    const double a = 0.05 * scan.venc;
    using V = std::vector<double>;
    const std::array<V, 3> applied{V{0.2 * a, 0.3 * a, -0.2 * a, 0.1 * a, 0.2 * a},
                                   V{-0.3 * a, 0, 0.2 * a, 0, 0, 0.15 * a},
                                   V{0.1 * a, -0.1 * a, 0, 0.3 * a, 0, 0, 0.2 * a}};
    mri::add_background(data, applied);
    mri::encode(data, mri::Encoding::through_plane);
    const auto dir = fresh_dir("mri2d-offset");
    mri::write_dicom(data, dir);
    nlohmann::json report, plain;
    const mri::Flow4D corrected = mri::read_corrected(dir, {}, report);
    const mri::Flow4D uncorrected = mri::read_corrected(dir, {0.0, true, false}, plain);
    const mri::Flow4D no_offset = mri::read_corrected(clean_dir, {0.0, true, false}, plain);
    // The fitted against the applied offset along the slice normal, over the lumen's pixels.
    const mri::ImageGrid& g = corrected.grid;
    const Vec3& n = g.direction[2];
    double worst_offset = 0.0;
    std::vector<double> mono;
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i) {
        const Vec3 p = g.point({double(i), double(j), 0.0}) - scan.axis_point;
        if (dot(p, p) - dot(p, scan.axis) * dot(p, scan.axis) > 36e-6) // outside the lumen
          continue;
        mri::monomials(mri::normalized_position(g, i, j, 0), 2, mono);
        double difference = 0.0;
        for (int c = 0; c < 3; ++c) {
          const char* names[] = {"x", "y", "z"};
          const auto fitted =
              report["background"]["coefficients_m_per_s"][names[c]].get<std::vector<double>>();
          for (std::size_t t = 0; t < mono.size(); ++t)
            difference += n[c] * mono[t] *
                          ((t < fitted.size() ? fitted[t] : 0.0) -
                           (t < applied[c].size() ? applied[c][t] : 0.0));
        }
        worst_offset = std::max(worst_offset, std::abs(difference));
      }
    const double reference = mri::measure_vessel(no_offset, "AAo", {}).mean_flow();
    const double before = mri::measure_vessel(uncorrected, "AAo", {}).mean_flow() / reference - 1;
    const double after = mri::measure_vessel(corrected, "AAo", {}).mean_flow() / reference - 1;
    double exact = 0.0;
    for (int k = 0; k < scan.frames; ++k)
      exact += mri::exact_frame_flow(scan, k) / scan.frames;
    std::printf("seed %u: mean flow against the scan without offset %.2f %% uncorrected, %.3f %% "
                "corrected (its noise: %.2f %% from the exact); offset left over the lumen "
                "%.4f m/s; %zu static pixels\n",
                seed, 100 * before, 100 * after, 100 * (reference / exact - 1), worst_offset,
                report["background"]["static_voxels"].get<std::size_t>());
    EXPECT_GT(std::abs(before), 0.02); // the offset matters
    EXPECT_LT(std::abs(after), 0.01);
    EXPECT_LT(worst_offset, 0.01 * scan.venc);
  }
}

TEST(Mri2d, InflowCommandMakesACaseThatTuneAndRunTake) {
  // The small tuning pipe's flow (radius 5 mm, 0.08 s cycle, 2-8 mL/s) scanned at its inlet
  // and outlet; `mri inflow` writes the case's inflow and the targets (the outlet the inlet's
  // flow, the pressures given), `tune` (0D stage) and `run` (two steps) accept them.
  mri::PipeScan scan = pc_slice(20.0, 0.0, 5e-3);
  scan.flow = mri::pulsatile_pipe_flow(5e-3, 0.064, 0.3);
  scan.flow.omega = 2 * std::numbers::pi / 0.08;
  scan.venc = 0.2;
  const auto dir = fresh_dir("mri2d-inflow");
  mri::write_dicom(mri::synthesize_pipe(scan), dir / "inlet");
  const Result r =
      run_tearflow("mri inflow " + (test_data / "tuning/small_pipe.yaml").string() + " --inlet " +
                   (dir / "inlet").string() + " --outlet outlet=" + (dir / "inlet").string() +
                   " --pressure 105/75/90mmHg -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto summary = read_json(dir / "out/mri_inflow.json");
  // 0.08 s at the case's 4 ms step: 20 samples; the spline's mean of the 20 frames.
  EXPECT_EQ(summary["case"]["inflow"]["samples"].get<int>(), 20);
  double exact = 0.0;
  for (int k = 0; k < scan.frames; ++k)
    exact += mri::exact_frame_flow(scan, k) / scan.frames;
  EXPECT_NEAR(summary["case"]["inflow"]["mean_mL_per_s"].get<double>() * 1e-6, exact, 0.02 * exact);
  EXPECT_NEAR(summary["case"]["splits_percent"]["outlet"].get<double>(), 100.0, 1e-9);
  const std::string out = (dir / "out").string();
  const Result tune = run_tearflow("tune " + out + "/case.yaml --targets " + out +
                                   "/targets.yaml --iterations 0 -q -o " + out + "/tuned.yaml");
  EXPECT_EQ(tune.code, 0) << tune.output;
  const Result run = run_tearflow("run " + out + "/tuned.yaml --steps 2 -q -o " + out + "/run");
  EXPECT_EQ(run.code, 0) << run.output;
}

TEST(MriCommand, BadInputOfInflow) {
  mri::PipeScan scan = pc_slice(0.0, 0.0, 5e-3);
  const auto dir = fresh_dir("mri2d-inflow-bad");
  mri::write_dicom(mri::synthesize_pipe(scan), dir / "pc");
  const std::string pc = (dir / "pc").string(), out = (dir / "out").string();
  const std::string pipe = (test_data / "tuning/small_pipe.yaml").string();
  auto expect = [&](const std::string& args, const std::string& says) {
    const Result r = run_tearflow(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << args << "\n" << r.output;
  };
  expect("mri inflow " + pipe + " --outlet outlet=" + pc + " -o " + out, "--pressure");
  expect("mri inflow " + pipe + " --outlet nowhere=" + pc + " --pressure 120/70/90 -o " + out,
         "not an rcr or resistance outlet");
  expect("mri inflow " + pipe + " --inlet " + pc + "@1,2 -o " + out, "three numbers");
  expect("mri inflow " + pipe + " --pressure 70/120/90 --outlet outlet=" + pc + " -o " + out,
         "diastolic < mean < systolic");
  // A 2D scan given to the 4D-flow command, and a 4D scan to the 2D one.
  expect("mri flow " + pc + " --landmarks " + (dir / "none.json").string() + " -o " + out,
         "mri inflow");
  mri::write_dicom(mri::synthesize_pipe(test_pipe_scan()), dir / "4d");
  expect("mri inflow " + pipe + " --inlet " + (dir / "4d").string() + " -o " + out,
         "2D phase contrast");
  // Numbers only partly numbers, a face scanned twice, a seed off the slice.
  expect("mri inflow " + pipe + " --pressure 126.5.1/60/86 --outlet outlet=" + pc + " -o " + out,
         "SYSTOLIC/DIASTOLIC/MEAN");
  expect("mri inflow " + pipe + " --pressure e/60/86 --outlet outlet=" + pc + " -o " + out,
         "SYSTOLIC/DIASTOLIC/MEAN");
  expect("mri inflow " + pipe + " --pressure 120/70/90 --outlet outlet=" + pc +
             " --outlet outlet=" + pc + " -o " + out,
         "two scans for the outlet");
  expect("mri inflow " + pipe + " --inlet " + pc + "@10,-20,500 -o " + out, "off the slice");
  expect("mri synthesize -o " + out + " --scan-type pc --format nifti", "written as DICOM");
  // A seed in tissue that fills the field of view: the lumen region floods to the edge.
  scan.tissue_radius = 1.0;
  mri::write_dicom(mri::synthesize_pipe(scan), dir / "tissue");
  expect("mri inflow " + pipe + " --inlet " + (dir / "tissue").string() + "@17.5,-20,50 -o " + out,
         "reaches the edge");
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "case.yaml")); // nothing written
}

TEST(Mri2d, AliasedObliquePhaseContrastIsUnwrapped) {
  // venc 0.55 m/s below the pipe's systolic centreline velocity (~0.65 m/s), the slice tilted
  // 25 degrees: systole aliases; the through-plane value is unwrapped as one number (its
  // stored components by 2 venc n_c would be wrong). Noise-free: the bound of the unaliased
  // scan, 2 % per frame.
  mri::PipeScan scan = pc_slice(25.0);
  scan.venc = 0.55;
  const auto dir = fresh_dir("mri2d-alias");
  mri::write_dicom(mri::synthesize_pipe(scan), dir);
  nlohmann::json report, plain;
  const mri::Flow4D unwrapped = mri::read_corrected(dir, {}, report);
  const mri::Flow4D aliased = mri::read_corrected(dir, {0.0, false, true}, plain);
  EXPECT_GT(report["unwrap"]["values_unwrapped"].get<std::size_t>(), 0u);
  EXPECT_GT(worst_error(scan, mri::measure_vessel(aliased, "AAo", {})), 0.1);
  const double worst = worst_error(scan, mri::measure_vessel(unwrapped, "AAo", {}));
  std::printf("unwrapped %zu values; worst frame %.3f %%\n",
              report["unwrap"]["values_unwrapped"].get<std::size_t>(), 100 * worst);
  EXPECT_LT(worst, 0.02);
}

TEST(Mri2d, CineTracksBothLuminaOfAMovingWall) {
  // Two lumina (radii 6 and 8 mm) 2.5 mm apart, their walls dilating by up to 5 % of the radius
  // over the cycle (the area by 10 %; the flap between them then 1.8 mm, the study's is 2 mm),
  // imaged as 2D cine at 1 mm pixels, SNR 20, 30 frames; the tracked areas against the run's
  // own (its landmark sections, linear between its saved frames as the scan reads them).
  // Bound 5 % at every frame (issue 29); expected: the edge's blood fractions carry the
  // magnitude noise (1/SNR over a contrast of 0.8 per pixel, ~80 edge and ring pixels: ~0.6
  // pixel of ~115) and the scanner's sampling of the moving edge: ~1-2 %.
  SyntheticRun run;
  run.lumina = {{-7.5e-3, 6e-3, 0.5, 1e4}, {9.0e-3, 8e-3, 0.3, 1e4}};
  run.length = 10e-3;
  run.element_size = 1e-3;
  run.frames = 11;
  run.dilation = [](double t) { return 0.025 * (1 - std::cos(2 * std::numbers::pi * t / 0.8)); };
  const auto dir = fresh_dir("mri2d-cine-run");
  write_synthetic_run(run, dir);
  geometry::Landmarks landmarks;
  landmarks.planes = {plane_at(run, "TL1", 5e-3, 0, "TL"), plane_at(run, "FL1", 5e-3, 1, "FL")};
  std::filesystem::create_directories(dir / "geometry");
  geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");
  // The scans through the command, as a user makes them.
  const Result synth = run_tearflow("mri synthesize " + dir.string() + " --scan-type cine " +
                                    "--voxel 1mm --thickness 5mm --fov 60mm --frames 30 " +
                                    "--snr 20 -o " + (dir / "cine").string());
  ASSERT_EQ(synth.code, 0) << synth.output;
  const Result cine = run_tearflow("mri cine --at 1=" + (dir / "cine/station1").string() +
                                   " --landmarks " + (dir / "geometry/landmarks.json").string() +
                                   " -o " + (dir / "measured").string());
  ASSERT_EQ(cine.code, 0) << cine.output;
  const auto report = read_json(dir / "measured/cine.json");
  EXPECT_EQ(report["scans"]["1"]["swaps"].get<int>(), 0);
  // The run's areas, and the measured table as `analyze` reads it.
  analysis::AnalyzeOptions o;
  o.run_dir = dir;
  const analysis::Analysis sim = analysis::analyze_run(o);
  o.run_dir = dir / "measured";
  const analysis::Analysis mri_areas = analysis::analyze_run(o);
  const double period = 0.8;
  for (std::size_t l = 0; l < 2; ++l) {
    const auto& s = sim.series[l];
    const auto& m = mri_areas.series[l];
    ASSERT_EQ(s.landmark.name, m.landmark.name);
    double worst = 0.0, swing = 0.0;
    for (std::size_t k = 0; k < mri_areas.time.size(); ++k) {
      // The run's area at the frame's centre, averaged over its window (T / 30).
      const double t0 = mri_areas.time[k], dt = period / 30;
      double expected = 0.0;
      for (int q = 0; q < 60; ++q) {
        double t = t0 + ((q + 0.5) / 60 - 0.5) * dt;
        t -= period * std::floor(t / period);
        std::size_t i = 1;
        while (i + 1 < sim.time.size() && sim.time[i] < t)
          ++i;
        const double w = (t - sim.time[i - 1]) / (sim.time[i] - sim.time[i - 1]);
        expected += ((1 - w) * s.samples[i - 1].area + w * s.samples[i].area) / 60;
      }
      worst = std::max(worst, std::abs(m.samples[k].area - expected) / expected);
      swing = std::max(swing, expected / s.samples[0].area - 1);
    }
    std::printf("%s: worst frame area difference %.2f %% (the wall moves the area by %.1f %%)\n",
                s.landmark.name.c_str(), 100 * worst, 100 * swing);
    EXPECT_GT(swing, 0.08); // the area changes by more than the bound: tracking is tested
    EXPECT_LT(worst, 0.05) << s.landmark.name;
  }
  // The report overlays them: both analysed folders' A(t)/A_0 on the comparison page.
  ASSERT_EQ(run_tearflow("analyze " + dir.string() + " -q").code, 0);
  ASSERT_EQ(run_tearflow("analyze " + (dir / "measured").string() + " -q").code, 0);
  const Result page = run_tearflow("report " + dir.string() + " " + (dir / "measured").string() +
                                   " -q -o " + (dir / "comparison.html").string());
  ASSERT_EQ(page.code, 0) << page.output;
  std::ifstream html(dir / "comparison.html");
  const std::string text((std::istreambuf_iterator<char>(html)), {});
  EXPECT_NE(text.find("\"measured\""), std::string::npos); // the measured folder's series
  EXPECT_NE(text.find("area_over_A_0"), std::string::npos);
  // One station measured twice (by number and by name) is refused.
  const Result twice =
      run_tearflow("mri cine --at 1=" + (dir / "cine/station1").string() +
                   " --at TL1=" + (dir / "cine/station1").string() + " --landmarks " +
                   (dir / "geometry/landmarks.json").string() + " -o " + (dir / "twice").string());
  EXPECT_EQ(twice.code, 2) << twice.output;
  EXPECT_NE(twice.output.find("measured twice"), std::string::npos) << twice.output;
}

TEST(Mri2d, CineSplitsLuminaJoinedAcrossAThinFlap) {
  // The lumina 0.4 mm apart, less than the 1 mm pixel: the pixels astride the flap are mostly
  // blood, the two regions join, and the watershed from the two markers splits them at the
  // flap's dark ridge. Each area within 5 % of the exact (pi r^2, no wall motion), the labels
  // where the markers are.
  SyntheticRun run;
  run.lumina = {{-6.2e-3, 6e-3, 0.5, 1e4}, {6.2e-3, 6e-3, 0.3, 1e4}};
  run.length = 10e-3;
  run.element_size = 0.8e-3;
  run.frames = 5;
  const auto dir = fresh_dir("mri2d-cine-thin");
  write_synthetic_run(run, dir);
  mri::RunScan scan;
  scan.run_dir = dir;
  scan.frames = 4;
  scan.encoding = mri::Encoding::magnitude;
  scan.grid = mri::centred_grid({0, 0, 5e-3}, mri::rotation({0, 0, 1}, 10.0), {40, 40, 1},
                                {1e-3, 1e-3, 5e-3});
  const mri::Flow4D cine = mri::synthesize_run(scan);
  const mri::LuminaSeries s =
      mri::track_lumina(cine, "1", {-6.2e-3, 0, 5e-3}, Vec3{6.2e-3, 0, 5e-3});
  EXPECT_EQ(s.split_frames, 4);
  EXPECT_EQ(s.swaps, 0);
  const double exact = std::numbers::pi * 36e-6;
  for (std::size_t k = 0; k < s.time.size(); ++k) {
    std::printf("frame %zu: TL %.1f, FL %.1f mm2 (exact %.1f)\n", k, s.tl_area[k] * 1e6,
                s.fl_area[k] * 1e6, exact * 1e6);
    EXPECT_NEAR(s.tl_area[k], exact, 0.05 * exact);
    EXPECT_NEAR(s.fl_area[k], exact, 0.05 * exact);
  }
  // Bad input: a point off the slice, both points on one pixel, a phase-contrast scan.
  expect_input_error(
      [&] {
        mri::track_lumina(cine, "1", {0.5, 0, 5e-3}, std::nullopt);
      },
      "outside the cine slice");
  expect_input_error(
      [&] {
        mri::track_lumina(cine, "1", {-6.2e-3, 0, 5e-3}, Vec3{-6.2e-3, 1e-4, 5e-3});
      },
      "one pixel");
  expect_input_error(
      [&] {
        mri::track_lumina(cine, "1", {-6.2e-3, 0, 15e-3}, std::nullopt);
      },
      "off the slice"); // 10 mm off a 5 mm slice: another plane's point
  // A NaN in the magnitude next to a lumen is refused, not turned into a NaN area.
  mri::Flow4D damaged = cine;
  damaged.frames[1].magnitude[cine.grid.linear(20, 26, 0)] = std::nanf("");
  expect_input_error(
      [&] {
        mri::track_lumina(damaged, "1", {-6.2e-3, 0, 5e-3}, Vec3{6.2e-3, 0, 5e-3});
      },
      "station 1, frame 1 (t = ");
  expect_input_error(
      [&] {
        mri::track_lumina(damaged, "1", {-6.2e-3, 0, 5e-3}, Vec3{6.2e-3, 0, 5e-3});
      },
      "not numbers (NaN or infinite), from magnitude; the areas would be wrong");
  // One frame without an R-R interval has no cycle.
  mri::Flow4D one = cine;
  one.frames.resize(1);
  one.period = 0.0;
  expect_input_error([&] { one.cycle("cine"); }, "one frame");
}

TEST(MriDicom, BadInputOf2dScans) {
  // A through-plane series over several slices, and a magnitude-only series over several
  // slices (neither cine nor 4D flow): each said, naming the folder.
  mri::PipeScan pc = test_pipe_scan();
  pc.grid.size[2] = 3;
  mri::Flow4D data = mri::synthesize_pipe(pc);
  const auto dir = fresh_dir("mri2d-bad-dicom");
  // Written as 4D flow without the phase series: magnitude only, 3 slices.
  mri::write_dicom(data, dir / "magnitude-only",
                   {mri::PhaseConvention::classic, true, true, false});
  std::filesystem::remove_all(dir / "magnitude-only/vx");
  std::filesystem::remove_all(dir / "magnitude-only/vy");
  expect_input_error([&] { mri::read_dicom(dir / "magnitude-only"); }, "one slice");
  // Issue 62: what it most likely is, a 4D export short of its phase series, is said first.
  expect_input_error([&] { mri::read_dicom(dir / "magnitude-only"); },
                     "a magnitude series alone, 3 slices per frame: the phase series are missing");
  expect_input_error([&] { mri::encode(data, mri::Encoding::through_plane); }, "one slice");
}
