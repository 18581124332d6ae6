#include "system_factor.h"

#include <algorithm>

namespace drape {

namespace {

// The six pairs of a bending element's four corners.
constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

}  // namespace

void SystemFactor::prepare(const ClothModel& model) {
  const int32_t n = model.size();
  const int32_t rows = 3 * n;
  // The pattern: every entry of each block in the lower triangle, as zeros.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(6 * static_cast<size_t>(n) +
                  9 * (model.springs.size() + 6 * model.bending.size()));
  auto pattern = [&](int32_t p, int32_t q) {  // the block of particles p ≥ q
    for (int c = 0; c < 3; ++c)
      for (int r = (p == q ? c : 0); r < 3; ++r) entries.emplace_back(3 * p + r, 3 * q + c, 0.0);
  };
  for (int32_t i = 0; i < n; ++i) pattern(i, i);
  for (const Spring& s : model.springs) pattern(std::max(s.i, s.j), std::min(s.i, s.j));
  for (const BendingElement& b : model.bending)
    for (const auto& pair : kPairs)
      pattern(std::max(b.v[pair[0]], b.v[pair[1]]), std::min(b.v[pair[0]], b.v[pair[1]]));
  {
    Eigen::SparseMatrix<double> lower(rows, rows);
    lower.setFromTriplets(entries.begin(), entries.end());  // duplicates sum (to zero)
    entries = {};
    cholesky_.analyse(lower);
  }

  diag_at_.resize(n);
  for (int32_t i = 0; i < n; ++i) diag_at_[i] = find(i, i);
  spring_at_.resize(model.springs.size());
  spring_transposed_.resize(model.springs.size());
  for (size_t k = 0; k < model.springs.size(); ++k) {
    const Spring& s = model.springs[k];
    spring_transposed_[k] = s.i < s.j;
    spring_at_[k] = find(std::max(s.i, s.j), std::min(s.i, s.j));
  }
  bending_at_.resize(6 * model.bending.size());
  bending_transposed_.resize(6 * model.bending.size());
  for (size_t e = 0; e < model.bending.size(); ++e)
    for (int k = 0; k < 6; ++k) {
      const int32_t p = model.bending[e].v[kPairs[k][0]], q = model.bending[e].v[kPairs[k][1]];
      bending_transposed_[6 * e + k] = p < q;
      bending_at_[6 * e + k] = find(std::max(p, q), std::min(p, q));
    }
  work_.resize(rows);
}

SystemFactor::BlockAt SystemFactor::find(int32_t row, int32_t col) const {
  BlockAt at{};
  int k = 0;
  for (int c = 0; c < 3; ++c)
    for (int r = row == col ? c : 0; r < 3; ++r)
      at[k++] = static_cast<int32_t>(cholesky_.find(3 * row + r, 3 * col + c));
  return at;
}

void SystemFactor::add_block(const BlockAt& at, bool diagonal, bool transposed, const Mat3& block) {
  double* values = cholesky_.values();
  int k = 0;
  for (int c = 0; c < 3; ++c)
    for (int r = diagonal ? c : 0; r < 3; ++r)
      values[at[k++]] += transposed ? block(c, r) : block(r, c);
}

bool SystemFactor::factorise(const ClothModel& model, const std::vector<Mat3>& diag,
                             const std::vector<Mat3>& spring_block, double h,
                             const std::vector<Mat3>& filter) {
  std::fill(cholesky_.values(), cholesky_.values() + cholesky_.nonzeros(), 0.0);
  const Mat3 I = Mat3::Identity();
  auto filtered = [&](int32_t p, const Mat3& a, int32_t q) -> Mat3 {
    return filter[p] * a * filter[q];  // S_p·A_pq·S_q
  };
  for (int32_t i = 0; i < model.size(); ++i) {
    // The constrained directions decoupled, at the particle's mass (any positive scale would
    // do: the filter removes them from what CG sees).
    add_block(diag_at_[i], true, false,
              filtered(i, diag[i], i) + (I - filter[i]) * std::max(model.mass[i], 1e-12));
  }
  for (size_t k = 0; k < model.springs.size(); ++k) {
    const Spring& s = model.springs[k];
    add_block(spring_at_[k], false, spring_transposed_[k], -filtered(s.i, spring_block[k], s.j));
  }
  for (size_t e = 0; e < model.bending.size(); ++e) {
    const BendingElement& b = model.bending[e];
    const double a = h * h * b.stiffness + h * b.damping;
    for (int k = 0; k < 6; ++k) {
      const int p = kPairs[k][0], q = kPairs[k][1];
      add_block(bending_at_[6 * e + k], false, bending_transposed_[6 * e + k],
                filtered(b.v[p], a * b.w[p] * b.w[q] * I, b.v[q]));
    }
  }
  return cholesky_.factorise();
}

void SystemFactor::apply(const std::vector<Vec3>& r, const std::vector<Mat3>& filter,
                         std::vector<Vec3>& out) {
  // Â⁻¹ = Pᵀ·L⁻ᵀ·L⁻¹·P.
  const int* p = cholesky_.permutation().data();
  const int32_t n = static_cast<int32_t>(r.size());
  for (int32_t i = 0; i < n; ++i) {
    const Vec3 sr = filter[i] * r[i];
    for (int c = 0; c < 3; ++c) work_(p[3 * i + c]) = sr[c];
  }
  cholesky_.solve_in_place(work_);
  for (int32_t i = 0; i < n; ++i)
    out[i] = filter[i] * Vec3(work_(p[3 * i]), work_(p[3 * i + 1]), work_(p[3 * i + 2]));
}

int64_t SystemFactor::bytes() const {
  return cholesky_.bytes() +
         heap_bytes(diag_at_, spring_at_, spring_transposed_, bending_at_, bending_transposed_) +
         work_.size() * int64_t{sizeof(double)};
}

}  // namespace drape
