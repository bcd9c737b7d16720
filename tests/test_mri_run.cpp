// Synthetic 4D-flow MRI of a simulation's VTU series: a two-lumen channel (true and false
// lumen side by side, Poiseuille flow pulsing in time; tests/analysis_support.hpp) imaged
// with voxels of 1.2 mm (8 across each lumen), then measured at its TL / FL planes: the MRI
// flows must reproduce the run's own (its landmark analysis) at every frame.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "mri/image_io.hpp"
#include "mri/plane_flow.hpp"
#include "mri/surface_alignment.hpp"
#include "mri/synthetic_run.hpp"
#include "mri_support.hpp"

using namespace tearflow;
using namespace tearflow::testing;

TEST(MriRunScan, TrueAndFalseLumenFlowsOfARun) {
  SyntheticRun run;
  run.lumina = {{-8e-3, 5e-3, 0.5, 1e4}, {8e-3, 5e-3, 0.3, 1e4}};
  run.length = 12e-3;
  run.element_size = 1e-3;
  run.frames = 9;
  const auto dir = fresh_dir("mri-run");
  write_synthetic_run(run, dir);
  geometry::Landmarks landmarks;
  landmarks.planes = {plane_at(run, "TL1", 6e-3, 0, "TL"), plane_at(run, "FL1", 6e-3, 1, "FL")};

  mri::RunScan scan;
  scan.run_dir = dir;
  scan.voxel = 1.2e-3;
  scan.frames = 16;
  scan.effects.venc = 1.0;
  const mri::Flow4D data = mri::synthesize_run(scan);
  ASSERT_EQ(data.frames.size(), 16u);
  const auto planes = mri::measure_planes(data, landmarks);

  // The run's own flows at the same planes (VTK sections of the P1 field), linear in time
  // between its 9 saved frames as the scan reads them, averaged over each MRI frame's window
  // (T / 16; 400-point midpoint rule): what an ideal scanner of this run would measure.
  analysis::AnalyzeOptions o;
  o.run_dir = dir;
  std::filesystem::create_directories(dir / "geometry");
  geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");
  const analysis::Analysis sim = analysis::analyze_run(o);
  const double period = sim.time.back() - sim.time.front(), dt = period / scan.frames;
  auto sim_flow = [&](std::size_t l, double t) {
    t -= period * std::floor(t / period);
    std::size_t i = 1;
    while (i + 1 < sim.time.size() && sim.time[i] < t)
      ++i;
    const double w = (t - sim.time[i - 1]) / (sim.time[i] - sim.time[i - 1]);
    return (1 - w) * sim.series[l].samples[i - 1].flow + w * sim.series[l].samples[i].flow;
  };
  std::array<double, 2> mean_mri{};
  for (std::size_t l = 0; l < 2; ++l) {
    double worst = 0.0;
    for (int k = 0; k < scan.frames; ++k) {
      double expected = 0.0;
      for (int q = 0; q < 400; ++q)
        expected += sim_flow(l, k * dt + ((q + 0.5) / 400 - 0.5) * dt) / 400;
      worst = std::max(worst, std::abs(planes[l].flow[k] - expected) / expected);
      mean_mri[l] += planes[l].flow[k] / scan.frames;
    }
    // 2 %, as for the analytic pipe (there ~0.3 % from partial volume and the flow margin);
    // here the profile is parabolic, with a steeper wall gradient: measured 0.57 %.
    std::printf("%s: worst frame difference %.3f %%\n", planes[l].name.c_str(), 100 * worst);
    EXPECT_LT(worst, 0.02) << planes[l].name;
  }
  // TL and FL told apart: their flows differ as the lumina's velocities (0.5 vs 0.3 m/s).
  EXPECT_NEAR(mean_mri[1] / mean_mri[0], 0.6, 0.02);
  // Both points in one lumen (the FL point moved into the TL): an unresolved flap, an error.
  geometry::Landmarks wrong = landmarks;
  wrong.planes[1].point = Vec3{run.lumina[0].x + 2e-3, 0.0, 6e-3};
  try {
    mri::measure_planes(data, wrong);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("one connected lumen region"), std::string::npos)
        << e.what();
  }
}

