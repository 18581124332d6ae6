// A sparse Cholesky factorisation for a matrix whose pattern is fixed and whose values change
// during a run (`fast` when its contacts change, `implicit`'s preconditioner): Eigen's
// SimplicialLLT with an AMD ordering, but the matrix is kept permuted (its upper triangle, the
// layout the factorisation reads), so that its values are set, and factorised, where they lie.
// SimplicialLLT::factorize permutes a copy of the whole matrix each time, an allocation the
// size of the matrix in a step, where drape's stepping allocates nothing.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

namespace drape {

class SparseCholesky {
 public:
  /// Orders the pattern of the symmetric matrix `a` (its lower triangle is read), keeps its
  /// values in the permuted layout and analyses the factor's pattern. Allocates.
  void analyse(const Eigen::SparseMatrix<double>& a);

  /// Where a's entry (row, col), or (col, row), lies in values(); −1 when not in the pattern.
  int64_t find(int32_t row, int32_t col) const;
  double* values() { return matrix_.valuePtr(); }
  int64_t nonzeros() const { return matrix_.nonZeros(); }

  /// Factorises the matrix as its values() are now. Returns false when it is not positive
  /// definite. Allocates nothing up to 16 384 rows (Eigen keeps its work rows on the stack up
  /// to EIGEN_STACK_ALLOCATION_LIMIT, 128 KB), three rows' worth above.
  bool factorise();
  bool ready() const { return ready_; }

  /// Solves L·Lᵀ·x = b in place, b and x in the permuted order: row permutation()[i] is a's
  /// row i. Allocates nothing.
  void solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const;
  /// The same for three right-hand sides at once, the rows of x (x, y and z of one unknown side
  /// by side): the factor is read once for the three, where three solves read it three times
  /// (`fast`, whose iterations are these solves). Allocates nothing.
  using Rows3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  void solve3_in_place(Rows3& x) const;
  const std::vector<int>& permutation() const { return permutation_; }

  /// From analyse(): the factor's entries (a solve reads each twice) and Σ over its columns of
  /// their entries squared (a factorisation's multiplications).
  int64_t entries() const { return entries_; }
  double factorise_work() const { return factorise_work_; }

  /// Heap bytes: the permuted matrix, the permutation and, once factorised, the factor.
  int64_t bytes() const;

 private:
  // Eigen's LLT on an already ordered upper triangle: its factorisation and column counts,
  // which SimplicialLLT keeps protected, reached from here.
  class Llt : public Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Upper,
                                          Eigen::NaturalOrdering<int>> {
   public:
    void factorise(const Eigen::SparseMatrix<double>& upper) { factorize_preordered<false>(upper); }
    const Eigen::VectorXi& column_entries() const { return m_nonZerosPerCol; }
    // L by columns, each column's diagonal first, then its rows below in increasing order.
    const Eigen::SparseMatrix<double>& factor() const { return m_matrix; }
  };

  Eigen::SparseMatrix<double> matrix_;  // the upper triangle of P·A·Pᵀ
  std::vector<int> permutation_;        // a's row → its row in matrix_
  Llt llt_;
  int64_t entries_ = 0;
  double factorise_work_ = 0.0;
  bool ready_ = false;
};

}  // namespace drape
