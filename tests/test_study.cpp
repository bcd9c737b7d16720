// `tearflow study` end to end on a CI-sized study (tests/data/study: two variants of the
// built-in dissection on a coarse mesh, 0D tuning, one cardiac cycle of 50 rigid-wall steps),
// and a study killed during its simulation that, run again, finishes with the same results.
#include <csignal>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace tearflow {
namespace {

using testing::read_json;

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// The CI study with its output in `out` (its case and targets from tests/data/study).
fs::path write_study(const fs::path& out) {
  fs::create_directories(out);
  std::string text = read_text(testing::test_data / "study" / "study.yaml");
  text.replace(text.find("case: case.yaml"), 15,
               fmt::format("case: {}\noutput: {}",
                           (testing::test_data / "study" / "case.yaml").string(),
                           (out / "results").string()));
  const fs::path file = out / "study.yaml";
  std::ofstream(file) << text;
  return file;
}

TEST(Study, BadStudyFileIsAClearError) {
  const fs::path dir = testing::fresh_dir("study-bad");
  const fs::path file = write_study(dir);
  std::string text = read_text(file);
  text.replace(text.find("element_size"), 12, "element_sise");
  std::ofstream(file) << text;
  const testing::Result r = testing::run_tearflow("study --check " + file.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("geometry.element_sise: not an option of `tearflow geometry tbad`; "
                          "did you mean 'element-size'?"),
            std::string::npos)
      << r.output;
}

TEST(Study, RunsEveryStageAndResumesAnInterruptedSimulation) {
  const fs::path a = testing::fresh_dir("study-a");
  testing::Result r = testing::run_tearflow("study " + write_study(a).string());
  ASSERT_EQ(r.code, 0) << r.output;
  const fs::path out = a / "results";
  for (const char* v : {"OR", "EN"})
    for (const char* file : {"geometry/mesh.msh", "geometry/landmarks.json", "case.yaml",
                             "targets.yaml", "tuned.yaml", "run/flow.pvd", "run/cycles.json",
                             "run/analysis/metrics.json", "run/analysis/report.html"})
      EXPECT_TRUE(fs::exists(out / v / file)) << v << "/" << file;
  EXPECT_TRUE(fs::exists(out / "report.html"));
  const json summary = read_json(out / "summary.json");

  // The variants differ in their entry tear: 228 and 62 mm^2 requested, measured on each
  // variant's mesh (the hole in the flap's mid-plane) within the 3 % of the geometry's
  // acceptance, a bound the 6 mm mesh's chords of the tear's ellipse meet (24 edges around).
  const json& tears_or = summary["variants"]["OR"]["tear_area_mm2"];
  const json& tears_en = summary["variants"]["EN"]["tear_area_mm2"];
  EXPECT_NEAR(tears_or["entry"].get<double>(), 228.0, 0.03 * 228.0);
  EXPECT_NEAR(tears_en["entry"].get<double>(), 62.0, 0.03 * 62.0);
  EXPECT_NEAR(tears_or["exit"].get<double>(), tears_en["exit"].get<double>(), 0.03 * 227.0);
  for (const char* v : {"OR", "EN"}) {
    const json& stations = summary["variants"][v]["stations"];
    ASSERT_EQ(stations.size(), 5u) << v;
    for (const auto& [k, s] : stations.items()) {
      const double fr = s["FR_FL_percent"].get<double>();
      EXPECT_GE(fr, 0.0) << v << " station " << k;
      EXPECT_LE(fr, 100.0) << v << " station " << k;
    }
    // Mass balance over the whole domain: with q = 1 in the weak continuity equation the
    // stabilization terms vanish, so the net outflow of all faces is zero to the Newton
    // tolerance (rtol 1e-6 of the step's residual): 1e-4 of the inflow volume is generous.
    const json cycle = read_json(out / v / "run" / "cycles.json")["cycles"].back();
    double net = 0, inflow = 0;
    for (const auto& [face, f] : cycle["faces"].items()) {
      const double volume = f["net_outflow_volume_m3"].get<double>();
      net += volume;
      inflow += std::max(0.0, -volume);
    }
    EXPECT_LE(std::abs(net), 1e-4 * inflow) << v;
    // The report's table compares achieved with target pressures and splits.
    EXPECT_NE(read_text(out / "report.html").find("inlet systolic pressure, target"),
              std::string::npos);
  }

  // A second study from the same recipe, killed during OR's simulation once a checkpoint
  // exists (every 10 steps), then run again: it must continue (not redo geometry or tuning)
  // and end where the uninterrupted study ended.
  const fs::path b = testing::fresh_dir("study-b");
  const fs::path study_b = write_study(b);
  const fs::path log = b / "first.log";
  const std::string start =
      fmt::format("setsid sh -c 'echo $$ > {}; exec {} study {}' > {} 2>&1 &", (b / "pid").string(),
                  TEARFLOW_BINARY, study_b.string(), log.string());
  ASSERT_EQ(std::system(start.c_str()), 0);
  bool reached = false;
  for (int i = 0; i < 1800 && !reached; ++i) { // at most 15 minutes
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    reached = read_text(log).find("[OR run] step    12/") != std::string::npos;
  }
  ASSERT_TRUE(reached) << read_text(log);
  const pid_t group = std::stoi(read_text(b / "pid"));
  ASSERT_EQ(kill(-group, SIGKILL), 0);
  for (int i = 0; i < 100 && kill(-group, 0) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(fs::exists(b / "results" / "OR" / "run" / "analysis"));

  r = testing::run_tearflow("study " + study_b.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("[OR geometry]"), std::string::npos) << "geometry was redone";
  EXPECT_EQ(r.output.find("[OR tune]"), std::string::npos) << "tuning was redone";
  EXPECT_NE(r.output.find("[OR run] restarting from step"), std::string::npos) << r.output;
  // Same results: the restart reproduces the uninterrupted run to solver tolerance (Newton
  // rtol 1e-6), so the cycle's metrics agree far inside 1e-4 relative.
  for (const char* v : {"OR", "EN"}) {
    const json ma = read_json(out / v / "run" / "analysis" / "metrics.json");
    const json mb = read_json(b / "results" / v / "run" / "analysis" / "metrics.json");
    for (const auto& [k, s] : ma["stations"].items()) {
      const double fa = s["FR_FL_percent"].get<double>();
      const double fb = mb["stations"][k]["FR_FL_percent"].get<double>();
      EXPECT_NEAR(fb, fa, 1e-4 * std::max(1.0, std::abs(fa))) << v << " station " << k;
      const double pa = s["dP_TL_minus_FL_peak_systole_Pa"].get<double>();
      const double pb = mb["stations"][k]["dP_TL_minus_FL_peak_systole_Pa"].get<double>();
      EXPECT_NEAR(pb, pa, 1e-4 * std::max(1.0, std::abs(pa))) << v << " station " << k;
    }
  }
}

} // namespace
} // namespace tearflow
