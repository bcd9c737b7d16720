// One `tearflow run` per output folder (issue 62): two runs into one folder both went on,
// interleaving their frames, faces.csv rows and checkpoints. A run holds the folder's lock
// (RunFiles::kLock, io/output_lock.hpp) from before it writes anything to its end:
//  - a second run on a held folder is refused, exit 2, naming the holder as its record says;
//  - a killed run leaves its record, and the next run takes the lock over and says so;
//  - a run that ends, well or with an error, releases it: the next one goes on quietly;
//  - on two ranks rank 0 alone holds it and a refusal ends both, said once.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/file_layout.hpp"
#include "io/output_lock.hpp"

namespace fs = std::filesystem;
using tearflow::testing::fresh_dir;
using tearflow::testing::Result;
using testing::HasSubstr;

namespace {

const std::string small_pipe = (tearflow::testing::test_data / "runs/small_pipe.yaml").string();

Result run(const std::string& args, const std::string& launcher = "") {
  return tearflow::testing::run_tearflow(args, launcher);
}

long count_matches(const std::string& text, const std::string& pattern) {
  const std::regex re(pattern);
  return std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator());
}

fs::path lock_of(const fs::path& folder) {
  return folder / tearflow::RunFiles::kLock;
}

std::string read_record(const fs::path& lock) {
  std::ifstream in(lock);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  while (!text.empty() && text.back() == '\n')
    text.pop_back();
  return text;
}

/// The small pipe run on until killed (a million steps) in the background, into `out`: its pid.
int start_long_run(const fs::path& out) {
  const Result r = tearflow::testing::run_command(
      std::string(TEARFLOW_BINARY) + " run " + small_pipe + " -q --steps 1000000 -o " +
      out.string() + " > " + out.string() + ".log 2>&1 & echo $!");
  return std::stoi(r.output);
}

/// The lock's record once its holder has written it (at most 60 s; "" if never).
std::string wait_for_record(const fs::path& lock) {
  for (int i = 0; i < 600; ++i) {
    if (const std::string record = read_record(lock); !record.empty())
      return record;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return "";
}

/// Kills `pid` and waits until its lock is free: the kernel releases it when the process's
/// files close (whether or not anyone reaps it).
void kill_and_wait(int pid, const fs::path& lock) {
  ::kill(pid, SIGKILL);
  for (int i = 0; i < 600; ++i) {
    const int fd = ::open(lock.c_str(), O_RDONLY);
    const bool free = fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0;
    if (fd >= 0)
      ::close(fd);
    if (free)
      return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ADD_FAILURE() << "the killed run's lock was never released";
}

std::string host() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

} // namespace

TEST(CliRunLock, ASecondRunOnAHeldFolderIsRefusedNamingTheHolder) {
  const fs::path out = fresh_dir("lock-held");
  const int pid = start_long_run(out);
  const std::string record = wait_for_record(lock_of(out));
  // The record names the holder: pid, host, start, the command line and the case.
  EXPECT_EQ(record.rfind(fmt::format("pid {} on host {}, started ", pid, host()), 0), 0u) << record;
  EXPECT_THAT(record, HasSubstr(": tearflow run " + small_pipe + " -q --steps 1000000 -o " +
                                out.string() + " (case 'small-pipe')"));
  const Result second = run("run " + small_pipe + " -q -o " + out.string());
  const std::string after = read_record(lock_of(out)); // still the first run's
  kill_and_wait(pid, lock_of(out));
  EXPECT_EQ(second.code, 2) << second.output;
  EXPECT_THAT(second.output, HasSubstr("error: the run's output folder '" + out.string() +
                                       "' is in use by another `tearflow run` (" + record +
                                       "); wait for it to end, or give this run another output "
                                       "folder"));
  EXPECT_EQ(count_matches(second.output, "error:"), 1) << second.output;
  EXPECT_EQ(after, record);
}

TEST(CliRunLock, AKilledRunsLockIsTakenOverSayingSo) {
  const fs::path out = fresh_dir("lock-killed");
  const int pid = start_long_run(out);
  const std::string record = wait_for_record(lock_of(out));
  ASSERT_FALSE(record.empty());
  kill_and_wait(pid, lock_of(out));
  // A killed holder cannot empty its record: that is how the next run tells a stale lock.
  EXPECT_EQ(read_record(lock_of(out)), record);
  const Result next = run("run " + small_pipe + " -q -o " + out.string());
  EXPECT_EQ(next.code, 0) << next.output;
  EXPECT_THAT(next.output, HasSubstr("'" + out.string() +
                                     "': took over the lock of a run that ended without "
                                     "releasing it (" +
                                     record + "): killed or crashed?"));
  EXPECT_EQ(count_matches(next.output, "took over"), 1) << next.output;
  EXPECT_EQ(read_record(lock_of(out)), ""); // and released at its own end
}

TEST(CliRunLock, ARunReleasesItsLockAtItsEndWellOrNot) {
  const fs::path out = fresh_dir("lock-released");
  const Result first = run("run " + small_pipe + " -q -o " + out.string());
  ASSERT_EQ(first.code, 0) << first.output;
  ASSERT_TRUE(fs::exists(lock_of(out)));
  EXPECT_EQ(read_record(lock_of(out)), ""); // a normal end empties the record
  // A run that stops with an error (PETSc refuses an option once the run holds the folder)
  // releases it too.
  const Result failed =
      run("run " + small_pipe + " -q -o " + out.string() + " -- -fluid_pc_type nonexistent_pc");
  EXPECT_NE(failed.code, 0) << failed.output;
  EXPECT_THAT(failed.output, HasSubstr("nonexistent_pc"));
  EXPECT_EQ(read_record(lock_of(out)), "");
  const Result next = run("run " + small_pipe + " -q -o " + out.string());
  EXPECT_EQ(next.code, 0) << next.output;
  EXPECT_THAT(next.output, testing::Not(HasSubstr("took over")));
}

TEST(CliRunLock, OnTwoRanksRankZeroDecidesForBothAndSaysItOnce) {
  const fs::path out = fresh_dir("lock-ranks");
  {
    // The folder held by this test process, as a running `tearflow run` holds it.
    const tearflow::io::OutputLock held(out, {tearflow::RunFiles::kLock, "tearflow run",
                                              "the run's output folder", "the lock test",
                                              "give this run another output folder"});
    const Result r = run("run " + small_pipe + " -q -o " + out.string(), "mpirun -n 2");
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_EQ(count_matches(r.output, "error: the run's output folder '" + out.string() +
                                          "' is in use by another `tearflow run` \\(pid " +
                                          std::to_string(::getpid()) + " on host "),
              1)
        << r.output;
    EXPECT_THAT(r.output, testing::Not(HasSubstr("MPI_ABORT")));
  }
  // A record left by a killed run: taken over, said once, and both ranks run. (Were the lock
  // taken on every rank, the second would find it held by the first and the run would stop.)
  std::ofstream(lock_of(out)) << "pid 999999 on host elsewhere, started then: a killed run\n";
  const Result r = run("run " + small_pipe + " -q -o " + out.string(), "mpirun -n 2");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(count_matches(r.output, "took over the lock of a run that ended without releasing "
                                    "it \\(pid 999999 on host elsewhere"),
            1)
      << r.output;
  EXPECT_EQ(read_record(lock_of(out)), "");
}
