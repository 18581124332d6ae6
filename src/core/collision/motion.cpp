#include "collision/motion.h"

#include <cmath>
#include <numbers>

namespace drape {

Mat3 rotation_xyz(const Vec3& degrees) {
  MeshTransform t;
  t.rotate = degrees;
  return t.rotation();
}

double motion_time(const MotionDef& m, double t) {
  if (!m.loop || m.keys.size() < 2) return t;
  const double first = m.keys.front().t, span = m.keys.back().t - first;
  if (t <= first || span <= 0.0) return t;
  return first + std::fmod(t - first, span);
}

Pose pose_at(const MotionDef& m, const Vec3& reference, double t) {
  Pose pose;
  if (m.keys.empty()) return pose;
  t = motion_time(m, t);
  // The keys around t (the first or last alone outside their span).
  size_t k = 0;
  while (k + 1 < m.keys.size() && m.keys[k + 1].t <= t) ++k;
  const MotionKey& a = m.keys[k];
  Vec3 translate = a.translate;
  Eigen::Quaterniond q(rotation_xyz(a.rotate));
  if (k + 1 < m.keys.size() && t > a.t) {
    const MotionKey& b = m.keys[k + 1];
    const double s = (t - a.t) / (b.t - a.t);
    translate = (1.0 - s) * a.translate + s * b.translate;
    q = q.slerp(s, Eigen::Quaterniond(rotation_xyz(b.rotate)));
  }
  // x ↦ R·(x − pivot) + pivot + translate.
  const Vec3 pivot = m.has_pivot ? m.pivot : reference;
  pose.rotation = q.toRotationMatrix();
  pose.translation = pivot + translate - pose.rotation * pivot;
  return pose;
}

}  // namespace drape
