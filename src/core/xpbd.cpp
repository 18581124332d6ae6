// `xpbd` and `hierarchical`: extended position-based dynamics with small steps (Macklin,
// Müller & Chentanez 2016, "XPBD"; Macklin et al. 2019, "Small steps in physics simulation"),
// written for the cloth's regular grid. Per substep: predict with the external forces, project
// the springs as compliant distance constraints (α = 1/k, damping from the spring's c) by
// Gauss–Seidel colour by colour, apply long-range attachments, derive v = (x − x_prev)/h,
// resolve contacts.
//
// `hierarchical` adds, before the springs, a coarse-to-fine pass over a grid hierarchy
// (after Müller 2008, "Hierarchical position based dynamics"): level ℓ keeps every 2^ℓ-th
// row and column; each level holds its nodes' horizontal and vertical distances to at most
// their rest length (unilateral, so the cloth may still fold between nodes); the correction of
// a level is interpolated bilinearly to the next finer one. Gauss–Seidel on the fine springs
// alone removes a stretch over w particles in about w² sweeps; the hierarchy removes it in
// about log w, which is what lets a stiff cloth meet a 1% strain bar at a few substeps.
//
// The state is kept as structure-of-arrays, and a family of springs (one direction of one
// kind) is swept row by row, so the inner loops are contiguous (or strided by 2 or 4 along a
// row) and vectorise. Rows are split between threads; a colour's springs share no particle,
// so the result has the same bits for any thread count.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "constraints.h"
#include "drape/error.h"
#include "forces.h"
#include "long_range.h"
#include "parallel.h"
#include "solver.h"

namespace drape {

namespace {

constexpr int kDefaultIterations = 1;
constexpr int kCoarsestNodes = 5;     ///< coarsen while a side has more nodes than this
constexpr int kCoarseIterations = 2;  ///< Gauss–Seidel sweeps per coarse level and substep

/// Positions (or any 3-vector field) as three arrays.
struct Soa {
  std::vector<double> x, y, z;
  void resize(size_t n) {
    x.assign(n, 0.0);
    y.assign(n, 0.0);
    z.assign(n, 0.0);
  }
};

/// One family of fine springs: from (c, r) to (c + dc, r + dr), all of one kind, with one rest
/// length, stiffness and damping (build_grid makes them so; prepare() checks).
struct Family {
  int dc = 0, dr = 0;  ///< dr ≥ 0; dr = 0 means dc > 0
  int shift = 0;       ///< for dc < 0, the spring starts at column c + 1: (c + 1, r)–(c, r + 1)
  double rest = 0.0, stiffness = 0.0, damping = 0.0;
};

/// One coarse level: a sub-grid of the fine grid, stored compactly.
struct Level {
  int cols = 0, rows = 0;
  std::vector<int> col, row;  ///< fine column / row of each node
  /// Where each node of the next finer level lies: left (top) node index here and weight of the
  /// right (bottom) one, for the bilinear interpolation of corrections.
  std::vector<int> finer_col_left, finer_row_top;
  std::vector<double> finer_col_t, finer_row_t;
  std::vector<double> rest_h, rest_v;  ///< per column gap, per row gap
  std::vector<double> inv_mass;        ///< 0 where the node is pinned or held
  Soa x, x0;                           ///< now, and at the start of the substep
  int size() const { return cols * rows; }
};

class GridXpbd final : public Solver {
 public:
  explicit GridXpbd(bool hierarchy) : hierarchy_(hierarchy) {}

  void prepare(const World& w, const SolverDef& def) override {
    const ClothModel& m = w.model;
    cols_ = m.cols;
    rows_ = m.rows;
    const int32_t n = m.size();
    x_.resize(n);
    x_prev_.resize(n);
    v_.resize(n);
    accel_.resize(n);
    scratch_.assign(n, Vec3::Zero());
    inv_mass_ = w.state.inv_mass;
    prepare_families(m);
    iterations_ = def.iterations > 0 ? def.iterations : kDefaultIterations;
    lambda_.assign(iterations_ > 1 ? families_.size() * static_cast<size_t>(n) : 0, 0.0);
    attachments_.prepare(m, w.state, w.long_range);
    attachment_limit_.resize(attachments_.pins().size() * static_cast<size_t>(n));
    for (size_t k = 0; k < attachments_.pins().size(); ++k)
      for (int32_t i = 0; i < n; ++i)
        attachment_limit_[k * n + i] = attachments_.limit(m, i, attachments_.pins()[k]);
    levels_.clear();
    if (hierarchy_) prepare_levels(m, w.state);
    if (def.substeps > 0) {
      substeps_ = def.substeps;
      return;
    }
    substeps_ = automatic_substeps(w, def);
  }

