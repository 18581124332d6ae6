// Constraint math for the position-based method, as small pure functions tested on their own.
#pragma once

#include <cmath>

#include "drape/math.h"

namespace drape {

/// One XPBD step on a distance constraint C = |x_j − x_i| − L with compliance α̃ = α/h² and
/// damping γ = α̃·β̃/h (Macklin, Müller & Chentanez 2016, eqs. 18 and 26).
struct DistanceCorrection {
  Vec3 dxi = Vec3::Zero();  ///< m, move of x_i
  Vec3 dxj = Vec3::Zero();  ///< m, move of x_j
  double dlambda = 0.0;     ///< N·s², change of the constraint's Lagrange multiplier
};

/// Δλ for a constraint of value c and rate ċ = ∇C·(x − x_prev), with w the sum of the inverse
/// masses times |∇C|² (= wi + wj for a distance) and λ the multiplier so far. 0 when nothing
/// can move and the constraint is hard.
inline double xpbd_delta_lambda(double c, double w, double alpha_tilde, double gamma, double c_dot,
                                double lambda) {
  const double denominator = (1.0 + gamma) * w + alpha_tilde;
  return denominator > 0.0 ? (-c - alpha_tilde * lambda - gamma * c_dot) / denominator : 0.0;
}

/// `moved_i` and `moved_j` are x − x_prev over the substep (for the damping term); `lambda` is
/// the multiplier accumulated so far this substep (0 on the first iteration).
inline DistanceCorrection xpbd_distance(const Vec3& xi, double wi, const Vec3& xj, double wj,
                                        double rest, double alpha_tilde, double gamma,
                                        const Vec3& moved_i, const Vec3& moved_j, double lambda) {
  DistanceCorrection out;
  const double w = wi + wj;
  const Vec3 d = xj - xi;
  const double len = d.norm();
  if (w == 0.0 || len == 0.0) return out;
  const Vec3 n = d / len;  // ∇_j C = n, ∇_i C = −n
  const double c = len - rest;
  const double c_dot = n.dot(moved_j - moved_i);  // ∇C·(x − x_prev)
  out.dlambda = xpbd_delta_lambda(c, w, alpha_tilde, gamma, c_dot, lambda);
  out.dxi = (-wi * out.dlambda) * n;
  out.dxj = (wj * out.dlambda) * n;
  return out;
}

}  // namespace drape
