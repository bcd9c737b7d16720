#pragma once
// A run's output folder is written by one `tearflow run` at a time (io/output_lock.hpp; the
// lock file RunFiles::kLock). Under MPI rank 0 alone takes the lock, as it alone writes the
// folder's files, and tells the other ranks the outcome, so that a refusal ends every rank
// together with one message.
#include <filesystem>
#include <memory>
#include <string>

#include <mpi.h>

#include "io/output_lock.hpp"

namespace tearflow::run {

/// Takes the lock of the run folder `folder` on rank 0 of `comm` (null elsewhere); collective.
/// `command`: the command line, recorded for the message of a run refused while this one
/// holds it. When another process holds it, every rank throws the same collective InputError
/// naming the folder and the holder (pid, host, start, command): said once, exit 2. A lock
/// left by a run that ended without releasing it (killed) is taken over, and rank 0 says so.
std::unique_ptr<io::OutputLock> hold_run_folder(const std::filesystem::path& folder,
                                                const std::string& command, MPI_Comm comm);

} // namespace tearflow::run
