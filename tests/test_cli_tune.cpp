// `tearflow tune` end to end on the small pipe (one RCR outlet, one 3D run of two cycles of
// 20 steps): the tuned case and the target / achieved / error table are written and
// consistent; targets no Windkessel can meet stop before any fit or run.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "io/case.hpp"

namespace fs = std::filesystem;
using testing::HasSubstr;
using testing::Not;

namespace {

using tearflow::testing::fresh_dir;
using tearflow::testing::Result;
using tearflow::testing::SmallFileSystem;
const fs::path data = tearflow::testing::test_data / "tuning";

std::string read(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1))
    ++n;
  return n;
}

/// How often the regular expression `pattern` matches in `text` (a message printed once, not
/// once per rank).
long count_matches(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  return std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator());
}

} // namespace

TEST(CliTune, WritesTheTunedCaseAndTheTable) {
  const fs::path dir = fresh_dir("tune");
  const fs::path tuned = dir / "tuned.yaml";
  const Result r = tearflow::testing::run_tearflow(
      "tune " + (data / "small_pipe.yaml").string() + " --targets " +
      (data / "small_pipe_targets.yaml").string() + " -o " + tuned.string());
  // Met within the targets' 10 % after the one 3D run the targets file allows.
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(count(r.output, "tune 0D 0:"), 1) << r.output;
  EXPECT_EQ(count(r.output, "tune 3D "), 1) << r.output;
  for (const char* row : {"P_sys mmHg", "P_dias mmHg", "MAP mmHg", "split outlet"})
    EXPECT_THAT(r.output, HasSubstr(row));

  // The tuned case: headed by the same table, loadable, its outlet the last step's RCR.
  ASSERT_TRUE(fs::exists(tuned)) << r.output;
  const std::string text = read(tuned);
  EXPECT_THAT(text, HasSubstr("targets met after 1 3D run(s)"));
  EXPECT_THAT(text, HasSubstr("#                    target   achieved     error"));
  EXPECT_THAT(text, HasSubstr("# P_sys mmHg"));
  const tearflow::io::Case c = tearflow::io::load_case(tuned);
  const tearflow::bc::BoundaryCondition* outlet = nullptr;
  for (const auto& b : c.boundary_conditions)
    if (b.face == "outlet")
      outlet = &b;
  ASSERT_NE(outlet, nullptr);
  ASSERT_TRUE(outlet->outlet());
  ASSERT_TRUE(std::holds_alternative<tearflow::bc::RcrOutlet>(outlet->outlet()->law));
  const tearflow::bc::WindkesselRCR& rcr =
      std::get<tearflow::bc::RcrOutlet>(outlet->outlet()->law).rcr;

  std::ifstream in(dir / "tuned.tuning.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_TRUE(j["met"].get<bool>());
  ASSERT_EQ(j["steps"].size(), 2u);
  const nlohmann::json& last = j["steps"][1];
  EXPECT_EQ(last["stage"], "3D");
  // One outlet takes R_T whole: R_p + R_d = R_T, C = C_T, R_d = k_d R_T (written to 6
  // significant digits).
  const double R_T = last["R_T_Pa_s_per_m3"], C_T = last["C_T_m3_per_Pa"], k_d = last["k_d"];
  EXPECT_NEAR(rcr.proximal_resistance + rcr.distal_resistance, R_T, 1e-5 * R_T);
  EXPECT_NEAR(rcr.distal_resistance, k_d * R_T, 1e-5 * R_T);
  EXPECT_NEAR(rcr.capacitance, C_T, 1e-5 * C_T);
  EXPECT_LE(double(last["pressure_error_percent"]), 10.0);
  EXPECT_NEAR(double(last["split_percent"]["outlet"]), 100.0, 1e-9);
}

TEST(CliTune, TargetsNoWindkesselCanMeetStopBeforeAnyRun) {
  const std::pair<const char*, const char*> bad[] = {
      {"bad_pressures.yaml", "expected diastolic < mean < systolic"},
      {"bad_splits.yaml", "bad_splits.yaml:3: splits: the splits sum to 93.50 %"}};
  for (const auto& [file, message] : bad) {
    const fs::path dir = fresh_dir("tune-bad");
    const Result r = tearflow::testing::run_tearflow("tune " + (data / "small_pipe.yaml").string() +
                                                     " --targets " + (data / file).string() +
                                                     " -o " + (dir / "tuned.yaml").string());
    EXPECT_EQ(r.code, 2) << file << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(file));
    EXPECT_THAT(r.output, HasSubstr(message));
    EXPECT_THAT(r.output, Not(HasSubstr("tune 0D"))) << file; // no fit
    EXPECT_THAT(r.output, Not(HasSubstr("tune 3D"))) << file; // no run
    EXPECT_FALSE(fs::exists(dir / "tuned.yaml")) << file;
  }
}

