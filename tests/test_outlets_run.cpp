// Outlets through the program: RCR and RC restart mid-cycle, Newton iterations under stiff
// Windkessels, backflow with and without stabilization, the cycle summary, the periodicity
// stop; NaN-safe verification metrics.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bc/windkessel.hpp"
#include "cli_support.hpp"
#include "verify/verification.hpp"

namespace fs = std::filesystem;

namespace {

using tearflow::testing::fresh_dir;
using tearflow::testing::Result;
const fs::path data = tearflow::testing::test_data;

Result run(const std::string& args) {
  return tearflow::testing::run_tearflow(args);
}

struct Row {
  double flow, pressure, distal;
};
/// faces.csv as (step, face) -> row.
std::map<std::pair<int, std::string>, Row> read_faces(const fs::path& dir) {
  std::ifstream in(dir / "faces.csv");
  std::string line;
  std::getline(in, line);
  std::map<std::pair<int, std::string>, Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');)
      c.push_back(cell);
    c.resize(8);
    rows[{std::stoi(c[0]), c[2]}] = {std::stod(c[3]), std::stod(c[4]),
                                     c[7].empty() ? 0.0 : std::stod(c[7])};
  }
  return rows;
}

/// Newton iterations of every step, from the progress lines.
std::vector<int> newton_per_step(const std::string& output) {
  std::vector<int> its;
  const std::regex re(R"(Newton (\d+) )");
  for (auto it = std::sregex_iterator(output.begin(), output.end(), re);
       it != std::sregex_iterator(); ++it)
    its.push_back(std::stoi((*it)[1]));
  return its;
}

} // namespace

/// The small pipe closed by an outlet law with a state (GetParam(): rcr or rc).
class OutletRestart : public testing::TestWithParam<std::string> {};

