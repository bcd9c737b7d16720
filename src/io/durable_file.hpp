#pragma once
// Writing files so that nothing is lost: every write is checked through the buffer's flush,
// fsync and close (a full disk often shows only there), a failure is an InputError naming
// the file and the system's reason, and a replaced file is replaced whole or not at all.
#include <filesystem>
#include <string>

namespace tearflow::io {

/// Writes `bytes` to `path` through `path`.tmp and a rename: readers see the old file or the
/// new one, never a part; on failure the old file stays and the temporary one is removed.
void write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

/// Appends `bytes` to `path` (created if missing) and flushes them to disk.
void append_to_file(const std::filesystem::path& path, const std::string& bytes);

} // namespace tearflow::io
