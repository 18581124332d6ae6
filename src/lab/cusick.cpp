#include "lab/cusick.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "drape/simulation.h"
#include "lab/settle.h"

namespace drape::lab {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kShadowPixels = 640;
constexpr double kShadowWidth = 2.0 * kSpecimenRadius + 0.04;  // m, the specimen and a margin

}  // namespace

Shadow cast_shadow(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles, double width,
                   int pixels) {
  Shadow s;
  s.size = pixels;
  s.width = width;
  s.covered.assign(static_cast<size_t>(s.size) * s.size, 0);
  const double px = s.pixel(), half = 0.5 * s.width;
  auto at = [&](const Vec3& p) { return Vec2((p.x() + half) / px, (p.z() + half) / px); };
  for (const Triangle& t : triangles) {
    const Vec2 a = at(x[t[0]]), b = at(x[t[1]]), c = at(x[t[2]]);
    const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area2 == 0.0) continue;  // seen edge-on: it covers no area
    const Vec2 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const int i0 = std::max(0, static_cast<int>(std::floor(lo.x()))),
              i1 = std::min(s.size - 1, static_cast<int>(std::ceil(hi.x()))),
              j0 = std::max(0, static_cast<int>(std::floor(lo.y()))),
              j1 = std::min(s.size - 1, static_cast<int>(std::ceil(hi.y())));
    // A pixel is covered when its centre is inside the triangle: the three edge functions
    // have the sign of the triangle's area.
    auto edge = [](const Vec2& p, const Vec2& q, const Vec2& r) {
      return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
    };
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 p(i + 0.5, j + 0.5);
        const double e0 = edge(a, b, p), e1 = edge(b, c, p), e2 = edge(c, a, p);
        if (area2 > 0 ? e0 >= 0 && e1 >= 0 && e2 >= 0 : e0 <= 0 && e1 <= 0 && e2 <= 0)
          s.covered[static_cast<size_t>(j) * s.size + i] = 1;
      }
  }
  return s;
}

double covered_area(const Shadow& s) {
  int64_t count = 0;
  for (uint8_t c : s.covered) count += c;
  return static_cast<double>(count) * s.pixel() * s.pixel();
}

namespace {

bool covered(const Shadow& s, double x, double z) {
  const int i = static_cast<int>(std::floor((x + 0.5 * s.width) / s.pixel()));
  const int j = static_cast<int>(std::floor((z + 0.5 * s.width) / s.pixel()));
  return i >= 0 && j >= 0 && i < s.size && j < s.size &&
         s.covered[static_cast<size_t>(j) * s.size + i] != 0;
}

// The outline: at each degree the farthest covered point from the axis, smoothed over ±3°.
std::vector<double> trace_hem(const Shadow& s) {
  std::vector<double> raw(360, 0.0);
  const double step = 0.5 * s.pixel();
  for (int k = 0; k < 360; ++k) {
    const double a = k * kPi / 180.0;
    for (double r = 0.5 * s.width; r > 0.0; r -= step)
      if (covered(s, r * std::cos(a), r * std::sin(a))) {
        raw[k] = r;
        break;
      }
  }
  std::vector<double> hem(360, 0.0);
  for (int k = 0; k < 360; ++k) {
    for (int d = -3; d <= 3; ++d) hem[k] += raw[(k + d + 360) % 360];
    hem[k] /= 7.0;
  }
  return hem;
}

// Lobes of the outline: rises and falls of more than a tenth of its range (and more than two
// pixels), counted around the circle from its lowest point, so that ripples are not folds.
int count_folds(const std::vector<double>& hem, double pixel) {
  const auto [lo, hi] = std::minmax_element(hem.begin(), hem.end());
  const double swing = std::max(0.1 * (*hi - *lo), 2.0 * pixel);
  if (*hi - *lo < 2.0 * swing) return 0;
  const int n = static_cast<int>(hem.size());
  const int start = static_cast<int>(lo - hem.begin());
  int folds = 0;
  bool rising = true;
  double extreme = *lo;
  for (int k = 1; k <= n; ++k) {
    const double h = hem[(start + k) % n];
    if (rising) {
      extreme = std::max(extreme, h);
      if (h < extreme - swing) {
        ++folds;
        rising = false;
        extreme = h;
      }
    } else {
      extreme = std::min(extreme, h);
      if (h > extreme + swing) {
        rising = true;
        extreme = h;
      }
    }
  }
  return folds;
}

}  // namespace

