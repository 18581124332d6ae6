// The particles as the xpbd solvers keep them: structure-of-arrays in the solver's precision,
// each position as a base plus a move, and the stages of a substep that act on particles alone
// (predict, attachments, contacts, velocities), each over a range of slots so that a solver
// may fuse them with its own loops (the grid solver runs them row by row).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "chains.h"
#include "collision/feature_contacts.h"
#include "collision/layer_contact.h"
#include "collision/triangle_contact.h"
#include "drape/collider.h"
#include "forces.h"
#include "long_range.h"
#include "parallel.h"

namespace drape::xpbd {

/// The cloth's triangles with their corners as slots (for triangle_contacts), `slot` mapping a
/// particle to its slot.
template <typename Slot>
std::vector<Triangle> triangle_slots(const ClothModel& m, Slot slot) {
  std::vector<Triangle> triangles;
  triangles.reserve(m.triangles.size());
  for (const Triangle& t : m.triangles) triangles.push_back({slot(t[0]), slot(t[1]), slot(t[2])});
  return triangles;
}

template <typename Real>
class Particles {
 public:
  Soa<Real> base, move, v, accel;  ///< x = base + move (see split); per slot
  AlignedVector<Real> inv_mass;    ///< per slot; zero for pins, held particles and padding

  /// Sizes the arrays for `slots` slots and `slack` more inverse masses (read past the end by
  /// Lanes::load); every slot starts still, at the origin, with zero inverse mass.
  void resize(int32_t slots, int32_t slack) {
    slots_ = slots;
    for (Soa<Real>* a : {&base, &move, &v, &accel}) a->resize(slots);
    inv_mass.assign(slots + slack, 0.0);
  }
  int32_t slots() const { return slots_; }

  /// Tabulates the attachments' limits by slot (slot_of(p): particle p's slot).
  template <class SlotOf>
  void prepare_attachments(const LongRange& lr, int32_t particles, SlotOf slot_of) {
    tethers_ = lr.active() ? lr.tethers() : 0;
    uniform_ = lr.uniform();
    pin_at_.resize(lr.pins().size());
    // A missing tether never pulls: an infinite limit.
    tether_limit_.assign(size_t(tethers_) * slots_, std::numeric_limits<Real>::max());
    tether_pin_.assign(uniform_ ? 0 : size_t(tethers_) * slots_, 0);
    for (int t = 0; t < tethers_; ++t) {
      for (int32_t i = 0; i < particles; ++i) {
        const int32_t pin = lr.pin(i, t);
        if (pin < 0) continue;
        const size_t at = size_t(t) * slots_ + slot_of(i);
        tether_limit_[at] = static_cast<Real>(lr.limit(i, t));
        if (!uniform_)
          tether_pin_[at] = static_cast<int32_t>(
              std::lower_bound(lr.pins().begin(), lr.pins().end(), pin) - lr.pins().begin());
      }
    }
  }
  bool attached() const { return tethers_ > 0; }

  /// The pins' positions as the frame starts (pins do not move during it).
  void read_pins(const ClothState& s, const LongRange& lr) {
    for (size_t k = 0; k < pin_at_.size(); ++k)
      for (int d = 0; d < 3; ++d)
        split(s.x[lr.pins()[k]][d], pin_at_[k].base[d], pin_at_[k].move[d]);
  }

  /// Particle i of the state into slot p: its acceleration a, and when `state`, its position,
  /// velocity and inverse mass.
  void read(const ClothState& s, int32_t i, int32_t p, const Vec3& a, bool state) {
    for (int d = 0; d < 3; ++d) accel[d][p] = static_cast<Real>(a[d]);
    if (!state) return;
    for (int d = 0; d < 3; ++d) {
      v[d][p] = static_cast<Real>(s.v[i][d]);
      split(s.x[i][d], base[d][p], move[d][p]);
    }
    inv_mass[p] = static_cast<Real>(s.inv_mass[i]);
  }
  /// Slot p back into particle i of the state. Pinned and held particles did not move: keeping
  /// their positions as they are keeps them exact in single precision too.
  void write(ClothState& s, int32_t i, int32_t p) const {
    if (s.inv_mass[i] == 0.0) return;
    s.x[i] = position(p);
    s.v[i] = Vec3(v.x[p], v.y[p], v.z[p]);
  }

