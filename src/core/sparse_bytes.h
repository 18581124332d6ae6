// Heap bytes of Eigen's sparse matrices and factorisations, for Solver::workspace_bytes.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>

namespace drape {

/// A compressed sparse matrix: a value and an index per non-zero, and the outer pointers.
inline int64_t sparse_bytes(const Eigen::SparseMatrix<double>& a) {
  return a.nonZeros() * int64_t{sizeof(double) + sizeof(int)} +
         (a.outerSize() + 1) * int64_t{sizeof(int)};
}

/// A simplicial Cholesky factorisation: its factor L and a few integers per unknown
/// (permutations, elimination tree).
template <class Factorisation>
int64_t factor_bytes(const Factorisation& llt) {
  const auto& factor = llt.matrixL().nestedExpression();
  return sparse_bytes(factor) + factor.outerSize() * 4 * int64_t{sizeof(int)};
}

}  // namespace drape
