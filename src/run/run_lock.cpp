#include "run/run_lock.hpp"

#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "fem/petsc.hpp"

namespace tearflow::run {

std::unique_ptr<io::OutputLock> hold_run_folder(const std::filesystem::path& folder,
                                                const std::string& command, MPI_Comm comm) {
  std::unique_ptr<io::OutputLock> lock;
  std::string refusal;
  if (fem::mpi_rank(comm) == 0) {
    try {
      lock = std::make_unique<io::OutputLock>(
          folder,
          io::LockHolder{RunFiles::kLock, "tearflow run", "the run's output folder", command,
                         "give this run another output folder (-o or the case's "
                         "output.directory)"});
    } catch (const InputError& e) {
      refusal = e.what();
    }
  }
  // Rank 0's outcome to all: the refusal's text, empty when the lock is held.
  int length = static_cast<int>(refusal.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, comm);
  refusal.resize(static_cast<std::size_t>(length));
  if (length > 0)
    MPI_Bcast(refusal.data(), length, MPI_CHAR, 0, comm);
  if (!refusal.empty())
    throw InputError(refusal, true);
  if (lock && !lock->taken_over().empty())
    spdlog::warn("'{}': took over the lock of a run that ended without releasing it ({}): "
                 "killed or crashed?",
                 folder.string(), lock->taken_over());
  return lock;
}

} // namespace tearflow::run
