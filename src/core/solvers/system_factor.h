// A sparse Cholesky factorisation of `implicit`'s filtered system, CG's preconditioner where the
// block-Jacobi one is weak.
//
// The system A = M + Σ_s (h²K_s + h·C_s) + Σ_e (h²k_e + h·d_e)·w_e·w_eᵀ ⊗ I is, on fine or stiff
// cloth, badly conditioned in the smooth directions (a strip's sag, a sheet's slow swing): h²k/m
// grows as the cells shrink, and block-Jacobi CG needs hundreds of iterations a substep (about
// 650 on a 160-cell denim strip, 263 on 64² denim over the sphere). A Cholesky factor of A itself
// makes it one or two. The factor is of the filtered matrix Â = S·A·S + (I − S)·m (S the
// particle's contact and pin filter, as CG's; the constrained directions decoupled at the
// particle's mass), so Â⁻¹ maps filtered residuals to filtered directions.
//
// The factor is lagged: made when asked (Implicit decides from CG's iteration counts and the
// costs below), it preconditions later substeps as S·Â_old⁻¹·S, which CG accepts as any
// symmetric positive definite preconditioner; while the cloth changes slowly (a strip coming to
// rest) it stays good for many frames. Its pattern (per particle a 3×3 block, per spring and per
// pair of a bending element's corners an off-diagonal one) is fixed, so only the numeric
// factorisation is repeated. It is dear: L holds 130 (32² grid) to 220 (64²) entries a row, a
// factorisation costs as much as 400 to 1600 block-Jacobi iterations and a solve with it 12 to
// 20 (measured on one core), so it pays only where CG would otherwise take hundreds.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "drape/cloth.h"
#include "drape/math.h"
#include "sparse_cholesky.h"

namespace drape {

class SystemFactor {
 public:
  /// The largest cloth a factor is made for: its entries grow faster than the particles.
  static constexpr int32_t kMaxParticles = 17000;
  /// Bytes a factor may hold for a cloth of `particles`: measured 9.5 KB a particle on a 64²
  /// grid with a material, 13.7 KB at 128², so 16 KiB up to kMaxParticles; none beyond.
  static int64_t estimated_bytes(int64_t particles) {
    return particles <= kMaxParticles ? particles * 16384 : 0;
  }

  /// Builds the pattern for the model's springs and bending elements, orders it (AMD) and
  /// counts the factor's entries. Forgets any factor.
  void prepare(const ClothModel& model);

  /// The factor's size and work, known from prepare() (SparseCholesky's).
  int64_t entries() const { return cholesky_.entries(); }
  double factorise_work() const { return cholesky_.factorise_work(); }

  /// Factorises Â from the system's per-particle diagonal blocks `diag` (mass, springs and
  /// bending included), each spring's block `spring_block` (its coupling is −block), the
  /// bending elements' weight (h²k + h·d per element, from the model and h) and the filter
  /// (per particle: I, a projection, or 0 for a pinned one). Returns false (and keeps no
  /// factor) when Â is not positive definite, which a sound system never is. Allocates
  /// nothing up to 5461 particles (SparseCholesky::factorise).
  bool factorise(const ClothModel& model, const std::vector<Mat3>& diag,
                 const std::vector<Mat3>& spring_block, double h, const std::vector<Mat3>& filter);

  bool ready() const { return cholesky_.ready(); }

  /// out = S·Â⁻¹·S·r with S the filter given now. Allocates nothing.
  void apply(const std::vector<Vec3>& r, const std::vector<Mat3>& filter, std::vector<Vec3>& out);

  /// Heap bytes: the entries' places, the matrix and its factor.
  int64_t bytes() const;

 private:
  // Where a 3×3 block's entries lie in the matrix's values, row by row within each column
  // (a diagonal block's lower triangle only: its first six).
  using BlockAt = std::array<int32_t, 9>;
  // The block of rows of particle `row` and columns of `col` (row ≥ col).
  BlockAt find(int32_t row, int32_t col) const;
  void add_block(const BlockAt& at, bool diagonal, bool transposed, const Mat3& block);

  SparseCholesky cholesky_;                 // of Â, 3 rows per particle
  std::vector<BlockAt> diag_at_;            // per particle
  std::vector<BlockAt> spring_at_;          // per spring
  std::vector<uint8_t> spring_transposed_;  // 1: stored as the (j, i) block
  std::vector<BlockAt> bending_at_;         // per element, its 6 corner pairs (a < b)
  std::vector<uint8_t> bending_transposed_;
  Eigen::VectorXd work_;  // the permuted right-hand side, solved in place
};

}  // namespace drape