  // The position x = b + m as a base b (where the particle stands at the substep's start) and
  // its move m since, both in Real. Splitting a double this way keeps it to about ε² relative.
  static void split(double x, Real& b, Real& m) {
    b = static_cast<Real>(x);
    m = static_cast<Real>(x - static_cast<double>(b));
  }
  Vec3 position(int32_t p) const {
    return Vec3(double(base.x[p]) + double(move.x[p]), double(base.y[p]) + double(move.y[p]),
                double(base.z[p]) + double(move.z[p]));
  }

  /// Drag on the cloth's area (forces::apply_area_drag) from this frame on: particle i's normal
  /// n_i and coefficient ½ρC·A_i/m_i (1/s per m/s of normal speed) into slot p, held over the
  /// frame as the wind is. `area_drag(false)` turns it off (the seed's scenes).
  void area_drag(bool on) {
    area_ = on;
    normal_.resize(on ? slots_ : 0);
    area_k_.assign(on ? slots_ : 0, Real(0));
  }
  void read_area(const ClothModel& m, const ClothState& s, double half_rho_c, int32_t i,
                 int32_t p) {
    for (int d = 0; d < 3; ++d) normal_[d][p] = static_cast<Real>(s.normal[i][d]);
    area_k_[p] = s.inv_mass[i] > 0.0 ? static_cast<Real>(half_rho_c * s.area[i] / m.mass[i]) : 0;
  }

  void predict(Real h, Real air_drag) {
    if (area_)
      predict<true>(h, air_drag);
    else
      predict<false>(h, air_drag);
  }

  // The new base is b + m rounded, and the rounding (Knuth's two-sum, exact) starts the new
  // move, so no position is lost to round-off however small the step; then v += h·a,
  // semi-implicit drag, m += h·v. Pinned and held particles stay put. Shared out to the team.
  // The rounding carried in the move is where the particle stood, not where it went: the
  // velocity at the substep's end is (m − rounding)/h, so the velocity arrays, which nothing
  // reads during a substep, keep −rounding/h for velocities() to add. (Taken as m/h, a float
  // cloth's velocity gained up to an ulp of its position per substep: a float free fall fell
  // 0.1% too fast.) With kArea, the area drag after the particle's own, on the normal part of
  // the velocity: u_n ← u_n/(1 + h·k·|u_n|).
  template <bool kArea>
  void predict(Real h, Real air_drag) {
    const int32_t n = slots_;
    Real *__restrict bx = base.x.data(), *__restrict by = base.y.data(),
                     *__restrict bz = base.z.data();
    Real *__restrict mx = move.x.data(), *__restrict my = move.y.data(),
                     *__restrict mz = move.z.data();
    Real *__restrict vx = v.x.data(), *__restrict vy = v.y.data(), *__restrict vz = v.z.data();
    const Real *__restrict ax = accel.x.data(), *__restrict ay = accel.y.data(),
                           *__restrict az = accel.z.data();
    const Real* __restrict w = inv_mass.data();
    const Real *__restrict nx = normal_.x.data(), *__restrict ny = normal_.y.data(),
                           *__restrict nz = normal_.z.data(), *__restrict ak = area_k_.data();
    const Real inv_h = 1 / h;
    auto rebase = [](Real& b, Real& m) {
      const Real sum = b + m, m_part = sum - b;
      m = (b - (sum - m_part)) + (m - m_part);
      b = sum;
    };
#pragma omp for simd schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      rebase(bx[i], mx[i]);
      rebase(by[i], my[i]);
      rebase(bz[i], mz[i]);
      // Branch-free so the loop vectorises: `free` is 1 for a free particle, 0 otherwise.
      const Real free = w[i] > Real(0) ? Real(1) : Real(0), hf = h * free;
      const Real ux = vx[i] + hf * ax[i], uy = vy[i] + hf * ay[i], uz = vz[i] + hf * az[i];
      const Real f = forces::drag_factor(air_drag * w[i] * h, ux, uy, uz);
      Real dx = f * ux, dy = f * uy, dz = f * uz;
      if constexpr (kArea) {
        const Real un = dx * nx[i] + dy * ny[i] + dz * nz[i];
        const Real cut = forces::area_drag_cut(h * ak[i], un);
        dx -= cut * nx[i], dy -= cut * ny[i], dz -= cut * nz[i];
      }
      vx[i] = -mx[i] * inv_h;
      vy[i] = -my[i] * inv_h;
      vz[i] = -mz[i] * inv_h;
      mx[i] += hf * dx;
      my[i] += hf * dy;
      mz[i] += hf * dz;
    }
  }

