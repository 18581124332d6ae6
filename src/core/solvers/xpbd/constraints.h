// Constraint math for the position-based method, as small pure functions tested on their own.
#pragma once

#include <cmath>
#include <cstdint>

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
/// Unilateral constraints act only when stretched. Softened ones (a material's threads, Choi &
/// Ko 2002) act with compression·k while compressed: α̃/compression and γ/compression, written
/// with numerator and denominator multiplied by s = compression (s = 1 stretched) so that
/// compression 0 (no stiffness, the damping still acting) needs no infinity:
///   Δλ/|d| = (−s(|d|² − L|d|) − α̃λ|d| − γ d·Δ) / (((s + γ)(wi + wj) + α̃)|d|²).
/// Real is double or float (the solver's storage); the arithmetic is done in it. Returns Δλ.
template <bool kUnilateral, bool kDamped, bool kSoftened = false, typename Real>
[[gnu::always_inline]] inline Real xpbd_project(
    const Real* __restrict bx, const Real* __restrict by, const Real* __restrict bz,
    Real* __restrict mx, Real* __restrict my, Real* __restrict mz, const Real* __restrict w, int i,
    int j, Real rest, Real alpha_tilde, Real gamma, Real lambda, Real compression = 1) {
  const Real rx = mx[j] - mx[i], ry = my[j] - my[i], rz = mz[j] - mz[i];
  const Real dx = (bx[j] - bx[i]) + rx, dy = (by[j] - by[i]) + ry, dz = (bz[j] - bz[i]) + rz;
  const Real len2 = dx * dx + dy * dy + dz * dz;
  const Real len = std::sqrt(len2);
  Real d_dot = 0;
  if constexpr (kDamped) d_dot = dx * rx + dy * ry + dz * rz;
  const Real wi = w[i], wj = w[j];
  Real soft = 1;
  if constexpr (kSoftened) soft = len < rest ? compression : Real(1);
  const Real numerator = -soft * (len2 - rest * len) - alpha_tilde * lambda * len - gamma * d_dot;
  const Real denominator = ((soft + gamma) * (wi + wj) + alpha_tilde) * len2;
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

/// One XPBD isometric bending constraint (forces/bending.h) on corners v[0..3] with weights
/// wt[0..3]: the curvature vector C = Σ_k w_k·x_k, linear in the positions, with a spring's
/// compliance α̃ = 1/(k·h²); its damping is taken on the velocities (forces::BendingDamping). Its
/// gradient on corner k is w_k·I, so J·M⁻¹·Jᵀ = W·I with W = Σ_k w_k²/m_k and one projection is
///   Δλ = (−C − α̃λ) / (W + α̃),   m_k += (w_k/m_k)·Δλ,
/// λ (a vector) the multiplier so far. Positions as xpbd_project's, b + m; the weights sum to
/// zero, so C = Σ_{k≥1} w_k·((b_k − b_0) + (m_k − m_0)) carries the round-off of the element's
/// size, not of |x|. Adds Δλ to lambda.
template <typename Real>
[[gnu::always_inline]] inline void xpbd_bend(const Real* __restrict bx, const Real* __restrict by,
                                             const Real* __restrict bz, Real* __restrict mx,
                                             Real* __restrict my, Real* __restrict mz,
                                             const Real* __restrict w, const int32_t* v,
                                             const Real* wt, Real alpha_tilde, Real* lambda) {
  const int32_t a = v[0];
  Real cx = 0, cy = 0, cz = 0, sum = wt[0] * wt[0] * w[a];
  for (int k = 1; k < 4; ++k) {
    const int32_t p = v[k];
    cx += wt[k] * ((bx[p] - bx[a]) + (mx[p] - mx[a]));
    cy += wt[k] * ((by[p] - by[a]) + (my[p] - my[a]));
    cz += wt[k] * ((bz[p] - bz[a]) + (mz[p] - mz[a]));
    sum += wt[k] * wt[k] * w[p];
  }
  const Real denominator = sum + alpha_tilde;
  if (!(denominator > 0)) return;  // all four corners fixed, a hard constraint
  const Real inv = 1 / denominator;
  const Real lx = (-cx - alpha_tilde * lambda[0]) * inv, ly = (-cy - alpha_tilde * lambda[1]) * inv,
             lz = (-cz - alpha_tilde * lambda[2]) * inv;
  for (int k = 0; k < 4; ++k) {
    const int32_t p = v[k];
    const Real s = wt[k] * w[p];
    mx[p] += s * lx, my[p] += s * ly, mz[p] += s * lz;
  }
  lambda[0] += lx, lambda[1] += ly, lambda[2] += lz;
}

/// Damping apart from the elastic projections, on the velocities after a substep (a material's
/// stiffness-proportional damping): one Gauss–Seidel step of backward Euler for a spring's
/// damping force c·((v_j − v_i)·d̂)·d̂, which takes the ends' relative speed along d̂, u, to
/// u/(1 + h·c·(wi + wj)), momentum kept; hc = h·c. Still particles feel nothing, so unlike
/// XPBD's damping term γ it cannot shift where the cloth comes to rest: with one sweep a
/// substep leaving the constraints unconverged, γ = c/(k·h) grows as the substeps shrink and
/// held a cantilever strip 15% below its elastica at 1082 substeps.
template <typename Real>
[[gnu::always_inline]] inline void damp_spring(const Real* __restrict bx, const Real* __restrict by,
                                               const Real* __restrict bz, const Real* __restrict mx,
                                               const Real* __restrict my, const Real* __restrict mz,
                                               Real* __restrict vx, Real* __restrict vy,
                                               Real* __restrict vz, const Real* __restrict w, int i,
                                               int j, Real hc) {
  const Real dx = (bx[j] - bx[i]) + (mx[j] - mx[i]), dy = (by[j] - by[i]) + (my[j] - my[i]),
             dz = (bz[j] - bz[i]) + (mz[j] - mz[i]);
  const Real len2 = dx * dx + dy * dy + dz * dz, wi = w[i], wj = w[j];
  const Real u = dx * (vx[j] - vx[i]) + dy * (vy[j] - vy[i]) + dz * (vz[j] - vz[i]);  // ·|d|
  // The impulse along d, divided by |d|² once for both of d's factors.
  const Real p = len2 > 0 ? -hc * u / ((1 + hc * (wi + wj)) * len2) : Real(0);
  vx[i] -= wi * p * dx, vy[i] -= wi * p * dy, vz[i] -= wi * p * dz;
  vx[j] += wj * p * dx, vy[j] += wj * p * dy, vz[j] += wj * p * dz;
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
/// `compression` softens it while compressed, as xpbd_project's kSoftened (1: not softened).
inline DistanceCorrection xpbd_distance(const Vec3& xi, double wi, const Vec3& xj, double wj,
                                        double rest, double alpha_tilde, double gamma,
                                        const Vec3& moved_i, const Vec3& moved_j, double lambda,
                                        double compression = 1.0) {
  const Vec3 bi = xi - moved_i, bj = xj - moved_j;
  const double bx[2] = {bi.x(), bj.x()}, by[2] = {bi.y(), bj.y()}, bz[2] = {bi.z(), bj.z()},
               w[2] = {wi, wj};
  double mx[2] = {moved_i.x(), moved_j.x()}, my[2] = {moved_i.y(), moved_j.y()},
         mz[2] = {moved_i.z(), moved_j.z()};
  DistanceCorrection out;
  out.dlambda = xpbd_project<false, true, true>(bx, by, bz, mx, my, mz, w, 0, 1, rest, alpha_tilde,
                                                gamma, lambda, compression);
  out.dxi = Vec3(mx[0], my[0], mz[0]) - moved_i;
  out.dxj = Vec3(mx[1], my[1], mz[1]) - moved_j;
  return out;
}

}  // namespace drape
