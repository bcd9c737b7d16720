// A run killed (SIGKILL: no handler runs, no buffer is flushed) at arbitrary moments and
// restarted each time from its checkpoint:
//  - loses at most one checkpoint interval per kill (the restart's step against the steps
//    faces.csv held when the process died), and
//  - ends with the uninterrupted run's results, digit for digit (faces.csv as text).
// The moments are pseudo-random with a fixed seed (repeatable), spread over start-up, steps,
// frame and checkpoint writes.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_support.hpp"

namespace fs = std::filesystem;

namespace {

using tearflow::testing::fresh_dir;

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), {}};
}

/// Starts `tearflow ARGS` with its output in `log`; returns its pid.
pid_t start(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(TEARFLOW_BINARY)};
    for (const std::string& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(TEARFLOW_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

/// Kills the process `delay` after `trigger()` first holds (polled), unless it ended before.
/// Returns its exit code, or -1 if it was killed.
template <typename Trigger>
int kill_after(pid_t pid, Trigger trigger, std::chrono::duration<double, std::micro> delay) {
  int status = 0;
  auto ended = [&] { return waitpid(pid, &status, WNOHANG) == pid; };
  auto code = [&] { return WIFEXITED(status) ? WEXITSTATUS(status) : 128; };
  while (!trigger())
    if (ended())
      return code();
    else
      std::this_thread::sleep_for(std::chrono::microseconds(500));
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(delay);
  while (std::chrono::steady_clock::now() < until)
    if (ended())
      return code();
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1; // it may have ended just before
}

/// The last step faces.csv holds a whole row of every face for (-1 if none).
int last_whole_step(const fs::path& faces, int faces_per_step) {
  std::ifstream in(faces);
  std::string line;
  std::getline(in, line); // header
  int last = -1, count = 0, step = -1;
  while (std::getline(in, line)) {
    if (std::count(line.begin(), line.end(), ',') < 7)
      break; // a row cut short by the kill
    const int s = std::stoi(line.substr(0, line.find(',')));
    count = s == step ? count + 1 : 1;
    step = s;
    if (count == faces_per_step)
      last = s;
  }
  return last;
}

} // namespace

TEST(KilledRun, AtArbitraryMomentsLosesAtMostOneCheckpointIntervalAndRestartsIdentically) {
  // The RCR pipe (its outlet's 0D state is part of the checkpoint) over 3 cycles of 8 steps,
  // a checkpoint every 2 steps, a frame every 3.
  std::string text = read_text(tearflow::testing::test_data / "runs/small_pipe_rcr.yaml");
  text = std::regex_replace(text, std::regex("cycles: 2"), "cycles: 3");
  text = std::regex_replace(text, std::regex("output: \\{[^}]*\\}"),
                            "output: {every: 3, checkpoint_every: 2}");
  constexpr int interval = 2, faces = 3; // faces.csv: inlet, wall, outlet
  const fs::path file = fs::temp_directory_path() / "tearflow-test-killed.yaml";
  std::ofstream(file) << text;

  const fs::path full = fresh_dir("killed-reference"), dir = fresh_dir("killed");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(
      tearflow::testing::run_tearflow("run " + file.string() + " -q -o " + full.string()).code, 0);
  constexpr int steps = 24;
  const auto step_time =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0) /
      steps;

  // Six kills, each at a pseudo-random moment: in start-up (the mesh, the 0D start, reading
  // the checkpoint) or some way into a step after a random one had ended (its solve, its
  // rows, its frame, its checkpoint), as a fraction of a step's time on this machine now.
  std::mt19937 random(28);
  std::uniform_real_distribution<double> fraction(0.0, 1.0);
  const fs::path log = fs::temp_directory_path() / "tearflow-test-killed.log";
  int kills = 0, code = -1, restarts = 0;
  for (int attempt = 0; attempt < 40 && code != 0; ++attempt) {
    const bool restart = fs::exists(dir / "checkpoint.bin");
    std::vector<std::string> args{"run", file.string(), "-o", dir.string()};
    if (restart)
      args.push_back("--restart");
    else
      fs::remove_all(dir); // killed before its first checkpoint: start again
    // What the dead process had finished, against where its checkpoint lets it go on.
    const int done = restart ? last_whole_step(dir / "faces.csv", faces) : -1;
    const pid_t pid = start(args, log);
    if (kills == 6) {
      code = kill_after(
          pid, [] { return true; }, std::chrono::hours(1));
    } else if (fraction(random) < 0.25) { // in start-up
      code = kill_after(
          pid, [] { return true; }, step_time * (2.0 * fraction(random)));
    } else {
      const int after = std::max(done, 0) + 1 + static_cast<int>(fraction(random) * 4);
      code = kill_after(
          pid, [&] { return last_whole_step(dir / "faces.csv", faces) >= after; },
          step_time * fraction(random));
    }
    std::smatch m;
    const std::string out = read_text(log);
    if (restart && std::regex_search(out, m, std::regex("restarting from step (\\d+)"))) {
      EXPECT_LE(done - std::stoi(m[1]), interval) << "attempt " << attempt << ":\n" << out;
      ++restarts;
    }
    if (code == -1)
      ++kills;
    else
      ASSERT_EQ(code, 0) << read_text(log);
  }
  ASSERT_EQ(code, 0) << "not finished after 40 attempts";
  EXPECT_EQ(kills, 6);
  EXPECT_GE(restarts, 3); // the loss was measured at several restarts
  // Same binary, same state, same operations: the same digits.
  EXPECT_EQ(read_text(dir / "faces.csv"), read_text(full / "faces.csv"));
  EXPECT_EQ(read_text(dir / "cycles.json"), read_text(full / "cycles.json"));
}