  // Long-range attachments on the free particles of slots [begin, end), tether after tether:
  // project_attachment's rule (long_range.h) written branch-free on the arrays so it
  // vectorises, with the limits tabulated at set-up. With few pins every slot's tether t is pin
  // t (uniform); else each slot names its pin.
  void attachments(int32_t begin, int32_t end) {
    const Real *__restrict bx = base.x.data(), *__restrict by = base.y.data(),
                           *__restrict bz = base.z.data();
    Real *__restrict mx = move.x.data(), *__restrict my = move.y.data(),
                     *__restrict mz = move.z.data();
    const Real* __restrict w = inv_mass.data();
    const PinAt* __restrict pins = pin_at_.data();
    for (int t = 0; t < tethers_; ++t) {
      const Real* __restrict limit = tether_limit_.data() + size_t(t) * slots_;
      const int32_t* __restrict pin = uniform_ ? nullptr : tether_pin_.data() + size_t(t) * slots_;
      auto one = [&](int32_t c, const PinAt& a) {
        // x − x_pin, and x_pin + (limit/len)·(x − x_pin) written as a change of the move.
        const Real dx = (bx[c] - a.base[0]) + (mx[c] - a.move[0]),
                   dy = (by[c] - a.base[1]) + (my[c] - a.move[1]),
                   dz = (bz[c] - a.base[2]) + (mz[c] - a.move[2]);
        const Real len = std::sqrt(dx * dx + dy * dy + dz * dz);
        const bool pull = w[c] > 0 && len > limit[c];
        const Real shrink = pull ? limit[c] / len - 1 : Real(0);
        mx[c] += shrink * dx;
        my[c] += shrink * dy;
        mz[c] += shrink * dz;
      };
      if (uniform_) {
        const PinAt a = pins[t];
#pragma omp simd
        for (int32_t c = begin; c < end; ++c) one(c, a);
      } else {
#pragma omp simd
        for (int32_t c = begin; c < end; ++c) one(c, pins[pin[c]]);
      }
    }
  }

  // Contacts (PositionContact in collider.h, x_prev being the base) of the free particles of
  // slots [begin, end), collider after collider; branch-free so it vectorises, in runs of
  // kContactRun slots, each skipped after a cheaper test (no square root) where none of it can
  // touch. A skipped particle is one that apply() would leave as it is: the same result. On the
  // grid's drape-128 that took about 0.2 ms off a one-thread frame of 6 ms; shorter runs were
  // slower, their loops too short to vectorise without scalar remainders.
  static constexpr int kContactRun = 16;
  void contacts(const std::vector<Collider>& colliders, int32_t begin, int32_t end) {
    const Real* __restrict w = inv_mass.data();
    const Real *__restrict bx = base.x.data(), *__restrict by = base.y.data(),
                           *__restrict bz = base.z.data();
    Real *__restrict mx = move.x.data(), *__restrict my = move.y.data(),
                     *__restrict mz = move.z.data();
    for (const Collider& col : colliders) {
      if (!col.simple()) {
        contacts_any(col, begin, end);
        continue;
      }
      const PositionContact<Real> contact(col);
      const Real cx = static_cast<Real>(col.center.x()), cy = static_cast<Real>(col.center.y()),
                 cz = static_cast<Real>(col.center.z());
      for (int32_t c0 = begin; c0 < end; c0 += kContactRun) {
        const int32_t c1 = std::min(end, c0 + kContactRun);
        Real clearance = std::numeric_limits<Real>::max();
#pragma omp simd reduction(min : clearance)
        for (int32_t c = c0; c < c1; ++c)
          clearance = std::min(
              clearance,
              contact.clearance((bx[c] - cx) + mx[c], (by[c] - cy) + my[c], (bz[c] - cz) + mz[c]));
        if (clearance > 0) continue;
#pragma omp simd
        for (int32_t c = c0; c < c1; ++c)
          contact.apply(w[c] > Real(0), (bx[c] - cx) + mx[c], (by[c] - cy) + my[c],
                        (bz[c] - cz) + mz[c], mx[c], my[c], mz[c]);
      }
    }
  }

