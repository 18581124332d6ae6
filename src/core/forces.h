// Forces on the cloth: springs, gravity, wind, air drag. The per-spring math is a set of small
// pure functions (tested on their own against finite differences); the loops over the cloth
// are below them.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "drape/cloth.h"
#include "drape/scene.h"

namespace drape::forces {

/// Elastic force on particle i of a spring (i, j): k(|d| − L)·d̂, d = x_j − x_i.
inline Vec3 spring_elastic(const Vec3& xi, const Vec3& xj, double k, double rest) {
  const Vec3 d = xj - xi;
  const double len = d.norm();
  if (len == 0.0) return Vec3::Zero();  // direction undefined; no force rather than NaN
  return (k * (len - rest) / len) * d;
}

/// The stiffness a spring acts with now: k stretched, compression·k compressed, so that cloth
/// resists compression far less than tension and buckles out of its plane instead (Choi & Ko
/// 2002, "Stable but responsive cloth"). The energy ½k(|d| − L)² with this k is continuous with
/// a continuous gradient. compression = 1 (the seed's model) returns k exactly.
inline double acting_stiffness(const Vec3& xi, const Vec3& xj, double k, double rest,
                               double compression) {
  return (xj - xi).squaredNorm() < rest * rest ? compression * k : k;
}

/// The compression factor a spring of `kind` takes from the model: structural springs (the
/// threads) buckle; shear springs keep their stiffness both ways, so shear stays the material's.
inline double compression_of(const ClothModel& model, SpringKind kind) {
  return kind == SpringKind::structural ? model.compression : 1.0;
}

/// Damping force on particle i of a spring: c((v_j − v_i)·d̂)·d̂.
inline Vec3 spring_damping(const Vec3& xi, const Vec3& xj, const Vec3& vi, const Vec3& vj,
                           double c) {
  const Vec3 d = xj - xi;
  const double len2 = d.squaredNorm();
  if (len2 == 0.0) return Vec3::Zero();
  return (c * (vj - vi).dot(d) / len2) * d;
}

/// Elastic energy ½k(|d| − L)².
inline double spring_energy(const Vec3& xi, const Vec3& xj, double k, double rest) {
  const double stretch = (xj - xi).norm() - rest;
  return 0.5 * k * stretch * stretch;
}

/// ∂f_i/∂x_j of the elastic force (= −∂f_i/∂x_i):
/// k[d̂d̂ᵀ + (1 − L/|d|)(I − d̂d̂ᵀ)]. With `clamp`, the transverse term of a compressed spring
/// (negative) is dropped so the matrix stays positive semi-definite (Baraff & Witkin 1998;
/// Choi & Ko 2002).
inline Mat3 spring_stiffness(const Vec3& xi, const Vec3& xj, double k, double rest, bool clamp) {
  const Vec3 d = xj - xi;
  const double len = d.norm();
  if (len == 0.0) return Mat3::Zero();
  const Vec3 u = d / len;
  const Mat3 uu = u * u.transpose();
  double transverse = 1.0 - rest / len;
  if (clamp && transverse < 0.0) transverse = 0.0;
  return k * (uu + transverse * (Mat3::Identity() - uu));
}

/// The backward-Euler system block of a spring for step h: h²·K + h·c·d̂d̂ᵀ, with K the clamped
/// stiffness (spring_stiffness) and c·d̂d̂ᵀ = −∂f_i/∂v_i of the damping force. The Newton step's
/// matrix is M plus this block coupling i and j (+ on the diagonal, − off it).
inline Mat3 implicit_spring_block(const Vec3& xi, const Vec3& xj, double k, double rest, double c,
                                  double h) {
  const Vec3 d = xj - xi;
  const double len2 = d.squaredNorm();
  const Mat3 damping = len2 > 0.0 ? Mat3((c / len2) * (d * d.transpose())) : Mat3::Zero();
  return (h * h) * spring_stiffness(xi, xj, k, rest, true) + h * damping;
}

/// Adds every spring's elastic and damping forces to f (N). Colour by colour, in parallel.
void add_springs(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                 std::vector<Vec3>& f);

/// Wind strength at time t (s), with gusts: strength·(1 + gust·g(t)), g a smooth function in
/// [−1, 1] made of two incommensurate sines so the pattern does not repeat visibly.
double wind_strength(const WindDef& wind, double t);

/// Adds the wind force (N) at time t. Reads state.normal and state.area (update_normals first)
/// for the seed model, state.x and state.v for the aero model.
void add_wind(const ClothModel& model, const ClothState& state, const WindDef& wind, double t,
              std::vector<Vec3>& f);

/// Σ_i |f_wind,i · v_i| (W): an upper bound on the power the wind delivers now. `scratch` is
/// workspace (resized to the particle count).
double wind_power(const ClothModel& model, const ClothState& state, const WindDef& wind, double t,
                  std::vector<double>& scratch);

/// The factor the semi-implicit drag scales a velocity u by: 1/(1 + k·|u|) with
/// k = dt·(ρA/m), in double or float. A speed near overflow is left alone for the divergence
/// check to see: dividing by an infinite norm would quietly zero it.
template <typename Real>
inline Real drag_factor(Real k, Real ux, Real uy, Real uz) {
  const Real speed = std::sqrt(ux * ux + uy * uy + uz * uz);
  return speed <= Real(1e-8) * std::numeric_limits<Real>::max() ? 1 / (1 + k * speed) : Real(1);
}

/// What the semi-implicit drag on the area (apply_area_drag) takes off a normal speed u_n:
/// u_n − u_n/(1 + k·|u_n|), k = h·½ρC·A/m, in double or float.
template <typename Real>
inline Real area_drag_cut(Real k, Real un) {
  return un * (1 - 1 / (1 + k * std::abs(un)));
}

/// The seed's quadratic drag dv = −(ρA/m)|v|v dt, taken semi-implicitly:
/// v ← v / (1 + dt·(ρA/m)·|v|). Same terminal speed, stable for any dt. No-op where 1/m = 0.
void apply_drag(double air_drag, const std::vector<double>& inv_mass, double dt,
                std::vector<Vec3>& v);

/// Drag on the cloth's area, the same at any resolution: particle i, carrying the area A_i
/// (state.area) facing along n_i (state.normal), feels ½ρ·C·A_i·|v_n|v_n against its normal
/// velocity v_n = v_i·n_i, the particle's share of each triangle's drag on its area moving
/// through still air. Taken semi-implicitly as apply_drag is, on the normal part only:
/// v_n ← v_n / (1 + h·(½ρC·A_i/m_i)·|v_n|), stable for any h; since A_i/m_i is 1/density, a
/// falling sheet reaches sqrt(2·density·g/(ρC)) at every resolution. No-op where 1/m = 0.
void apply_area_drag(const ClothModel& model, const ClothState& state, double air_density,
                     double coefficient, double h, std::vector<Vec3>& v);

/// Energies (J): ½Σ m v², −Σ m g·x, Σ ½k(|d| − L)² (k as acting_stiffness says).
double kinetic_energy(const ClothModel& model, const std::vector<Vec3>& v);
double gravity_energy(const ClothModel& model, const std::vector<Vec3>& x, const Vec3& g);
double spring_energy(const ClothModel& model, const std::vector<Vec3>& x);
/// The spring energy of the springs longer than `ratio` (≥ 1) × their rest length only (J).
double spring_energy_beyond(const ClothModel& model, const std::vector<Vec3>& x, double ratio);

/// The largest squared length of a position (m²) or velocity (m²/s²) the divergence watch
/// accepts: beyond 1e150 a difference of two positions, squared, can overflow, so strains,
/// spring energies and normals of such a state are no longer numbers.
inline constexpr double kMaxSquaredMagnitude = 1e300;

/// What the divergence watch reads of the state after every frame, taken in one pass over it,
/// in parallel, with the same bits for any thread count.
struct StateWatch {
  /// every position and velocity is finite, with a squared length of at most
  /// kMaxSquaredMagnitude
  bool finite = true;
  double kinetic = 0.0;  ///< J, kinetic_energy up to round-off
  double gravity = 0.0;  ///< J, gravity_energy up to round-off
  StateWatch& operator+=(const StateWatch& o) {
    finite = finite && o.finite;
    kinetic += o.kinetic;
    gravity += o.gravity;
    return *this;
  }
};
StateWatch watch_state(const ClothModel& model, const ClothState& state, const Vec3& g);

}  // namespace drape::forces
