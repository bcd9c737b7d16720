#pragma once
// Adds element matrices of P1 tetrahedra (4 nodes x `block` unknowns, row-major) into an
// assembled AIJ matrix whose nonzero pattern is fixed: the pattern DofMap preallocates.
//
// Why: MatSetValues looks up every one of an element's (4 block)^2 entries by a search in
// its row; on the fluid Jacobian that cost five times the element kernel. All rows of one
// node have the same columns (the nodes it shares a tet with, `block` consecutive dofs
// each), so the first pass, through MatSetValues, records per element and node pair (a, d)
// where node d's columns start in the rows of node a; later passes add the 4 x block x
// block values by direct indexing into the CSR value arrays. Rows of ghost nodes belong to
// other ranks and still go through MatSetValues (PETSc's stash), a small fraction.
//
// Every row is assembled, Dirichlet rows included; the caller replaces those afterwards
// (MatZeroRows keeps the pattern: the matrix is set to MAT_KEEP_NONZERO_PATTERN).
#include <cstdint>
#include <vector>

#include "fem/dof_map.hpp"

namespace tearflow::fem {

class ElementInserter {
public:
  explicit ElementInserter(const DofMap& dofs);

  /// Zeroes A (unless `zero` is false: a second physics adding into the same pass) and
  /// prepares the insertion of this pass.
  void begin(Mat A, bool zero = true);
  /// Adds the element matrix Ke ((4 block) x (4 block), row-major, node-major dofs) of
  /// local tet e.
  void add(size_t e, const double* Ke);
  /// Ends the element pass (A may then take MatSetValues before its assembly).
  void end();

  bool direct() const { return direct_; } ///< false during the first, recording pass

private:
  void record_offsets(); ///< after the first assembly: the per-element column offsets
  void add_by_lookup(size_t e, int a, const double* Ke);

  const DofMap& dofs_;
  Mat A_ = nullptr;
  bool direct_ = false, recorded_ = false;
  // Per local tet and node pair (a, d): offset of node d's first column within node a's
  // rows, in the diagonal block (>= 0) or the off-diagonal block (-1 - offset).
  std::vector<std::int32_t> offsets_;
  Mat diag_ = nullptr, offdiag_ = nullptr;
  const PetscInt *diag_rows_ = nullptr, *offdiag_rows_ = nullptr;
  PetscScalar *diag_values_ = nullptr, *offdiag_values_ = nullptr;
};

} // namespace tearflow::fem
