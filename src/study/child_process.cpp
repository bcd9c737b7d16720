#include "study/child_process.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/error.hpp"

extern char** environ;

namespace tearflow::study {

namespace {

std::vector<std::string> snapshot_environment() {
  std::vector<std::string> out;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e)
    out.emplace_back(*e);
  return out;
}

// Static initialization runs before main() and so before MPI_Init.
const std::vector<std::string> kLaunchEnvironment = snapshot_environment();

} // namespace

const std::vector<std::string>& launch_environment() {
  return kLaunchEnvironment;
}

std::filesystem::path self_executable() {
  // A rebuild while a study runs replaces the file: the link then reads "PATH (deleted)",
  // and the new program at PATH runs the remaining stages.
  std::string path = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string deleted = " (deleted)";
  if (path.ends_with(deleted))
    path.erase(path.size() - deleted.size());
  return path;
}

int run_child(const std::vector<std::string>& argv, const std::filesystem::path& directory,
              const std::function<void(const std::string&)>& on_line) {
  int fds[2];
  if (pipe(fds) != 0)
    input_error("cannot create a pipe for '{}': {}", argv.front(), std::strerror(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  // The child starts in `directory` (a GNU extension of posix_spawn, glibc >= 2.29).
  posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
  std::vector<char*> args, env;
  for (const std::string& a : argv)
    args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> environment = launch_environment();
  // Open MPI's mpirun refuses to start as root unless told to; a study started as root (a
  // container, CI) means its stages to run as root too.
  if (geteuid() == 0)
    for (const char* allow : {"OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"}) {
      const std::string name = std::string(allow).substr(0, std::string(allow).find('=') + 1);
      if (std::none_of(environment.begin(), environment.end(),
                       [&](const std::string& e) { return e.rfind(name, 0) == 0; }))
        environment.emplace_back(allow);
    }
  for (const std::string& e : environment)
    env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);
  pid_t pid = 0;
  const int spawned =
      posix_spawnp(&pid, argv.front().c_str(), &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (spawned != 0) {
    close(fds[0]);
    input_error("cannot start '{}': {}", argv.front(), std::strerror(spawned));
  }
  std::string pending;
  char buffer[4096];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR)
        continue;
      break;
    }
    pending.append(buffer, static_cast<std::size_t>(n));
    for (std::size_t end; (end = pending.find('\n')) != std::string::npos;) {
      on_line(pending.substr(0, end));
      pending.erase(0, end + 1);
    }
  }
  if (!pending.empty())
    on_line(pending);
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    return 128 + WTERMSIG(status);
  return WEXITSTATUS(status);
}

} // namespace tearflow::study
