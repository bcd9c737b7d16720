// Checkpoint files (io/checkpoint.hpp):
//  - everything written reads back exactly, the Newton method included;
//  - a version 01 file (written before the method was recorded) still reads, as the
//    quasi-Newton method it then always was;
//  - a truncated file or another file is an InputError naming the file.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/error.hpp"
#include "io/checkpoint.hpp"

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
  c.time = 0.0425;
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
  }
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
}

TEST(Checkpoint, VersionOneFilesStillRead) {
  const fs::path dir = made_dir("checkpoint-01");
  write_checkpoint(dir / "new.bin", sample());
  // Version 01: magic "TFCKPT01" and no method after the extra values (4 bytes).
  std::string b = bytes(dir / "new.bin");
  ASSERT_EQ(b.substr(0, 8), "TFCKPT02");
  b[7] = '1';
  b.resize(b.size() - 4);
  write_bytes(dir / "old.bin", b);
  const Checkpoint r = read_checkpoint(dir / "old.bin");
  EXPECT_EQ(r.step, 17);
  EXPECT_EQ(r.extra, sample().extra);
  EXPECT_FALSE(r.exact_operator);
}

TEST(Checkpoint, DamagedFilesAreInputErrorsNamingTheFile) {
  const fs::path dir = made_dir("checkpoint-bad");
  write_checkpoint(dir / "good.bin", sample());
  const std::string b = bytes(dir / "good.bin");

  write_bytes(dir / "truncated.bin", b.substr(0, b.size() - 2));
  EXPECT_THAT(error_reading(dir / "truncated.bin"), HasSubstr("truncated.bin' is truncated"));
  write_bytes(dir / "other.bin", "solid,0,1\n" + b);
  EXPECT_THAT(error_reading(dir / "other.bin"),
              HasSubstr("other.bin' is not a tearflow checkpoint"));
  EXPECT_THAT(error_reading(dir / "missing.bin"), HasSubstr("no checkpoint '"));
}
