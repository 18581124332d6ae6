// A material's bending damping taken implicitly over a step: the velocities v' that solve
//   (M + dt·D)·v' = M·v,   D = Σ_e d_e·w_e·w_eᵀ (⊗ I₃),
// the elements' damping −d·w_k·Σ_l w_l·v_l (forces/bending.h) as backward Euler takes it. D is
// constant (isometric bending's weights are the rest shape's), so the matrix is factorised once
// per set of free particles and dt, and each step is a triangular solve for x, y and z.
//
// Why not a Gauss–Seidel sweep over the elements: with dt·d·Σw²/m ≫ 1 (fine cloth) one sweep
// zeroes each element's own curvature rate and barely touches the smooth motions, a strip's
// swing or a fold sliding, which need the whole system: on a 16-cell knit strip, a sweep
// with 500 times the preset's damping took 0.2% of the kinetic energy a frame.
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <vector>

#include "drape/cloth.h"

namespace drape::forces {

class BendingDamping {
 public:
  /// Factorises for the model's elements, the particles `pinned` does not mark (the pinned
  /// keep their velocity) and the step dt (s); does nothing when all of those are as at the
  /// last call. Leaves it empty when no element is damped. A particle the hand holds (inverse
  /// mass 0, not pinned) stays free here, so grabbing one costs no refactorisation: the
  /// solvers move it where the hand says whatever its velocity.
  void prepare(const ClothModel& model, const std::vector<uint8_t>& pinned, double dt);
  bool empty() const { return rows_ == 0; }
  double dt() const { return dt_; }

  /// v ← v' for the free particles, v given as three arrays indexed by particle. x, y and z
  /// are independent, one a thread: inside a parallel region every thread of the team calls it
  /// (a worksharing loop; outside one they run in turn). It allocates nothing (it runs inside
  /// step()).
  template <typename Real>
  void apply(Real* vx, Real* vy, Real* vz) {
    Real* v[3] = {vx, vy, vz};
#pragma omp for schedule(static)
    for (int d = 0; d < 3; ++d) {
      for (int32_t p = 0; p < static_cast<int32_t>(row_.size()); ++p)
        if (row_[p] >= 0) rhs_(row_[p], d) = row_mass_[row_[p]] * double(v[d][p]);
      for (const Coupling& c : couplings_) rhs_(c.row, d) -= c.weight * double(v[d][c.pinned]);
      solve(d);
      for (int32_t p = 0; p < static_cast<int32_t>(row_.size()); ++p)
        if (row_[p] >= 0) v[d][p] = static_cast<Real>(rhs_(row_[p], d));
    }
  }

  int64_t bytes() const;

 private:
  void solve(int d);  // rhs_.col(d) ← A⁻¹·rhs_.col(d)

  // A pinned particle's velocity moves to the right-hand side: rhs[row] −= weight·v[pinned].
  struct Coupling {
    int32_t row, pinned;
    double weight;  // dt·Σ d·w_a·w_b over the elements the two share
  };
  int32_t rows_ = 0;
  double dt_ = 0.0;
  // What the factorisation was made for (prepare's inputs).
  std::vector<uint8_t> pinned_;
  std::vector<double> masses_, dampings_;
  std::vector<int32_t> row_;  // per particle: its row, or −1 when it is not free
  std::vector<double> row_mass_;  // per row
  std::vector<Coupling> couplings_;
  using Factor = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>;
  std::unique_ptr<Factor> llt_;  // of M + dt·D over the free particles; null when empty
  Eigen::MatrixX3d rhs_, solution_;  // per row and coordinate; solution_: the solve's scratch
};

}  // namespace drape::forces
