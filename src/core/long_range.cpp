#include "long_range.h"

#include <algorithm>

#include "model/model.h"
#include "parallel.h"

namespace drape {

void LongRange::prepare(const ClothModel& model, const ClothState& state,
                        const LongRangeDef& def) {
  pins_.clear();
  pin_.clear();
  limit_.clear();
  tethers_ = 0;
  uniform_ = false;
  if (!def.enabled) return;
  for (int32_t i = 0; i < model.size(); ++i)
    if (state.pinned[i]) pins_.push_back(i);
  if (pins_.empty()) return;
  tethers_ = std::min<int>(kMaxTethers, static_cast<int>(pins_.size()));
  model::nearest_sources(model, pins_, tethers_, pin_, limit_);
  for (double& l : limit_) l *= 1.0 + def.slack;
  uniform_ = tethers_ == static_cast<int>(pins_.size());
  for (int32_t p = 0; p < model.size() && uniform_; ++p)
    for (int t = 0; t < tethers_; ++t) uniform_ = uniform_ && pin(p, t) == pins_[t];
}

void LongRange::apply(ClothState& state, bool fix_velocity) const {
  if (pins_.empty()) return;
  const int32_t n = static_cast<int32_t>(state.x.size());
  [[maybe_unused]] const int64_t work = int64_t{n} * tethers_;
  // Pins hold inverse mass 0, so reading x[a] while other threads write x[p] is no race.
#pragma omp parallel for schedule(static) if (worth_threads(work))
  for (int32_t p = 0; p < n; ++p) {
    if (state.inv_mass[p] == 0.0) continue;
    for (int t = 0; t < tethers_ && pin(p, t) >= 0; ++t) {
      const Vec3 u = project_attachment(state.x[pin(p, t)], limit(p, t), state.x[p]);
      if (fix_velocity) clamp_outward_velocity(u, state.v[p]);
    }
  }
}

}  // namespace drape
