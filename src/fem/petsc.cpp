#include "fem/petsc.hpp"

namespace tearflow::fem {

PetscSession::PetscSession(int* argc, char*** argv) {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized)
    TF_PETSC(PetscInitialize(argc, argv, nullptr, nullptr));
  // Our own messages explain failures; PETSc's traceback on stderr would only repeat them.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
}

PetscSession::~PetscSession() {
  PetscFinalize();
}

int mpi_rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

int mpi_size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

} // namespace tearflow::fem
