// Constraint math for the position-based method, as small pure functions tested on their own.
#pragma once

#include <cmath>

#include "drape/math.h"

namespace drape {

/// One XPBD distance constraint C = |x_j − x_i| − L between entries i and j of position arrays
/// (Macklin, Müller & Chentanez 2016, eqs. 18 and 26), with compliance α̃ = α/h², damping
/// γ = α̃·β̃/h, inverse masses w and λ the multiplier so far this substep. Written for arrays
/// so the solver's loops vectorise. Positions come in two parts, x = b + m: b where the particle
/// stood at the substep's start (x_prev) and m its move since; only m changes. Spring vectors
/// d = (b_j − b_i) + (m_j − m_i) and velocities m/h then carry round-off of their own size, not
/// of |x|, which is what lets the solver store them in float. Numerator and denominator are
/// multiplied by |d| so that one square root and one division do:
///   Δλ/|d| = (−(|d|² − L|d|) − α̃λ|d| − γ d·Δ) / (((1 + γ)(wi + wj) + α̃)|d|²),  Δ = m_j − m_i,
///   m_j += wj·(Δλ/|d|)·d,  m_i −= wi·(Δλ/|d|)·d.
/// Unilateral constraints act only when stretched. Real is double or float (the solver's
/// storage); the arithmetic is done in it. Returns Δλ.
template <bool kUnilateral, bool kDamped, typename Real>
[[gnu::always_inline]] inline Real xpbd_project(const Real* __restrict bx,
                                                const Real* __restrict by,
                                                const Real* __restrict bz, Real* __restrict mx,
                                                Real* __restrict my, Real* __restrict mz,
                                                const Real* __restrict w, int i, int j, Real rest,
                                                Real alpha_tilde, Real gamma, Real lambda) {
  const Real rx = mx[j] - mx[i], ry = my[j] - my[i], rz = mz[j] - mz[i];
  const Real dx = (bx[j] - bx[i]) + rx, dy = (by[j] - by[i]) + ry, dz = (bz[j] - bz[i]) + rz;
  const Real len2 = dx * dx + dy * dy + dz * dz;
  const Real len = std::sqrt(len2);
  Real d_dot = 0;
  if constexpr (kDamped) d_dot = dx * rx + dy * ry + dz * rz;
  const Real wi = w[i], wj = w[j];
  const Real numerator = -(len2 - rest * len) - alpha_tilde * lambda * len - gamma * d_dot;
  const Real denominator = ((1 + gamma) * (wi + wj) + alpha_tilde) * len2;
  // Nothing to do for coincident ends (no direction), or two fixed ends of a hard constraint.
  Real s = denominator > 0 ? numerator / denominator : Real(0);
  if constexpr (kUnilateral) s = len > rest ? s : Real(0);
  mx[i] -= wi * s * dx;
  my[i] -= wi * s * dy;
  mz[i] -= wi * s * dz;
  mx[j] += wj * s * dx;
  my[j] += wj * s * dy;
  mz[j] += wj * s * dz;
  return s * len;
}

/// The move of one distance constraint, for two particles given as vectors.
struct DistanceCorrection {
  Vec3 dxi = Vec3::Zero();  ///< m, move of x_i
  Vec3 dxj = Vec3::Zero();  ///< m, move of x_j
  double dlambda = 0.0;     ///< N·s², change of the constraint's Lagrange multiplier
};

/// xpbd_project on two particles: `moved_i` and `moved_j` are x − x_prev over the substep (for
/// the damping term); `lambda` is the multiplier accumulated so far this substep (0 on the
/// first iteration).
inline DistanceCorrection xpbd_distance(const Vec3& xi, double wi, const Vec3& xj, double wj,
                                        double rest, double alpha_tilde, double gamma,
                                        const Vec3& moved_i, const Vec3& moved_j, double lambda) {
  const Vec3 bi = xi - moved_i, bj = xj - moved_j;
  const double bx[2] = {bi.x(), bj.x()}, by[2] = {bi.y(), bj.y()}, bz[2] = {bi.z(), bj.z()},
               w[2] = {wi, wj};
  double mx[2] = {moved_i.x(), moved_j.x()}, my[2] = {moved_i.y(), moved_j.y()},
         mz[2] = {moved_i.z(), moved_j.z()};
  DistanceCorrection out;
  out.dlambda =
      xpbd_project<false, true>(bx, by, bz, mx, my, mz, w, 0, 1, rest, alpha_tilde, gamma, lambda);
  out.dxi = Vec3(mx[0], my[0], mz[0]) - moved_i;
  out.dxj = Vec3(mx[1], my[1], mz[1]) - moved_j;
  return out;
}

}  // namespace drape
