// End-to-end through the command-line program: a pulsatile pipe with a resistance outlet.
//  - a run restarted from its checkpoint gives the same results as an uninterrupted one;
//  - 2 MPI ranks give the serial results to solver tolerance;
//  - bad input gives a clear message and a non-zero exit code.
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

namespace {

using tearflow::testing::fresh_dir;
using tearflow::testing::Result;
using tearflow::testing::SmallFileSystem;
const fs::path data = tearflow::testing::test_data;

Result run(const std::string& args, const std::string& launcher = "") {
  return tearflow::testing::run_tearflow(args, launcher);
}

/// faces.csv as (step, face) -> {flow, pressure}.
std::map<std::pair<int, std::string>, std::pair<double, double>> read_faces(const fs::path& dir) {
  std::ifstream in(dir / "faces.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "step,time_s,face,flow_m3_per_s,pressure_Pa,area_m2,reversed_flow_m3_per_s,"
                  "distal_pressure_Pa");
  std::map<std::pair<int, std::string>, std::pair<double, double>> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string step, time, face, flow, pressure;
    std::getline(s, step, ',');
    std::getline(s, time, ',');
    std::getline(s, face, ',');
    std::getline(s, flow, ',');
    std::getline(s, pressure, ',');
    rows[{std::stoi(step), face}] = {std::stod(flow), std::stod(pressure)};
  }
  return rows;
}

/// tests/data/runs/small_pipe.yaml with `from` replaced by `to`, written as
/// `<tmp>/tearflow-test-<name>.yaml`; returns its path.
std::string small_pipe_variant(const std::string& name, const std::string& from,
                               const std::string& to) {
  std::ifstream in(data / "runs/small_pipe.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  const fs::path file = fs::temp_directory_path() / ("tearflow-test-" + name + ".yaml");
  std::ofstream(file) << text;
  return file.string();
}

} // namespace

TEST(CliRun, RestartReproducesUninterruptedRun) {
  const fs::path full = fresh_dir("full"), split = fresh_dir("split");
  const Result a =
      run("run " + (data / "runs/small_pipe.yaml").string() + " -q -o " + full.string());
  ASSERT_EQ(a.code, 0) << a.output;
  // First half, then the full-length case continued from the half's checkpoint.
  ASSERT_EQ(
      run("run " + (data / "runs/small_pipe_half.yaml").string() + " -q -o " + split.string()).code,
      0);
  // The probe's full disk left flow.pvd empty: the restart lists the frames on disk again.
  std::ofstream(split / "flow.pvd", std::ios::trunc).close();
  // A kill while step 4's rows were appended leaves a row cut short: dropped, not an error.
  std::ofstream(split / "faces.csv", std::ios::app) << "4,0.04,inl";
  const Result b =
      run("run " + (data / "runs/small_pipe.yaml").string() + " -q --restart -o " + split.string());
  ASSERT_EQ(b.code, 0) << b.output;
  const auto ra = read_faces(full), rb = read_faces(split);
  ASSERT_EQ(ra.size(), rb.size()); // every step once, no duplicated rows after the restart
  ASSERT_EQ(ra.size(), 7u * 3u);   // steps 0..6, three faces
  // Same binary, same state, same operations: the continuation is identical, so the
  // printed values (11 significant digits) must agree to round-off.
  for (const auto& [key, v] : ra) {
    EXPECT_NEAR(rb.at(key).first, v.first, 1e-12 * (std::abs(v.first) + 1e-9)) << key.second;
    EXPECT_NEAR(rb.at(key).second, v.second, 1e-9 * (std::abs(v.second) + 1e-3)) << key.second;
  }
  // The .pvd lists each saved frame once, the first half's too: steps 0, 3, 6.
  std::ifstream pvd(split / "flow.pvd");
  std::string text((std::istreambuf_iterator<char>(pvd)), {});
  size_t frames = 0;
  for (size_t at = text.find("<DataSet"); at != std::string::npos;
       at = text.find("<DataSet", at + 1))
    ++frames;
  EXPECT_EQ(frames, 3u);
}