  void step_frame(World& w, double dt) override {
    const double h = dt / substeps_;
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    // External acceleration, held over the frame: gravity plus the wind at the frame's start.
    // The wind does not depend on the substep's positions, so it is as stable at the frame
    // step as gravity, and evaluating it once keeps many substeps cheap.
    const bool wind = w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0;
    if (wind) {
      std::fill(scratch_.begin(), scratch_.end(), Vec3::Zero());
      update_normals(m, s);
      forces::add_wind(m, s, w.forces.wind, w.time, scratch_);
    }
    const Vec3 g = w.forces.gravity;
    const double drag = w.forces.air_drag;

#pragma omp parallel if (worth_threads(n))
    {
#pragma omp for schedule(static)
      for (int32_t i = 0; i < n; ++i) {
        const Vec3 a = wind ? Vec3(g + s.inv_mass[i] * scratch_[i]) : g;
        accel_.x[i] = a.x();
        accel_.y[i] = a.y();
        accel_.z[i] = a.z();
        x_.x[i] = s.x[i].x();
        x_.y[i] = s.x[i].y();
        x_.z[i] = s.x[i].z();
        v_.x[i] = s.v[i].x();
        v_.y[i] = s.v[i].y();
        v_.z[i] = s.v[i].z();
        inv_mass_[i] = s.inv_mass[i];
      }
      for (int k = 0; k < substeps_; ++k) {
        predict(h, drag);
        if (!levels_.empty()) coarse_to_fine();
        for (int it = 0; it < iterations_; ++it) project_springs(h, it);
        if (attachments_.active()) apply_attachments();
        finish_substep(w.colliders, h);
      }
#pragma omp for schedule(static)
      for (int32_t i = 0; i < n; ++i) {
        s.x[i] = Vec3(x_.x[i], x_.y[i], x_.z[i]);
        s.v[i] = Vec3(v_.x[i], v_.y[i], v_.z[i]);
      }
    }
    update_normals(m, s);
  }

  int substeps() const override {
    return substeps_;
  }

 private:
  // ---- Set-up --------------------------------------------------------------------------------

  // Groups the model's springs into families by direction and kind, and checks that each family
  // is uniform (the grid builder makes it so; a model that is not would be a programming error).
  void prepare_families(const ClothModel& m) {
    families_.clear();
    std::vector<int64_t> counts;
    for (const Spring& sp : m.springs) {
      const int ci = sp.i % cols_, ri = sp.i / cols_, cj = sp.j % cols_, rj = sp.j / cols_;
      Family f;
      f.dc = cj - ci;
      f.dr = rj - ri;
      if (f.dr < 0 || (f.dr == 0 && f.dc <= 0))
        throw std::logic_error("xpbd: spring not in grid order");
      f.shift = f.dc < 0 ? -f.dc : 0;
      f.rest = sp.rest;
      f.stiffness = sp.stiffness;
      f.damping = sp.damping;
      auto same = [&](const Family& o) { return o.dc == f.dc && o.dr == f.dr; };
      auto it = std::find_if(families_.begin(), families_.end(), same);
      if (it == families_.end()) {
        families_.push_back(f);
        counts.push_back(1);
      } else {
        if (std::abs(it->rest - f.rest) > 1e-12 * f.rest || it->stiffness != f.stiffness ||
            it->damping != f.damping)
          throw std::logic_error("xpbd: springs of one grid direction differ");
        ++counts[it - families_.begin()];
      }
    }
    // Every spring of a family must be present for the row loops to be right.
    for (size_t k = 0; k < families_.size(); ++k) {
      const Family& f = families_[k];
      const int64_t expected = int64_t{cols_ - std::abs(f.dc)} * (rows_ - f.dr);
      if (counts[k] != expected) throw std::logic_error("xpbd: grid family incomplete");
    }
  }

