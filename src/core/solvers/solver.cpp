#include "solver.h"

#include <cstdio>

#include "forces.h"
#include "long_range.h"
#include "parallel.h"

namespace drape {

std::unique_ptr<Solver> make_solver(const SolverDef& def, const ClothModel& model) {
  switch (def.method) {
    case Method::symplectic: return make_symplectic();
    case Method::implicit: return make_implicit();
    case Method::xpbd:
      return model.grid.present() ? make_grid_xpbd(def.precision) : make_mesh_xpbd(def.precision);
    case Method::fast: return make_fast();
    case Method::automatic: return make_auto();
  }
  return nullptr;
}

std::string count_text(double count) {
  char text[48];
  std::snprintf(text, sizeof text, "%.0f", count);
  return text;
}

void drag_drift_constrain(World& w, double h) {
  ClothState& s = w.state;
  const int32_t n = w.model.size();
  forces::apply_drag(w.forces.air_drag, s.inv_mass, h, s.v);
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t i = 0; i < n; ++i) s.x[i] += h * s.v[i];
  w.attachments.apply(s, true);
  resolve_contacts(w.colliders, s);
}

}  // namespace drape