  // The contacts of one collider of any shape, moving or not (position_contact in collider.h,
  // in double), on the free particles of slots [begin, end): runs that lie wholly outside the
  // collider's bounding sphere, or a box's slabs, are skipped by tests that vectorise, the rest
  // taken one by one.
  void contacts_any(const Collider& col, int32_t begin, int32_t end) {
    const Real* __restrict w = inv_mass.data();
    const Real *__restrict bx = base.x.data(), *__restrict by = base.y.data(),
                           *__restrict bz = base.z.data();
    Real* __restrict mx = move.x.data(), * __restrict my = move.y.data(), * __restrict mz = move.z.data();
    const bool bounded = std::isfinite(col.bound_radius);
    const Real cx = static_cast<Real>(col.bound_center.x()),
               cy = static_cast<Real>(col.bound_center.y()),
               cz = static_cast<Real>(col.bound_center.z());
    // Widened by 0.1% and a millimetre, far above the test's round-off in single precision.
    const double reach = 1.001 * (col.bound_radius + col.thickness) + 1e-3;
    const Real reach2 = bounded ? static_cast<Real>(reach * reach) : Real(0);
    // A box's or mesh's contact follows the particle's path (entered_elsewhere), so a run is
    // skipped only where every particle's path since the substep began stays clear of it: its end
    // farther than the reach by more than its move (|x| + |y| + |z|, at least the move's length).
    const bool paths = col.type == ColliderType::box || col.type == ColliderType::mesh;
    for (int32_t c0 = begin; c0 < end; c0 += kContactRun) {
      const int32_t c1 = std::min(end, c0 + kContactRun);
      if (bounded) {
        Real clearance = std::numeric_limits<Real>::max();
        if (paths) {
#pragma omp simd reduction(min : clearance)
          for (int32_t c = c0; c < c1; ++c) {
            const Real px = (bx[c] - cx) + mx[c], py = (by[c] - cy) + my[c],
                       pz = (bz[c] - cz) + mz[c];
            const Real moved = std::abs(mx[c]) + std::abs(my[c]) + std::abs(mz[c]);
            clearance = std::min(clearance, std::sqrt(px * px + py * py + pz * pz) -
                                                static_cast<Real>(reach) - moved);
          }
        } else {
#pragma omp simd reduction(min : clearance)
          for (int32_t c = c0; c < c1; ++c) {
            const Real px = (bx[c] - cx) + mx[c], py = (by[c] - cy) + my[c],
                       pz = (bz[c] - cz) + mz[c];
            clearance = std::min(clearance, px * px + py * py + pz * pz - reach2);
          }
        }
        if (clearance > 0) continue;
      }
      if (col.type == ColliderType::box && beyond_box_slabs(col, c0, c1)) continue;
      for (int32_t c = c0; c < c1; ++c) {
        if (!(w[c] > Real(0))) continue;
        Vec3 m{double(mx[c]), double(my[c]), double(mz[c])};
        Vec3 x = Vec3(double(bx[c]), double(by[c]), double(bz[c])) + m;
        if (!position_contact(col, x, m)) continue;
        mx[c] = static_cast<Real>(m.x());
        my[c] = static_cast<Real>(m.y());
        mz[c] = static_cast<Real>(m.z());
      }
    }
  }