  // Builds the coarse levels: each keeps every other node of the level below, plus its last.
  void prepare_levels(const ClothModel& m, const ClothState& s) {
    std::vector<int> cols(cols_), rows(rows_);
    for (int c = 0; c < cols_; ++c) cols[c] = c;
    for (int r = 0; r < rows_; ++r) rows[r] = r;
    auto coarser = [](const std::vector<int>& fine) {
      std::vector<int> out;
      for (size_t k = 0; k < fine.size(); k += 2) out.push_back(fine[k]);
      if (out.back() != fine.back()) out.push_back(fine.back());
      return out;
    };
    // For each node of `fine`, the interval of `coarse` it lies in, by rest coordinate.
    auto locate = [](const std::vector<int>& fine, const std::vector<int>& coarse,
                     std::vector<int>& left, std::vector<double>& t) {
      left.assign(fine.size(), 0);
      t.assign(fine.size(), 0.0);
      size_t k = 0;
      for (size_t a = 0; a < fine.size(); ++a) {
        while (k + 2 < coarse.size() && coarse[k + 1] <= fine[a]) ++k;
        left[a] = static_cast<int>(k);
        t[a] = static_cast<double>(fine[a] - coarse[k]) / (coarse[k + 1] - coarse[k]);
      }
    };
    const double dx = (m.rest_position[m.index(1, 0)] - m.rest_position[0]).norm();
    const double dy = (m.rest_position[m.index(0, 1)] - m.rest_position[0]).norm();
    while (static_cast<int>(std::max(cols.size(), rows.size())) > kCoarsestNodes &&
           std::min(cols.size(), rows.size()) > 2) {
      Level lv;
      lv.col = coarser(cols);
      lv.row = coarser(rows);
      lv.cols = static_cast<int>(lv.col.size());
      lv.rows = static_cast<int>(lv.row.size());
      locate(cols, lv.col, lv.finer_col_left, lv.finer_col_t);
      locate(rows, lv.row, lv.finer_row_top, lv.finer_row_t);
      for (int a = 0; a + 1 < lv.cols; ++a) lv.rest_h.push_back((lv.col[a + 1] - lv.col[a]) * dx);
      for (int b = 0; b + 1 < lv.rows; ++b) lv.rest_v.push_back((lv.row[b + 1] - lv.row[b]) * dy);
      lv.x.resize(lv.size());
      lv.x0.resize(lv.size());
      levels_.push_back(std::move(lv));
      cols = levels_.back().col;
      rows = levels_.back().row;
    }
    // Node masses: each fine particle's mass shared among the corners of its cell at that level
    // by its bilinear weights, so a level carries the whole cloth's mass.
    for (Level& lv : levels_) {
      std::vector<double> mass(lv.size(), 0.0);
      std::vector<int> left, top;
      std::vector<double> tc, tr;
      std::vector<int> all_cols(cols_), all_rows(rows_);
      for (int c = 0; c < cols_; ++c) all_cols[c] = c;
      for (int r = 0; r < rows_; ++r) all_rows[r] = r;
      locate(all_cols, lv.col, left, tc);
      locate(all_rows, lv.row, top, tr);
      for (int r = 0; r < rows_; ++r)
        for (int c = 0; c < cols_; ++c) {
          const double mp = m.mass[m.index(c, r)];
          const int a = left[c], b = top[r];
          mass[b * lv.cols + a] += mp * (1 - tc[c]) * (1 - tr[r]);
          mass[b * lv.cols + a + 1] += mp * tc[c] * (1 - tr[r]);
          mass[(b + 1) * lv.cols + a] += mp * (1 - tc[c]) * tr[r];
          mass[(b + 1) * lv.cols + a + 1] += mp * tc[c] * tr[r];
        }
      lv.inv_mass.resize(lv.size());
      for (int b = 0; b < lv.rows; ++b)
        for (int a = 0; a < lv.cols; ++a) {
          const int k = b * lv.cols + a;
          const bool fixed = s.inv_mass[m.index(lv.col[a], lv.row[b])] == 0.0;
          lv.inv_mass[k] = fixed || mass[k] <= 0.0 ? 0.0 : 1.0 / mass[k];
        }
    }
  }

