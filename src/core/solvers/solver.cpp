#include "solver.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "forces.h"
#include "long_range.h"
#include "parallel.h"

namespace drape {

std::unique_ptr<Solver> make_solver(const SolverDef& def, const ClothModel& model) {
  switch (def.method) {
    case Method::symplectic: return make_symplectic();
    case Method::implicit: return make_implicit();
    // The grid solver's kernels are for the seed's uniform spring families; a material's
    // springs differ by direction and at the border, and it bends by elements: the mesh
    // solver runs it on a grid too.
    case Method::xpbd:
      return model.grid.present() && !model.material ? make_grid_xpbd(def.precision)
                                                     : make_mesh_xpbd(def.precision);
    case Method::fast: return make_fast();
    // auto's ladder holds the strain to solver.tolerance with xpbd's line passes, which solve
    // the threads as inextensible chains; a material's threads stretch as the fabric does and
    // buckle: a choice of its own (auto_solver.cpp).
    case Method::automatic: return model.material ? make_material_auto() : make_auto();
  }
  return nullptr;
}

std::string count_text(double count) {
  char text[48];
  std::snprintf(text, sizeof text, "%.0f", count);
  return text;
}

int substeps_in(double dt, double frame_dt, int per_frame) {
  // A part of a frame is dt = frame_dt / parts up to round-off, which must not add a substep.
  const double share = std::ceil(per_frame * (dt / frame_dt) * (1.0 - 1e-9));
  return std::clamp(static_cast<int>(share), 1, per_frame);
}

void apply_air_drag(World& w, double h) {
  ClothState& s = w.state;
  forces::apply_drag(w.air_drag(), s.inv_mass, h, s.v);
  if (w.area_drag()) {
    update_normals(w.model, s);
    forces::apply_area_drag(w.model, s, w.air_density(), w.forces.drag_coefficient, h, s.v);
  }
}

void drift_constrain(World& w, double h) {
  ClothState& s = w.state;
  const int32_t n = w.model.size();
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t i = 0; i < n; ++i) s.x[i] += h * s.v[i];
  w.attachments.apply(s, true);
  resolve_all_contacts(w);
}

void resolve_all_contacts(World& w) {
  resolve_contacts(w.colliders, w.model, w.state);
  if (w.features) {
    StateCloth cloth{w.state};
    w.features->apply(w.colliders, cloth);
  }
}

}  // namespace drape
