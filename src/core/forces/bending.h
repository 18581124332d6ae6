// Isometric bending (Bergou, Wardetzky, Harmon, Zorin & Grinspun 2006): per element the
// curvature vector c = Σ_k w_k·x_k over an edge's two ends and two far corners, the energy
// ½k|c|², the force −k·w_k·c on corner k and the constant Hessian k·w_k·w_l·I. Damping is
// stiffness-proportional: −d·w_k·Σ_l w_l·v_l. Small pure functions, tested against finite
// differences, and the loops over a model's elements.
#pragma once

#include <vector>

#include "drape/cloth.h"

namespace drape::forces {

/// c = Σ_k w_k·x_{v_k} (m): zero while the two triangles lie as flat as they were at rest.
inline Vec3 bending_vector(const BendingElement& b, const std::vector<Vec3>& x) {
  return b.w[0] * x[b.v[0]] + b.w[1] * x[b.v[1]] + b.w[2] * x[b.v[2]] + b.w[3] * x[b.v[3]];
}

/// The element's energy ½k|c|² (J).
inline double bending_energy(const BendingElement& b, const std::vector<Vec3>& x) {
  return 0.5 * b.stiffness * bending_vector(b, x).squaredNorm();
}

/// Force on corner k (N): −k·w_k·c − d·w_k·ċ, with ċ the same sum over the velocities.
inline Vec3 bending_force(const BendingElement& b, int k, const std::vector<Vec3>& x,
                          const std::vector<Vec3>& v) {
  return -b.w[k] * (b.stiffness * bending_vector(b, x) + b.damping * bending_vector(b, v));
}

/// Σ ½k|c|² over the model's elements (J).
double bending_energy(const ClothModel& model, const std::vector<Vec3>& x);

/// Per particle, the Gershgorin row sum of the elements' stiffness (N/m) and damping (N·s/m):
/// Σ over its elements of k·|w_k|·Σ_l|w_l| (and d·...), for stability bounds.
void bending_row_sums(const ClothModel& model, std::vector<double>& stiffness,
                      std::vector<double>& damping);

}  // namespace drape::forces
