// A solid-only case end to end through the command-line program (tests/data/solid/rod.yaml:
// a clamped rubber rod under a follower pressure on the tissue support):
//  - the outputs exist and the rod is pushed the way the load points;
//  - a run restarted from its checkpoint gives the results of an uninterrupted one;
//  - 2 MPI ranks give the serial results to solver tolerance;
//  - bad input (negative modulus, nu >= 0.5, robin on a face the mesh lacks) gives a clear
//    message and exit code 2; a solver PETSc cannot set up gives PETSc's reason, exit 3.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using testing::HasSubstr;

namespace {

using tearflow::testing::fresh_dir;
using tearflow::testing::Result;

const fs::path data = tearflow::testing::test_data / "solid";

Result run(const std::string& args, const std::string& launcher = "") {
  return tearflow::testing::run_tearflow(args, launcher);
}

std::string read_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// wall_faces.csv as (step, face) -> mean displacement.
std::map<std::pair<int, std::string>, std::array<double, 3>> read_faces(const fs::path& dir) {
  std::ifstream in(dir / "wall_faces.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "step,time_s,face,mean_ux_m,mean_uy_m,mean_uz_m,area_m2");
  std::map<std::pair<int, std::string>, std::array<double, 3>> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string step, time, face, x, y, z;
    std::getline(s, step, ',');
    std::getline(s, time, ',');
    std::getline(s, face, ',');
    std::getline(s, x, ',');
    std::getline(s, y, ',');
    std::getline(s, z, ',');
    rows[{std::stoi(step), face}] = {std::stod(x), std::stod(y), std::stod(z)};
  }
  return rows;
}

/// rod.yaml with `steps` steps, written to `dir`.
fs::path rod_with_steps(const fs::path& dir, int steps) {
  std::string text = read_text(data / "rod.yaml");
  const std::string from = "steps: 4";
  text.replace(text.find(from), from.size(), "steps: " + std::to_string(steps));
  fs::create_directories(dir);
  const fs::path f = dir / "rod.yaml";
  std::ofstream(f) << text;
  return f;
}

} // namespace

TEST(SolidRun, WritesOutputsAndFollowsTheLoad) {
  const fs::path out = fresh_dir("solid-outputs");
  const Result r = run("run " + (data / "rod.yaml").string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "solid.pvd"));
  EXPECT_TRUE(fs::exists(out / "checkpoint.bin"));
  const std::string vtu = read_text(out / "solid_000004.vtu");
  for (const char* field : {"displacement", "velocity", "pressure", "von_mises", "\"J\""})
    EXPECT_THAT(vtu, HasSubstr(field)) << field;
  const auto faces = read_faces(out);
  // The pressure pushes the free end (outward normal +z) towards the clamp; the clamp holds.
  EXPECT_LT(faces.at({4, "outlet"})[2], -1e-6);
  EXPECT_EQ(faces.at({4, "inlet"})[2], 0.0);
}

TEST(SolidRun, RestartContinuesTheSameRun) {
  const fs::path whole = fresh_dir("solid-whole"), split = fresh_dir("solid-split");
  ASSERT_EQ(run("run " + (data / "rod.yaml").string() + " -q -o " + whole.string()).code, 0);
  const fs::path first = rod_with_steps(fresh_dir("solid-case2"), 2);
  ASSERT_EQ(run("run " + first.string() + " -q -o " + split.string()).code, 0);
  // A row cut short by a kill or a full disk after the checkpoint (step 12's "12,..." cut
  // after its first digit) must not come back as a row of step 1.
  std::ofstream(split / "wall_faces.csv", std::ios::app) << "1";
  const Result r =
      run("run " + (data / "rod.yaml").string() + " -q --restart -o " + split.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto a = read_faces(whole), b = read_faces(split);
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [key, u] : a)
    for (int c = 0; c < 3; ++c) // bit for bit: the checkpoint holds the whole state
      EXPECT_EQ(u[c], b.at(key)[c]) << key.first << " " << key.second << " " << c;
}

TEST(SolidRun, TwoRanksGiveTheSerialResult) {
  const fs::path one = fresh_dir("solid-one"), two = fresh_dir("solid-two");
  ASSERT_EQ(run("run " + (data / "rod.yaml").string() + " -q -o " + one.string()).code, 0);
  const Result r =
      run("run " + (data / "rod.yaml").string() + " -q -o " + two.string(), "mpirun -n 2");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto a = read_faces(one), b = read_faces(two);
  ASSERT_EQ(a.size(), b.size());
  const double scale = std::abs(a.at({4, "outlet"})[2]);
  for (const auto& [key, u] : a)
    for (int c = 0; c < 3; ++c) // Newton rtol 1e-8 and a different partition: 1e-6 of u
      EXPECT_NEAR(u[c], b.at(key)[c], 1e-6 * scale) << key.first << " " << key.second;
}

TEST(SolidRun, BadInputIsAClearError) {
  struct Bad {
    const char* file;
    const char* message;
  };
  for (const Bad& b :
       {Bad{"bad_negative_modulus.yaml",
            "bad_negative_modulus.yaml:9: solid.youngs_modulus: solid material: Young's modulus "
            "must be > 0 Pa, got -1200000 Pa"},
        Bad{"bad_poisson_half.yaml", "bad_poisson_half.yaml:10: solid.poisson_ratio: solid "
                                     "material: Poisson's ratio must be in (-1, 0.5), got 0.5"},
        Bad{"bad_robin_face.yaml", "robin on face 'outer_wall', but the mesh"},
        Bad{"bad_both_moduli.yaml", "bad_both_moduli.yaml:10: solid.shear_modulus: give "
                                    "youngs_modulus and poisson_ratio, or shear_modulus"},
        Bad{"bad_robin_key.yaml", "key 'components' does not apply here (type: robin)"},
        Bad{"bad_fsi.yaml", "a fluid-structure case needs volume regions 'fluid' and 'wall'; "
                            "the mesh pipe"}}) {
    const Result r =
        run("run " + (data / b.file).string() + " -q -o " + fresh_dir("solid-bad").string());
    EXPECT_EQ(r.code, 2) << b.file << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(b.message)) << b.file;
  }
  // The robin face message lists the faces the mesh has.
  const Result r = run("run " + (data / "bad_robin_face.yaml").string() + " -q -o " +
                       fresh_dir("solid-bad").string());
  EXPECT_THAT(r.output, HasSubstr("its faces are inlet, outlet and wall"));
}

TEST(SolidRun, SolverFailureGivesPetscsReason) {
  // A direct solver this PETSc lacks fails inside the Newton solve (at the first
  // preconditioner setup), not while reading the options: the step's error says PETSc's why.
  const Result r = run("run " + (data / "rod.yaml").string() + " --steps 1 -q -o " +
                       fresh_dir("solid-bad-solver").string() +
                       " -- -solid_pc_type lu -solid_pc_factor_mat_solver_type nonexistent");
  EXPECT_EQ(r.code, 3) << r.output; // SolverError
  EXPECT_THAT(r.output, HasSubstr("solid: Newton failed in the step from t = 0 s"));
  EXPECT_THAT(r.output, HasSubstr("Could not locate solver type nonexistent"));
}
