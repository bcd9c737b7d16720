#include "fem/alike_on_every_rank.hpp"

namespace tearflow::fem {

std::string first_failure(MPI_Comm comm, const std::string& message, bool failed) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int first = failed ? rank : size;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size)
    return {};
  int length = rank == first ? static_cast<int>(message.size()) : 0;
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  std::string text = rank == first ? message : std::string(static_cast<size_t>(length), ' ');
  MPI_Bcast(text.data(), length, MPI_CHAR, first, comm);
  // An empty message from a failing rank still reports a failure.
  return text.empty() ? std::string("an input error on rank ") + std::to_string(first) : text;
}

} // namespace tearflow::fem