// `verify --progress` prints progress on stderr and the case's JSON alone on stdout, also
// for the tuning case, whose 3D runs print their step lines where a run's output goes.
TEST(CliVerify, ProgressOnStderrJsonAloneOnStdout) {
  const fs::path dir = fresh_dir("verify-progress");
  fs::create_directories(dir);
  const fs::path out = dir / "stdout.json", err = dir / "stderr.txt";
  const std::string cmd = std::string(TEARFLOW_BINARY) +
                          " verify tuning --coarsen 2 --progress > " + out.string() + " 2> " +
                          err.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read(err);
  const nlohmann::json j = nlohmann::json::parse(read(out)); // throws on stray lines
  EXPECT_EQ(j.at("case"), "tuning");
  EXPECT_THAT(read(err), HasSubstr("step "));
  EXPECT_THAT(read(out), Not(HasSubstr("step ")));
}

// An input that every rank checks alike (a --coarsen too coarse for the pulse's boundary
// layers) stops all ranks together: exit code 2 and the message once, not once per rank.
TEST(CliVerify, CollectiveInputErrorIsReportedOnce) {
  const Result r = tearflow::testing::run_tearflow("verify pulse --coarsen 2", "mpirun -n 2");
  EXPECT_NE(r.code, 0);
  EXPECT_THAT(r.output, HasSubstr("--coarsen 2 gives elements of 2.00 mm"));
  EXPECT_EQ(count_matches(r.output, "error: verify pulse"), 1) << r.output;
}

TEST(CliRun, BadCaseOnTwoRanksIsReportedOnceWithoutAbort) {
  // Issue 28: a bad case on 2 ranks was printed twice and followed by Open MPI's MPI_ABORT
  // banner. Every rank reads the same file: the same error, reported once, a clean exit 2.
  const Result r = tearflow::testing::run_tearflow(
      "run " + (tearflow::testing::test_data / "cases/bad_density_type.yaml").string(),
      "mpirun -n 2");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(count_matches(r.output, "error: .*fluid.density"), 1) << r.output;
  EXPECT_THAT(r.output, testing::Not(HasSubstr("MPI_ABORT")));

  // An unknown option: the command line, the same on every rank, is refused once too.
  const Result option = tearflow::testing::run_tearflow("run --no-such-option", "mpirun -n 2");
  EXPECT_NE(option.code, 0) << option.output;
  EXPECT_EQ(count_matches(option.output, "not expected: --no-such-option"), 1) << option.output;
  EXPECT_THAT(option.output, testing::Not(HasSubstr("MPI_ABORT")));
}

