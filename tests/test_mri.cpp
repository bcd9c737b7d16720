// 4D-flow MRI without file I/O: the synthetic scanner, plane flow against the exact
// Womersley flow, oblique grids, background-offset removal and phase unwrapping.
#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mri/alignment.hpp"
#include "mri/corrections.hpp"
#include "mri/plane_flow.hpp"
#include "mri_support.hpp"

using namespace tearflow;
using namespace tearflow::testing;

TEST(MriSynthetic, FrameFlowIsTheWindowMeanOfTheExactFlow) {
  // The closed form (sinc per mode) against a fine midpoint rule of Q(t) over the window.
  const mri::PipeScan scan = test_pipe_scan();
  const double dt = 0.8 / scan.frames;
  for (int k : {0, 7, 13}) {
    double mean = 0.0;
    const int m = 2000;
    for (int q = 0; q < m; ++q)
      mean += scan.flow.flow(k * dt + ((q + 0.5) / m - 0.5) * dt) / m;
    // Midpoint rule with 2000 points: relative error ~ (w dt / 2000)^2 / 24 ~ 1e-10.
    EXPECT_NEAR(mri::exact_frame_flow(scan, k), mean, 1e-8 * mean);
  }
}

TEST(MriSynthetic, NoiseFreePlaneFlowWithinTwoPercent) {
  // Issue 9: noise-free, 1.5 mm voxels, 8 across the lumen: within 2 % at every frame.
  const mri::PipeScan scan = test_pipe_scan();
  const double worst = worst_flow_error(scan, mri::synthesize_pipe(scan));
  std::printf("noise-free worst frame flow error %.3f %%\n", 100 * worst);
  EXPECT_LT(worst, 0.02);
}

TEST(MriSynthetic, ObliqueGridGivesTheSameFlows) {
  // Grid rotated 35 degrees about (1, 1, 0): the plane cuts the voxels obliquely. Same 2 %
  // bound as the axis-aligned scan, and the two agree to within it frame by frame.
  const mri::PipeScan straight = test_pipe_scan(0.0), oblique = test_pipe_scan(35.0);
  const auto a = mri::measure_planes(mri::synthesize_pipe(straight), test_pipe_landmarks(straight));
  const auto b = mri::measure_planes(mri::synthesize_pipe(oblique), test_pipe_landmarks(oblique));
  double worst = 0.0;
  for (int k = 0; k < straight.frames; ++k) {
    const double exact = mri::exact_frame_flow(oblique, k);
    EXPECT_NEAR(b[0].flow[k], exact, 0.02 * exact) << "frame " << k;
    worst = std::max(worst, std::abs(a[0].flow[k] - b[0].flow[k]) / exact);
  }
  std::printf("oblique vs axis-aligned: worst difference %.3f %%\n", 100 * worst);
  EXPECT_LT(worst, 0.02);
}

TEST(MriSynthetic, NoisyPlaneFlowWithinFivePercent) {
  // SNR 20: phase noise sigma_v = sqrt(2)/pi venc / 20 = 0.0225 m/s per lumen voxel, 5x that
  // in the tissue (a fifth of blood's signal) at the lumen's rim. In the descending aorta's
  // size (R 9 mm, 12 voxels across, ~130 voxels in the flow region) the frame flow's noise is
  // about 0.0225 m/s x 2.25 mm^2 x sqrt(130) = 0.6 mL/s, 1 % of the smallest frame flow
  // (58 mL/s), more with the rim and the trilinear reformat: measured worst of the 20 frames
  // 2.4-3.3 % for seeds 1-3 (about 3 sigma), under the 5 % of issue 9 for each seed.
  for (std::uint64_t seed : {1, 2, 3}) {
    mri::PipeScan scan = test_pipe_scan(0.0, 20.0, 9e-3);
    scan.seed = seed;
    const double worst = worst_flow_error(scan, mri::synthesize_pipe(scan));
    std::printf("SNR 20, seed %d: worst frame flow error %.3f %%\n", int(seed), 100 * worst);
    EXPECT_LT(worst, 0.05);
  }
}