nlohmann::json cusick_scene(const nlohmann::json& material) {
  const double h = kPedestalHeight, r = kPedestalRadius;
  return {{"name", "cusick"},
          {"cloth",
           {{"material", material},
            {"pins", {{{"ball", {{"center", {0.0, h, 0.0}}, {"radius", r}}}}}}}},
          {"forces",
           {{"gravity", {0.0, -9.81, 0.0}}, {"air_density", 1.225}, {"drag_coefficient", 1.2}}},
          // The clamp is the ball pin: the particles on the pedestal's disc stay where they
          // lie, as between the drapemeter's two discs. The column under them is thin (a rod
          // of 1 cm radius, out of reach of the hanging ring).
          {"colliders",
           {{{"type", "capsule"},
             {"a", {0.0, h - 0.08, 0.0}},
             {"b", {0.0, h - 0.015, 0.0}},
             {"radius", 0.01},
             {"friction", 0.3}}}},
          {"solver", {{"method", "implicit"}, {"dt", 1.0 / 60.0}}},
          {"duration", 6.0}};
}

void use_cusick_specimen(SceneDef& def, int rings) {
  ClothMesh disc = shapes::disc(kSpecimenRadius, rings);
  for (Vec3& p : disc.positions) p.y() += kPedestalHeight;
  def.cloth.mesh = std::make_shared<ClothMesh>(std::move(disc));
}

CusickMeasure measure_cusick(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles) {
  CusickMeasure m;
  m.shadow = cast_shadow(x, triangles, kShadowWidth, kShadowPixels);
  m.area = covered_area(m.shadow);
  const double pedestal = kPi * kPedestalRadius * kPedestalRadius;
  const double specimen = kPi * kSpecimenRadius * kSpecimenRadius;
  m.drape_coefficient = 100.0 * (m.area - pedestal) / (specimen - pedestal);
  m.hem = trace_hem(m.shadow);
  m.folds = count_folds(m.hem, m.shadow.pixel());
  return m;
}

CusickResult run_cusick(const SceneDef& def, double seconds, const CusickProgress& progress,
                        const std::atomic<bool>* stop) {
  Simulation sim(def);
  sim.set_stop_flag(stop);
  CusickResult out;
  const int most = std::max(1, static_cast<int>(std::lround(seconds / def.solver.dt)));
  // At rest: no particle moves faster than 0.5 mm/s; at least a second of draping first.
  const int least = std::min(most, static_cast<int>(std::lround(1.0 / def.solver.dt)));
  const Settled s = settle(sim, 5e-4, least, most, [&](int frame) {
    if (progress) progress(frame, most);
  });
  out.frames = s.frames;
  out.at_rest = s.at_rest;
  if (s.failed) {
    record_failure(sim, out);
    return out;
  }
  out.measure = measure_cusick(sim.state().x, sim.model().triangles);
  return out;
}

std::vector<uint8_t> shadow_picture(const CusickMeasure& m) {
  const Shadow& s = m.shadow;
  std::vector<uint8_t> rgba(static_cast<size_t>(s.size) * s.size * 4, 255);
  const double px = s.pixel(), half = 0.5 * s.width;
  auto paint = [&](int i, int j, uint8_t r, uint8_t g, uint8_t b) {
    if (i < 0 || j < 0 || i >= s.size || j >= s.size) return;
    uint8_t* p = &rgba[(static_cast<size_t>(j) * s.size + i) * 4];
    p[0] = r;
    p[1] = g;
    p[2] = b;
  };
  for (int j = 0; j < s.size; ++j)
    for (int i = 0; i < s.size; ++i) {
      const double x = (i + 0.5) * px - half, z = (j + 0.5) * px - half;
      const double r = std::hypot(x, z);
      const bool shade = s.covered[static_cast<size_t>(j) * s.size + i] != 0;
      if (shade && r <= kPedestalRadius)
        paint(i, j, 120, 134, 160);
      else if (shade)
        paint(i, j, 52, 64, 92);
      else if (r <= kSpecimenRadius)
        paint(i, j, 236, 236, 236);
      if (std::abs(r - kSpecimenRadius) < 0.75 * px) paint(i, j, 150, 150, 150);
    }
  // The traced outline, in orange.
  for (size_t k = 0; k < m.hem.size(); ++k) {
    const double a = static_cast<double>(k) * kPi / 180.0;
    const int i = static_cast<int>((m.hem[k] * std::cos(a) + half) / px);
    const int j = static_cast<int>((m.hem[k] * std::sin(a) + half) / px);
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) paint(i + di, j + dj, 240, 120, 30);
  }
  return rgba;
}

}  // namespace drape::lab