// Issue 62, part 3: the outside probe's input errors on 2 ranks, each printed once by one
// rank, exit 2, without Open MPI's MPI_ABORT banner or ORTE_ERROR_LOG line. Each rank reads
// the mesh and the checkpoint itself; they agree before going on (fem/alike_on_every_rank.hpp).
TEST(CliRun, BadInputOnTwoRanksIsPrintedOnceWithoutAbort) {
  const fs::path dir = fresh_dir("two-rank-errors");
  fs::create_directories(dir);
  const std::string pipe = "pipe: {radius: 0.005, length: 0.02, element_size: 0.003}";
  auto write_case = [&](const std::string& name, const std::string& mesh,
                        const std::string& outlet) {
    const fs::path file = dir / (name + ".yaml");
    std::ofstream(file) << "name: " << name << "\nmesh:\n  " << mesh
                        << "\nfluid: {density: 1060, viscosity: 0.004}\n"
                           "time: {step: 0.01, steps: 2}\n"
                           "boundary_conditions:\n"
                           "  - {face: wall, type: no_slip}\n"
                           "  - {face: inlet, type: inflow, flow: 1.0e-5}\n"
                           "  - {face: "
                        << outlet
                        << ", type: pressure, pressure: 0}\n"
                           "output: {every: 1, checkpoint_every: 1}\n";
    return file.string();
  };
  const std::string good = write_case("good", pipe, "outlet");
  // A .msh cut short inside its nodes.
  std::ofstream(dir / "cut.msh")
      << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0";
  const std::string two = "mpirun -n 2";
  auto expect_once = [&](const Result& r, const std::string& message, const std::string& probe) {
    EXPECT_EQ(r.code, 2) << probe << "\n" << r.output;
    EXPECT_EQ(count_matches(r.output, "error: "), 1) << probe << "\n" << r.output;
    EXPECT_THAT(r.output, HasSubstr(message)) << probe;
    EXPECT_THAT(r.output, Not(HasSubstr("MPI_ABORT"))) << probe;
    EXPECT_THAT(r.output, Not(HasSubstr("ORTE_ERROR_LOG"))) << probe;
  };
  const std::string out = " -q -o " + (dir / "run").string();
  expect_once(
      tearflow::testing::run_tearflow("run " + write_case("face", pipe, "outlet_2") + out, two),
      "has no face 'outlet_2'", "missing face");
  expect_once(
      tearflow::testing::run_tearflow(
          "run " + write_case("cut", "file: " + (dir / "cut.msh").string(), "outlet") + out, two),
      "cut.msh", "truncated .msh");
  expect_once(tearflow::testing::run_tearflow(
                  "run " + good + " --restart -q -o " + (dir / "empty").string(), two),
              "no checkpoint", "no checkpoint");
  ASSERT_EQ(tearflow::testing::run_tearflow("run " + good + out, two).code, 0);
  {
    std::fstream f(dir / "run" / "checkpoint.bin", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x5a'); // a byte changed: the checksum no longer matches
  }
  expect_once(tearflow::testing::run_tearflow("run " + good + " --restart" + out, two),
              "is damaged", "damaged checkpoint");
  expect_once(tearflow::testing::run_tearflow("run " + good + " --start-case " + good + out, two),
              "--start-case names the case of --start-from's run", "argument without its pair");
  const SmallFileSystem read_only(dir / "read-only", "size=100k,ro");
  if (read_only.mounted)
    expect_once(tearflow::testing::run_tearflow(
                    "run " + good + " -q -o " + (dir / "read-only" / "run").string(), two),
                "Read-only file system", "read-only folder");
}

TEST(CliRun, AOneProcessCommandOnTwoRanksSaysSoAndFailsOnceWithoutAbort) {
  // Issue 28: commands that run on one rank say so, and an error there ends every rank
  // with its code (the other rank waited; it was MPI_Abort's banner).
  const Result r = tearflow::testing::run_tearflow("analyze /nonexistent-run", "mpirun -n 2");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("`tearflow analyze` runs on one process; the other 1 rank(s)"));
  EXPECT_EQ(count_matches(r.output, "error: '/nonexistent-run'"), 1) << r.output;
  EXPECT_THAT(r.output, testing::Not(HasSubstr("MPI_ABORT")));
}

// Every rank reads or builds the whole mesh itself. Ranks holding different meshes (here two
// cases differing in element size, launched side by side) crashed in the partition
// (segmentation fault); a mesh file replaced while a run starts would do the same or run on
// two meshes. Now all ranks compare the mesh's digest and stop with one clear error.
TEST(CliRun, RanksHoldingDifferentMeshesStopWithOneClearError) {
  const fs::path dir = tearflow::testing::fresh_dir("different-meshes");
  fs::create_directories(dir);
  auto write_case = [&](const std::string& size) {
    const fs::path file = dir / ("pipe-" + size + ".yaml");
    std::ofstream(file) << "name: pipe\n"
                           "mesh:\n  pipe: {radius: 0.005, length: 0.04, element_size: "
                        << size
                        << "}\n"
                           "fluid: {density: 1060, viscosity: 0.004}\n"
                           "time: {step: 0.01, end: 0.02}\n"
                           "boundary_conditions:\n"
                           "  - {face: wall, type: no_slip}\n"
                           "  - {face: inlet, type: inflow, profile: parabolic, flow: {times: [0, "
                           "0.3, 0.6], values: [10, 10, 10], units: mL/s, period: 1.0}}\n"
                           "  - {face: outlet, type: pressure, pressure: 0}\n";
    return file.string();
  };
  const std::string out = " -q -o " + (dir / "run").string();
  const Result r =
      tearflow::testing::run_tearflow("run " + write_case("0.002") + out + " : -n 1 " +
                                          TEARFLOW_BINARY + " run " + write_case("0.0025") + out,
                                      "mpirun -n 1");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(count_matches(r.output, "error: .*the 2 MPI ranks hold different meshes"), 1)
      << r.output;
  EXPECT_THAT(r.output, testing::Not(HasSubstr("MPI_ABORT")));
  EXPECT_THAT(r.output, testing::Not(HasSubstr("Segmentation")));
  fs::remove_all(dir);
}

namespace {

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

} // namespace