TEST(MriCorrections, LinearPlusQuadraticBackgroundRemoved) {
  // An offset of up to ~10 % of venc per component, linear plus quadratic in position, on a
  // noisy (SNR 20) oblique scan. After the correction the offset left on static tissue (the
  // corrected data less the same scan without offset) must be below 1 % of venc (issue 9).
  // Static tissue fills a 60 mm field of view around the pipe, as around the aorta.
  mri::PipeScan scan = test_pipe_scan(20.0, 20.0);
  scan.tissue_radius = 30e-3;
  scan.grid = mri::centred_grid(scan.axis_point, mri::rotation({1, 1, 0}, 20.0), {44, 44, 12},
                                {1.5e-3, 1.5e-3, 1.5e-3});
  mri::Flow4D data = mri::synthesize_pipe(scan);
  const mri::Flow4D clean = data;
  const std::array<std::vector<double>, 3> injected{
      std::vector<double>{0.02, 0.03, -0.02, 0.01, 0.02, 0.0, -0.01, 0.01, 0.0, 0.0},
      std::vector<double>{-0.03, 0.0, 0.02, 0.0, 0.0, 0.015, 0.0, 0.0, -0.01, 0.005},
      std::vector<double>{0.01, -0.01, 0.0, 0.03, 0.0, 0.0, 0.02, 0.0, 0.01, 0.0}};
  mri::add_background(data, injected);
  const mri::BackgroundReport report = mri::correct_background(data);
  // Residual against the clean data on tissue voxels (signal, outside the lumen).
  const std::vector<char> with_signal = mri::signal_mask(clean);
  double worst = 0.0;
  std::size_t tissue = 0;
  for (std::size_t v = 0; v < clean.grid.count(); ++v) {
    if (!with_signal[v] ||
        clean.frames[0].magnitude[v] > 0.5 * scan.tissue_signal + 0.5 * scan.lumen_signal)
      continue;
    ++tissue;
    for (int c = 0; c < 3; ++c)
      worst = std::max(
          worst, double(std::abs(data.frames[5].velocity[c][v] - clean.frames[5].velocity[c][v])));
  }
  std::printf("background: %zu static voxels fitted, worst residual on %zu tissue voxels "
              "%.4f m/s (venc %.1f m/s)\n",
              report.static_voxels, tissue, worst, scan.venc);
  EXPECT_GT(tissue, 1000u);
  EXPECT_LT(worst, 0.01 * scan.venc);
}

TEST(MriCorrections, BackgroundCorrectionDoesNotBiasNoisyFlow) {
  // No offset at all, SNR 20, an oblique grid with static tissue around the pipe (as the
  // offset test): the correction must leave the cycle-mean flow alone, to within what the
  // noise itself moves it by. Five seeds; the noise's spread is the SD over seeds of the
  // uncorrected cycle-mean flow's error (0.27 %). The fit has noise of its own: ~7900 tissue
  // voxels at a fifth of blood's signal, time-mean noise ~0.025 m/s each, ten quadratic terms:
  // ~0.001 m/s at the pipe, 0.25 % of its mean velocity, random in sign. So the correction's
  // RMS change over the seeds must stay below the noise's spread, and its mean (a bias) below a
  // third of it. Before the flow region was excluded: mean -0.20 %, RMS 0.30 % (failing both);
  // now +0.03 %, 0.25 %.
  std::vector<double> raw_error, change;
  for (std::uint64_t seed : {1, 2, 3, 4, 5}) {
    mri::PipeScan scan = test_pipe_scan(25.0, 20.0);
    scan.tissue_radius = 30e-3;
    scan.grid = mri::centred_grid(scan.axis_point, mri::rotation({1, 1, 0}, 25.0), {44, 44, 12},
                                  {1.5e-3, 1.5e-3, 1.5e-3});
    scan.seed = seed;
    const mri::Flow4D raw = mri::synthesize_pipe(scan);
    mri::Flow4D corrected = raw;
    const mri::BackgroundReport report = mri::correct_background(corrected);
    auto cycle_mean = [&](const mri::Flow4D& d) {
      const auto planes = mri::measure_planes(d, test_pipe_landmarks(scan));
      double q = 0.0;
      for (double f : planes[0].flow)
        q += f / scan.frames;
      return q;
    };
    double exact = 0.0;
    for (int k = 0; k < scan.frames; ++k)
      exact += mri::exact_frame_flow(scan, k) / scan.frames;
    const double q_raw = cycle_mean(raw), q_corrected = cycle_mean(corrected);
    raw_error.push_back((q_raw - exact) / exact);
    change.push_back((q_corrected - q_raw) / exact);
    std::printf("seed %d: %zu static voxels; uncorrected %+.3f %%, correction %+.3f %%\n",
                int(seed), report.static_voxels, 100 * raw_error.back(), 100 * change.back());
  }
  double mean = 0.0, bias = 0.0, rms = 0.0;
  for (std::size_t s = 0; s < raw_error.size(); ++s) {
    mean += raw_error[s] / raw_error.size(), bias += change[s] / change.size();
    rms += change[s] * change[s] / change.size();
  }
  rms = std::sqrt(rms);
  double var = 0.0;
  for (double e : raw_error)
    var += (e - mean) * (e - mean) / (raw_error.size() - 1);
  const double spread = std::sqrt(var);
  std::printf("noise spread %.3f %%; correction's change: mean %+.3f %%, RMS %.3f %%\n",
              100 * spread, 100 * bias, 100 * rms);
  EXPECT_LT(rms, spread);
  EXPECT_LT(std::abs(bias), spread / 3.0);
}

