// The landmark analysis on synthetic runs with known answers (tests/analysis_support.hpp):
// a rigid pipe with a Poiseuille velocity of time-varying amplitude and a linear pressure,
// and a two-lumen channel (two pipes side by side) with different flows and pressures.
//
// Tolerances. The analysis integrates the P1 fields exactly over the polygonal section of the
// P1 mesh; what differs from the smooth answer is
//   - area: the section's boundary points lie on chords of the circle (the surface
//     triangles); a chord of length c loses a segment of c^3 / (12 r), N = 2 pi r / c chords
//     lose |dA| / A = c^2 / (6 r^2). With c the mesh's RMS edge l, and a factor 1.5 for the
//     spread of the chords (the loss goes as c^3): |dA| / A <= l^2 / (4 r^2);
//   - flow: on a section triangle with edges l_i the P1 interpolant of u = U (1 - rho^2/r^2)
//     misses its mean by U sum l_i^2 / (12 r^2) (the vertex mean of |x|^2 exceeds its area
//     mean by sum l_i^2 / 12), so |dQ| / Q = <l^2> / (2 r^2) (Q = A U / 2), <l^2> the mean
//     square edge of the section's triangles, bounded by that of the tetrahedra (a cut
//     polygon lies inside its tetrahedron), the wall strip lost to the chords carrying almost
//     no flow;
//   - pressure: p is linear, so P1 carries it exactly and its area mean is its value at the
//     section's centroid: exact on planes normal to the axis (rounding only), and within
//     |grad p| l_max on an oblique plane (the polygon's centroid moves by less than an edge).
// The meshes are sized (h = r / 10) so that these estimates stay below the 1 % of issue 7;
// the tests check both.
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"

namespace tearflow {
namespace {

using testing::read_json;

using testing::SyntheticLumen;
using testing::SyntheticRun;

double relative(double value, double exact) {
  return std::abs(value - exact) / std::abs(exact);
}

TEST(Analysis, RigidPipeRecoversFlowAreaAndPressure) {
  SyntheticRun run;
  run.lumina = {SyntheticLumen{}};
  run.length = 0.006;
  const double r = run.lumina[0].radius;
  const std::filesystem::path dir = testing::fresh_dir("analysis-pipe");
  const testing::EdgeLengths edges = testing::write_synthetic_run(run, dir);
  const double l = edges.rms;
  const double area_tol = l * l / (4 * r * r), flow_tol = l * l / (2 * r * r);
  std::printf("edges: RMS %.3f mm, longest %.3f mm: area tolerance %.3f %%, flow %.3f %%\n",
              l * 1e3, edges.longest * 1e3, 100 * area_tol, 100 * flow_tol);
  ASSERT_LE(flow_tol, 0.01) << "mesh too coarse for the 1 % acceptance";

  // Normal planes, and one tilted by 30 degrees about y: an ellipse of area pi r^2 / cos 30,
  // the same flow, the pressure of its centre.
  const double tilt = M_PI / 6;
  geometry::Landmarks landmarks;
  landmarks.planes = {testing::plane_at(run, "inlet", 0.001),
                      {"AAo", {0.0, 0.0, 0.003}, {std::sin(tilt), 0.0, std::cos(tilt)}},
                      testing::plane_at(run, "outlet", 0.005)};
  geometry::write_landmarks(landmarks, dir / "landmarks.json");

  analysis::AnalyzeOptions options;
  options.run_dir = dir;
  options.landmarks = dir / "landmarks.json";
  const analysis::Analysis a = analysis::analyze_run(options);
  ASSERT_EQ(a.time.size(), static_cast<std::size_t>(run.frames));
  const double area[] = {M_PI * r * r, M_PI * r * r / std::cos(tilt), M_PI * r * r};
  const double height[] = {0.001, 0.003, 0.005};
  double worst_q = 0, worst_a = 0, worst_p = 0;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t i = 0; i < a.time.size(); ++i) {
      const analysis::SectionValues& v = a.series[k].samples[i];
      const double t = a.time[i];
      worst_q = std::max(worst_q, relative(v.flow, run.flow(0, t)));
      worst_a = std::max(worst_a, relative(v.area, area[k]));
      const double p = run.pressure(0, height[k], t);
      const double p_tol = k == 1 ? run.gradient * edges.longest / p : 1e-9; // see the header
      EXPECT_LE(relative(v.pressure, p), p_tol) << a.series[k].landmark.name << " t = " << t;
      worst_p = std::max(worst_p, relative(v.pressure, p));
      // The centreline carries U a(t) (through the tilted plane u.n = U a(t) cos 30); the P1
      // section reaches it within the interpolation error of the quadratic near the axis,
      // U l_max^2 / r^2.
      const double u_c = run.lumina[0].u_peak * run.amplitude(t) * (k == 1 ? std::cos(tilt) : 1);
      EXPECT_NEAR(v.max_velocity, u_c, u_c * edges.longest * edges.longest / (r * r))
          << a.series[k].landmark.name;
    }
  std::printf("worst relative errors: flow %.4f %%, area %.4f %%, pressure %.2e\n", 100 * worst_q,
              100 * worst_a, worst_p);
  EXPECT_LE(worst_q, flow_tol);
  EXPECT_LE(worst_a, area_tol);
  // a(t) = 1 + sin(2 pi t / T) / 2 peaks at t = T / 4, a saved frame.
  EXPECT_DOUBLE_EQ(a.time[a.peak_systole], run.period / 4);

