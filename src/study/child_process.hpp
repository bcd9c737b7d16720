#pragma once
// Running another program from tearflow (the study's stages run `tearflow geometry`, `tune`,
// `run` ... as child processes, under mpirun for several ranks). The child gets the
// environment this process was started with: MPI_Init of this process (a singleton) adds
// PMIx and Open MPI variables that would make a child `mpirun` attach to this process's
// runtime and silently start nothing.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace tearflow::study {

/// The environment as it was before main() (captured by a static initializer), "NAME=value".
const std::vector<std::string>& launch_environment();

/// Runs `argv` (argv[0] looked up in PATH) in `directory` with launch_environment(), calls
/// `on_line` with each line it writes to stdout or stderr, and returns its exit code (128 +
/// signal number when a signal ended it). InputError when it cannot be started.
int run_child(const std::vector<std::string>& argv, const std::filesystem::path& directory,
              const std::function<void(const std::string&)>& on_line);

/// This program's own executable (/proc/self/exe).
std::filesystem::path self_executable();

} // namespace tearflow::study
