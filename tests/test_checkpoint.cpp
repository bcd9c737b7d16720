// Checkpoint files (io/checkpoint.hpp):
//  - everything written reads back exactly, the Newton method and the fingerprint included;
//  - a file of an earlier format (no fingerprint, no checksum) is refused, saying why;
//  - a truncated, damaged (one byte changed) or inconsistent file, or another file, is an
//    InputError naming the file and what is wrong, never a crash or an allocation of a
//    damaged length;
//  - a restart whose case differs from the checkpoint's run names every changed part.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/digest.hpp"
#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "run/run_fingerprint.hpp"

namespace fs = std::filesystem;
using tearflow::InputError;
using tearflow::io::Checkpoint;
using tearflow::io::read_checkpoint;
using tearflow::io::write_checkpoint;
using testing::HasSubstr;

namespace {

/// An empty directory of the test's own.
fs::path made_dir(const std::string& name) {
  const fs::path d = tearflow::testing::fresh_dir(name);
  fs::create_directories(d);
  return d;
}

Checkpoint sample() {
  Checkpoint c;
  c.step = 17;
  c.time = 17 * 0.0025;
  c.time_step = 0.0025;
  c.fingerprint = {{"mesh", "3 nodes"}, {"time step", "0.0025 s"}};
  c.num_nodes = 3;
  c.block = 2;
  c.solution = {1.0, -2.0, 3.5, 0.25, 1e-300, -0.0};
  c.derivative = {6.0, 5.0, 4.0, 3.0, 2.0, 1.0};
  c.extra = {133.3, 2e-6};
  c.exact_operator = true;
  return c;
}

std::string bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& file, const std::string& b) {
  std::ofstream(file, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

std::string error_reading(const fs::path& file) {
  try {
    read_checkpoint(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

} // namespace

TEST(Checkpoint, ReadsBackWhatWasWritten) {
  const fs::path file = made_dir("checkpoint") / "checkpoint.bin";
  for (const bool exact_operator : {true, false}) {
    Checkpoint c = sample();
    c.exact_operator = exact_operator;
    write_checkpoint(file, c);
    const Checkpoint r = read_checkpoint(file);
    EXPECT_EQ(r.step, c.step);
    EXPECT_EQ(r.time, c.time); // bit for bit: the file holds the doubles themselves
    EXPECT_EQ(r.num_nodes, c.num_nodes);
    EXPECT_EQ(r.block, c.block);
    EXPECT_EQ(r.solution, c.solution);
    EXPECT_EQ(r.derivative, c.derivative);
    EXPECT_EQ(r.extra, c.extra);
    EXPECT_EQ(r.exact_operator, exact_operator);
    EXPECT_EQ(r.time_step, c.time_step);
    EXPECT_EQ(r.fingerprint, c.fingerprint);
  }
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
}

TEST(Checkpoint, EarlierFormatsAreRefusedSayingWhy) {
  const fs::path dir = made_dir("checkpoint-02");
  write_checkpoint(dir / "new.bin", sample());
  std::string b = bytes(dir / "new.bin");
  ASSERT_EQ(b.substr(0, 8), "TFCKPT03");
  b[7] = '2';
  write_bytes(dir / "old.bin", b);
  EXPECT_THAT(error_reading(dir / "old.bin"), HasSubstr("old.bin' is of an earlier format (02)"));
}

TEST(Checkpoint, DamagedFilesAreInputErrorsNamingTheFile) {
  const fs::path dir = made_dir("checkpoint-bad");
  write_checkpoint(dir / "good.bin", sample());
  const std::string b = bytes(dir / "good.bin");

  write_bytes(dir / "truncated.bin", b.substr(0, b.size() - 2));
  EXPECT_THAT(error_reading(dir / "truncated.bin"),
              HasSubstr("truncated.bin' is damaged: its checksum does not match its contents "
                        "(cut short"));
  write_bytes(dir / "stub.bin", b.substr(0, 12));
  EXPECT_THAT(error_reading(dir / "stub.bin"), HasSubstr("stub.bin' is truncated"));
  write_bytes(dir / "other.bin", "solid,0,1\n" + b);
  EXPECT_THAT(error_reading(dir / "other.bin"),
              HasSubstr("other.bin' is not a tearflow checkpoint"));
  EXPECT_THAT(error_reading(dir / "missing.bin"), HasSubstr("no checkpoint '"));

  // One velocity changed (the probe's 3 m/s), or random bytes in the solution: the checksum.
  std::string changed = b;
  const double three = 3.0;
  const std::size_t first_velocity = b.size() - 8 - 4 - (8 + 2 * 8) - (8 + 6 * 8) - 6 * 8;
  std::memcpy(changed.data() + first_velocity, &three, 8);
  write_bytes(dir / "changed.bin", changed);
  EXPECT_THAT(error_reading(dir / "changed.bin"),
              HasSubstr("changed.bin' is damaged: its checksum does not match"));

  // Damaged fields with a checksum that matches them (written so, or forged): every field
  // is checked. A vector length of 2^60 is "corrupt", not an allocation.
  const auto forged = [&](const std::string& name, auto&& change) {
    Checkpoint c = sample();
    change(c);
    write_checkpoint(dir / name, c);
    return error_reading(dir / name);
  };
  EXPECT_THAT(forged("negative.bin", [](Checkpoint& c) { c.step = -5; }),
              HasSubstr("negative.bin' is corrupt: its step is out of range"));
  EXPECT_THAT(forged("time.bin", [](Checkpoint& c) { c.time = 0.055; }),
              HasSubstr("time.bin' is inconsistent: time 0.055 s is not step 17 x 0.0025 s"));
  EXPECT_THAT(forged("nan.bin", [](Checkpoint& c) { c.solution[4] = std::nan(""); }),
              HasSubstr("its solution holds a value that is not finite (value 4"));
  EXPECT_THAT(forged("sizes.bin", [](Checkpoint& c) { c.num_nodes = 4; }),
              HasSubstr("sizes.bin' is inconsistent: 4 nodes x 2 unknowns, but 6 values"));
  std::string huge = b;
  const std::int64_t length = std::int64_t{1} << 60;
  const std::size_t solution_length = b.size() - 8 - 4 - (8 + 2 * 8) - (8 + 6 * 8) - (8 + 6 * 8);
  ASSERT_EQ(std::memcmp(huge.data() + solution_length, "\x06\0\0\0\0\0\0\0", 8), 0);
  std::memcpy(huge.data() + solution_length, &length, 8);
  const std::uint64_t sum = tearflow::fnv1a(huge.data(), huge.size() - 8);
  std::memcpy(huge.data() + huge.size() - 8, &sum, 8);
  write_bytes(dir / "huge.bin", huge);
  EXPECT_THAT(error_reading(dir / "huge.bin"),
              HasSubstr("huge.bin' is corrupt: its solution is out of range"));
}

TEST(Checkpoint, RestartNamesWhatChanged) {
  Checkpoint c = sample();
  const tearflow::io::Fingerprint now = {{"mesh", "3 nodes"}, {"time step", "0.005 s"}};
  const auto error = [&](const tearflow::io::Fingerprint& f, int last_step) {
    try {
      tearflow::run::check_restart(c, f, 3, 2, last_step, "run/checkpoint.bin");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error(c.fingerprint, 30), "no error");
  EXPECT_THAT(error(now, 30), HasSubstr("time step: 0.0025 s in the checkpoint; now 0.005 s"));
  EXPECT_THAT(error(now, 30), testing::Not(HasSubstr("mesh:")));
  EXPECT_THAT(error({{"mesh", "3 nodes"}}, 30),
              HasSubstr("time step: 0.0025 s in the checkpoint; not in the case now"));
  EXPECT_THAT(error(c.fingerprint, 10), HasSubstr("is at step 17 (t = 0.0425 s), past the "
                                                  "case's last step 10"));
}

TEST(Checkpoint, StartFromMayChangeHowTimeIsDiscretizedNotTheRun) {
  // --start-from takes a state into a run at another step or stabilization time scale
  // (the same physics, discretized otherwise); --restart continues one run, so it refuses both.
  const Checkpoint c = sample(); // step 17 of 0.0025 s, no stabilization time scale
  const tearflow::io::Fingerprint now = {
      {"mesh", "3 nodes"}, {"time step", "0.005 s"}, {"stabilization time scale", "0.005 s"}};
  const auto error = [&](auto check) {
    try {
      check();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error([&] { tearflow::run::check_start(c, now, 3, 2, 0.0025, 30, "c.bin"); }),
            "no error");
  EXPECT_THAT(error([&] { tearflow::run::check_restart(c, now, 3, 2, 30, "c.bin"); }),
              HasSubstr("stabilization time scale: not in the checkpoint; now 0.005 s"));
  tearflow::io::Fingerprint other_mesh = now;
  other_mesh[0].second = "4 nodes";
  EXPECT_THAT(error([&] { tearflow::run::check_start(c, other_mesh, 3, 2, 0.0025, 30, "c.bin"); }),
              HasSubstr("interpolated to this mesh when --start-case"));
}
