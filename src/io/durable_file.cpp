#include "io/durable_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <unistd.h>

#include "core/error.hpp"

namespace tearflow::io {

namespace {

/// Writes and syncs; the reason of the first failure, or empty.
std::string write_synced(const std::filesystem::path& path, const std::string& bytes,
                         const char* mode) {
  std::FILE* out = std::fopen(path.c_str(), mode);
  if (out == nullptr)
    return std::strerror(errno);
  std::string reason;
  if (std::fwrite(bytes.data(), 1, bytes.size(), out) != bytes.size() || std::fflush(out) != 0 ||
      ::fsync(::fileno(out)) != 0)
    reason = std::strerror(errno);
  if (std::fclose(out) != 0 && reason.empty())
    reason = std::strerror(errno);
  return reason;
}

} // namespace

void write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  if (const std::string reason = write_synced(tmp, bytes, "wb"); !reason.empty()) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    input_error("cannot write '{}': {} (the previous version, if any, is kept)", path.string(),
                reason);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec)
    input_error("cannot write '{}': {}", path.string(), ec.message());
}

void append_to_file(const std::filesystem::path& path, const std::string& bytes) {
  if (const std::string reason = write_synced(path, bytes, "ab"); !reason.empty())
    input_error("cannot append to '{}': {}", path.string(), reason);
}

} // namespace tearflow::io