  // Substeps per frame when the scene leaves it to the method.
  int automatic_substeps(const World& w, const SolverDef& def) const {
    double kw = 0.0;
    for (const Spring& s : w.model.springs)
      kw = std::max(kw, s.stiffness * std::max(w.state.inv_mass[s.i], w.state.inv_mass[s.j]));
    // With one iteration per substep a spring reaches an effective stiffness of about
    // min(k, m/h²), so the smallest count with m/h² ≥ k for every spring: below it, stiff and
    // soft springs (stretch and bending) look alike and the cloth acts like rubber. The same
    // rule holds with the hierarchy, which adds length limits but no bending softness.
    const double needed = std::ceil(def.dt * std::sqrt(kw));
    if (!(needed <= def.max_substeps)) {
      throw InputError("solver.substeps",
                       "the " + std::string(hierarchy_ ? "hierarchical" : "xpbd") +
                           " method needs " + std::to_string(needed) +
                           " substeps per frame to reach the springs' stiffness, more than "
                           "solver.max_substeps = " +
                           std::to_string(def.max_substeps) +
                           "; lower the stiffness, raise the mass, use a smaller dt, or fix "
                           "solver.substeps yourself (softer cloth)");
    }
    return std::max(1, static_cast<int>(needed));
  }

  // ---- The substep (all called inside one parallel region) -----------------------------------

  // v += h·a, semi-implicit drag, x_prev = x, x += h·v. Pinned and held particles stay put.
  void predict(double h, double air_drag) {
    const int32_t n = cols_ * rows_;
    double* __restrict px = x_.x.data(), * __restrict py = x_.y.data(), * __restrict pz = x_.z.data();
    double *__restrict qx = x_prev_.x.data(), *__restrict qy = x_prev_.y.data(),
                       *__restrict qz = x_prev_.z.data();
    double* __restrict vx = v_.x.data(), * __restrict vy = v_.y.data(), * __restrict vz = v_.z.data();
    const double *__restrict ax = accel_.x.data(), *__restrict ay = accel_.y.data(),
                             *__restrict az = accel_.z.data();
    const double* __restrict w = inv_mass_.data();
#pragma omp for simd schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      qx[i] = px[i];
      qy[i] = py[i];
      qz[i] = pz[i];
      // Branch-free so the loop vectorises: `free` is 1 for a free particle, 0 otherwise.
      const double free = w[i] > 0.0 ? 1.0 : 0.0, hf = h * free;
      const double ux = vx[i] + hf * ax[i], uy = vy[i] + hf * ay[i], uz = vz[i] + hf * az[i];
      const double f = forces::drag_factor(air_drag * w[i] * h, ux, uy, uz);
      vx[i] = f * ux;
      vy[i] = f * uy;
      vz[i] = f * uz;
      px[i] += hf * vx[i];
      py[i] += hf * vy[i];
      pz[i] += hf * vz[i];
    }
  }

  // One Gauss–Seidel sweep over every fine spring, family by family and colour by colour.
  void project_springs(double h, int iteration) {
    for (size_t k = 0; k < families_.size(); ++k) {
      const Family& f = families_[k];
      if (f.stiffness <= 0.0) continue;  // infinite compliance: no constraint
      const double alpha_tilde = 1.0 / (f.stiffness * h * h);
      // β = c (N·s/m): γ = α̃·β·h²/h = c/(k·h) (Macklin et al. 2016, eq. 26).
      const double gamma = f.damping / (f.stiffness * h);
      for (int colour = 0; colour < 2; ++colour) {
        if (lambda_.empty()) {
          sweep_family<false>(f, colour, alpha_tilde, gamma, nullptr, true);
        } else {
          double* lambda = lambda_.data() + k * cols_ * rows_;
          sweep_family<true>(f, colour, alpha_tilde, gamma, lambda, iteration == 0);
        }
      }
    }
  }

