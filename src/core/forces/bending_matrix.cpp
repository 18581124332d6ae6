#include "forces/bending_matrix.h"

#include <algorithm>
#include <numeric>

#include "fnv.h"
#include "parallel.h"

namespace drape::forces {

namespace {

// Identifies what the matrices are built from: the particles, each element's corners, weights,
// stiffness and damping (their bits).
uint64_t elements_key(const ClothModel& model) {
  Fnv1a hash;
  hash.mix(static_cast<uint64_t>(model.size()));
  hash.mix(model.bending.size());
  for (const BendingElement& b : model.bending) {
    for (int p = 0; p < 4; ++p) hash.mix(uint32_t(b.v[p])), hash.mix_bits(b.w[p]);
    hash.mix_bits(b.stiffness), hash.mix_bits(b.damping);
  }
  return hash.key;
}

}  // namespace

void BendingMatrix::prepare(const ClothModel& model) {
  const uint64_t key = elements_key(model);
  if (key == key_) return;
  *this = BendingMatrix();
  key_ = key;
  if (model.bending.empty()) return;
  const int32_t n = model.size();
  // Each element adds k·w_p·w_q (and d·w_p·w_q) to entry (v_p, v_q) for its 16 pairs of corners:
  // first every addition, row by row in the elements' order...
  std::vector<int32_t> start(n + 1, 0);
  for (const BendingElement& b : model.bending)
    for (int p = 0; p < 4; ++p) start[b.v[p] + 1] += 4;
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int32_t> fill(start.begin(), start.end() - 1), cols(start[n]);
  std::vector<double> ks(start[n]), ds(start[n]);
  for (const BendingElement& b : model.bending)
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q) {
        const int32_t at = fill[b.v[p]]++;
        const double ww = b.w[p] * b.w[q];  // so that (p, q) and (q, p) are the same bits
        cols[at] = b.v[q];
        ks[at] = b.stiffness * ww;
        ds[at] = b.damping * ww;
      }
  // ... then each row's additions to one column summed, in that order, the columns ascending.
  row_begin_.assign(n + 1, 0);
  diagonal_.assign(n, -1);
  std::vector<int32_t> order;
  for (int32_t i = 0; i < n; ++i) {
    order.resize(start[i + 1] - start[i]);
    std::iota(order.begin(), order.end(), start[i]);
    std::stable_sort(order.begin(), order.end(),
                     [&](int32_t a, int32_t b) { return cols[a] < cols[b]; });
    for (size_t k = 0; k < order.size(); ++k) {
      const int32_t at = order[k];
      if (k == 0 || cols[at] != col_.back()) {
        if (cols[at] == i) diagonal_[i] = static_cast<int32_t>(col_.size());
        col_.push_back(cols[at]);
        k_.push_back(0.0);
        d_.push_back(0.0);
      }
      k_.back() += ks[at];
      d_.back() += ds[at];
    }
    row_begin_[i + 1] = static_cast<int32_t>(col_.size());
  }
  combined_.assign(k_.size(), 0.0);  // combine() fills it, allocating nothing in a step
}

void BendingMatrix::combine(double a, double b) {
  if (a == a_ && b == b_) return;
  a_ = a;
  b_ = b;
  const int64_t entries = static_cast<int64_t>(k_.size());
#pragma omp parallel for schedule(static) if (worth_threads(entries))
  for (int64_t k = 0; k < entries; ++k) combined_[k] = a * k_[k] + b * d_[k];
}

int64_t BendingMatrix::bytes() const {
  return heap_bytes(row_begin_, col_, diagonal_, k_, d_, combined_);
}

}  // namespace drape::forces
