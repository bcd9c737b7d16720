#include "fem/element_inserter.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include <spdlog/spdlog.h>

namespace tearflow::fem {

namespace {
constexpr int kNodes = 4;

/// The diagonal and off-diagonal SeqAIJ blocks of an (MPI)AIJ matrix, or none for other
/// types; colmap maps off-diagonal columns to global ones.
bool aij_blocks(Mat A, Mat& diag, Mat& offdiag, const PetscInt*& colmap) {
  MatType type;
  TF_PETSC(MatGetType(A, &type));
  if (std::strcmp(type, MATSEQAIJ) == 0) {
    diag = A;
    offdiag = nullptr;
    colmap = nullptr;
    return true;
  }
  if (std::strcmp(type, MATMPIAIJ) == 0) {
    TF_PETSC(MatMPIAIJGetSeqAIJ(A, &diag, &offdiag, &colmap));
    return true;
  }
  return false;
}

struct Csr {
  PetscInt n = 0;
  const PetscInt *rows = nullptr, *cols = nullptr;
};
Csr get_csr(Mat M) {
  Csr c;
  PetscBool done;
  TF_PETSC(MatGetRowIJ(M, 0, PETSC_FALSE, PETSC_FALSE, &c.n, &c.rows, &c.cols, &done));
  if (!done)
    throw std::logic_error("MatGetRowIJ is not available for this matrix");
  return c;
}
void restore_csr(Mat M, Csr& c) {
  PetscBool done;
  TF_PETSC(MatRestoreRowIJ(M, 0, PETSC_FALSE, PETSC_FALSE, &c.n, &c.rows, &c.cols, &done));
}

/// Position of `col` in row `row` of c relative to the row's start, or -1.
std::int32_t find_in_row(const Csr& c, PetscInt row, PetscInt col) {
  const PetscInt *begin = c.cols + c.rows[row], *end = c.cols + c.rows[row + 1];
  const PetscInt* it = std::lower_bound(begin, end, col);
  return it != end && *it == col ? static_cast<std::int32_t>(it - begin) : -1;
}
} // namespace

ElementInserter::ElementInserter(const DofMap& dofs) : dofs_(dofs) {}

void ElementInserter::begin(Mat A, bool zero) {
  A_ = A;
  if (!recorded_ && A_ != nullptr) {
    PetscBool assembled;
    TF_PETSC(MatAssembled(A_, &assembled));
    if (assembled)
      record_offsets(); // the pattern is complete after the first pass
  }
  if (zero)
    TF_PETSC(MatZeroEntries(A_));
  direct_ = recorded_ && !offsets_.empty();
  if (!direct_)
    return;
  const PetscInt* colmap;
  aij_blocks(A_, diag_, offdiag_, colmap);
  Csr d = get_csr(diag_);
  diag_rows_ = d.rows;
  TF_PETSC(MatSeqAIJGetArray(diag_, &diag_values_));
  if (offdiag_ != nullptr) {
    Csr o = get_csr(offdiag_);
    offdiag_rows_ = o.rows;
    TF_PETSC(MatSeqAIJGetArray(offdiag_, &offdiag_values_));
  }
}

void ElementInserter::end() {
  if (!direct_)
    return;
  TF_PETSC(MatSeqAIJRestoreArray(diag_, &diag_values_));
  Csr d{0, diag_rows_, nullptr};
  restore_csr(diag_, d);
  if (offdiag_ != nullptr) {
    TF_PETSC(MatSeqAIJRestoreArray(offdiag_, &offdiag_values_));
    Csr o{0, offdiag_rows_, nullptr};
    restore_csr(offdiag_, o);
  }
  direct_ = false;
}

void ElementInserter::add(size_t e, const double* Ke) {
  const Tet& t = dofs_.mesh().tets()[e];
  const int bs = dofs_.block(), n = kNodes * bs;
  const Index owned = dofs_.mesh().num_owned();
  for (int a = 0; a < kNodes; ++a) {
    if (!direct_ || t[a] >= owned) {
      add_by_lookup(e, a, Ke);
      continue;
    }
    const std::int32_t* off = &offsets_[kNodes * kNodes * e + kNodes * a];
    for (int c = 0; c < bs; ++c) {
      const PetscInt row = static_cast<PetscInt>(bs) * t[a] + c;
      const double* Krow = Ke + static_cast<size_t>(bs * a + c) * n;
      for (int d = 0; d < kNodes; ++d) {
        PetscScalar* v = off[d] >= 0 ? diag_values_ + diag_rows_[row] + off[d]
                                     : offdiag_values_ + offdiag_rows_[row] + (-1 - off[d]);
        for (int k = 0; k < bs; ++k)
          v[k] += Krow[bs * d + k];
      }
    }
  }
}

void ElementInserter::add_by_lookup(size_t e, int a, const double* Ke) {
  const Tet& t = dofs_.mesh().tets()[e];
  const int bs = dofs_.block(), n = kNodes * bs;
  std::array<PetscInt, 8> rows;
  std::array<PetscInt, 4 * 8> cols;
  for (int c = 0; c < bs; ++c)
    rows[c] = dofs_.global_dof(t[a], c);
  for (int d = 0; d < kNodes; ++d)
    for (int k = 0; k < bs; ++k)
      cols[bs * d + k] = dofs_.global_dof(t[d], k);
  TF_PETSC(MatSetValues(A_, bs, rows.data(), n, cols.data(), Ke + static_cast<size_t>(bs * a) * n,
                        ADD_VALUES));
}

void ElementInserter::record_offsets() {
  recorded_ = true;
  Mat diag, offdiag;
  const PetscInt* colmap;
  if (!aij_blocks(A_, diag, offdiag, colmap)) {
    spdlog::debug("element insertion through MatSetValues: the matrix is not AIJ");
    return;
  }
  const int bs = dofs_.block();
  PetscInt col_start, col_end;
  TF_PETSC(MatGetOwnershipRangeColumn(A_, &col_start, &col_end));
  PetscInt n_colmap = 0;
  if (offdiag != nullptr)
    TF_PETSC(MatGetSize(offdiag, nullptr, &n_colmap));
  Csr d = get_csr(diag), o;
  if (offdiag != nullptr)
    o = get_csr(offdiag);

  const auto& tets = dofs_.mesh().tets();
  const Index owned = dofs_.mesh().num_owned();
  std::vector<std::int32_t> offsets(tets.size() * kNodes * kNodes, 0);
  bool uniform = true;
  for (size_t e = 0; e < tets.size() && uniform; ++e)
    for (int a = 0; a < kNodes && uniform; ++a) {
      if (tets[e][a] >= owned)
        continue;
      for (int dn = 0; dn < kNodes && uniform; ++dn) {
        const PetscInt gcol = dofs_.global_dof(tets[e][dn], 0);
        const bool in_diag = gcol >= col_start && gcol < col_end;
        PetscInt col = gcol - col_start;
        if (!in_diag) {
          const PetscInt* it = std::lower_bound(colmap, colmap + n_colmap, gcol);
          col = it - colmap;
        }
        // Every row of node a must hold the block's columns at the same offset.
        std::int32_t first = -1;
        for (int c = 0; c < bs && uniform; ++c) {
          const PetscInt row = static_cast<PetscInt>(bs) * tets[e][a] + c;
          const Csr& m = in_diag ? d : o;
          const std::int32_t pos = find_in_row(m, row, col);
          uniform =
              pos >= 0 && (c == 0 || pos == first) && pos + bs <= m.rows[row + 1] - m.rows[row];
          for (int k = 1; k < bs && uniform; ++k)
            uniform = m.cols[m.rows[row] + pos + k] == col + k;
          first = c == 0 ? pos : first;
        }
        offsets[kNodes * kNodes * e + kNodes * a + dn] = in_diag ? first : -1 - first;
      }
    }
  restore_csr(diag, d);
  if (offdiag != nullptr)
    restore_csr(offdiag, o);
  if (uniform)
    offsets_ = std::move(offsets);
  else
    spdlog::warn("element insertion through MatSetValues: the matrix pattern is not node-blocked");
}

} // namespace tearflow::fem