TEST(CliRun, RestartOfAChangedCaseIsRefusedNamingTheChange) {
  // The probe's cases: time.step 0.01 -> 0.005 s (faces.csv's time then jumped back), an
  // outlet changed, and a case that ends before the checkpoint's step. Each is refused with
  // what changed; the run's files stay as they were.
  const fs::path dir = fresh_dir("restart-changed");
  ASSERT_EQ(
      run("run " + (data / "runs/small_pipe_half.yaml").string() + " -q -o " + dir.string()).code,
      0);
  const auto restart = [&](const std::string& from, const std::string& to) {
    return run("run " + small_pipe_variant("restart-changed", from, to) + " -q --restart -o " +
               dir.string());
  };
  std::ifstream faces_in(dir / "faces.csv");
  const std::string faces((std::istreambuf_iterator<char>(faces_in)), {});

  const Result step = restart("step: 0.01, steps: 6", "step: 0.005, steps: 12");
  EXPECT_NE(step.code, 0);
  EXPECT_THAT(step.output, testing::HasSubstr("time step: 0.01 s in the checkpoint; now 0.005 s"));
  EXPECT_THAT(step.output, testing::HasSubstr("--start-from " + (dir / "checkpoint.bin").string()));
  const Result outlet = restart("resistance: 1.0e8", "resistance: 2.0e8");
  EXPECT_NE(outlet.code, 0);
  EXPECT_THAT(outlet.output, testing::HasSubstr("face outlet: resistance 100000000 Pa s/m^3"));
  EXPECT_THAT(outlet.output, testing::HasSubstr("now resistance 200000000 Pa s/m^3"));
  const Result shorter = restart("steps: 6", "steps: 2");
  EXPECT_NE(shorter.code, 0);
  EXPECT_THAT(shorter.output, testing::HasSubstr("is at step 3 (t = 0.03 s), past the case's "
                                                 "last step 2"));
  std::ifstream after_in(dir / "faces.csv");
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(after_in)), {}), faces);
}

TEST(CliRun, RestartOfAnotherCasesRunIsRefusedNamingWhatDiffers) {
  // Issue 62: `--restart` into a folder whose run is another case's. Same mesh, another
  // outlet law: refused naming the face. Another mesh: refused as a different run naming the
  // mesh and every other part, where it said only that the node counts differ.
  const fs::path dir = fresh_dir("restart-another");
  ASSERT_EQ(
      run("run " + (data / "runs/small_pipe_half.yaml").string() + " -q -o " + dir.string()).code,
      0);
  std::ifstream faces_in(dir / "faces.csv");
  const std::string faces((std::istreambuf_iterator<char>(faces_in)), {});
  const Result rcr = run("run " + (data / "runs/small_pipe_rcr.yaml").string() +
                         " -q --restart -o " + dir.string());
  EXPECT_EQ(rcr.code, 2) << rcr.output;
  EXPECT_THAT(rcr.output, testing::HasSubstr("was written by a different run"));
  EXPECT_THAT(rcr.output, testing::HasSubstr("face outlet: resistance 100000000 Pa s/m^3"));
  const Result other = run("run " + (data / "runs/coarse_pipe_steady.yaml").string() +
                           " -q --restart -o " + dir.string());
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_THAT(other.output, testing::HasSubstr("was written by a different run"));
  EXPECT_THAT(other.output, testing::HasSubstr("\n  mesh: 583 nodes"));
  EXPECT_THAT(other.output,
              testing::HasSubstr("\n  time step: 0.01 s in the checkpoint; now 0.02 s"));
  std::ifstream after_in(dir / "faces.csv");
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(after_in)), {}), faces);
}

