#include "lab/elastica.h"

#include <array>
#include <cmath>

namespace drape::lab {

StripTip elastica_tip(double B, double w, double L) {
  if (!(L > 0.0)) return {};
  const int steps = 4000;
  const double ds = L / steps, load = w / B;
  // State (θ, θ', x, y) along s; returns θ'(L), which must vanish at the free end.
  auto shoot = [&](double slope0, StripTip* tip) {
    using State = std::array<double, 4>;
    auto rate = [&](double s, const State& q) {
      return State{q[1], -load * (L - s) * std::cos(q[0]), std::cos(q[0]), std::sin(q[0])};
    };
    auto plus = [](const State& q, double h, const State& k) {
      return State{q[0] + h * k[0], q[1] + h * k[1], q[2] + h * k[2], q[3] + h * k[3]};
    };
    State q{0.0, slope0, 0.0, 0.0};
    for (int i = 0; i < steps; ++i) {
      const double s = i * ds;
      const State k1 = rate(s, q);
      const State k2 = rate(s + ds / 2, plus(q, ds / 2, k1));
      const State k3 = rate(s + ds / 2, plus(q, ds / 2, k2));
      const State k4 = rate(s + ds, plus(q, ds, k3));
      for (int j = 0; j < 4; ++j) q[j] += ds / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    if (tip) *tip = {q[2], q[3]};
    return q[1];
  };
  // θ'(L) grows with θ'(0): bisect between a slope that falls short and one that overshoots
  // (the straight strip's moment w·L²/2 over B bounds the slope at the clamp).
  double lo = 0.0, hi = load * L * L + 1.0 / L;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (shoot(mid, nullptr) < 0.0 ? lo : hi) = mid;
  }
  StripTip tip;
  shoot(0.5 * (lo + hi), &tip);
  return tip;
}

double elastica_overhang(double B, double w, double angle) {
  // The shape depends on w·L³/B alone, and the tip's angle grows with it until the strip hangs
  // nearly straight down (far beyond the test's 41.5°, where the shooting has more than one
  // answer): double L from below the bending length until the tip passes the plane, then
  // bisect between the last two lengths.
  auto angle_at = [&](double L) {
    const StripTip t = elastica_tip(B, w, L);
    return std::atan2(t.drop, t.along);
  };
  double lo = 0.0, hi = 0.5 * std::cbrt(B / w);
  for (int it = 0; it < 20 && angle_at(hi) < angle; ++it) {
    lo = hi;
    hi *= 2.0;
  }
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (angle_at(mid) < angle ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace drape::lab
