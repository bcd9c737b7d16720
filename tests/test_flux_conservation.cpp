// Mass balance across landmark planes (analysis/conservative_flux.hpp): a coarse pipe (two
// elements across the radius) run to a steady flow by the solver, analysed at five planes,
// two of them oblique. Between any two planes no fluid leaves, so their flows must agree.
//
// The plane integral of the interpolated P1-P1 (PSPG) velocity does not balance on this mesh
// (int div u between planes is not zero: the planes' flows differ by about 13 %); the
// conservative flux is the solver's own continuity equation tested with a step function, so
// it balances up to the Newton residual (rtol 1e-10): the frames (one per step, each with
// du/dt) give each step's generalized-alpha stage exactly. Measured: 2e-15 of the flow; the
// tolerance, 0.1 % of the flow, is the one a demo frame without its step's start meets
// (the estimate from one frame), against the plane integrals' 12 %.
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "cli_support.hpp"

namespace tearflow {
namespace {

TEST(FluxConservation, ConservativeFlowBalancesWherePlaneIntegralsDoNot) {
  const std::filesystem::path dir = testing::fresh_dir("flux-conservation");
  const std::filesystem::path case_file = testing::test_data / "runs/coarse_pipe_steady.yaml";
  const testing::Result run = testing::run_tearflow(
      fmt::format("run {} -q -o {}", case_file.string(), (dir / "run").string()));
  ASSERT_EQ(run.code, 0) << run.output;

  // Planes off the axis and tilted, so that they cut the tetrahedra anyhow.
  geometry::Landmarks landmarks;
  landmarks.planes = {{"inlet", {3e-4, 2e-4, 1e-3}, {0, 0, 1}},
                      {"AAo", {3e-4, 2e-4, 5.3e-3}, {0, 0, 1}},
                      {"DAo_prox", {3e-4, 2e-4, 9.1e-3}, {0, 0.2, 1}},
                      {"DAo_dist", {3e-4, 2e-4, 13.7e-3}, {0.3, 0, 1}},
                      {"outlet", {3e-4, 2e-4, 22.9e-3}, {0, 0, 1}}};
  geometry::write_landmarks(landmarks, dir / "landmarks.json");
  analysis::AnalyzeOptions o;
  o.run_dir = dir / "run";
  o.landmarks = dir / "landmarks.json";
  o.all_frames = true;
  o.case_file = case_file;
  const analysis::Analysis a = analysis::analyze_run(o);
  ASSERT_EQ(a.flow_method, "conservative");
  ASSERT_GE(a.time.size(), 6u);

  const double q_in = 20e-6; // the inflow, 20 mL/s
  // The last three frames: the flow has settled (r^2 / nu = 0.07 s, t >= 0.2 s).
  const std::size_t first = a.time.size() - 3;
  const double tolerance = 1e-3 * q_in; // see the file comment
  double worst = 0, worst_interpolated = 0;
  for (std::size_t i = first; i < a.time.size(); ++i)
    for (const analysis::LandmarkSeries& s : a.series) {
      const analysis::SectionValues& v = s.samples[i];
      const analysis::SectionValues& ref = a.series[0].samples[i];
      worst = std::max(worst, std::abs(v.flow - ref.flow));
      worst_interpolated =
          std::max(worst_interpolated, std::abs(v.flow_interpolated - ref.flow_interpolated));
      // Every plane carries the inflow: nothing leaves between the inlet face and the outlet.
      EXPECT_NEAR(v.flow, q_in, tolerance) << s.landmark.name;
    }
  std::printf("largest difference between planes: conservative %.3g %%, plane integrals %.3g %% "
              "of the flow (tolerance %.3g %%)\n",
              100 * worst / q_in, 100 * worst_interpolated / q_in, 100 * tolerance / q_in);
  EXPECT_LE(worst, tolerance);
  // What the test guards against: on this mesh the plane integrals do not balance (4.7 % of
  // the flow with the stabilization of navier_stokes_kernel.hpp, 2026-12-07; more before the
  // grad-div scale fell to svSolver's), twenty times the tolerance above.
  EXPECT_GT(worst_interpolated, 0.02 * q_in);

  // Through the program: the method is recorded and the conservation keys are both there.
  const testing::Result analyze = testing::run_tearflow(
      fmt::format("analyze {} --landmarks {} --frames all --case {} -q", o.run_dir.string(),
                  o.landmarks.string(), case_file.string()));
  ASSERT_EQ(analyze.code, 0) << analyze.output;
  const nlohmann::json m = testing::read_json(o.run_dir / "analysis" / "metrics.json");
  EXPECT_EQ(m["flow_method"], "conservative");
}

// The largest |(Q - W) at a plane - (Q - W) at the first plane| over frames [first, end) and
// the largest |Q| and |W difference| seen, for the planes of `a`.
struct Balance {
  double worst = 0, peak = 0, stored = 0;
};
Balance balance(const analysis::Analysis& a, std::size_t first) {
  Balance b;
  for (std::size_t i = first; i < a.time.size(); ++i) {
    const analysis::SectionValues& ref = a.series[0].samples[i];
    for (const analysis::LandmarkSeries& s : a.series) {
      const analysis::SectionValues& v = s.samples[i];
      b.worst =
          std::max(b.worst, std::abs((v.flow - v.wall_outflow) - (ref.flow - ref.wall_outflow)));
      b.peak = std::max(b.peak, std::abs(v.flow));
      b.stored = std::max(b.stored, std::abs(v.wall_outflow - ref.wall_outflow));
    }
  }
  return b;
}

analysis::Analysis analyse_every_frame(const std::filesystem::path& dir,
                                       const std::filesystem::path& case_file,
                                       const geometry::Landmarks& landmarks) {
  std::filesystem::create_directories(dir);
  geometry::write_landmarks(landmarks, dir / "landmarks.json");
  const testing::Result run = testing::run_tearflow(
      fmt::format("run {} -q -o {}", case_file.string(), (dir / "run").string()));
  EXPECT_EQ(run.code, 0) << run.output;
  analysis::AnalyzeOptions o;
  o.run_dir = dir / "run";
  o.landmarks = dir / "landmarks.json";
  o.all_frames = true;
  o.case_file = case_file;
  return analysis::analyze_run(o);
}

// A flow changing by up to 40 % of its peak per step (dt 20 ms): the frames hold du/dt, so
// each step's stage is rebuilt from its two frames and the flux balances to the solver's
// tolerance at every frame, where one frame's estimate (u at t_{n+1}, du/dt by differences)
// is off by O(dt) of the change. The Newton residual (rtol 1e-10, KSP 1e-12) leaves the
// continuity rows at about 1e-10 of the flow; the tolerance, 1e-6 of the peak flow, leaves
// room for rounding in the cut and is a thousand times below the 0.1 % of the steady test.
TEST(FluxConservation, UnsteadyFlowBalancesAtEveryFrame) {
  const std::filesystem::path dir = testing::fresh_dir("flux-conservation-unsteady");
  geometry::Landmarks landmarks;
  landmarks.planes = {{"inlet", {3e-4, 2e-4, 1e-3}, {0, 0, 1}},
                      {"AAo", {3e-4, 2e-4, 5.3e-3}, {0, 0, 1}},
                      {"DAo_prox", {3e-4, 2e-4, 9.1e-3}, {0, 0.2, 1}},
                      {"DAo_dist", {3e-4, 2e-4, 13.7e-3}, {0.3, 0, 1}},
                      {"outlet", {3e-4, 2e-4, 22.9e-3}, {0, 0, 1}}};
  const analysis::Analysis a =
      analyse_every_frame(dir, testing::test_data / "runs/coarse_pipe_pulsatile.yaml", landmarks);
  ASSERT_EQ(a.time.size(), 11u);
  EXPECT_EQ(a.stage_frames, 10u); // every frame but the initial state
  const Balance b = balance(a, 1);
  std::printf("unsteady: largest difference between planes %.3g of the peak flow\n",
              b.worst / b.peak);
  EXPECT_LE(b.worst, 1e-6 * b.peak);
  EXPECT_EQ(b.stored, 0.0); // rigid walls store nothing
  // Extrapolated from the stages to the frames' times, the flow is the inflow through the
  // inlet face at that time (faces.csv, from u_{n+1}). The extrapolation is second order:
  // off by about (1 - af)(2 - af) / 2 dt^2 |Q''| = 0.44 (0.02 s)^2 x 1e4 mL/s^3, 1.8 mL/s or
  // 4 % of the peak where the waveform bends most (measured: at most 1.1 %); the tolerance,
  // 2 % of the peak, fails the stage's own time level, (1 - af) dt |Q'| = 2.7 mL/s (7 %) off.
  std::ifstream faces(dir / "run" / "faces.csv");
  std::string line;
  std::map<int, double> inflow; // step -> flow into the inlet face [m^3/s]
  while (std::getline(faces, line))
    if (line.find(",inlet,") != std::string::npos) {
      std::stringstream fields(line);
      std::string step, time, face, flow;
      std::getline(fields, step, ',');
      std::getline(fields, time, ',');
      std::getline(fields, face, ',');
      std::getline(fields, flow, ',');
      inflow[std::stoi(step)] = -std::stod(flow);
    }
  ASSERT_EQ(inflow.size(), a.time.size());
  for (std::size_t i = 2; i < a.time.size(); ++i) // step 1: no stage before its own
    EXPECT_NEAR(a.series[0].samples[i].flow, inflow[static_cast<int>(i)], 0.02 * 40e-6)
        << "t = " << a.time[i];
}

// A wall that swells under a flow pulse: the planes' flows differ by the rate of the volume
// stored between them, W_A - W_B (analysis/conservative_flux.hpp). With it the balance holds
// to the Newton tolerance (rtol 1e-9); without it the planes differ by the stored rate,
// which the test requires to be large (more than 5 % of the flow) so that it can fail.
TEST(FluxConservation, MovingWallStoresTheDifference) {
  const std::filesystem::path dir = testing::fresh_dir("flux-conservation-fsi");
  geometry::Landmarks landmarks;
  landmarks.planes = {{"inlet", {2e-4, 1e-4, 1.5e-3}, {0, 0, 1}},
                      {"AAo", {2e-4, 1e-4, 4.1e-3}, {0.1, 0, 1}},
                      {"DAo_prox", {2e-4, 1e-4, 7.3e-3}, {0, 0.2, 1}},
                      {"outlet", {2e-4, 1e-4, 10.2e-3}, {0, 0, 1}}};
  const analysis::Analysis a =
      analyse_every_frame(dir, testing::test_data / "fsi/tube_flow.yaml", landmarks);
  ASSERT_EQ(a.time.size(), 6u);
  EXPECT_EQ(a.stage_frames, 5u);
  const Balance b = balance(a, 1);
  std::printf("moving wall: largest difference between planes %.3g of the peak flow, stored "
              "rate up to %.3g of it\n",
              b.worst / b.peak, b.stored / b.peak);
  EXPECT_LE(b.worst, 1e-5 * b.peak);
  EXPECT_GE(b.stored, 0.05 * b.peak);
}

} // namespace
} // namespace tearflow
