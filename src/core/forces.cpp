#include "forces.h"

#include <cmath>
#include <numbers>
#include "parallel.h"

namespace drape::forces {

void add_springs(const ClothModel& model, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                 std::vector<Vec3>& f) {
  for (int c = 0; c < model.colours(); ++c) {
    const int32_t begin = model.colour_begin[c], end = model.colour_begin[c + 1];
#pragma omp parallel for schedule(static) if (colour_in_parallel(model, c))
    for (int32_t s = begin; s < end; ++s) {
      const Spring& sp = model.springs[s];
      const double k = acting_stiffness(x[sp.i], x[sp.j], sp.stiffness, sp.rest, compression_of(model, sp.kind));
      const Vec3 fi = spring_elastic(x[sp.i], x[sp.j], k, sp.rest) +
                      spring_damping(x[sp.i], x[sp.j], v[sp.i], v[sp.j], sp.damping);
      f[sp.i] += fi;
      f[sp.j] -= fi;
    }
  }
}

double wind_strength(const WindDef& wind, double t) {
  if (wind.gust == 0.0) return wind.strength;
  const double w = 2.0 * std::numbers::pi * wind.gust_frequency * t;
  const double g = (std::sin(w) + 0.5 * std::sin(2.31 * w + 1.0)) / 1.5;
  return wind.strength * (1.0 + wind.gust * g);
}

namespace {

// The aero drag on triangle t: ½ρ·C·A·|u·n|(u·n)·n with u the wind relative to the triangle.
Vec3 aero_triangle(const ClothState& s, const Triangle& t, const Vec3& wind_velocity,
                   double half_rho_c) {
  const Vec3 cross = (s.x[t[1]] - s.x[t[0]]).cross(s.x[t[2]] - s.x[t[0]]);
  const double twice_area = cross.norm();
  if (twice_area == 0.0) return Vec3::Zero();
  const Vec3 n = cross / twice_area;
  const Vec3 u = wind_velocity - (s.v[t[0]] + s.v[t[1]] + s.v[t[2]]) / 3.0;
  const double un = u.dot(n);
  return (half_rho_c * 0.5 * twice_area * std::abs(un) * un) * n;
}

// Calls out(p, force) for each particle's wind force.
template <class Out>
void for_each_wind_force(const ClothModel& model, const ClothState& s, const WindDef& wind,
                         double t, Out out) {
  const double strength = wind_strength(wind, t);
  if (strength == 0.0 || wind.coefficient == 0.0) return;
  const Vec3 dir = wind.direction.normalized();
  const int32_t n = model.size();
  if (wind.model == WindModel::seed) {
    // f = c·d·|cos θ|·dA, so that dv = f/m·dt is the seed's c·d·|cos θ|·(dA/dm)·dt.
    const Vec3 d = strength * dir;
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t p = 0; p < n; ++p)
      out(p, (wind.coefficient * std::abs(s.normal[p].dot(dir)) * s.area[p]) * d);
  } else {
    const Vec3 wind_velocity = strength * dir;
    const double half_rho_c = 0.5 * wind.density * wind.coefficient;
    // Gathered per particle: each takes a third of its triangles' forces.
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t p = 0; p < n; ++p) {
      Vec3 sum = Vec3::Zero();
      for (int32_t k = model.vertex_triangle_begin[p]; k < model.vertex_triangle_begin[p + 1]; ++k)
        sum +=
            aero_triangle(s, model.triangles[model.vertex_triangles[k]], wind_velocity, half_rho_c);
      out(p, sum / 3.0);
    }
  }
}

}  // namespace

void add_wind(const ClothModel& model, const ClothState& state, const WindDef& wind, double t,
              std::vector<Vec3>& f) {
  for_each_wind_force(model, state, wind, t, [&](int32_t p, const Vec3& fw) { f[p] += fw; });
}

double wind_power(const ClothModel& model, const ClothState& state, const WindDef& wind, double t,
                  std::vector<double>& power) {
  power.assign(model.size(), 0.0);
  for_each_wind_force(model, state, wind, t,
                      [&](int32_t p, const Vec3& fw) { power[p] = std::abs(fw.dot(state.v[p])); });
  double sum = 0.0;
  for (double p : power) sum += p;
  return sum;
}

void apply_drag(double air_drag, const std::vector<double>& inv_mass, double dt,
                std::vector<Vec3>& v) {
  if (air_drag == 0.0) return;
  const int32_t n = static_cast<int32_t>(v.size());
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t i = 0; i < n; ++i) {
    v[i] *= drag_factor(dt * air_drag * inv_mass[i], v[i].x(), v[i].y(), v[i].z());
  }
}

void apply_area_drag(const ClothModel& model, const ClothState& state, double air_density,
                     double coefficient, double h, std::vector<Vec3>& v) {
  if (air_density == 0.0 || coefficient == 0.0) return;
  const double half_rho_c = 0.5 * air_density * coefficient;
  const int32_t n = model.size();
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t i = 0; i < n; ++i) {
    if (state.inv_mass[i] == 0.0) continue;
    const Vec3& nrm = state.normal[i];
    const double vn = v[i].dot(nrm);
    const double k = h * half_rho_c * state.area[i] / model.mass[i];
    v[i] -= area_drag_cut(k, vn) * nrm;
  }
}

double kinetic_energy(const ClothModel& model, const std::vector<Vec3>& v) {
  double e = 0.0;
  for (int32_t i = 0; i < model.size(); ++i) e += 0.5 * model.mass[i] * v[i].squaredNorm();
  return e;
}

double gravity_energy(const ClothModel& model, const std::vector<Vec3>& x, const Vec3& g) {
  double e = 0.0;
  for (int32_t i = 0; i < model.size(); ++i) e -= model.mass[i] * g.dot(x[i]);
  return e;
}

StateWatch watch_state(const ClothModel& model, const ClothState& state, const Vec3& g) {
  return deterministic_sum<StateWatch>(model.size(), [&](int64_t i) {
    const Vec3 &x = state.x[i], &v = state.v[i];
    const double m = model.mass[i], x2 = x.squaredNorm(), v2 = v.squaredNorm();
    // NaN fails both comparisons.
    const bool bounded = x2 <= kMaxSquaredMagnitude && v2 <= kMaxSquaredMagnitude;
    return StateWatch{bounded, 0.5 * m * v2, -m * g.dot(x)};
  });
}

double spring_energy(const ClothModel& model, const std::vector<Vec3>& x) {
  double e = 0.0;
  for (const Spring& s : model.springs)
    e += spring_energy(x[s.i], x[s.j],
                       acting_stiffness(x[s.i], x[s.j], s.stiffness, s.rest, compression_of(model, s.kind)),
                       s.rest);
  return e;
}

double spring_energy_beyond(const ClothModel& model, const std::vector<Vec3>& x, double ratio) {
  double e = 0.0;
  for (const Spring& s : model.springs) {
    const double limit = ratio * s.rest;
    if ((x[s.j] - x[s.i]).squaredNorm() > limit * limit)
      e += spring_energy(x[s.i], x[s.j], s.stiffness, s.rest);  // stretched: k acts in full
  }
  return e;
}

}  // namespace drape::forces