TEST(MriRunScan, CommandLineFromRunToComparison) {
  // `mri synthesize RUN_DIR` -> `mri flow` -> `mri compare RUN_DIR`: SNR 20, background.
  SyntheticRun run;
  run.lumina = {{-8e-3, 5e-3, 0.5, 1e4}, {8e-3, 5e-3, 0.3, 1e4}};
  run.length = 12e-3;
  run.element_size = 1.25e-3;
  run.frames = 9;
  const auto dir = fresh_dir("mri-run-cli");
  write_synthetic_run(run, dir / "run");
  geometry::Landmarks landmarks;
  landmarks.planes = {plane_at(run, "TL1", 6e-3, 0, "TL"), plane_at(run, "FL1", 6e-3, 1, "FL")};
  std::filesystem::create_directories(dir / "run" / "geometry");
  geometry::write_landmarks(landmarks, dir / "run" / "geometry" / "landmarks.json");
  const std::string r = (dir / "run").string(), scan = (dir / "scan").string(),
                    flow = (dir / "flow").string();
  auto out = run_tearflow("mri synthesize " + r + " -o " + scan +
                          " --voxel 1.2mm --frames 8 --snr 20 --background 0.03m/s");
  ASSERT_EQ(out.code, 0) << out.output;
  out = run_tearflow("mri flow " + scan + "/images --landmarks " + scan + "/landmarks.json -o " +
                     flow);
  ASSERT_EQ(out.code, 0) << out.output;
  out = run_tearflow("mri compare " + r + " " + flow + " -o " + (dir / "cmp").string() +
                     " --scan " + scan + "/images");
  ASSERT_EQ(out.code, 0) << out.output;
  const auto c = read_json(dir / "cmp" / "compare.json");
  for (const char* name : {"TL1", "FL1"}) {
    const auto& l = c["landmarks"][name];
    // The 5 % of issue 9 at SNR 20 bounds the mean difference too.
    EXPECT_LT(std::abs(l["difference_mean_mL_per_s"].get<double>()),
              0.05 * l["mean_flow_simulation_mL_per_s"].get<double>())
        << c.dump(2);
  }
  EXPECT_TRUE(c.contains("fl_flow_ratio_percent")) << c.dump(2);
  // Voxel-wise: the scan differs from the noise-free one of the same run by its noise,
  // sigma_v = sqrt(2)/pi venc / SNR = 0.0225 m/s per component where the magnitude is
  // blood's, up to 1.7x that in the lumen's partial-volume voxels (magnitude >= 0.6): the
  // speed differences' SD must lie in [sigma_v, 2 sigma_v], their mean (bias) below
  // sigma_v / 2. Angles: at the typical 0.2 m/s, noise across the flow tilts v by
  // ~ atan(0.0225 sqrt(2) / 0.2) = 9 degrees.
  const auto& v = c["voxels"];
  std::printf("voxels: %s\n", v.dump().c_str());
  EXPECT_GT(v["speed_difference_sd_m_per_s"].get<double>(), 0.0225);
  EXPECT_LT(v["speed_difference_sd_m_per_s"].get<double>(), 0.045);
  EXPECT_LT(std::abs(v["speed_difference_mean_m_per_s"].get<double>()), 0.0113);
  EXPECT_LT(v["angle_median_deg"].get<double>(), 15.0);
}

