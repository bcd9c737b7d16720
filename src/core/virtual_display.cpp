#include "core/virtual_display.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <X11/Xlib.h>

#include "core/error.hpp"

extern char** environ;

namespace tearflow {

namespace {

// Xvfb answers within a second on an idle machine; a loaded one (a build on every core) was
// seen to need several. Past this it is not coming.
constexpr int kStartTimeoutMs = 30000;

/// The server this process started; terminated when the process exits (static destruction).
struct OwnServer {
  pid_t pid = -1;
  std::string display;
  Display* held = nullptr; ///< a connection kept open for the server's life (no reset)
  void stop() {
    if (held != nullptr)
      XCloseDisplay(held), held = nullptr;
    if (pid <= 0)
      return;
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    pid = -1;
  }
  ~OwnServer() { stop(); }
};

/// A connection to `display`, retrying for a second; null when refused. Xvfb names its
/// display once it listens; the connection is then held open, so that the server never
/// finds itself without clients between two pictures (with -noreset, a second guard).
Display* connect_to(const std::string& display) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    if (Display* d = XOpenDisplay(display.c_str()))
      return d;
    usleep(50000);
  }
  return nullptr;
}

std::filesystem::path find_in_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::filesystem::path candidate =
        std::filesystem::path(dir.empty() ? "." : dir) / program;
    if (access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return {};
}

/// Starts Xvfb and returns its display number, read from the pipe it writes it to.
void start_xvfb(OwnServer& server, const std::string& purpose) {
  // TEARFLOW_XVFB names the server where it is not in PATH (and lets the tests take it away).
  const char* chosen = std::getenv("TEARFLOW_XVFB");
  const bool given = chosen != nullptr && *chosen != '\0';
  const std::filesystem::path xvfb =
      given ? (access(chosen, X_OK) == 0 ? std::filesystem::path(chosen) : std::filesystem::path())
            : find_in_path("Xvfb");
  if (xvfb.empty())
    input_error("{}: no X display (DISPLAY is not set) and no Xvfb {} to start one; install it "
                "(Debian: apt-get install xvfb) or run under an X server",
                purpose, given ? fmt::format("at '{}' (TEARFLOW_XVFB)", chosen) : "in PATH");
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    input_error("{}: cannot start Xvfb: pipe: {}", purpose, std::strerror(errno));
  // The child's end of the pipe becomes its descriptor 3, passed to -displayfd.
  // -noreset: an X server resets when its last client leaves, and refuses connections while
  // it does; every picture's window is a client of its own, so the next one could arrive
  // mid-reset and VTK aborts ("bad X server connection"): seen in a study's pictures stage.
  std::string args[] = {"Xvfb",         "-displayfd", "3",   "-screen", "0",
                        "1600x1200x24", "-nolisten",  "tcp", "-noreset"};
  char* argv[std::size(args) + 1];
  for (std::size_t i = 0; i < std::size(args); ++i)
    argv[i] = args[i].data();
  argv[std::size(args)] = nullptr;
  const std::string program = xvfb.string();
  const pid_t parent = getpid();
  // fork, not posix_spawn: the server must hold none of this process's descriptors but the
  // pipe (an inherited one, such as the MPI daemon's liveness pipe or a caller's stdout pipe,
  // outlives us in the server and keeps a reader waiting for EOF: a test blocked on the
  // output of `tearflow pictures` that way), and it must die with this process even when a
  // signal ends it (PR_SET_PDEATHSIG), which no destructor covers. Between fork and exec only
  // async-signal-safe calls.
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) // the parent ended before the line above
      _exit(127);
    if (fds[1] != 3)
      dup2(fds[1], 3);
    fcntl(3, F_SETFD, 0); // keep it across exec
    const int null = open("/dev/null", O_RDWR);
    // Xvfb's own start-up chatter (fonts, extensions) is not ours to show.
    for (int fd = 0; fd < 3; ++fd)
      dup2(null, fd);
    close_range(4, ~0U, 0);
    execve(program.c_str(), argv, environ);
    _exit(127);
  }
  close(fds[1]);
  if (pid < 0) {
    close(fds[0]);
    input_error("{}: cannot start '{}': {}", purpose, program, std::strerror(errno));
  }
  server.pid = pid;
  // Xvfb writes the display number and a newline once it accepts connections.
  std::string number;
  pollfd p{fds[0], POLLIN, 0};
  while (number.find('\n') == std::string::npos) {
    const int ready = poll(&p, 1, kStartTimeoutMs);
    if (ready < 0 && errno == EINTR)
      continue;
    char buffer[32];
    const ssize_t n = ready > 0 ? read(fds[0], buffer, sizeof buffer) : 0;
    if (n <= 0)
      break;
    number.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  const std::size_t end = number.find('\n');
  if (end == std::string::npos || end == 0) {
    int status = 0;
    const bool exited = waitpid(pid, &status, WNOHANG) == pid;
    if (!exited) {
      kill(pid, SIGTERM);
      waitpid(pid, &status, 0);
    }
    server.pid = -1;
    input_error("{}: no X display (DISPLAY is not set) and the virtual X server '{}' {}", purpose,
                xvfb.string(),
                exited ? fmt::format("exited (status {}) before naming its display", status)
                       : fmt::format("named no display within {} s", kStartTimeoutMs / 1000));
  }
  server.display = fmt::format(":{}", number.substr(0, end));
}

} // namespace

std::string ensure_display(const std::string& purpose) {
  static std::mutex mutex;
  static OwnServer server;
  const std::lock_guard lock(mutex);
  if (server.pid > 0)
    return server.display;
  if (const char* display = std::getenv("DISPLAY"); display != nullptr && *display != '\0')
    return display;
  // A server that names its display but refuses clients is replaced (twice at most).
  for (int start = 0; start < 3; ++start) {
    start_xvfb(server, purpose);
    server.held = connect_to(server.display);
    if (server.held != nullptr) {
      setenv("DISPLAY", server.display.c_str(), 1);
      return server.display;
    }
    server.stop();
  }
  input_error("{}: no X display (DISPLAY is not set) and three virtual X servers started here "
              "refused every connection",
              purpose);
}

} // namespace tearflow