TEST(CliRun, StartFromACheckpointGoesOnAtItsTimeWithTheCasesStep) {
  // A finer step from a periodic state (the time-step study of docs/performance.md): the
  // state and time come from the checkpoint, the step from the case.
  const fs::path full = fresh_dir("start-full"), half = fresh_dir("start-half");
  const fs::path same = fresh_dir("start-same"), finer = fresh_dir("start-finer");
  const std::string pipe = (data / "runs/small_pipe.yaml").string();
  ASSERT_EQ(run("run " + pipe + " -q -o " + full.string()).code, 0);
  ASSERT_EQ(
      run("run " + (data / "runs/small_pipe_half.yaml").string() + " -q -o " + half.string()).code,
      0);
  const std::string checkpoint = (half / "checkpoint.bin").string();
  const auto variant = small_pipe_variant;

  // The same step: the same operations on the same state as the uninterrupted run.
  const Result a = run("run " + pipe + " -q --start-from " + checkpoint + " -o " + same.string());
  ASSERT_EQ(a.code, 0) << a.output;
  const auto ra = read_faces(full), rs = read_faces(same);
  ASSERT_EQ(rs.size(), 4u * 3u); // steps 3..6
  for (const auto& [key, v] : rs) {
    EXPECT_NEAR(v.first, ra.at(key).first, 1e-12 * (std::abs(v.first) + 1e-9)) << key.second;
    EXPECT_NEAR(v.second, ra.at(key).second, 1e-9 * (std::abs(v.second) + 1e-3)) << key.second;
  }

  // Half the step: steps 6..12 from t = 0.03 s. The pipe is rigid and its fluid
  // incompressible, so the outlet's flow at t is the inlet's waveform at t whatever the step
  // (to the solver's 1e-10): the same at step 12 as the full run's step 6 if time goes on
  // from the checkpoint's.
  const Result b =
      run("run " + variant("start-finer", "step: 0.01, steps: 6", "step: 0.005, steps: 12") +
          " -q --start-from " + checkpoint + " -o " + finer.string());
  ASSERT_EQ(b.code, 0) << b.output;
  const auto rf = read_faces(finer);
  ASSERT_EQ(rf.size(), 7u * 3u); // steps 6..12
  EXPECT_NEAR(rf.at({12, "outlet"}).first, ra.at({6, "outlet"}).first,
              1e-8 * std::abs(ra.at({6, "outlet"}).first));
  EXPECT_NEAR(rf.at({6, "outlet"}).second, ra.at({3, "outlet"}).second, 1e-9); // the state
  std::ifstream pvd(finer / "flow.pvd");
  const std::string text((std::istreambuf_iterator<char>(pvd)), {});
  EXPECT_THAT(text, testing::HasSubstr("timestep=\"0.03\""));

  // Refused: a time that is no whole number of steps, another case, its own folder.
  const Result odd =
      run("run " + variant("start-odd", "step: 0.01, steps: 6", "step: 0.02, steps: 3") +
          " -q --start-from " + checkpoint + " -o " + fresh_dir("start-odd").string());
  EXPECT_NE(odd.code, 0);
  EXPECT_THAT(odd.output, testing::HasSubstr("not a whole number of the case's steps of 0.02 s"));
  const Result other =
      run("run " + variant("start-other", "viscosity: 0.004", "viscosity: 0.0035") +
          " -q --start-from " + checkpoint + " -o " + fresh_dir("start-other").string());
  EXPECT_NE(other.code, 0);
  EXPECT_THAT(other.output, testing::HasSubstr("is the state of a different case"));
  EXPECT_THAT(other.output, testing::HasSubstr("fluid: density 1060 kg/m^3, viscosity 0.004"));
  const Result own = run("run " + pipe + " -q --start-from " + checkpoint + " -o " + half.string());
  EXPECT_NE(own.code, 0);
  EXPECT_THAT(own.output, testing::HasSubstr("would replace that run's files"));
}

