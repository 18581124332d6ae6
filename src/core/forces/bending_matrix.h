// A model's bending elements as two constant sparse matrices over its particles,
//   K = Σ_e k_e·w_e·w_eᵀ,   D = Σ_e d_e·w_e·w_eᵀ   (each ⊗ I₃),
// so that the elements' force on particle i is −Σ_j (K_ij·x_j + D_ij·v_j) (forces/bending.h).
// Stored row by row (one pattern for both): a product with them is a loop over the particles
// whose rows are independent, shared out to threads, each row's sum in a fixed order, so its
// bits do not depend on the thread count. The loop over the elements instead scatters into four
// particles per element, which the springs' colours do not separate, and ran on one thread: on
// 128² denim over the sphere `implicit`'s conjugate gradients spent most of their time in it
// while the other thread waited.
#pragma once

#include <cstdint>
#include <vector>

#include "drape/cloth.h"

namespace drape::forces {

class BendingMatrix {
 public:
  /// Builds K and D from the model's elements; does nothing when the elements (corners,
  /// weights, stiffness and damping) are those it was built from. Empty without elements.
  void prepare(const ClothModel& model);
  bool empty() const { return col_.empty(); }

  /// Calls visit(j, K_ij, D_ij) for each entry of row i, in the row's fixed order.
  template <class Visit>
  void for_row(int32_t i, Visit&& visit) const {
    for (int32_t k = row_begin_[i]; k < row_begin_[i + 1]; ++k) visit(col_[k], k_[k], d_[k]);
  }

  /// Σ_j K_ij·x_j + D_ij·v_j: the negative of the elements' force on particle i (N).
  Vec3 force_row(int32_t i, const std::vector<Vec3>& x, const std::vector<Vec3>& v) const {
    Vec3 sum = Vec3::Zero();
    for_row(i, [&](int32_t j, double k, double d) { sum += k * x[j] + d * v[j]; });
    return sum;
  }

  /// Sets the weights of the combination a·K + b·D that combined_row multiplies by
  /// (`implicit`'s system: a = h², b = h); recomputes it only when they change.
  void combine(double a, double b);
  /// Σ_j (a·K_ij + b·D_ij)·p_j with combine()'s a and b.
  Vec3 combined_row(int32_t i, const std::vector<Vec3>& p) const {
    // Two sums, the row's entries taken in pairs, so that the additions do not all wait for
    // the one before (this product is most of `implicit`'s time on a material's cloth).
    Vec3 even = Vec3::Zero(), odd = Vec3::Zero();
    int32_t k = row_begin_[i];
    const int32_t end = row_begin_[i + 1];
    for (; k + 1 < end; k += 2) {
      even += combined_[k] * p[col_[k]];
      odd += combined_[k + 1] * p[col_[k + 1]];
    }
    if (k < end) even += combined_[k] * p[col_[k]];
    return even + odd;
  }
  /// a·K_ii + b·D_ii with combine()'s a and b.
  double combined_diagonal(int32_t i) const {
    return diagonal_[i] >= 0 ? combined_[diagonal_[i]] : 0.0;
  }

  int64_t bytes() const;

 private:
  uint64_t key_ = 0;  // of the elements the matrices were built from
  std::vector<int32_t> row_begin_, col_;
  std::vector<int32_t> diagonal_;  // per row: the entry of its diagonal, −1 when it has none
  std::vector<double> k_, d_, combined_;
  double a_ = 0.0, b_ = 0.0;  // of combined_ (0, 0 as prepared: all zero)
};

}  // namespace drape::forces