  // Whether every slot of [c0, c1) lies farther than the thickness and its move since the
  // substep began beyond one of a box's faces' planes (its slabs: a lower bound of the
  // distance, so the box's contacts, which follow the particle's path, would leave them as
  // they are). On a tablecloth most of the cloth hangs beside the table, within its bounding
  // sphere.
  bool beyond_box_slabs(const Collider& col, int32_t c0, int32_t c1) const {
    const Real *__restrict bx = base.x.data(), *__restrict by = base.y.data(),
                           *__restrict bz = base.z.data();
    const Real *__restrict mx = move.x.data(), *__restrict my = move.y.data(),
                           *__restrict mz = move.z.data();
    Real r[3][3], h[3];
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < 3; ++l) r[k][l] = static_cast<Real>(col.rotation(l, k));
      h[k] = static_cast<Real>(col.half_extents[k]);
    }
    const Real cx = static_cast<Real>(col.center.x()), cy = static_cast<Real>(col.center.y()),
               cz = static_cast<Real>(col.center.z());
    // Widened as the bounding sphere's test, far above its round-off in single precision.
    const Real reach = static_cast<Real>(
        1.001 * col.thickness + 1e-3 * (1.0 + col.center.norm() + col.half_extents.norm()));
    Real clearance = std::numeric_limits<Real>::max();
