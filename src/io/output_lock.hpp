#pragma once
// One process writing an output folder at a time: two `tearflow run`s (or studies) into one
// folder would interleave their frames, records and checkpoints, and each would report the
// other's files as its own. The lock is an advisory flock(2) on a file in the folder, held
// while the object lives and released by the kernel when the process ends however it ends, so
// a killed holder never blocks the folder. The file records its holder (pid, host, start,
// command) for the message of the one refused. A holder that ends normally empties the
// record; a record found on taking the lock is that of a holder that ended without releasing
// it (killed, crashed, aborted), and the taker says so (taken_over()).
#include <filesystem>
#include <string>

namespace tearflow::io {

/// Who takes a lock: for its record and its messages.
struct LockHolder {
  std::string file_name; ///< the lock file in the folder, e.g. ".run.lock"
  std::string program;   ///< "tearflow run": a refusal names "another `tearflow run`"
  std::string noun;      ///< "the run's output": how messages name the folder
  std::string command;   ///< recorded: the command line that holds it
  std::string advice;    ///< after "wait for it to end, or ", in a refusal
};

class OutputLock {
public:
  /// Takes the lock of `folder` (made if missing). InputError naming the folder and the
  /// holder's record when another process holds it, or naming the folder and the system's
  /// reason when it cannot be made or locked.
  OutputLock(const std::filesystem::path& folder, const LockHolder& holder);
  /// Empties the record (a normal end) and releases the lock.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  /// The record of an earlier holder that ended without releasing the lock (this one took
  /// it over); empty when the lock was free.
  const std::string& taken_over() const { return taken_over_; }

private:
  int fd_ = -1;
  std::string taken_over_;
};

} // namespace tearflow::io