TEST(MriRunScan, SurfaceAlignmentRecoversARotatedShiftedScan) {
  // Two lumina of different radii side by side, closed at both ends inside the field of
  // view, so that the surface fixes all six rigid degrees of freedom (up to the channel's
  // 180-degree symmetry, which the fit's smallest-rotation rule resolves).
  SyntheticRun run;
  run.lumina = {{-7e-3, 5e-3, 0.5, 1e4}, {6e-3, 3.5e-3, 0.3, 1e4}};
  run.length = 16e-3;
  run.element_size = 1e-3;
  run.frames = 3;
  const auto dir = fresh_dir("mri-run-align");
  write_synthetic_run(run, dir);
  mri::RunScan scan;
  scan.run_dir = dir;
  scan.voxel = 1.2e-3;
  scan.frames = 2;
  scan.effects.venc = 1.0;
  const mri::Flow4D model_frame = mri::synthesize_run(scan);
  // The same scan placed in a patient frame rotated by 4 degrees and shifted by
  // (3, -2, 4) mm from the model's: x_mri = R x_model + t, its grid's origin and axes moved.
  const Mat3 r =
      mri::rotation({1.0 / std::sqrt(14.0), 2.0 / std::sqrt(14.0), 3.0 / std::sqrt(14.0)}, 4.0);
  mri::RigidTransform truth;
  truth.rotation = r;
  truth.translation = {3e-3, -2e-3, 4e-3};
  // (its velocities rotated too: the fit below reads the magnitude only)
  const mri::Flow4D moved = moved_scan(model_frame, truth);

  // The fit sees the scan with SNR 20 noise (in the magnitude too: the iso-surface must cope
  // with it); the flows below are compared noise-free.
  mri::Flow4D noisy = moved;
  mri::ScannerEffects effects;
  effects.venc = 1.0;
  effects.snr = 20.0;
  mri::add_scanner_effects(noisy, effects);
  const std::vector<Vec3> boundary = mri::lumen_boundary_points(noisy);
  const mri::SurfaceFit fit = mri::fit_surface(mri::read_model_surface(dir), boundary, scan.voxel);
  // The rotation error: the angle of R_fit R^T; the position error: the largest distance
  // between truth and fit over the channel's bounding box corners.
  double trace = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      trace += fit.transform.rotation[a][b] * r[a][b];
  const double angle = std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
  double worst = 0;
  for (double x : {-12e-3, 10e-3})
    for (double y : {-5e-3, 5e-3})
      for (double z : {0.0, run.length}) {
        const Vec3 e = fit.transform.apply({x, y, z}) - truth.apply({x, y, z});
        worst = std::max(worst, std::sqrt(dot(e, e)));
      }
  std::printf("surface fit: start %s, %d iterations, %zu of %zu points, RMS %.3f mm; rotation "
              "error %.3f deg, worst corner %.3f mm\n",
              fit.start.c_str(), fit.iterations, fit.kept, fit.points, fit.transform.rms * 1e3,
              angle, worst * 1e3);
  // Issue 9's acceptance: within a voxel and a degree. The iso-surface of the partial-volume
  // magnitude places each boundary point within a fraction of a voxel of the wall, and the
  // fit averages thousands of them, so one voxel over the whole channel and one degree hold
  // with room (the measured errors are printed above).
  EXPECT_LT(angle, 1.0);
  EXPECT_LT(worst, scan.voxel);
  // The fit's residual is sub-voxel: the iso-surface and the mesh surface coincide.
  EXPECT_LT(fit.transform.rms, 0.5 * scan.voxel);

  // Through the command: the moved scan (its velocity rotated into the patient frame too)
  // measured at the model's landmarks moved by the surface fit gives the flows of the scan
  // in the model's frame at the landmarks themselves.
  mri::write_volumes(model_frame, dir / "scan-model", ".mha");
  mri::write_volumes(moved, dir / "scan-moved", ".mha");
  geometry::Landmarks landmarks;
  landmarks.planes = {plane_at(run, "TL1", 8e-3, 0, "TL"), plane_at(run, "FL1", 8e-3, 1, "FL")};
  geometry::write_landmarks(landmarks, dir / "landmarks.json");
  const std::string common =
      " --landmarks " + (dir / "landmarks.json").string() + " --no-background --no-unwrap -q -o ";
  auto out = run_tearflow("mri flow " + (dir / "scan-model").string() + common +
                          (dir / "flow-model").string());
  ASSERT_EQ(out.code, 0) << out.output;
  out = run_tearflow("mri flow " + (dir / "scan-moved").string() + common +
                     (dir / "flow-moved").string() + " --align-surface " + dir.string());
  ASSERT_EQ(out.code, 0) << out.output;
  const auto report = read_json(dir / "flow-moved" / "mri.json");
  EXPECT_EQ(report["alignment"]["method"], "surface ICP") << report.dump(2);
  analysis::AnalyzeOptions o0, o1;
  o0.run_dir = dir / "flow-model";
  o1.run_dir = dir / "flow-moved";
  const analysis::Analysis a0 = analysis::analyze_run(o0), a1 = analysis::analyze_run(o1);
  double worst_flow = 0;
  for (std::size_t l = 0; l < 2; ++l)
    for (std::size_t k = 0; k < a0.time.size(); ++k) {
      const double q0 = a0.series[l].samples[k].flow, q1 = a1.series[l].samples[k].flow;
      worst_flow = std::max(worst_flow, std::abs(q1 - q0) / std::abs(q0));
      // The same voxels sampled on a plane placed within 0.03 mm / 0.05 deg of the same
      // place: the 2 % of issue 9's noise-free round trip bounds the interpolation's change.
      EXPECT_NEAR(q1, q0, 0.02 * std::abs(q0)) << a0.series[l].landmark.name << " frame " << k;
    }

  std::printf("flows at the aligned landmarks: worst frame %.3f %% off\n", 100 * worst_flow);

  // A path that is neither a run folder nor a .vtu mesh is named in the error.
  try {
    mri::read_model_surface(dir / "nothing.stl");
    ADD_FAILURE() << "no error for a .stl path";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.stl': expected a run folder (flow.pvd) or a "
                                         ".vtu mesh"),
              std::string::npos)
        << e.what();
  }
}
