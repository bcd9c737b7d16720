#pragma once
// Input that every rank reads for itself (the case's mesh, a checkpoint) fails on every rank
// alike, or, on a machine whose ranks see different files, on some. Either way the ranks
// agree before going on: a rank that failed alone would leave the others waiting in the next
// collective call, and the program would end them with MPI_Abort's banner after printing the
// error once per rank (issue 62, part 3). So the reading function runs on every rank, the
// ranks then learn whether any failed, and all throw the lowest failing rank's error as a
// collective InputError, which the program prints once and exits 2 with.
//
// The function itself must make no collective call.
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include <mpi.h>

#include "core/error.hpp"

namespace tearflow::fem {

/// The message of the lowest rank whose `failed` is set, on every rank; empty if none.
std::string first_failure(MPI_Comm comm, const std::string& message, bool failed);

/// read() on every rank of comm; an InputError on any rank is thrown on all (file comment).
template <typename Read> auto alike_on_every_rank(MPI_Comm comm, Read&& read) {
  std::optional<std::invoke_result_t<Read>> value;
  std::string message;
  try {
    value.emplace(read());
  } catch (const InputError& e) {
    message = e.what();
  }
  if (std::string first = first_failure(comm, message, !value); !first.empty())
    throw InputError(first, true);
  return std::move(*value);
}

} // namespace tearflow::fem