  // The springs of family f whose colour is `colour`: for dr > 0 the rows r with
  // (r / dr) even or odd, each row's springs contiguous; for dr = 0 the springs along a row
  // whose (c / dc) is even or odd. Springs are indexed for λ by their first particle.
  template <bool kLambda>
  void sweep_family(const Family& f, int colour, double alpha_tilde, double gamma,
                    double* __restrict lambda, bool first) {
    double* __restrict px = x_.x.data(), * __restrict py = x_.y.data(), * __restrict pz = x_.z.data();
    const double *__restrict qx = x_prev_.x.data(), *__restrict qy = x_prev_.y.data(),
                             *__restrict qz = x_prev_.z.data();
    const double* __restrict w = inv_mass_.data();
    const int cols = cols_;
    const double rest = f.rest;
    // λ is kept only when several iterations need it; with one it is 0 at the start.
    auto one = [&](int i, int j) {
      if constexpr (kLambda) {
        const double l0 = first ? 0.0 : lambda[i];
        lambda[i] = l0 + xpbd_project<false, true>(px, py, pz, qx, qy, qz, w, i, j, rest,
                                                   alpha_tilde, gamma, l0);
      } else {
        xpbd_project<false, true>(px, py, pz, qx, qy, qz, w, i, j, rest, alpha_tilde, gamma, 0.0);
      }
    };
    if (f.dr > 0) {
      const int span = cols - std::abs(f.dc);
      const int bands = (rows_ - f.dr + f.dr - 1) / f.dr;  // row bands of height dr
      // Band b covers rows [b·dr, b·dr + dr); colour = b mod 2.
#pragma omp for schedule(static)
      for (int b = colour; b < bands; b += 2) {
        for (int r = b * f.dr; r < std::min((b + 1) * f.dr, rows_ - f.dr); ++r) {
          const int i0 = r * cols + f.shift, j0 = (r + f.dr) * cols + f.shift + f.dc;
#pragma omp simd
          for (int c = 0; c < span; ++c) one(i0 + c, j0 + c);
        }
      }
    } else {
      const int dc = f.dc;
#pragma omp for schedule(static)
      for (int r = 0; r < rows_; ++r) {
        const int row = r * cols;
        for (int e = 0; e < dc; ++e) {
          // Springs at c = (2q + colour)·dc + e, for q = 0, 1, ...
          const int first_c = colour * dc + e, step = 2 * dc;
          const int count = first_c + dc < cols ? (cols - dc - first_c + step - 1) / step : 0;
#pragma omp simd
          for (int q = 0; q < count; ++q) {
            const int i = row + first_c + q * step;
            one(i, i + dc);
          }
        }
      }
    }
  }

  // The coarse-to-fine pass: from the coarsest level down, start from the level's positions at
  // the start of the pass plus the interpolated correction of the level above, sweep its
  // unilateral distance limits, and hand the correction on. The finest level is the cloth.
  void coarse_to_fine() {
    // Snapshot every level's nodes from the cloth.
    for (Level& lv : levels_) {
#pragma omp for schedule(static)
      for (int b = 0; b < lv.rows; ++b)
        for (int a = 0; a < lv.cols; ++a) {
          const int k = b * lv.cols + a, i = lv.row[b] * cols_ + lv.col[a];
          lv.x0.x[k] = lv.x.x[k] = x_.x[i];
          lv.x0.y[k] = lv.x.y[k] = x_.y[i];
          lv.x0.z[k] = lv.x.z[k] = x_.z[i];
        }
    }
    for (size_t l = levels_.size(); l-- > 0;) {
      Level& lv = levels_[l];
      for (int it = 0; it < kCoarseIterations; ++it) sweep_level(lv);
      if (l > 0) {
        Level& finer = levels_[l - 1];
        prolong(lv, finer.cols, finer.rows, finer.inv_mass.data(), finer.x);
      } else {
        prolong(lv, cols_, rows_, inv_mass_.data(), x_);
      }
    }
  }

