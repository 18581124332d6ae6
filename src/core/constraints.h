// Constraint math for the position-based method, as small pure functions tested on their own.
#pragma once

#include <cmath>

#include "drape/math.h"

namespace drape {

/// One XPBD distance constraint C = |x_j − x_i| − L between entries i and j of position arrays
/// (Macklin, Müller & Chentanez 2016, eqs. 18 and 26), with compliance α̃ = α/h², damping
/// γ = α̃·β̃/h, inverse masses w and λ the multiplier so far this substep. Written for arrays
/// so the solver's loops vectorise. Numerator and denominator are multiplied by |d| so that one
/// square root and one division do:
///   Δλ/|d| = (−(|d|² − L|d|) − α̃λ|d| − γ d·Δ) / (((1 + γ)(wi + wj) + α̃)|d|²),
///   Δ = (x_j − x_prev,j) − (x_i − x_prev,i),  x_j += wj·(Δλ/|d|)·d,  x_i −= wi·(Δλ/|d|)·d.
/// Unilateral constraints act only when stretched; undamped ones read no x_prev (q).
/// Returns Δλ.
/// Real is double or float (the solver's storage); the arithmetic is done in it.
template <bool kUnilateral, bool kDamped, typename Real>
inline Real xpbd_project(Real* __restrict px, Real* __restrict py, Real* __restrict pz,
                         const Real* __restrict qx, const Real* __restrict qy,
                         const Real* __restrict qz, const Real* __restrict w, int i, int j,
                         Real rest, Real alpha_tilde, Real gamma, Real lambda) {
  const Real dx = px[j] - px[i], dy = py[j] - py[i], dz = pz[j] - pz[i];
  const Real len2 = dx * dx + dy * dy + dz * dz;
  const Real len = std::sqrt(len2);
  Real d_dot = 0;
  if constexpr (kDamped)
    d_dot = dx * ((px[j] - qx[j]) - (px[i] - qx[i])) + dy * ((py[j] - qy[j]) - (py[i] - qy[i])) +
            dz * ((pz[j] - qz[j]) - (pz[i] - qz[i]));
  const Real wi = w[i], wj = w[j];
  const Real numerator = -(len2 - rest * len) - alpha_tilde * lambda * len - gamma * d_dot;
  const Real denominator = ((1 + gamma) * (wi + wj) + alpha_tilde) * len2;
  // Nothing to do for coincident ends (no direction), or two fixed ends of a hard constraint.
  Real s = denominator > 0 ? numerator / denominator : Real(0);
  if constexpr (kUnilateral) s = len > rest ? s : Real(0);
  px[i] -= wi * s * dx;
  py[i] -= wi * s * dy;
  pz[i] -= wi * s * dz;
  px[j] += wj * s * dx;
  py[j] += wj * s * dy;
  pz[j] += wj * s * dz;
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
  double px[2] = {xi.x(), xj.x()}, py[2] = {xi.y(), xj.y()}, pz[2] = {xi.z(), xj.z()};
  const double qx[2] = {xi.x() - moved_i.x(), xj.x() - moved_j.x()},
               qy[2] = {xi.y() - moved_i.y(), xj.y() - moved_j.y()},
               qz[2] = {xi.z() - moved_i.z(), xj.z() - moved_j.z()}, w[2] = {wi, wj};
  DistanceCorrection out;
  out.dlambda =
      xpbd_project<false, true>(px, py, pz, qx, qy, qz, w, 0, 1, rest, alpha_tilde, gamma, lambda);
  out.dxi = Vec3(px[0], py[0], pz[0]) - xi;
  out.dxj = Vec3(px[1], py[1], pz[1]) - xj;
  return out;
}

}  // namespace drape