TEST(CliRun, StartFromAnotherMeshInterpolatesTheState) {
  // A coarse run's state starts a run on a finer mesh of the same pipe (how a study's
  // resolution starts from a coarse periodic state: docs/outputs.md).
  const fs::path coarse = fresh_dir("interp-coarse"), fine = fresh_dir("interp-fine");
  const std::string half = (data / "runs/small_pipe_half.yaml").string();
  ASSERT_EQ(run("run " + half + " -q -o " + coarse.string()).code, 0);
  const auto variant = small_pipe_variant;
  const std::string finer = variant("interp-fine", "element_size: 0.0016", "element_size: 0.0012");
  const std::string start = " -q --start-from " + (coarse / "checkpoint.bin").string();
  const Result r = run("run " + finer + " --start-from " + (coarse / "checkpoint.bin").string() +
                       " --start-case " + half + " -o " + fine.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_THAT(r.output, testing::HasSubstr("interpolated to this mesh"));
  const auto rc = read_faces(coarse), rf = read_faces(fine);
  ASSERT_EQ(rf.size(), 4u * 3u); // steps 3..6
  // The interpolated state's outlet flow: the coarse P1 field's flow up to the interpolation
  // error of the parabolic profile, (1/8) h^2 |u''| = h^2 / (4 R^2) of its peak (h 1.6 mm, R
  // 5 mm: 2.6 %; the mean flow is half the peak's: 5.1 % of it).
  const double q = rc.at({3, "outlet"}).first;
  EXPECT_NEAR(rf.at({3, "outlet"}).first, q, 0.051 * std::abs(q));

  // Refused: another mesh without its case, a case other than the checkpoint's, and a
  // source case with other physics.
  const Result bare = run("run " + finer + start + " -o " + fresh_dir("interp-bare").string());
  EXPECT_NE(bare.code, 0);
  EXPECT_THAT(bare.output, testing::HasSubstr("when --start-case names the case"));
  const Result wrong = run("run " + finer + start + " --start-case " + finer + " -o " +
                           fresh_dir("interp-wrong").string());
  EXPECT_NE(wrong.code, 0);
  EXPECT_THAT(wrong.output, testing::HasSubstr("is the state of a different case"));
  EXPECT_THAT(wrong.output, testing::HasSubstr("mesh: "));
  const std::string thicker = variant("interp-other", "viscosity: 0.004", "viscosity: 0.0035");
  const Result other = run("run " + thicker + start + " --start-case " + half + " -o " +
                           fresh_dir("interp-other").string());
  EXPECT_NE(other.code, 0);
  EXPECT_THAT(other.output, testing::HasSubstr("differs from this case in more than the mesh"));
}

TEST(CliRun, AFullDiskStopsTheRunWithItsFramesListedAndItsCheckpointGood) {
  // The probe's full disk: a 600 kB file system (tmpfs, where this machine lets the tests
  // mount one) fills while frame 6 is written.
  const fs::path disk = fresh_dir("full-disk"), moved = fresh_dir("full-disk-moved");
  const SmallFileSystem small(disk, "size=600k");
  if (!small.mounted)
    GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): the full-disk test is skipped";
  const fs::path file = small_pipe_variant("full-disk", "every: 3, checkpoint_every: 3",
                                           "every: 1, checkpoint_every: 2");
  const Result r = run("run " + file.string() + " -q -o " + (disk / "run").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, testing::HasSubstr("No space left on device"));
  EXPECT_THAT(r.output, testing::HasSubstr("cannot write frame"));
  EXPECT_THAT(r.output, testing::Not(testing::HasSubstr("vtkExecutive"))); // said once
  // flow.pvd lists every whole frame on disk and nothing else; no temporary is left.
  std::ifstream pvd(disk / "run" / "flow.pvd");
  const std::string listed((std::istreambuf_iterator<char>(pvd)), {});
  size_t frames = 0;
  for (const auto& entry : fs::directory_iterator(disk / "run")) {
    const std::string name = entry.path().filename().string();
    EXPECT_FALSE(name.ends_with(".tmp")) << name;
    if (name.ends_with(".vtu")) {
      ++frames;
      EXPECT_THAT(listed, testing::HasSubstr(name));
    }
  }
  EXPECT_GE(frames, 2u);
  // Its checkpoint continues it elsewhere to the uninterrupted run's results.
  fs::copy(disk / "run", moved, fs::copy_options::recursive);
  const Result b = run("run " + file.string() + " -q --restart -o " + moved.string());
  ASSERT_EQ(b.code, 0) << b.output;
  const fs::path full = fresh_dir("full-disk-reference");
  ASSERT_EQ(run("run " + file.string() + " -q -o " + full.string()).code, 0);
  const auto ra = read_faces(full), rb = read_faces(moved);
  ASSERT_EQ(ra.size(), rb.size());
  for (const auto& [key, v] : ra) // same operations from the same state: round-off
    EXPECT_NEAR(rb.at(key).first, v.first, 1e-12 * (std::abs(v.first) + 1e-9)) << key.second;
}

