#include <cmath>
#include <cstdio>
#include <string>

#include "drape/error.h"
#include "drape/scene.h"
#include "model/model.h"

namespace drape {

const char* to_string(Method m) {
  switch (m) {
    case Method::symplectic:
      return "symplectic";
    case Method::implicit:
      return "implicit";
    case Method::xpbd:
      return "xpbd";
    case Method::fast:
      return "fast";
    case Method::automatic:
      return "auto";
  }
  return "?";
}

std::optional<Method> method_from_string(const std::string& name) {
  for (Method m : kAllMethods)
    if (name == to_string(m)) return m;
  return std::nullopt;
}

std::string method_names() {
  std::string out;
  const size_t count = std::size(kAllMethods);
  for (size_t k = 0; k < count; ++k)
    out += std::string(k == 0 ? "" : k + 1 == count ? " or " : ", ") + to_string(kAllMethods[k]);
  return out;
}

const char* to_string(Precision p) {
  return p == Precision::f64 ? "double" : "single";
}
const char* to_string(WindModel m) {
  return m == WindModel::seed ? "seed" : "aero";
}
const char* to_string(ColliderType t) {
  switch (t) {
    case ColliderType::sphere:
      return "sphere";
    case ColliderType::plane:
      return "plane";
    case ColliderType::capsule:
      return "capsule";
    case ColliderType::box:
      return "box";
    case ColliderType::mesh:
      return "mesh";
  }
  return "?";
}
const char* to_string(Orientation o) {
  return o == Orientation::vertical ? "vertical" : "horizontal";
}

namespace {

// Particle and spring indices are 32-bit; this keeps every count well inside that. (How much a
// run may cost is the command line's budget, which --force lifts: see app/runner.h.)
constexpr int64_t kMaxParticles = 100'000'000;

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

void require(bool ok, const std::string& path, const std::string& problem) {
  if (!ok) throw InputError(path, problem);
}

void finite(double x, const std::string& path) {
  require(std::isfinite(x), path, "must be a finite number");
}

void finite(const Vec3& x, const std::string& path) {
  require(x.allFinite(), path, "must hold finite numbers");
}

// lo <= x <= hi (with lo_open: lo < x).
void range(double x, double lo, double hi, const std::string& path, bool lo_open = false) {
  finite(x, path);
  const bool ok = (lo_open ? x > lo : x >= lo) && x <= hi;
  if (!ok) {
    std::string problem = "is " + num(x) + ", must be in ";
    problem += lo_open ? '(' : '[';
    problem += num(lo) + ", " + num(hi) + "]";
    throw InputError(path, problem);
  }
}

void nonnegative(double x, const std::string& path) {
  finite(x, path);
  require(x >= 0.0, path, "is " + num(x) + ", must not be negative");
}

// Key times strictly increasing, every value finite, the pivot too.
void check_motion(const MotionDef& m, const std::string& path) {
  for (size_t k = 0; k < m.keys.size(); ++k) {
    const std::string at = path + ".keys[" + std::to_string(k) + "]";
    finite(m.keys[k].t, at + ".t");
    finite(m.keys[k].translate, at + ".translate");
    finite(m.keys[k].rotate, at + ".rotate");
    if (k > 0)
      require(m.keys[k].t > m.keys[k - 1].t, at + ".t",
              "is " + num(m.keys[k].t) + ", not after the previous key's " + num(m.keys[k - 1].t) +
                  "; key times must increase");
  }
  if (m.has_pivot) finite(m.pivot, path + ".pivot");
}

void check_springs(const SpringParams& p, const std::string& path) {
  nonnegative(p.stiffness, path + ".stiffness");
  nonnegative(p.damping, path + ".damping");
}

}  // namespace

std::string cloth_mesh_key(const ClothDef& c) {
  return c.mesh_file.empty() ? "cloth.mesh" : "cloth.mesh (" + c.mesh_file + ")";
}

void check(const SceneDef& def) {
  const ClothDef& c = def.cloth;
  if (c.mesh) {
    // The grid's keys mean nothing beside a mesh: one set to other than its default is a
    // mistake worth naming (a scene file's loader names the keys it found, too).
    const ClothDef grid;
    std::string grid_keys;
    auto key = [&](bool changed, const char* name) {
      if (changed) grid_keys += std::string(grid_keys.empty() ? "" : ", ") + name;
    };
    key(c.width != grid.width || c.height != grid.height, "cloth.size");
    key(c.cols != grid.cols || c.rows != grid.rows, "cloth.resolution");
    key(c.origin != grid.origin, "cloth.origin");
    key(c.orientation != grid.orientation, "cloth.orientation");
    require(grid_keys.empty(), "cloth.mesh",
            "is given, so the grid's keys (" + grid_keys +
                ") have no meaning; place the mesh with cloth.transform instead");
    model::check_mesh(*c.mesh, cloth_mesh_key(c));
    finite(c.transform.translate, "cloth.transform.translate");
    finite(c.transform.rotate, "cloth.transform.rotate");
    finite(c.transform.scale, "cloth.transform.scale");
    for (int k = 0; k < 3; ++k)
      require(c.transform.scale[k] != 0.0 && std::abs(c.transform.scale[k]) <= 1e6,
              "cloth.transform.scale",
              "is " + num(c.transform.scale[k]) + " along " + "xyz"[k] +
                  ", must be non-zero and at most 1e6 in size (a zero scale flattens the cloth)");
  } else {
    range(c.width, 0.0, 1e4, "cloth.size[0]", true);
    range(c.height, 0.0, 1e4, "cloth.size[1]", true);
    require(c.cols >= 2 && c.rows >= 2, "cloth.resolution",
            "is " + std::to_string(c.cols) + "x" + std::to_string(c.rows) +
                ", must be at least 2x2 particles");
    const int64_t particles = int64_t{c.cols} * int64_t{c.rows};
    require(particles <= kMaxParticles, "cloth.resolution",
            std::to_string(c.cols) + "x" + std::to_string(c.rows) + " is " +
                std::to_string(particles) + " particles, more than the limit of " +
                std::to_string(kMaxParticles));
    finite(c.origin, "cloth.origin");
  }
  range(c.mass, 0.0, 1e6, "cloth.mass", true);
  for (size_t k = 0; k < c.pins.size(); ++k) {
    const Pin& p = c.pins[k];
    const std::string path = "cloth.pins[" + std::to_string(k) + "]";
    check_motion(p.motion, path + ".motion");
    switch (p.kind) {
      case PinKind::grid: {
        require(!c.mesh, path,
                "a grid index or corner name needs a grid cloth; pin a mesh by {\"vertex\": i}, "
                "{\"box\": {\"min\": [x, y, z], \"max\": [x, y, z]}} or {\"ball\": "
                "{\"center\": [x, y, z], \"radius\": r}}");
        if (p.col >= -c.cols && p.col < c.cols && p.row >= -c.rows && p.row < c.rows) break;
        char problem[200];
        std::snprintf(problem, sizeof problem,
                      "[%d, %d] is outside the %dx%d grid (columns 0..%d, rows 0..%d, or negative "
                      "from the end)",
                      p.col, p.row, c.cols, c.rows, c.cols - 1, c.rows - 1);
        throw InputError(path, problem);
      }
      case PinKind::vertex: {
        const int64_t count =
            c.mesh ? static_cast<int64_t>(c.mesh->positions.size()) : int64_t{c.cols} * c.rows;
        require(p.vertex >= 0 && p.vertex < count, path + ".vertex",
                "is " + std::to_string(p.vertex) + ", but the cloth has " + std::to_string(count) +
                    " vertices (0 to " + std::to_string(count - 1) + ")");
        break;
      }
      case PinKind::box:
        finite(p.box_min, path + ".box.min");
        finite(p.box_max, path + ".box.max");
        for (int a = 0; a < 3; ++a)
          require(p.box_min[a] <= p.box_max[a], path + ".box",
                  std::string("min is above max along ") + "xyz"[a] + " (" + num(p.box_min[a]) +
                      " > " + num(p.box_max[a]) + ")");
        break;
      case PinKind::ball:
        finite(p.ball_center, path + ".ball.center");
        range(p.ball_radius, 0.0, 1e6, path + ".ball.radius", true);
        break;
    }
  }
  check_springs(c.structural, "cloth.springs.structural");
  check_springs(c.shear, "cloth.springs.shear");
  check_springs(c.bending, "cloth.springs.bending");
  range(c.perturbation, 0.0, 1.0, "cloth.perturbation");
  range(c.long_range.slack, 0.0, 10.0, "cloth.long_range.slack");
  nonnegative(c.self_collision.thickness, "cloth.self_collision.thickness");
  nonnegative(c.self_collision.friction, "cloth.self_collision.friction");
  if (c.material) {
    const MaterialDef& m = *c.material;
    range(m.density, 0.0, 1e4, "cloth.material.density", true);
    for (int a = 0; a < 2; ++a) {
      const std::string index = "[" + std::to_string(a) + "]";
      range(m.stretch[a], 0.0, 1e9, "cloth.material.stretch" + index, true);
      range(m.bending[a], 0.0, 1e3, "cloth.material.bending" + index);
    }
    range(m.shear, 0.0, 1e9, "cloth.material.shear");
    range(m.compression, 0.0, 1.0, "cloth.material.compression");
    range(m.damping, 0.0, 10.0, "cloth.material.damping");
    require(def.solver.line_passes == 0, "solver.line_passes",
            "solves the threads as inextensible chains of one stiffness, which cloth.material's "
            "threads are not (they differ by direction and buckle under compression); leave it "
            "at 0 with a material");
  }

  const ForcesDef& f = def.forces;
  finite(f.gravity, "forces.gravity");
  if (f.air_drag) nonnegative(*f.air_drag, "forces.air_drag");
  if (f.air_density) range(*f.air_density, 0.0, 1e4, "forces.air_density");
  range(f.drag_coefficient, 0.0, 100.0, "forces.drag_coefficient");
  const WindDef& w = f.wind;
  finite(w.direction, "forces.wind.direction");
  nonnegative(w.strength, "forces.wind.strength");
  require(w.strength == 0.0 || w.direction.norm() > 0.0, "forces.wind.direction",
          "must not be zero when the wind blows");
  nonnegative(w.coefficient, "forces.wind.coefficient");
  nonnegative(w.density, "forces.wind.density");
  range(w.gust, 0.0, 1.0, "forces.wind.gust");
  nonnegative(w.gust_frequency, "forces.wind.gust_frequency");

  for (size_t k = 0; k < def.colliders.size(); ++k) {
    const ColliderDef& col = def.colliders[k];
    const std::string path = "colliders[" + std::to_string(k) + "]";
    switch (col.type) {
      case ColliderType::sphere:
        finite(col.center, path + ".center");
        range(col.radius, 0.0, 1e6, path + ".radius", true);
        break;
      case ColliderType::plane:
        finite(col.center, path + ".point");
        finite(col.normal, path + ".normal");
        require(col.normal.norm() > 0.0, path + ".normal", "must not be zero");
        break;
      case ColliderType::capsule:
        // a = b is accepted: the capsule is then a sphere of its radius.
        finite(col.a, path + ".a");
        finite(col.b, path + ".b");
        range(col.radius, 0.0, 1e6, path + ".radius", true);
        break;
      case ColliderType::box:
        finite(col.center, path + ".center");
        finite(col.rotate, path + ".rotate");
        finite(col.half_extents, path + ".half_extents");
        for (int a = 0; a < 3; ++a)
          require(col.half_extents[a] > 0.0 && col.half_extents[a] <= 1e6,
                  path + ".half_extents[" + std::to_string(a) + "]",
                  "is " + num(col.half_extents[a]) + ", must be in (0, 1e6]");
        break;
      case ColliderType::mesh:
        require(col.mesh != nullptr, path + ".file", "missing; expected the path of an OBJ file");
        finite(col.transform.translate, path + ".transform.translate");
        finite(col.transform.rotate, path + ".transform.rotate");
        finite(col.transform.scale, path + ".transform.scale");
        for (int a = 0; a < 3; ++a)
          require(col.transform.scale[a] != 0.0, path + ".transform.scale",
                  "must not be zero along any axis");
        require(!col.mesh->triangles.empty(), path + ".file",
                "(" + col.mesh_file + ") has no faces; a collider needs triangles");
        for (const Triangle& t : col.mesh->triangles)
          for (const int32_t v : t)
            require(v >= 0 && size_t(v) < col.mesh->positions.size(), path + ".file",
                    "a triangle's vertex index " + std::to_string(v) + " is out of range");
        for (const Vec3& v : col.mesh->positions) finite(v, path + ".file");
        break;
    }
    nonnegative(col.friction, path + ".friction");
    nonnegative(col.thickness, path + ".thickness");
    check_motion(col.motion, path + ".motion");
  }

  const SolverDef& s = def.solver;
  range(s.dt, 1e-6, 0.1, "solver.dt");
  range(s.tolerance, 1e-4, 1.0, "solver.tolerance");
  require(s.precision == Precision::f64 || s.method == Method::xpbd ||
              s.method == Method::automatic,  // which says why below
          "solver.precision",
          std::string("\"single\" is implemented by the xpbd method only, not by ") +
              to_string(s.method) + "; use \"double\" or solver.method \"xpbd\"");
  require(s.substeps >= 0 && s.substeps <= 1'000'000, "solver.substeps",
          "is " + std::to_string(s.substeps) + ", must be in [0, 1000000] (0 = automatic)");
  range(s.safety, 0.0, 1.0, "solver.safety", true);
  require(s.max_substeps >= 1 && s.max_substeps <= 1'000'000, "solver.max_substeps",
          "is " + std::to_string(s.max_substeps) + ", must be in [1, 1000000]");
  require(
      s.iterations >= 0 && s.iterations <= 10000, "solver.iterations",
      "is " + std::to_string(s.iterations) + ", must be in [0, 10000] (0 = the method's default)");
  require(s.stiff_sweeps >= 0 && s.stiff_sweeps <= 10000, "solver.stiff_sweeps",
          "is " + std::to_string(s.stiff_sweeps) + ", must be in [0, 10000]");
  require(s.line_passes >= 0 && s.line_passes <= 10000, "solver.line_passes",
          "is " + std::to_string(s.line_passes) + ", must be in [0, 10000]");
  if (s.method == Method::automatic) {
    // auto sets these itself; a value asked for would be silently replaced.
    const SolverDef defaults;
    auto chosen = [&](bool set, const char* key) {
      require(!set, std::string("solver.") + key,
              "is chosen by the auto method (the default) itself; remove it, or name a method "
              "(e.g. solver.method \"xpbd\") to set it");
    };
    chosen(s.precision != defaults.precision, "precision");
    chosen(s.substeps != defaults.substeps, "substeps");
    chosen(s.iterations != defaults.iterations, "iterations");
    chosen(s.stiff_sweeps != defaults.stiff_sweeps, "stiff_sweeps");
    chosen(s.line_passes != defaults.line_passes, "line_passes");
  }
  // Solved exactly, rows and columns are rigid, and rigid chains under a pin's whole load
  // oscillate and tear at the steps line passes are for; attachments take that load.
  require(s.line_passes == 0 || def.cloth.pins.empty() || def.cloth.long_range.enabled,
          "solver.line_passes",
          "needs cloth.long_range: true on a pinned cloth (its rows and columns, solved exactly, "
          "are rigid, and rigid chains carrying the cloth's weight to a pin become unstable at "
          "large steps; the attachments carry it)");
  finite(s.line_relaxation, "solver.line_relaxation");
  require(s.line_relaxation > 0.0 && s.line_relaxation < 2.0, "solver.line_relaxation",
          "is " + num(s.line_relaxation) +
              ", must be in (0, 2) (over-relaxation diverges from 2 up; 1 = none)");
  range(s.cg_tolerance, 0.0, 1.0, "solver.cg_tolerance", true);
  require(s.cg_tolerance < 1.0, "solver.cg_tolerance", "must be below 1");
  require(s.cg_max_iterations >= 1 && s.cg_max_iterations <= 100000, "solver.cg_max_iterations",
          "is " + std::to_string(s.cg_max_iterations) + ", must be in [1, 100000]");
  range(s.chebyshev_rho, 0.0, 1.0, "solver.chebyshev_rho");
  require(s.chebyshev_rho < 1.0, "solver.chebyshev_rho", "must be below 1 (0 = automatic)");
  range(def.duration, 0.0, 1e7, "duration");
}

int64_t frame_count(const SceneDef& def) {
  return static_cast<int64_t>(std::llround(def.duration / def.solver.dt));
}

}  // namespace drape
