#pragma once
// Running the `tearflow` program (and other programs) from tests: its exit code and output,
// and fresh output directories under the system's temporary folder.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

namespace tearflow::testing {

struct Result {
  int code;
  std::string output; // stdout and stderr
};

/// Runs the shell command `cmd`, its standard error with its output.
inline Result run_command(const std::string& cmd) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p))
    out.append(buf, n);
  const int status = pclose(p);
  return {WEXITSTATUS(status), out};
}

/// Runs `tearflow ARGS`, optionally under a launcher such as "mpirun -n 2".
inline Result run_tearflow(const std::string& args, const std::string& launcher = "") {
  return run_command(launcher + " " + TEARFLOW_BINARY + " " + args);
}

/// An empty directory path `<tmp>/tearflow-test-<name>` (removed if it existed). ctest runs
/// tests in parallel (-j 2): every test needs names of its own.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("tearflow-test-" + name);
  std::filesystem::remove_all(d);
  return d;
}

/// A JSON file the program wrote.
inline nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

inline const std::filesystem::path test_data =
    std::filesystem::path(TEARFLOW_SOURCE_DIR) / "tests/data";

/// A small tmpfs mounted at `dir` while alive (the tests run as root on this machine; where
/// they cannot mount, `mounted` is false and the test is skipped).
struct SmallFileSystem {
  std::string dir;
  bool mounted = false;
  SmallFileSystem(const std::filesystem::path& at, const std::string& options) : dir(at.string()) {
    std::filesystem::create_directories(at);
    mounted = std::system(
                  ("mount -t tmpfs -o " + options + " tmpfs " + dir + " 2>/dev/null").c_str()) == 0;
  }
  ~SmallFileSystem() {
    if (mounted && std::system(("umount " + dir).c_str()) != 0)
      ADD_FAILURE() << "could not unmount " << dir;
  }
};

} // namespace tearflow::testing
