#pragma once
// Thin RAII ownership of PETSc handles and error translation. PETSc stays visible: these
// hold a handle and destroy it, nothing more.
#include <string>
#include <utility>
#include <vector>

#include <petscksp.h>
#include <petscsnes.h>

#include "core/error.hpp"

namespace tearflow::fem {

/// PETSc's own words for an error code: its class and the message of the call that raised
/// it (e.g. "Invalid argument: Unknown type ..."), kept by PETSc under our silent handler.
std::string petsc_error_text(PetscErrorCode ierr);

/// Turns a PETSc error code into a SolverError naming the call.
inline void check(PetscErrorCode ierr, const char* what) {
  if (ierr != 0)
    throw SolverError(std::string("PETSc call failed: ") + what + " (" + petsc_error_text(ierr) +
                      ")");
}
#define TF_PETSC(call) ::tearflow::fem::check((call), #call)

template <typename Handle, PetscErrorCode (*Destroy)(Handle*)> class Owned {
public:
  Owned() = default;
  explicit Owned(Handle h) : h_(h) {}
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  Owned(Owned&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Owned& operator=(Owned&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  ~Owned() { reset(); }
  void reset() {
    if (h_)
      Destroy(&h_);
    h_ = nullptr;
  }
  Handle get() const { return h_; }
  Handle* out() { // for PETSc's XxxCreate(..., &h)
    reset();
    return &h_;
  }
  operator Handle() const { return h_; }

private:
  Handle h_ = nullptr;
};

using OwnedVec = Owned<Vec, VecDestroy>;
using OwnedMat = Owned<Mat, MatDestroy>;
using OwnedKSP = Owned<KSP, KSPDestroy>;
using OwnedSNES = Owned<SNES, SNESDestroy>;
using OwnedIS = Owned<IS, ISDestroy>;
using OwnedScatter = Owned<VecScatter, VecScatterDestroy>;

/// Read access to a Vec's local array for the scope of the object.
class ReadArray {
public:
  explicit ReadArray(Vec v) : v_(v) { TF_PETSC(VecGetArrayRead(v_, &a_)); }
  ~ReadArray() { VecRestoreArrayRead(v_, &a_); }
  ReadArray(const ReadArray&) = delete;
  ReadArray& operator=(const ReadArray&) = delete;
  const PetscScalar* data() const { return a_; }
  const PetscScalar& operator[](PetscInt i) const { return a_[i]; }

private:
  Vec v_;
  const PetscScalar* a_ = nullptr;
};

/// Write access to a Vec's local array for the scope of the object.
class WriteArray {
public:
  explicit WriteArray(Vec v) : v_(v) { TF_PETSC(VecGetArray(v_, &a_)); }
  ~WriteArray() { VecRestoreArray(v_, &a_); }
  WriteArray(const WriteArray&) = delete;
  WriteArray& operator=(const WriteArray&) = delete;
  PetscScalar* data() { return a_; }
  PetscScalar& operator[](PetscInt i) { return a_[i]; }

private:
  Vec v_;
  PetscScalar* a_ = nullptr;
};

/// PETSc (and MPI) initialised for the scope of the object; options from `args` are
/// inserted into PETSc's options database.
class PetscSession {
public:
  PetscSession(int* argc, char*** argv);
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;
};

/// PETSc options as (name, value) pairs, e.g. {"-fluid_ksp_rtol", "1e-2"}.
using OptionList = std::vector<std::pair<std::string, std::string>>;

/// Whether PETSc's (default) options database has `name` ("-solid_pc_type").
bool option_set(const std::string& name);

/// Enters each option into PETSc's database unless it is already there: our defaults give
/// way to whatever the case file or the command line set.
void set_default_options(const OptionList& options);

/// BoomerAMG as tuned for our 3D P1 blocks, under `prefix` (e.g. "-fluid_fieldsplit_1_"):
/// HMIS coarsening, ext+i interpolation, P_max 4, one level of aggressive coarsening, strong
/// threshold 0.5: cheaper setup and V-cycles than hypre's defaults at equal iteration counts
/// (pipe-fsi: 16.4 against 35 s/step, docs/performance.md).
OptionList boomeramg_3d_options(const std::string& prefix);

/// GMRES restarted every `restart` directions, with a second Gram-Schmidt pass where the
/// basis loses orthogonality (PETSc's default has none; options still override both).
void use_gmres(KSP ksp, PetscInt restart);

int mpi_rank(MPI_Comm comm = PETSC_COMM_WORLD);
int mpi_size(MPI_Comm comm = PETSC_COMM_WORLD);

} // namespace tearflow::fem
