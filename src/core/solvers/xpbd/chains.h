// Chains of distance constraints solved exactly (xpbd's line passes): a chain's XPBD step
// linearised at the current positions is one tridiagonal system in the multipliers' changes,
//   ((1 + γ)·J W Jᵀ + α̃) Δλ = −C − α̃·λ − γ·J·(x − x_prev),
//   (J W Jᵀ)_t,t = w_t + w_t+1,   (J W Jᵀ)_t−1,t = −w_t·(n_t−1 · n_t),
// n_t the unit direction of constraint t, solved by the Thomas algorithm. These are its steps,
// written for one number (Real) or a vector of them (a Lanes vector, one lane a chain), and the
// arrays the solves keep. The grid's rows and columns and a mesh's path cover both use them.
#pragma once

#include <cmath>

#include "aligned.h"
#include "drape/cloth.h"

namespace drape::xpbd {

/// Positions (or any 3-vector field) as three arrays.
template <typename T>
struct Soa {
  AlignedVector<T> x, y, z;
  AlignedVector<T>& operator[](int d) { return d == 0 ? x : d == 1 ? y : z; }
  void resize(size_t n) {
    x.assign(n, T{});
    y.assign(n, T{});
    z.assign(n, T{});
  }
};

/// The line passes' arrays for one direction (rows or columns), by chain entry. Each chain has an
/// entry before its first constraint and one after its last, never written, that end the
/// recurrences; how the entries are laid out is the direction's (see eliminate_columns and
/// solve_rows). T is a number (columns) or a vector of numbers, one lane a chain (rows, see
/// Lanes).
template <typename T>
struct ChainScratch {
  Soa<T> n;                         ///< the constraint's unit direction
  AlignedVector<T> f, g, inv_beta;  ///< Thomas: e/β (see eliminate), g (then Δλ), 1/β
  AlignedVector<T> lambda;          ///< λ accumulated over this substep's passes

  void prepare(size_t entries) {
    n.resize(entries);
    f.assign(entries, T{});
    g.assign(entries, T{});
    inv_beta.assign(entries, T{} + 1);
    lambda.assign(entries, T{});
  }
  int64_t bytes() const { return heap_bytes(n.x, n.y, n.z, f, g, inv_beta, lambda); }
};

// What a chain's constraint contributes to its system, from its two ends i and j: the unit
// direction n, the diagonal b and the right-hand side r without the α̃λ term. `live` false
// (both ends fixed, or a chain swept spring by spring) leaves r = 0: no change.
template <typename T>
struct ChainRowOf {
  T nx, ny, nz, b, r;
};
template <typename Real>
inline ChainRowOf<Real> chain_row(const Real* __restrict bx, const Real* __restrict by,
                          const Real* __restrict bz, const Real* __restrict mx,
                          const Real* __restrict my, const Real* __restrict mz,
                          const Real* __restrict w, int i, int j, bool live, Real rest,
                          Real alpha_tilde, Real gamma) {
  const Real rx = mx[j] - mx[i], ry = my[j] - my[i], rz = mz[j] - mz[i];
  const Real dx = (bx[j] - bx[i]) + rx, dy = (by[j] - by[i]) + ry, dz = (bz[j] - bz[i]) + rz;
  const Real len = std::sqrt(dx * dx + dy * dy + dz * dz);
  const Real inv = len > 0 ? 1 / len : Real(0);  // coincident ends: no direction
  const Real ux = dx * inv, uy = dy * inv, uz = dz * inv;
  live = live && w[i] + w[j] > 0;
  return {ux, uy, uz, (1 + gamma) * (w[i] + w[j]) + alpha_tilde,
          live ? -(len - rest) - gamma * (ux * rx + uy * ry + uz * rz) : Real(0)};
}

// The coupling of constraint c to the constraint of entry p eliminated before it, wi being
// the inverse mass of the particle the two share: the off-diagonal entry e and f = e/β_p.
// T: Real or a Lanes vector.
template <typename T>
struct Pivot {
  T e, f;
};
template <typename T, typename Real>
inline Pivot<T> pivot(const ChainRowOf<T>& c, T wi, Real gamma, const T* __restrict nx,
                      const T* __restrict ny, const T* __restrict nz,
                      const T* __restrict inv_beta, int p) {
  const T e = -(1 + gamma) * wi * (nx[p] * c.nx + ny[p] * c.ny + nz[p] * c.nz);
  return {e, e * inv_beta[p]};
}

// One step of the elimination for constraint entry q after entry p (the previous constraint
// of the chain, or the zero entry before the first): f = e/β_p, β = b − f·e, g = r − f·g_p,
// f kept at entry qf (q, or p when the substitution runs the other way). One division a step:
// the recurrence's latency, not its arithmetic, is what bounds it.
template <typename T, typename Real>
inline void eliminate(const ChainRowOf<T>& c, T wi, Real gamma, T alpha_lambda, T* __restrict nx,
                      T* __restrict ny, T* __restrict nz, T* __restrict fe, T* __restrict g,
                      T* __restrict inv_beta, int p, int q, int qf) {
  const auto [e, f] = pivot(c, wi, gamma, nx, ny, nz, inv_beta, p);
  nx[q] = c.nx;
  ny[q] = c.ny;
  nz[q] = c.nz;
  fe[qf] = f;
  inv_beta[q] = Real(1) / (c.b - f * e);
  g[q] = c.r - alpha_lambda - f * g[p];
}

// Entry q's Δλ into g, and ω·Δλ onto λ (the pass's relaxation, which scales the moves alike).
template <typename T, typename Real>
inline T take(T* __restrict g, T* __restrict lambda, Real keep, Real omega, int q, T dl) {
  g[q] = dl;
  lambda[q] = keep * lambda[q] + omega * dl;
  return dl;
}

// The back substitution for entry q, from the next constraint's f and Δλ (zero after the
// last): Δλ = g/β − f_next·Δλ_next, taken.
template <typename T, typename Real>
inline T substitute(T* __restrict g, const T* __restrict inv_beta, T* __restrict lambda,
                    Real keep, Real omega, int q, T f_next, T dl_next) {
  return take(g, lambda, keep, omega, q, g[q] * inv_beta[q] - f_next * dl_next);
}

}  // namespace drape::xpbd
