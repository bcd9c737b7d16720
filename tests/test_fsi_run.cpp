// A fluid-structure case end to end through the command-line program
// (tests/data/fsi/tube.yaml: a compliant tube under an inlet pressure step):
//  - the outputs exist, the frames carry the displacement, and the inlet pressure pushes
//    fluid into the tube while the wall bulges near the inlet;
//  - 2 MPI ranks give the serial result to solver tolerance;
//  - a run restarted from its checkpoint continues the uninterrupted one;
//  - a run whose wall is overloaded (tube_diverges.yaml) stops with a message that says what
//    failed, where and in which step, and a non-zero exit.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using tearflow::testing::fresh_dir;
using tearflow::testing::run_tearflow;
using testing::HasSubstr;

namespace {

const fs::path tube = tearflow::testing::test_data / "fsi/tube.yaml";

/// faces.csv as (step, face) -> (flow, pressure, area).
std::map<std::pair<int, std::string>, std::array<double, 3>> read_faces(const fs::path& dir) {
  std::ifstream in(dir / "faces.csv");
  std::string line;
  std::getline(in, line);
  std::map<std::pair<int, std::string>, std::array<double, 3>> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string step, time, face, q, p, a;
    std::getline(s, step, ',');
    std::getline(s, time, ',');
    std::getline(s, face, ',');
    std::getline(s, q, ',');
    std::getline(s, p, ',');
    std::getline(s, a, ',');
    rows[{std::stoi(step), face}] = {std::stod(q), std::stod(p), std::stod(a)};
  }
  return rows;
}

/// Every value of b within tol * (largest |value| of its column in a) of a's.
void expect_same(const std::map<std::pair<int, std::string>, std::array<double, 3>>& a,
                 const std::map<std::pair<int, std::string>, std::array<double, 3>>& b,
                 double tol) {
  ASSERT_EQ(a.size(), b.size());
  std::array<double, 3> scale{};
  for (const auto& [key, v] : a)
    for (int c = 0; c < 3; ++c)
      scale[c] = std::max(scale[c], std::abs(v[c]));
  for (const auto& [key, v] : a)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(v[c], b.at(key)[c], tol * scale[c]) << key.first << " " << key.second << " " << c;
}

} // namespace

TEST(FsiRun, WritesTheDeformingTube) {
  const fs::path out = fresh_dir("fsi-outputs");
  const auto r = run_tearflow("run " + tube.string() + " -q -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"flow.pvd", "faces.csv", "checkpoint.bin", "flow_000004.vtu"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream vtu(out / "flow_000004.vtu");
  std::stringstream text;
  text << vtu.rdbuf();
  EXPECT_THAT(text.str(), HasSubstr("Name=\"displacement\""));
  EXPECT_THAT(text.str(), HasSubstr("Name=\"wall_pressure\""));
  const auto faces = read_faces(out);
  // Fluid enters at the inlet (outward flux < 0) while the tube near it inflates, so less
  // leaves at the outlet than enters.
  const double q_in = faces.at({4, "inlet"})[0], q_out = faces.at({4, "outlet"})[0];
  EXPECT_LT(q_in, 0.0);
  EXPECT_LT(q_out, -q_in);
}

TEST(FsiRun, TwoRanksGiveTheSerialResult) {
  const fs::path one = fresh_dir("fsi-one"), two = fresh_dir("fsi-two");
  ASSERT_EQ(run_tearflow("run " + tube.string() + " -q -o " + one.string()).code, 0);
  const auto r = run_tearflow("run " + tube.string() + " -q -o " + two.string(), "mpirun -n 2");
  ASSERT_EQ(r.code, 0) << r.output;
  // Newton to 1e-9 relative, GMRES per iteration to 1e-4 on a different partition: the
  // states agree to about 1e-6 of each quantity's scale.
  expect_same(read_faces(one), read_faces(two), 1e-5);
}

TEST(FsiRun, RestartContinuesTheRun) {
  const fs::path whole = fresh_dir("fsi-whole"), split = fresh_dir("fsi-split");
  ASSERT_EQ(run_tearflow("run " + tube.string() + " -q -o " + whole.string()).code, 0);
  ASSERT_EQ(run_tearflow("run " + tube.string() + " -q --steps 2 -o " + split.string()).code, 0);
  const auto r = run_tearflow("run " + tube.string() + " -q --restart -o " + split.string());
  ASSERT_EQ(r.code, 0) << r.output;
  // The checkpoint holds velocity, pressures, acceleration, displacement and the outlets;
  // only the lagged preconditioner starts afresh: solver tolerance, not bit for bit.
  expect_same(read_faces(whole), read_faces(split), 1e-5);
}

TEST(FsiRun, OverloadedWallStopsWithAClearMessage) {
  const fs::path out = fresh_dir("fsi-diverges");
  const auto r =
      run_tearflow("run " + (tearflow::testing::test_data / "fsi/tube_diverges.yaml").string() +
                   " -q -o " + out.string());
  EXPECT_EQ(r.code, 3) << r.output; // SolverError
  EXPECT_THAT(r.output, HasSubstr("Newton failed in the step from t ="));
  EXPECT_THAT(r.output, HasSubstr("mesh inverted: a tet near"));
  EXPECT_THAT(r.output, HasSubstr("(step "));
  EXPECT_TRUE(fs::exists(out / "faces.csv")); // the steps before the failure are recorded

  // On 2 ranks every rank sees the same failure: one message, no MPI_Abort of the others.
  const auto two =
      run_tearflow("run " + (tearflow::testing::test_data / "fsi/tube_diverges.yaml").string() +
                       " -q -o " + fresh_dir("fsi-diverges-2").string(),
                   "mpirun -n 2");
  EXPECT_EQ(two.code, 3) << two.output;
  const size_t first = two.output.find("error: Newton failed");
  ASSERT_NE(first, std::string::npos) << two.output;
  EXPECT_EQ(two.output.find("error: Newton failed", first + 1), std::string::npos) << two.output;
  EXPECT_THAT(two.output, Not(HasSubstr("MPI_ABORT"))) << two.output;
}