#pragma omp simd reduction(min : clearance)
    for (int32_t c = c0; c < c1; ++c) {
      const Real px = (bx[c] - cx) + mx[c], py = (by[c] - cy) + my[c], pz = (bz[c] - cz) + mz[c];
      Real beyond = std::abs(r[0][0] * px + r[0][1] * py + r[0][2] * pz) - h[0];
      beyond = std::max(beyond, std::abs(r[1][0] * px + r[1][1] * py + r[1][2] * pz) - h[1]);
      beyond = std::max(beyond, std::abs(r[2][0] * px + r[2][1] * py + r[2][2] * pz) - h[2]);
      // Beyond a face's plane by more than its move: its whole path since the substep began
      // lay beyond it (its distance from the plane changes by at most the move's length).
      const Real moved = std::abs(mx[c]) + std::abs(my[c]) + std::abs(mz[c]);
      clearance = std::min(clearance, beyond - reach - moved);
    }
    return clearance > 0;
  }

  // The triangles (corners as slots) against moving spheres and capsules
  // (collision/triangle_contact.h), one after another: triangles share particles, and such
  // bodies are few and small.
  void triangle_contacts(const std::vector<Collider>& colliders,
                         const std::vector<Triangle>& triangles) {
    const auto same = [](int32_t c) { return c; };
    SlotCloth<decltype(same)> cloth{*this, same};
    for (const Collider& col : colliders) {
      if (!holds_triangles_out(col)) continue;
      for (const Triangle& t : triangles) {
        PointPush push;
        if (!triangle_push(col, position(t[0]), position(t[1]), position(t[2]), push)) continue;
        for (int k = 0; k < 3; ++k) push.index[k] = t[k];
        cloth.push(push, col);
      }
    }
  }

  // The cloth's edges and triangles against boxes' and meshes' sharp features
  // (collision/feature_contacts.h), `slot` mapping a particle to its slot; serial.
  template <typename Slot>
  void feature_contacts(const FeatureContacts& features, const std::vector<Collider>& colliders,
                        Slot slot) {
    SlotCloth<Slot> cloth{*this, slot};
    features.apply(colliders, cloth);
  }

  // The layers self-collision left touching (collision/layer_contact.h), held apart, `slot`
  // mapping a particle to its slot; serial.
  template <typename Slot>
  void held_layers(const HeldLayers& held, Slot slot) {
    SlotCloth<Slot> cloth{*this, slot};
    held.apply(cloth);
  }

  // The velocities over slots [begin, end): v = (move − the rounding it started with)/h, the
  // second part left in v by predict().
  void velocities(Real h, int32_t begin, int32_t end) {
    const Real inv_h = 1 / h;
    const Real *__restrict mx = move.x.data(), *__restrict my = move.y.data(),
                           *__restrict mz = move.z.data();
    Real *__restrict vx = v.x.data(), *__restrict vy = v.y.data(), *__restrict vz = v.z.data();
#pragma omp simd
    for (int32_t c = begin; c < end; ++c) {
      vx[c] += mx[c] * inv_h;
      vy[c] += my[c] * inv_h;
      vz[c] += mz[c] * inv_h;
    }
  }

  int64_t bytes() const {
    return heap_bytes(base.x, base.y, base.z, move.x, move.y, move.z, v.x, v.y, v.z, accel.x,
                      accel.y, accel.z, inv_mass, pin_at_, tether_limit_, tether_pin_, normal_.x,
                      normal_.y, normal_.z, area_k_);
  }

 private:
  // The particles as a cloth that point pushes move (collision/point_push.h), `slot` mapping a
  // particle's index in a push to its slot.
  template <typename Slot>
  struct SlotCloth {
    Particles& p;
    const Slot& slot;
    Vec3 position(int32_t i) const { return p.position(slot(i)); }
    double inv_mass(int32_t i) const { return double(p.inv_mass[slot(i)]); }
    Vec3 moved(int32_t i) const {
      const int32_t c = slot(i);
      return Vec3(p.move.x[c], p.move.y[c], p.move.z[c]);
    }
    // The push, then friction on positions as the particle contacts have it: the point's
    // slide over the surface this substep is cancelled within friction·depth, else
    // shortened by it.
    void push(const PointPush& push, const Collider& col) {
      Vec3 moves[3];
      double sum = 0.0;
      auto inverse_mass = [&](int32_t i) { return double(p.inv_mass[slot(i)]); };
      if (!push_moves(push, inverse_mass, moves, sum)) return;
      Vec3 point = Vec3::Zero(), slide = Vec3::Zero();
      for (int k = 0; k < push.count; ++k) {
        const int32_t c = slot(push.index[k]);
        add_at(c, moves[k]);
        point += push.w[k] * p.position(c);
        slide += push.w[k] * Vec3(p.move.x[c], p.move.y[c], p.move.z[c]);
      }
      const Vec3 held =
          friction_change(slide - col.surface_move(point), push.n, col.friction, push.depth);
      for (int k = 0; k < push.count; ++k)
        add_at(slot(push.index[k]), (-push.w[k] * inverse_mass(push.index[k]) / sum) * held);
    }
    void add_at(int32_t c, const Vec3& d) {
      p.move.x[c] += static_cast<Real>(d.x());
      p.move.y[c] += static_cast<Real>(d.y());
      p.move.z[c] += static_cast<Real>(d.z());
    }
    // Particle i's move (a velocity), or where it started the substep too (none).
    void add(int32_t i, const Vec3& d) { add_at(slot(i), d); }
    void shift(int32_t i, const Vec3& d) {
      const int32_t c = slot(i);
      p.base.x[c] += static_cast<Real>(d.x());
      p.base.y[c] += static_cast<Real>(d.y());
      p.base.z[c] += static_cast<Real>(d.z());
    }
  };

  // A pin's position split as the frame's start split it.
  struct PinAt {
    Real base[3], move[3];
  };
  int32_t slots_ = 0;
  bool area_ = false;
  Soa<Real> normal_;            ///< per slot, with area drag: the frame's unit normal
  AlignedVector<Real> area_k_;  ///< per slot, with area drag: ½ρC·A/m, 1/m
  std::vector<PinAt> pin_at_;
  int tethers_ = 0;
  bool uniform_ = false;
  AlignedVector<Real> tether_limit_;   ///< per tether and slot, m
  AlignedVector<int32_t> tether_pin_;  ///< per tether and slot: the pin's index (not uniform)
};

}  // namespace drape::xpbd
