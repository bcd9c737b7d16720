#include "io/output_lock.hpp"

#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::io {

namespace {

/// The file's text, its trailing newlines and spaces dropped.
std::string record_of(int fd) {
  char text[1024] = {};
  const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
  std::string s = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : "";
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  return s;
}

} // namespace

OutputLock::OutputLock(const std::filesystem::path& folder, const LockHolder& holder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec)
    input_error("cannot create directories '{}': {}", folder.string(), ec.message());
  const std::filesystem::path file = folder / holder.file_name;
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    input_error("cannot open the lock '{}': {}", file.string(), std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string who = record_of(fd_);
    ::close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK)
      input_error("cannot lock '{}': {}", file.string(), std::strerror(error));
    input_error("{} '{}' is in use by another `{}` ({}); wait for it to end, or {}", holder.noun,
                folder.string(), holder.program, who.empty() ? "holder unknown" : who,
                holder.advice);
  }
  // Ours now. A record left in the file is a holder's that ended without emptying it.
  taken_over_ = record_of(fd_);
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) != 0)
    std::strcpy(host, "unknown");
  const std::time_t t = std::time(nullptr);
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S", std::localtime(&t));
  const std::string me =
      fmt::format("pid {} on host {}, started {}: {}\n", ::getpid(), host, when, holder.command);
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, me.data(), me.size(), 0) < 0) {
    // The lock holds without the record; only a refused second one's message is poorer.
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0)
    return;
  if (::ftruncate(fd_, 0) != 0) {
    // The record stays: the next holder takes the lock all the same and reports this one as
    // ended without releasing it.
  }
  ::close(fd_); // releases the lock
}

} // namespace tearflow::io
