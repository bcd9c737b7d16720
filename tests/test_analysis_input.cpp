// Bad input to `tearflow analyze`, through the program: exit code 2 (InputError) and a message
// naming the landmark (or the file) and what was expected.
#include <fstream>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "analysis_support.hpp"
#include "cli_support.hpp"

namespace tearflow {
namespace {

using ::testing::HasSubstr;
using testing::SyntheticLumen;
using testing::SyntheticRun;

/// A coarse pipe run (the answers do not matter here), one per test (ctest runs them in
/// parallel).
std::filesystem::path pipe_run(const std::string& name) {
  SyntheticRun run;
  run.lumina = {SyntheticLumen{}};
  run.element_size = 0.002;
  run.length = 0.01;
  run.frames = 3;
  const std::filesystem::path dir = testing::fresh_dir("analysis-input-" + name);
  testing::write_synthetic_run(run, dir);
  return dir;
}

testing::Result analyze_with(const std::filesystem::path& run, const geometry::Landmarks& landmarks,
                             const std::string& extra = "") {
  const std::filesystem::path file = run / "landmarks-test.json";
  geometry::write_landmarks(landmarks, file);
  return testing::run_tearflow(
      fmt::format("analyze {} --landmarks {} {}", run.string(), file.string(), extra));
}

TEST(AnalysisInput, PlaneMissingTheMeshNamesTheLandmark) {
  geometry::Landmarks l;
  l.planes = {{"inlet", {0, 0, 0.001}, {0, 0, 1}},
              {"DAo_dist", {0, 0, 0.3}, {0, 0, 1}}}; // 29 cm past the pipe's end
  const testing::Result r = analyze_with(pipe_run("missing"), l);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("landmark 'DAo_dist'"));
  EXPECT_THAT(r.output, HasSubstr("misses the fluid mesh"));
}

TEST(AnalysisInput, LumenPointOutsideTheSectionNamesTheLandmark) {
  // The plane cuts the pipe, but its point lies 2 cm beside it.
  geometry::Landmarks l;
  l.planes = {{"FL3", {0, 0, 0.005}, {0, 0, 1}, "FL", Vec3{0.03, 0, 0.005}}};
  const testing::Result r = analyze_with(pipe_run("outside"), l);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("landmark 'FL3'"));
  EXPECT_THAT(r.output, HasSubstr("not inside the fluid section"));
}

TEST(AnalysisInput, StationInOneRegionNamesTheStation) {
  // TL2 and FL2 on one plane with both points in the single lumen of the pipe.
  geometry::Landmarks l;
  l.planes = {{"TL2", {0, 0, 0.005}, {0, 0, 1}, "TL", Vec3{-0.002, 0, 0.005}},
              {"FL2", {0, 0, 0.005}, {0, 0, 1}, "FL", Vec3{0.002, 0, 0.005}}};
  const testing::Result r = analyze_with(pipe_run("one-region"), l);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("TL2 and FL2"));
  EXPECT_THAT(r.output, HasSubstr("one connected region"));
}

TEST(AnalysisInput, RunWithoutCompleteCycle) {
  geometry::Landmarks l;
  l.planes = {{"inlet", {0, 0, 0.001}, {0, 0, 1}}};
  const std::filesystem::path run = pipe_run("no-cycle"), cycles = run / "cycles.json";
  // cycles.json as a run shorter than one period writes it: no complete cycle.
  std::ofstream(cycles) << R"({"period_s": 0.8, "cycles": []})";
  testing::Result r = analyze_with(run, l);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no complete cardiac cycle"));
  EXPECT_THAT(r.output, HasSubstr("--frames all"));
  // A cycle that does not exist.
  std::ofstream(cycles) << R"({"period_s": 0.8, "cycles": [{"cycle": 1, "t_begin_s": 0,
                                "t_end_s": 0.8}]})";
  r = analyze_with(run, l, "--cycle 4");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no complete cycle 4"));
  // Without cycles.json, --frames all still analyses what was saved.
  std::filesystem::remove(cycles);
  r = analyze_with(run, l);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("cycles.json"));
  r = analyze_with(run, l, "--frames all");
  EXPECT_EQ(r.code, 0) << r.output;
}

} // namespace
} // namespace tearflow