TEST_P(OutletRestart, MidCycleReproducesTheUninterruptedRun) {
  const std::string law = GetParam();
  const fs::path full = fresh_dir(law + "-full"), split = fresh_dir(law + "-split");
  const fs::path whole = data / "runs" / ("small_pipe_" + law + ".yaml"),
                 half = data / "runs" / ("small_pipe_" + law + "_half.yaml");
  const Result a = run("run " + whole.string() + " -q -o " + full.string());
  ASSERT_EQ(a.code, 0) << a.output;
  ASSERT_EQ(run("run " + half.string() + " -q -o " + split.string()).code, 0);
  const Result b = run("run " + whole.string() + " -q --restart -o " + split.string());
  ASSERT_EQ(b.code, 0) << b.output;
  const auto ra = read_faces(full), rb = read_faces(split);
  ASSERT_EQ(ra.size(), 17u * 3u); // steps 0..16 (two cycles of 8), three faces
  ASSERT_EQ(ra.size(), rb.size());
  // Newton and GMRES converge to 1e-10 relative; after the restart the preconditioner is
  // rebuilt at a different iteration than in the uninterrupted run, so the two agree to
  // that solver tolerance, not bit for bit: 1e-8 relative on pressures (~1e3 Pa).
  int distal_rows = 0;
  for (const auto& [key, v] : ra) {
    const Row& w = rb.at(key);
    EXPECT_NEAR(w.pressure, v.pressure, 1e-8 * std::abs(v.pressure) + 1e-8) << key.second;
    EXPECT_NEAR(w.distal, v.distal, 1e-8 * std::abs(v.distal) + 1e-8) << key.second;
    distal_rows += key.second == "outlet" && v.distal > 0.0;
  }
  EXPECT_EQ(distal_rows, 17); // every outlet row carries the capacitor's pressure

  // Both runs summarize the same two cycles.
  const auto cycles = [](const fs::path& d) {
    std::ifstream in(d / "cycles.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json ca = cycles(full), cb = cycles(split);
  ASSERT_EQ(ca["cycles"].size(), 2u);
  ASSERT_EQ(cb["cycles"].size(), 2u);
  const double pa = ca["cycles"][1]["faces"]["outlet"]["mean_pressure_Pa"];
  const double pb = cb["cycles"][1]["faces"]["outlet"]["mean_pressure_Pa"];
  EXPECT_NEAR(pa, pb, 1e-8 * std::abs(pa));
  EXPECT_NEAR(double(ca["cycles"][1]["faces"]["outlet"]["flow_split_percent"]), 100.0, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(OutletRun, OutletRestart, testing::Values("rcr", "rc"));

TEST(OutletRun, NewtonIterationsDoNotGrowWithStiffWindkessels) {
  // The outlet's dP/dQ is in the Newton tangent (as a low-rank term), so R_p and R_d 100
  // times larger change the pressures 100-fold but not the convergence.
  const Result base = run("run " + (data / "runs/small_pipe_rcr.yaml").string() + " -o " +
                          fresh_dir("base").string());
  const Result stiff = run("run " + (data / "runs/small_pipe_rcr_stiff.yaml").string() + " -o " +
                           fresh_dir("stiff").string());
  ASSERT_EQ(base.code, 0) << base.output;
  ASSERT_EQ(stiff.code, 0) << stiff.output;
  const std::vector<int> a = newton_per_step(base.output), b = newton_per_step(stiff.output);
  ASSERT_EQ(a.size(), 16u);
  ASSERT_EQ(b.size(), 16u);
  int sum_a = 0, sum_b = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sum_a += a[i];
    sum_b += b[i];
    EXPECT_LE(b[i], a[i] + 1) << "step " << i + 1; // one more at most, in any step
  }
  EXPECT_LE(sum_b, sum_a) << "total Newton iterations, base " << sum_a << ", stiff " << sum_b;
}

TEST(OutletRun, BackflowWithoutStabilizationIsSaidAndWithItBounded) {
  using testing::HasSubstr;
  // Without the stabilization this case failed Newton at t = 0.8 s under the selfp Schur
  // preconditioner (10 iterations, stalled at 8e-4 of the first residual); under the compact
  // pressure Laplacian (physics/pressure_schur.hpp) it completes with bounded pressures, so the
  // failure was the linear solver's, not a blow-up (2026-12-07). The run says that the
  // outlet's inflow ran without backflow stabilization.
  const Result off =
      run("run " + (data / "runs/backflow_off.yaml").string() + " -o " + fresh_dir("off").string());
  EXPECT_EQ(off.code, 0) << off.output;
  EXPECT_THAT(off.output, HasSubstr("no backflow stabilization"));

  const fs::path dir = fresh_dir("on");
  const Result on = run("run " + (data / "runs/backflow_on.yaml").string() + " -o " + dir.string());
  ASSERT_EQ(on.code, 0) << on.output;
  // The reversal is reported, and the pressures stay bounded: below 10 rho U^2 with the
  // peak mean velocity U = 1.5e-3 m^3/s / (pi 1e-4 m^2) = 4.8 m/s, i.e. 2.4e5 Pa.
  EXPECT_THAT(on.output, HasSubstr("reversed"));
  double worst = 0.0;
  for (const auto& [key, row] : read_faces(dir))
    worst = std::max(worst, std::abs(row.pressure));
  EXPECT_LT(worst, 10.0 * 1060.0 * 4.8 * 4.8);
}

TEST(OutletRun, ExamplePipeRcrRunsOnTheFieldsMesh) {
  // examples/pipe-rcr on the reference mesh (170 k tets), three steps: mass is conserved
  // through the real mesh and the distal pressure follows the trapezoidal update (2) of
  // bc/windkessel.hpp from the recorded outlet fluxes.
  const fs::path dir = fresh_dir("pipe-rcr");
  const Result r =
      run("run " + (fs::path(TEARFLOW_SOURCE_DIR) / "examples/pipe-rcr/case.yaml").string() +
          " --steps 3 -q -o " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = read_faces(dir);
  const tearflow::bc::WindkesselRCR rcr{1.21e7, 1.5e-10, 1.212e8, 0.0};
  for (int step = 1; step <= 3; ++step) {
    const Row& in = rows.at({step, "lumen_inlet"});
    const Row& out = rows.at({step, "lumen_outlet"});
    // The discrete divergence is zero only weakly (PSPG): 1e-6 of the flux.
    EXPECT_NEAR(out.flow, -in.flow, 1e-6 * std::abs(in.flow)) << "step " << step;
    const Row& prev = rows.at({step - 1, "lumen_outlet"});
    const double expected =
        tearflow::bc::distal_update(rcr, prev.distal, prev.flow, 0.005)(out.flow);
    EXPECT_NEAR(out.distal, expected, 1e-9 * std::abs(expected) + 1e-9) << "step " << step;
  }
}

TEST(OutletRun, PeriodicityToleranceStopsTheRunOrRunsToMaxCycles) {
  // time.periodicity: the run stops after the first cycle whose change from the previous one
  // (max over outlets and samples of |difference| / peak, flow and pressure) is below the
  // tolerance, else after max_cycles. Cycle 1 starts with the fluid at rest, so its first
  // outlet flow is 0 where cycle 2 has Q_in(0) = 2 of the peak 8 mL/s: change 0.25. From
  // then the RCR (R_d C = 10 ms, period 80 ms) relaxes by exp(-8) = 3e-4 per cycle; cycle 3
  // measured 1.7e-5. Loose (1e-3, max 5): stops after cycle 3, two before its maximum.
  // Tight (1e-6, 17 times below cycle 3's change; max 3): runs all 3 and says so.
  const auto cycles = [](const fs::path& d) {
    std::ifstream in(d / "cycles.json");
    return nlohmann::json::parse(in);
  };
  const fs::path loose = fresh_dir("periodic-loose"), tight = fresh_dir("periodic-tight");
  const Result a = run("run " + (data / "runs/small_pipe_rcr_periodic_loose.yaml").string() +
                       " -o " + loose.string());
  ASSERT_EQ(a.code, 0) << a.output;
  const nlohmann::json ca = cycles(loose);
  ASSERT_EQ(ca["cycles"].size(), 3u) << a.output;
  EXPECT_TRUE(ca["cycles"][0]["change_from_previous"].is_null()); // nothing to compare with
  EXPECT_GT(double(ca["cycles"][1]["change_from_previous"]), 1e-3);
  EXPECT_LT(double(ca["cycles"][2]["change_from_previous"]), 1e-3);
  EXPECT_EQ(newton_per_step(a.output).size(), 24u); // stopped at step 24 of 40
  EXPECT_THAT(a.output, testing::HasSubstr("(periodic)"));
  EXPECT_THAT(a.output, testing::Not(testing::HasSubstr("not periodic")));

  const Result b = run("run " + (data / "runs/small_pipe_rcr_periodic_tight.yaml").string() +
                       " -o " + tight.string());
  ASSERT_EQ(b.code, 0) << b.output;
  const nlohmann::json cb = cycles(tight);
  ASSERT_EQ(cb["cycles"].size(), 3u) << b.output;
  for (size_t k = 1; k < 3; ++k)
    EXPECT_GT(double(cb["cycles"][k]["change_from_previous"]), 1e-6) << "cycle " << k + 1;
  EXPECT_EQ(newton_per_step(b.output).size(), 24u);
  EXPECT_THAT(b.output, testing::Not(testing::HasSubstr("(periodic)")));
  EXPECT_THAT(b.output,
              testing::HasSubstr("not periodic within 1e-06 after 3 cycle(s) (last change"));
}

TEST(OutletRun, PeriodicityByTheCyclesNumbers) {
  // measure: pressures_and_splits: the change is the largest relative change of the inlet's
  // systolic, diastolic and mean pressure (one outlet: its split is always 100 %), here
  // recomputed from cycles.json; the run stops at the first cycle below the tolerance.
  const fs::path dir = fresh_dir("periodic-metrics");
  const Result r = run("run " + (data / "runs/small_pipe_rcr_periodic_metrics.yaml").string() +
                       " -o " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(dir / "cycles.json");
  const nlohmann::json c = nlohmann::json::parse(in)["cycles"];
  ASSERT_GE(c.size(), 2u);
  for (size_t k = 1; k < c.size(); ++k) {
    double expected = 0;
    for (const char* key : {"systolic_pressure_Pa", "diastolic_pressure_Pa", "mean_pressure_Pa"}) {
      const double a = c[k - 1]["faces"]["inlet"][key], b = c[k]["faces"]["inlet"][key];
      expected = std::max(expected, std::abs(b - a) / std::abs(b));
    }
    EXPECT_NEAR(double(c[k]["change_from_previous"]), expected, 1e-12) << "cycle " << k + 1;
    EXPECT_EQ(k + 1 == c.size(), expected < 1e-3) << "cycle " << k + 1; // stops at the first
  }
  EXPECT_LT(c.size(), 5u); // before max_cycles
}

TEST(VerifyMetric, NanOrMissingErrorsFail) {
  // The verification drivers take their max errors with worst_of: a NaN (a diverged run, a
  // missing sample) must fail the metric instead of vanishing in std::max.
  using tearflow::verify::worst_of;
  EXPECT_EQ(worst_of(worst_of(0.0, 0.2), 0.1), 0.2);
  EXPECT_TRUE(std::isnan(worst_of(0.1, NAN)));
  EXPECT_TRUE(std::isnan(worst_of(worst_of(0.0, NAN), 0.3))); // a later sample cannot hide it
  EXPECT_FALSE((tearflow::verify::Metric{"e", worst_of(0.0, NAN), 1.0, ""}.passed()));
  EXPECT_TRUE((tearflow::verify::Metric{"e", worst_of(0.0, 0.5), 1.0, ""}.passed()));
}