  // Through the program: metrics.json and the CSV per landmark.
  const testing::Result result = testing::run_tearflow(
      fmt::format("analyze {} --landmarks {} -q", dir.string(), (dir / "landmarks.json").string()));
  ASSERT_EQ(result.code, 0) << result.output;
  const nlohmann::json m = read_json(dir / "analysis" / "metrics.json");
  EXPECT_EQ(m["frames"], "cycle 1");
  // A rigid wall: the same section at every frame, no dilation.
  EXPECT_NEAR(m["AAo_min_to_max_dilation_percent"].get<double>(), 0.0, 1e-9);
  // The volume is the trapezoidal rule over the frames; on the exact flows it gives:
  double volume = 0;
  for (int i = 1; i < run.frames; ++i)
    volume += 0.5 * (run.time(i) - run.time(i - 1)) *
              (run.flow(0, run.time(i)) + run.flow(0, run.time(i - 1)));
  for (const char* name : {"inlet", "AAo", "outlet"}) {
    const nlohmann::json& j = m["landmarks"][name];
    EXPECT_LE(relative(j["net_flow_volume_m3"].get<double>(), volume), flow_tol) << name;
    EXPECT_LE(relative(j["net_flow_volume_mL"].get<double>(), volume / 1e-6), flow_tol) << name;
  }
  EXPECT_LE(relative(m["landmarks"]["inlet"]["A_0_mm2"].get<double>(), M_PI * 25.0), area_tol);
  EXPECT_LE(relative(m["landmarks"]["inlet"]["peak_systolic_pressure_Pa"].get<double>(),
                     run.pressure(0, 0.001, run.period / 4)),
            1e-9);
  EXPECT_LE(relative(m["pressure_drops"]["inlet_to_outlet"]["peak_systole_Pa"].get<double>(),
                     run.gradient * 0.004),
            1e-6);
  std::ifstream csv(dir / "analysis" / "inlet.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "time_s,flow_m3_per_s,flow_mL_per_s,area_m2,area_mm2,area_over_A_0,"
            "mean_pressure_Pa,mean_pressure_mmHg,max_through_plane_velocity_m_per_s,"
            "wall_displacement_mm,flow_interpolated_m3_per_s,flap_displacement_toward_FL_mm");
  int rows = 0;
  for (std::string line; std::getline(csv, line);)
    ++rows;
  EXPECT_EQ(rows, run.frames);
}

TEST(Analysis, TwoLumenChannelRecoversFlowRatioAndPressureDifference) {
  SyntheticRun run;
  // The true lumen and, 3 mm beside it, a narrower false lumen with less flow and a lower
  // pressure: one mesh of two disjoint pieces, as a plane through the flap cuts two.
  run.lumina = {SyntheticLumen{0.0, 0.005, 0.6, 1.2e4}, SyntheticLumen{0.012, 0.004, 0.3, 1.1e4}};
  run.length = 0.003;
  const std::filesystem::path dir = testing::fresh_dir("analysis-two-lumen");
  const double l = testing::write_synthetic_run(run, dir).rms;
  const double r_min = 0.004;
  const double flow_tol = l * l / (2 * r_min * r_min);
  ASSERT_LE(flow_tol, 0.01) << "mesh too coarse for the 1 % acceptance";

  geometry::Landmarks landmarks;
  landmarks.planes = {
      testing::plane_at(run, "TL1", 0.001, 0, "TL"), testing::plane_at(run, "FL1", 0.001, 1, "FL"),
      testing::plane_at(run, "FL2", 0.002, 1, "FL"), testing::plane_at(run, "TL2", 0.002, 0, "TL")};
  geometry::write_landmarks(landmarks, dir / "landmarks.json");
  const testing::Result result = testing::run_tearflow(
      fmt::format("analyze {} --landmarks {} -q", dir.string(), (dir / "landmarks.json").string()));
  ASSERT_EQ(result.code, 0) << result.output;
  const nlohmann::json m = read_json(dir / "analysis" / "metrics.json");

  // Both lumina follow a(t), so the ratio of the cycle means is that of the amplitudes.
  const double q_tl = run.flow(0, 0), q_fl = run.flow(1, 0);
  const double fr = 100 * q_fl / (q_fl + q_tl);
  const double t_peak = run.period / 4;
  for (const char* k : {"1", "2"}) {
    const nlohmann::json& s = m["stations"][k];
    const double z = k[0] == '1' ? 0.001 : 0.002;
    // FR_FL = q_fl / (q_fl + q_tl): its relative error is at most that of the flows.
    EXPECT_LE(relative(s["FR_FL_percent"].get<double>(), fr), flow_tol) << k;
    // Cycle-mean flows: trapezoidal mean of a(t) over the frames (exact for this sine).
    EXPECT_LE(relative(s["mean_flow_TL_m3_per_s"].get<double>(), q_tl), flow_tol) << k;
    EXPECT_LE(relative(s["mean_flow_FL_m3_per_s"].get<double>(), q_fl), flow_tol) << k;
    // dP = P_TL - P_FL: linear pressures, exact in P1 (rounding only).
    const double dp_ps = run.pressure(0, z, t_peak) - run.pressure(1, z, t_peak);
    const double dp_ed = run.pressure(0, z, 0) - run.pressure(1, z, 0);
    EXPECT_LE(relative(s["dP_TL_minus_FL_peak_systole_Pa"].get<double>(), dp_ps), 1e-6) << k;
    EXPECT_LE(relative(s["dP_TL_minus_FL_end_diastole_Pa"].get<double>(), dp_ed), 1e-6) << k;
    std::printf("station %s: FR_FL %.4f %% (exact %.4f %%), dP peak %.4f Pa (exact %.4f Pa)\n", k,
                s["FR_FL_percent"].get<double>(), fr,
                s["dP_TL_minus_FL_peak_systole_Pa"].get<double>(), dp_ps);
  }
  std::ifstream csv(dir / "analysis" / "pressure_difference.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "time_s,dP1_TL_minus_FL_Pa,dP2_TL_minus_FL_Pa");
}

} // namespace
} // namespace tearflow
