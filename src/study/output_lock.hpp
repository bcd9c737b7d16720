#pragma once
// One `tearflow study` per output folder: two at once would run the same stages into the
// same files. The lock is an advisory flock(2) on OUTPUT/.study.lock, held while the object
// lives and released by the kernel when the process ends however it ends (no stale lock
// after a kill); the file names its holder for the message of the one refused.
#include <filesystem>

namespace tearflow::study {

class OutputLock {
public:
  /// Takes the lock; InputError naming the folder and the holder (pid, start) when another
  /// process has it.
  explicit OutputLock(const std::filesystem::path& folder);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

private:
  int fd_ = -1;
};

} // namespace tearflow::study
