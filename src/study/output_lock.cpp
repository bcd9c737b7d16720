#include "study/output_lock.hpp"

#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::study {

OutputLock::OutputLock(const std::filesystem::path& folder) {
  const std::filesystem::path file = folder / ".study.lock";
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    input_error("cannot open the study's lock '{}': {}", file.string(), std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    char holder[256] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
    ::close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK)
      input_error("cannot lock '{}': {}", file.string(), std::strerror(error));
    std::string who = n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : "";
    while (!who.empty() && (who.back() == '\n' || who.back() == ' '))
      who.pop_back();
    input_error("the study's output '{}' is in use by another `tearflow study` ({}); wait for "
                "it to end, or give this study another `output`",
                folder.string(), who.empty() ? "holder unknown" : who);
  }
  const std::time_t t = std::time(nullptr);
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  const std::string me = fmt::format("pid {}, started {}\n", ::getpid(), when);
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, me.data(), me.size(), 0) < 0) {
    // The lock holds without the note; only a refused second study's message is poorer.
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0)
    ::close(fd_); // releases the lock
}

} // namespace tearflow::study