TEST(CliRun, AFailedWriteStopsTheRunKeepingWhatItWrote) {
  // An injected write failure that needs no mount: files may not grow past 80 kB
  // (RLIMIT_FSIZE, with its signal ignored a write fails with EFBIG as on a full disk); frame
  // 0 (68 kB) fits, frame 1 (89 kB) does not.
  const fs::path dir = fresh_dir("write-fails");
  const fs::path file = small_pipe_variant("write-fails", "every: 3, checkpoint_every: 3",
                                           "every: 1, checkpoint_every: 2");
  const Result r = run("run " + file.string() + " -q -o " + dir.string(),
                       // PMIx's shared-memory store would be the first file to fail
                       "trap '' XFSZ; PMIX_MCA_gds=hash prlimit --fsize=81920");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output,
              testing::HasSubstr("cannot write frame '" + (dir / "flow_000001.vtu").string() +
                                 "': File too large"));
  std::ifstream pvd(dir / "flow.pvd");
  const std::string listed((std::istreambuf_iterator<char>(pvd)), {});
  EXPECT_THAT(listed, testing::HasSubstr("flow_000000.vtu"));
  EXPECT_FALSE(fs::exists(dir / "flow_000001.vtu"));
  EXPECT_FALSE(fs::exists(dir / "flow_000001.vtu.tmp"));
  EXPECT_EQ(read_faces(dir).size(), 2u * 3u); // steps 0 and 1, three faces
}