TEST(MriCorrections, UnwrappingLeavesUnaliasedNoisyDataAlone) {
  // SNR 20, air around the tissue (random phase there), nothing beyond venc: no value may
  // move; air must stay out of the voxels with signal.
  mri::PipeScan scan = test_pipe_scan(0.0, 20.0);
  scan.tissue_radius = 9e-3;
  mri::Flow4D data = mri::synthesize_pipe(scan);
  const mri::UnwrapReport report = mri::unwrap_temporal(data);
  EXPECT_EQ(report.values_unwrapped, 0u);
}

TEST(MriCorrections, AliasingToTwiceVencUnwrapped) {
  // A more pulsatile flow (0.4 to 1.7 Q0) imaged with venc 0.5 m/s: frame 0 (end diastole)
  // is free of aliasing, the systolic frames alias up to ~1.9 venc. Temporal unwrapping
  // must restore the flows to the unaliased 2 %.
  mri::PipeScan scan = test_pipe_scan();
  scan.flow = test_pipe_flow(6e-3, 0.6);
  scan.venc = 0.5;
  mri::Flow4D data = mri::synthesize_pipe(scan);
  float peak = 0;
  for (const auto& f : mri::synthesize_pipe([&] {
                         auto s = scan;
                         s.wrap = false;
                         return s;
                       }())
                           .frames)
    for (float v : f.velocity[2])
      peak = std::max(peak, v);
  std::printf("peak velocity %.3f m/s = %.2f venc\n", peak, peak / scan.venc);
  ASSERT_GT(peak, 1.5 * scan.venc);
  ASSERT_LT(peak, 2.0 * scan.venc);
  EXPECT_GT(worst_flow_error(scan, data), 0.2); // aliased: far off
  const mri::UnwrapReport report = mri::unwrap_temporal(data);
  EXPECT_GT(report.voxels, 0u);
  EXPECT_LT(worst_flow_error(scan, data), 0.02);
}

TEST(MriCorrections, AliasingUnwrappedInNoisyData) {
  // The same aliasing (peak ~1.9 venc) at SNR 20 in the aorta-sized pipe: unwrapped, the
  // flows must meet the 5 % that issue 9 sets for SNR 20.
  mri::PipeScan scan = test_pipe_scan(0.0, 20.0, 9e-3);
  scan.flow = test_pipe_flow(9e-3, 0.6);
  scan.venc = 0.55;
  mri::Flow4D data = mri::synthesize_pipe(scan);
  EXPECT_GT(worst_flow_error(scan, data), 0.2);
  mri::unwrap_temporal(data);
  const double worst = worst_flow_error(scan, data);
  std::printf("SNR 20, aliased and unwrapped: worst frame flow error %.3f %%\n", 100 * worst);
  EXPECT_LT(worst, 0.05);
}

