#include "sparse_cholesky.h"

#include <Eigen/OrderingMethods>
#include <algorithm>

#include "sparse_bytes.h"

namespace drape {

void SparseCholesky::analyse(const Eigen::SparseMatrix<double>& a) {
  ready_ = false;
  const Eigen::SparseMatrix<double> lower = a.triangularView<Eigen::Lower>();
  // AMD orders the symmetric pattern (it reads lower + lowerᵀ) and gives the inverse
  // permutation; P·A·Pᵀ moves a's row i to P.indices()[i].
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  Eigen::AMDOrdering<int>()(lower, inverse);
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p = inverse.inverse();
  permutation_.assign(p.indices().data(), p.indices().data() + p.size());

  // The upper triangle of P·A·Pᵀ, as SimplicialLLT::factorize makes it (the same entries in the
  // same order within each column, so the same bits as Eigen's own path).
  matrix_.resize(a.rows(), a.cols());
  matrix_.selfadjointView<Eigen::Upper>() = lower.selfadjointView<Eigen::Lower>().twistedBy(p);
  matrix_.makeCompressed();

  llt_.analyzePattern(matrix_);  // natural order: reads matrix_ as it is
  entries_ = 0;
  factorise_work_ = 0.0;
  for (int c = 0; c < matrix_.cols(); ++c) {
    const double below = llt_.column_entries()[c];  // below the diagonal
    entries_ += static_cast<int64_t>(below) + 1;
    factorise_work_ += (below + 1) * (below + 1);
  }
}

int64_t SparseCholesky::find(int32_t row, int32_t col) const {
  const int r = permutation_[row], c = permutation_[col];
  const int i = std::min(r, c), j = std::max(r, c);
  // A column's rows are in the order the permutation left them (unsorted): searched through.
  for (int k = matrix_.outerIndexPtr()[j]; k < matrix_.outerIndexPtr()[j + 1]; ++k)
    if (matrix_.innerIndexPtr()[k] == i) return k;
  return -1;
}

bool SparseCholesky::factorise() {
  llt_.factorise(matrix_);
  ready_ = llt_.info() == Eigen::Success;
  return ready_;
}

void SparseCholesky::solve_in_place(Eigen::Ref<Eigen::VectorXd> x) const {
  llt_.matrixL().solveInPlace(x);
  llt_.matrixU().solveInPlace(x);
}

void SparseCholesky::solve3_in_place(Rows3& x) const {
  const Eigen::SparseMatrix<double>& l = llt_.factor();
  const int* begin = l.outerIndexPtr();
  const int* row = l.innerIndexPtr();
  const double* value = l.valuePtr();
  const int n = static_cast<int>(l.cols());
  double* b = x.data();  // unknown i at b[3i], b[3i + 1], b[3i + 2]
  // L·y = b, column by column: y_j = b_j / L_jj, then b_i −= L_ij·y_j below it.
  for (int j = 0; j < n; ++j) {
    const double d = value[begin[j]];
    const double y0 = b[3 * j] / d, y1 = b[3 * j + 1] / d, y2 = b[3 * j + 2] / d;
    b[3 * j] = y0, b[3 * j + 1] = y1, b[3 * j + 2] = y2;
    for (int k = begin[j] + 1; k < begin[j + 1]; ++k) {
      double* bi = b + 3 * row[k];
      bi[0] -= y0 * value[k];
      bi[1] -= y1 * value[k];
      bi[2] -= y2 * value[k];
    }
  }
  // Lᵀ·x = y, last row first: x_j = (y_j − Σ_i L_ij·x_i) / L_jj over the rows i below j.
  for (int j = n - 1; j >= 0; --j) {
    double t0 = b[3 * j], t1 = b[3 * j + 1], t2 = b[3 * j + 2];
    for (int k = begin[j] + 1; k < begin[j + 1]; ++k) {
      const double* xi = b + 3 * row[k];
      t0 -= value[k] * xi[0];
      t1 -= value[k] * xi[1];
      t2 -= value[k] * xi[2];
    }
    const double d = value[begin[j]];
    b[3 * j] = t0 / d, b[3 * j + 1] = t1 / d, b[3 * j + 2] = t2 / d;
  }
}

int64_t SparseCholesky::bytes() const {
  return sparse_bytes(matrix_) + (ready_ ? factor_bytes(llt_) : 0) +
         static_cast<int64_t>(permutation_.capacity() * sizeof(int));
}

}  // namespace drape
