// Synthetic 4D-flow MRI of a simulation's VTU series: a two-lumen channel (true and false
// lumen side by side, Poiseuille flow pulsing in time; tests/analysis_support.hpp) imaged
// with voxels of 1.2 mm (8 across each lumen), then measured at its TL / FL planes: the MRI
// flows must reproduce the run's own (its landmark analysis) at every frame.
#include <cmath>

#include <gtest/gtest.h>

#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "mri/plane_flow.hpp"
#include "mri/synthetic_run.hpp"

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