TEST(CliRun, AReadOnlyFolderIsAClearErrorNamingIt) {
  const fs::path folder = fresh_dir("read-only");
  const SmallFileSystem read_only(folder, "size=100k,ro");
  if (!read_only.mounted)
    GTEST_SKIP() << "cannot mount a read-only tmpfs here (needs root)";
  const Result r = run("run " + (data / "runs/small_pipe.yaml").string() + " -q -o " +
                       (folder / "run").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_THAT(r.output, testing::HasSubstr("error: cannot create directories '" +
                                           (folder / "run").string() + "': Read-only file system"));
}

TEST(CliRun, TwoRanksAgreeWithOne) {
  const fs::path one = fresh_dir("one"), two = fresh_dir("two");
  const std::string args = (data / "runs/small_pipe.yaml").string() + " -q -o ";
  ASSERT_EQ(run("run " + args + one.string()).code, 0);
  const Result r = run("run " + args + two.string(), "mpirun -n 2");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto r1 = read_faces(one), r2 = read_faces(two);
  ASSERT_EQ(r1.size(), r2.size());
  // Newton is converged to 1e-10 relative with KSP rtol 1e-10: the partitioned run
  // differs only by the different preconditioner's inexactness, far below 1e-6.
  for (const auto& [key, v] : r1) {
    EXPECT_NEAR(r2.at(key).first, v.first, 1e-6 * std::abs(v.first) + 1e-14) << key.second;
    EXPECT_NEAR(r2.at(key).second, v.second, 1e-6 * std::abs(v.second) + 1e-6) << key.second;
  }
}

TEST(CliRun, BadInputIsAClearErrorWithNonZeroExit) {
  using testing::HasSubstr;
  const Result face = run("run " + (data / "runs/bad_face.yaml").string());
  EXPECT_NE(face.code, 0);
  EXPECT_THAT(face.output, HasSubstr("has no face 'outlett'"));
  EXPECT_THAT(face.output, HasSubstr("did you mean 'outlet'"));

  const Result wave = run("run " + (data / "runs/bad_waveform.yaml").string());
  EXPECT_NE(wave.code, 0);
  EXPECT_THAT(wave.output, HasSubstr("bad_time.csv:4"));
  EXPECT_THAT(wave.output, HasSubstr("does not increase"));

  // Issue 28: `--steps -1` printed a 309-digit bound (CLI11's PositiveNumber).
  const Result steps = run("run " + (data / "runs/small_pipe.yaml").string() + " --steps -1");
  EXPECT_NE(steps.code, 0);
  EXPECT_THAT(steps.output, HasSubstr("--steps: Value -1 not in range 1 to 1000000000"));
  EXPECT_LT(steps.output.size(), 200u) << steps.output;

  const Result yaml = run("run " + (data / "cases/bad_malformed.yaml").string());
  EXPECT_NE(yaml.code, 0);
  EXPECT_THAT(yaml.output, HasSubstr("bad_malformed.yaml:"));

  const Result key = run("run " + (data / "cases/bad_unknown_key.yaml").string());
  EXPECT_NE(key.code, 0);
  EXPECT_THAT(key.output, HasSubstr("bad_unknown_key.yaml:"));

  const Result mesh = run("run " + (data / "cases/bad_mesh_missing_file.yaml").string());
  EXPECT_NE(mesh.code, 0);
  EXPECT_THAT(mesh.output, HasSubstr("mesh.file"));

  const Result inverted = run("run " + (data / "runs/bad_inverted.yaml").string());
  EXPECT_EQ(inverted.code, 2);
  EXPECT_THAT(inverted.output, HasSubstr("inverted_tet.msh"));
  EXPECT_THAT(inverted.output, HasSubstr("inverted element"));

  const Result rcr = run("run " + (data / "runs/bad_rcr_face.yaml").string());
  EXPECT_EQ(rcr.code, 2);
  EXPECT_THAT(rcr.output, HasSubstr("boundary_conditions[2].face"));
  EXPECT_THAT(rcr.output, HasSubstr("has no face 'outlett' (did you mean 'outlet'?)"));

  // Zero capacitance or distal resistance: the RCR ODE has no solution (R_p = 0, the RC
  // Windkessel, is accepted: docs/case-file.md).
  const std::pair<const char*, const char*> zeros[] = {
      {"bad_rcr_capacitance_zero.yaml", "boundary_conditions[1].capacitance"},
      {"bad_rcr_distal_zero.yaml", "boundary_conditions[1].distal_resistance"}};
  for (const auto& [file, key] : zeros) {
    const Result zero = run("run " + (data / "cases" / file).string());
    EXPECT_EQ(zero.code, 2) << file;
    EXPECT_THAT(zero.output, HasSubstr(file));
    EXPECT_THAT(zero.output, HasSubstr(key));
    EXPECT_THAT(zero.output, HasSubstr("expected a number > 0"));
  }

  // A misspelt PETSc option: PETSc's own reason, not only the call that failed.
  const Result option =
      run("run " + (data / "fsi/tube.yaml").string() + " --steps 1 -q -o " +
          fresh_dir("bad-petsc-option").string() + " -- -fsi_pc_type nonexistent_pc");
  EXPECT_NE(option.code, 0);
  EXPECT_THAT(option.output, HasSubstr("Unable to find requested PC type nonexistent_pc"));

  const Result missing = run("run /nonexistent/case.yaml");
  EXPECT_NE(missing.code, 0);
  EXPECT_THAT(missing.output, HasSubstr("/nonexistent/case.yaml"));
}