  // Adds the bilinear interpolation of lv's correction (x − x0) to the finer level's free nodes.
  void prolong(const Level& lv, int cols, int rows, const double* __restrict w, Soa& out) {
    const double *__restrict cx = lv.x.x.data(), *__restrict cy = lv.x.y.data(),
                             *__restrict cz = lv.x.z.data();
    const double *__restrict c0x = lv.x0.x.data(), *__restrict c0y = lv.x0.y.data(),
                             *__restrict c0z = lv.x0.z.data();
    double* __restrict ox = out.x.data(), * __restrict oy = out.y.data(), * __restrict oz = out.z.data();
    const int* __restrict left = lv.finer_col_left.data();
    const double* __restrict tc = lv.finer_col_t.data();
    const int lc = lv.cols;
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const int top = lv.finer_row_top[r];
      const double s = lv.finer_row_t[r];
      const int k0 = top * lc, k1 = (top + 1) * lc;
#pragma omp simd
      for (int c = 0; c < cols; ++c) {
        const int i = r * cols + c;
        const double free = w[i] > 0.0 ? 1.0 : 0.0;
        const int a = left[c];
        const double t = tc[c];
        const double w00 = free * (1 - t) * (1 - s), w01 = free * t * (1 - s),
                     w10 = free * (1 - t) * s, w11 = free * t * s;
        ox[i] += w00 * (cx[k0 + a] - c0x[k0 + a]) + w01 * (cx[k0 + a + 1] - c0x[k0 + a + 1]) +
                 w10 * (cx[k1 + a] - c0x[k1 + a]) + w11 * (cx[k1 + a + 1] - c0x[k1 + a + 1]);
        oy[i] += w00 * (cy[k0 + a] - c0y[k0 + a]) + w01 * (cy[k0 + a + 1] - c0y[k0 + a + 1]) +
                 w10 * (cy[k1 + a] - c0y[k1 + a]) + w11 * (cy[k1 + a + 1] - c0y[k1 + a + 1]);
        oz[i] += w00 * (cz[k0 + a] - c0z[k0 + a]) + w01 * (cz[k0 + a + 1] - c0z[k0 + a + 1]) +
                 w10 * (cz[k1 + a] - c0z[k1 + a]) + w11 * (cz[k1 + a + 1] - c0z[k1 + a + 1]);
      }
    }
  }

  // One Gauss–Seidel sweep of a level's limits |x_j − x_i| ≤ rest between horizontal and
  // vertical neighbours (hard: α = 0, no damping).
  void sweep_level(Level& lv) {
    double* __restrict px = lv.x.x.data(), * __restrict py = lv.x.y.data(), * __restrict pz = lv.x.z.data();
    const double* __restrict w = lv.inv_mass.data();
    const double* __restrict rest_h = lv.rest_h.data();
    const int lc = lv.cols;
    for (int colour = 0; colour < 2; ++colour) {
#pragma omp for schedule(static)
      for (int b = 0; b < lv.rows; ++b) {
        const int row = b * lc;
        const int count = (lc - 1 - colour + 1) / 2;
#pragma omp simd
        for (int q = 0; q < count; ++q) {
          const int a = 2 * q + colour;
          xpbd_project<true, false>(px, py, pz, nullptr, nullptr, nullptr, w, row + a, row + a + 1,
                                    rest_h[a], 0.0, 0.0, 0.0);
        }
      }
    }
    for (int colour = 0; colour < 2; ++colour) {
#pragma omp for schedule(static)
      for (int b = colour; b < lv.rows - 1; b += 2) {
        const int row = b * lc;
        const double rest = lv.rest_v[b];
#pragma omp simd
        for (int a = 0; a < lc; ++a)
          xpbd_project<true, false>(px, py, pz, nullptr, nullptr, nullptr, w, row + a, row + lc + a,
                                    rest, 0.0, 0.0, 0.0);
      }
    }
  }

