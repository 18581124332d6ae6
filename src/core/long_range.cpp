#include "long_range.h"

#include "parallel.h"

namespace drape {

void LongRange::prepare(const ClothModel& model, const ClothState& state, const LongRangeDef& def) {
  pins_.clear();
  scale_ = 1.0 + def.slack;
  if (!def.enabled) return;
  for (int32_t i = 0; i < model.size(); ++i)
    if (state.pinned[i]) pins_.push_back(i);
}

void LongRange::apply(const ClothModel& model, ClothState& state, bool fix_velocity) const {
  if (pins_.empty()) return;
  const int32_t n = model.size();
  [[maybe_unused]] const int64_t work = int64_t{n} * static_cast<int64_t>(pins_.size());
  // Pins hold inverse mass 0, so reading x[a] while other threads write x[p] is no race.
#pragma omp parallel for schedule(static) if (worth_threads(work))
  for (int32_t p = 0; p < n; ++p) {
    if (state.inv_mass[p] == 0.0) continue;
    for (const int32_t a : pins_) {
      const Vec3 u = project_attachment(state.x[a], limit(model, p, a), state.x[p]);
      if (fix_velocity) clamp_outward_velocity(u, state.v[p]);
    }
  }
}

}  // namespace drape