TEST(MriPlanes, LumenPointOutsideTheImageIsAnError) {
  const mri::PipeScan scan = test_pipe_scan();
  auto landmarks = test_pipe_landmarks(scan);
  landmarks.planes[0].point = scan.axis_point + Vec3{0.2, 0, 0};
  landmarks.planes[0].name = "TL3";
  try {
    mri::measure_planes(mri::synthesize_pipe(scan), landmarks);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("TL3"), std::string::npos) << e.what();
  }
}

TEST(MriPlanes, NotANumberInALumenIsRefusedNamingLandmarkAndFrame) {
  // Issue 28: a NaN in a NIfTI velocity volume gave that frame's flow as 0, without a word.
  // One voxel next to the lumen point, in one velocity component of frame 3, then in the
  // magnitude of frame 5 (a hole in the lumen mask): each names the landmark and frame.
  const mri::PipeScan scan = test_pipe_scan();
  const auto landmarks = test_pipe_landmarks(scan);
  const auto error = [&](int frame, int component) {
    mri::Flow4D data = mri::synthesize_pipe(scan);
    const Vec3 ijk = data.grid.index(scan.axis_point);
    const std::size_t voxel = data.grid.linear(static_cast<int>(std::lround(ijk[0])) + 1,
                                               static_cast<int>(std::lround(ijk[1])),
                                               static_cast<int>(std::lround(ijk[2])));
    mri::Frame& f = data.frames[static_cast<std::size_t>(frame)];
    (component < 0 ? f.magnitude : f.velocity[static_cast<std::size_t>(component)])[voxel] =
        std::nanf("");
    try {
      mri::measure_planes(data, landmarks);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string velocity = error(3, 2), magnitude = error(5, -1);
  EXPECT_NE(velocity.find("landmark 'AAo', frame 3"), std::string::npos) << velocity;
  // Issue 62: the component too (a scan made in memory has no file to name).
  EXPECT_NE(velocity.find("not numbers (NaN or infinite), from vz;"), std::string::npos)
      << velocity;
  EXPECT_NE(magnitude.find("landmark 'AAo', frame 5"), std::string::npos) << magnitude;
  EXPECT_NE(magnitude.find("from magnitude;"), std::string::npos) << magnitude;
}

TEST(MriAlignment, LandmarksMovedByTheFittedTransformMeasureTheSameFlows) {
  // The model's frame differs from the scanner's by a rotation of 40 degrees and a shift.
  // Four noisy-free paired points give the transform (Kabsch), exact to rounding; the model's
  // landmarks moved by it must measure the flows of the scanner-frame landmarks.
  const mri::PipeScan scan = test_pipe_scan(15.0);
  const mri::Flow4D data = mri::synthesize_pipe(scan);
  const geometry::Landmarks truth = test_pipe_landmarks(scan);
  mri::RigidTransform to_model;
  to_model.rotation = mri::rotation({0.3, -1, 0.5}, 40.0);
  to_model.translation = {0.02, -0.05, 0.11};
  const std::vector<Vec3> mri_points{{0, 0, 0}, {0.1, 0, 0}, {0, 0.05, 0.02}, {0.03, 0.01, 0.2}};
  std::vector<Vec3> model_points;
  for (const Vec3& p : mri_points)
    model_points.push_back(to_model.apply(p));
  const mri::RigidTransform fit = mri::fit_rigid(model_points, mri_points);
  EXPECT_LT(fit.rms, 1e-12);
  const geometry::Landmarks model_landmarks = mri::transformed(truth, to_model);
  const auto a = mri::measure_planes(data, truth);
  const auto b = mri::measure_planes(data, mri::transformed(model_landmarks, fit));
  for (int k = 0; k < scan.frames; ++k) // same planes to rounding: the same pixels
    EXPECT_NEAR(b[0].flow[k], a[0].flow[k], 1e-9 * a[0].flow[k]) << "frame " << k;
  // Without the alignment the model's landmarks miss the pipe.
  EXPECT_THROW(mri::measure_planes(data, model_landmarks), InputError);
  EXPECT_THROW(mri::fit_rigid({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}),
               InputError);
}