  // Long-range attachments on every free particle, pin after pin (project_attachment in
  // long_range.h, branch-free so it vectorises; the limits are tabulated at set-up).
  void apply_attachments() {
    const int32_t n = cols_ * rows_;
    double* __restrict px = x_.x.data(), * __restrict py = x_.y.data(), * __restrict pz = x_.z.data();
    const double* __restrict w = inv_mass_.data();
    const std::vector<int32_t>& pins = attachments_.pins();
#pragma omp for schedule(static)
    for (int r = 0; r < rows_; ++r) {
      for (size_t k = 0; k < pins.size(); ++k) {
        const double ax = px[pins[k]], ay = py[pins[k]], az = pz[pins[k]];
        const double* __restrict limit = attachment_limit_.data() + k * n;
#pragma omp simd
        for (int i = r * cols_; i < (r + 1) * cols_; ++i) {
          const double dx = px[i] - ax, dy = py[i] - ay, dz = pz[i] - az;
          const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
          const bool pull = w[i] > 0.0 && len > limit[i];
          const double scale = limit[i] / (pull ? len : 1.0);
          px[i] = pull ? ax + scale * dx : px[i];
          py[i] = pull ? ay + scale * dy : py[i];
          pz[i] = pull ? az + scale * dz : pz[i];
        }
      }
    }
  }

  // Contacts for the particles near a collider (position-level, with friction), then
  // v = (x − x_prev)/h.
  void finish_substep(const std::vector<Collider>& colliders, double h) {
    const double inv_h = 1.0 / h;
#pragma omp for schedule(static)
    for (int r = 0; r < rows_; ++r) {
      const int i0 = r * cols_;
      double* __restrict px = x_.x.data() + i0, * __restrict py = x_.y.data() + i0, * __restrict pz = x_.z.data() + i0;
      const double *__restrict qx = x_prev_.x.data() + i0, *__restrict qy = x_prev_.y.data() + i0,
                               *__restrict qz = x_prev_.z.data() + i0;
      double* __restrict vx = v_.x.data() + i0, * __restrict vy = v_.y.data() + i0, * __restrict vz = v_.z.data() + i0;
      for (const Collider& col : colliders) {
        for (int c = 0; c < cols_; ++c) {
          if (inv_mass_[i0 + c] == 0.0 || !near(col, px[c], py[c], pz[c])) continue;
          Vec3 x(px[c], py[c], pz[c]);
          resolve_contact_position(col, Vec3(qx[c], qy[c], qz[c]), x);
          px[c] = x.x();
          py[c] = x.y();
          pz[c] = x.z();
        }
      }
#pragma omp simd
      for (int c = 0; c < cols_; ++c) {
        vx[c] = (px[c] - qx[c]) * inv_h;
        vy[c] = (py[c] - qy[c]) * inv_h;
        vz[c] = (pz[c] - qz[c]) * inv_h;
      }
    }
  }

  // A cheap test that passes every particle resolve_contact_position would move.
  static bool near(const Collider& c, double x, double y, double z) {
    const double dx = x - c.center.x(), dy = y - c.center.y(), dz = z - c.center.z();
    if (c.type == ColliderType::plane)
      return c.normal.x() * dx + c.normal.y() * dy + c.normal.z() * dz < c.thickness;
    const double reach = c.radius + c.thickness;
    return dx * dx + dy * dy + dz * dz < reach * reach;
  }

  bool hierarchy_;
  int cols_ = 0, rows_ = 0;
  int substeps_ = 1;
  int iterations_ = kDefaultIterations;
  Soa x_, x_prev_, v_, accel_;
  std::vector<double> inv_mass_;
  std::vector<Vec3> scratch_;  ///< wind forces, AoS as forces.h writes them
  std::vector<Family> families_;
  std::vector<double> lambda_;  ///< per family and first particle; only with iterations > 1
  std::vector<Level> levels_;
  LongRange attachments_;
  std::vector<double> attachment_limit_;  ///< per pin, per particle, m
};

}  // namespace

std::unique_ptr<Solver> make_xpbd() {
  return std::make_unique<GridXpbd>(false);
}

std::unique_ptr<Solver> make_hierarchical() {
  return std::make_unique<GridXpbd>(true);
}

}  // namespace drape