// `tearflow run --targets` (tuning/corrected_run.hpp): the small pipe's first cycle misses the
// 1 % targets (by 1.15 %, small_pipe_in_run_targets.yaml) and is corrected; the second meets
// them (0.79 %) but is corrected again, being above half the tolerance while the outlet's
// capacitor still settles; the third gets 0.04 % and is periodic within the case's 1 %; an
// interrupted run continues with the outlet that ran at its checkpoint and ends as the
// uninterrupted one.
TEST(CliTune, RunCorrectsItsOutletsAtCycleEndsUntilAPeriodicCycleMeetsTheTargets) {
  const fs::path case_file = data / "small_pipe_in_run.yaml",
                 targets = data / "small_pipe_in_run_targets.yaml";
  const fs::path whole = fresh_dir("in-run"), split = fresh_dir("in-run-split");
  const Result r = tearflow::testing::run_tearflow("run " + case_file.string() + " --targets " +
                                                   targets.string() + " -o " + whole.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(count(r.output, "tune 0D 0:"), 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("targets met by the last cycle"));

  const nlohmann::json j = read_json(whole / "tuning.json");
  EXPECT_TRUE(j["met"].get<bool>());
  EXPECT_EQ(j["method"]["runs"], "in_run");
  const nlohmann::json& steps = j["steps"];
  ASSERT_EQ(steps.size(), 4u) << j.dump(2); // 0D, then cycles 1-3
  EXPECT_EQ(steps[0]["stage"], "0D");
  EXPECT_GT(double(steps[1]["pressure_error_percent"]), 1.0); // corrected after cycle 1 ...
  EXPECT_NE(double(steps[1]["R_T_Pa_s_per_m3"]), double(steps[2]["R_T_Pa_s_per_m3"]));
  EXPECT_LE(double(steps[2]["pressure_error_percent"]), 1.0); // ... met by cycle 2, but
  EXPECT_GT(double(steps[2]["pressure_error_percent"]), 0.5); // above half: corrected ...
  EXPECT_NE(double(steps[2]["R_T_Pa_s_per_m3"]), double(steps[3]["R_T_Pa_s_per_m3"]));
  EXPECT_LE(double(steps[3]["pressure_error_percent"]), 0.5); // ... and cycle 3, periodic
  const nlohmann::json cycles = read_json(whole / "cycles.json");
  ASSERT_EQ(cycles["cycles"].size(), 3u);
  EXPECT_LT(double(cycles["cycles"][2]["change_from_previous"]), 0.01);

  // The tuned case: the outlet of the last cycle, headed by what that cycle achieved.
  const std::string text = read(whole / "tuned.yaml");
  EXPECT_THAT(text, HasSubstr("Outlets of cycle 3 of this run"));
  EXPECT_THAT(text, HasSubstr("targets met by the cycle"));
  const tearflow::io::Case tuned = tearflow::io::load_case(whole / "tuned.yaml");
  const double R_T = steps[3]["R_T_Pa_s_per_m3"];
  for (const auto& b : tuned.boundary_conditions)
    if (b.face == "outlet") { // the sum of two exact doubles, and R_T printed to 17 digits
      const auto& rcr = std::get<tearflow::bc::RcrOutlet>(b.outlet()->law).rcr;
      EXPECT_NEAR(rcr.proximal_resistance + rcr.distal_resistance, R_T, 1e-15 * R_T);
    }
  // ... exactly the outlets the run ended with: its checkpoint starts the tuned case.
  const Result next = tearflow::testing::run_tearflow(
      "run " + (whole / "tuned.yaml").string() + " -q --steps 64 --start-from " +
      (whole / "checkpoint.bin").string() + " -o " + fresh_dir("in-run-next").string());
  EXPECT_EQ(next.code, 0) << next.output;

  // Interrupted in cycle 2 (after the correction at step 20, checkpoint at step 25), then
  // continued: the same steps and the same record as the uninterrupted run.
  const std::string command =
      "run " + case_file.string() + " --targets " + targets.string() + " -q -o " + split.string();
  ASSERT_EQ(tearflow::testing::run_tearflow(command + " --steps 28").code, 0);
  const Result resumed = tearflow::testing::run_tearflow(command + " --restart");
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  const nlohmann::json k = read_json(split / "tuning.json");
  ASSERT_EQ(k["steps"].size(), steps.size()) << k.dump(2);
  for (size_t i = 0; i < steps.size(); ++i) // the same solves: equal to solver tolerance
    EXPECT_NEAR(double(k["steps"][i]["systolic_mmHg"]), double(steps[i]["systolic_mmHg"]),
                1e-6 * double(steps[i]["systolic_mmHg"]));
  EXPECT_EQ(read(split / "faces.csv").size(), read(whole / "faces.csv").size());
}
