#include "forces/bending_damping.h"

#include <map>

#include "drape/error.h"
#include "sparse_bytes.h"

namespace drape::forces {

void BendingDamping::prepare(const ClothModel& model, const std::vector<uint8_t>& pinned,
                             double dt) {
  bool damped = false;
  for (const BendingElement& b : model.bending) damped = damped || b.damping > 0.0;
  if (!damped || !(dt > 0.0)) {  // nothing to solve: keep nothing (no copies for the check)
    *this = BendingDamping();
    dt_ = dt;
    return;
  }
  std::vector<double> dampings(model.bending.size());
  for (size_t e = 0; e < model.bending.size(); ++e) dampings[e] = model.bending[e].damping;
  if (dt == dt_ && pinned == pinned_ && model.mass == masses_ && dampings == dampings_) return;
  pinned_ = pinned;
  masses_ = model.mass;
  dampings_ = std::move(dampings);
  const int32_t n = model.size();
  dt_ = dt;
  rows_ = 0;
  row_.assign(n, -1);
  row_mass_.clear();
  couplings_.clear();
  for (int32_t p = 0; p < n; ++p)
    if (!pinned[p]) {
      row_[p] = rows_++;
      row_mass_.push_back(model.mass[p]);
    }
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(rows_ + 16 * model.bending.size());
  for (int32_t r = 0; r < rows_; ++r) entries.emplace_back(r, r, row_mass_[r]);
  std::map<std::pair<int32_t, int32_t>, double> coupled;
  for (const BendingElement& b : model.bending) {
    if (!(b.damping > 0.0)) continue;
    for (int k = 0; k < 4; ++k) {
      const int32_t r = row_[b.v[k]];
      if (r < 0) continue;
      for (int l = 0; l < 4; ++l) {
        const double weight = dt * b.damping * b.w[k] * b.w[l];
        const int32_t c = row_[b.v[l]];
        if (c >= 0)
          entries.emplace_back(r, c, weight);
        else
          coupled[{r, b.v[l]}] += weight;
      }
    }
  }
  for (const auto& [key, weight] : coupled) couplings_.push_back({key.first, key.second, weight});
  Eigen::SparseMatrix<double> a(rows_, rows_);  // M + dt·D over the free particles
  a.setFromTriplets(entries.begin(), entries.end());
  llt_ = std::make_unique<Factor>(a);
  // M + dt·D is M (positive) plus a positive semidefinite sum: only a broken model fails here.
  if (llt_->info() != Eigen::Success)
    throw InputError("cloth.material", "bending damping: the system could not be factorised");
  rhs_.resize(rows_, 3);
  solution_.resize(rows_, 3);
}

void BendingDamping::solve(int d) {
  // A⁻¹ = Pᵀ·L⁻ᵀ·L⁻¹·P by hand, through solution_'s column: Eigen's solve() allocates for its
  // permutations.
  const int* p = llt_->permutationP().indices().data();
  auto y = solution_.col(d);
  for (int32_t i = 0; i < rows_; ++i) y(p[i]) = rhs_(i, d);  // y = P·b
  llt_->matrixL().solveInPlace(y);
  llt_->matrixU().solveInPlace(y);
  for (int32_t i = 0; i < rows_; ++i) rhs_(i, d) = y(p[i]);  // x = Pᵀ·y
}

int64_t BendingDamping::bytes() const {
  return heap_bytes(row_, row_mass_, couplings_, pinned_, masses_, dampings_) +
         (llt_ ? factor_bytes(*llt_) : 0) +
         static_cast<int64_t>(rhs_.size() + solution_.size()) * int64_t{sizeof(double)};
}

}  // namespace drape::forces
