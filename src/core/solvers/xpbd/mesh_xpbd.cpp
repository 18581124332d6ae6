// `xpbd` on any mesh (Macklin, Müller & Chentanez 2016, "XPBD"; Macklin et al. 2019, "Small
// steps in physics simulation"): the grid solver's pipeline without the grid. Per substep:
// predict, project the springs as compliant distance constraints by Gauss–Seidel colour by
// colour (the model's colours: a colour's springs share no particle, so a team of threads sweeps
// it at once, and the springs no colour could take, around a vertex of very high valence, are
// swept by one thread), stiff sweeps, attachments, contacts, v = (x − x_prev)/h.
//
// With solver.line_passes the structural springs are solved as chains, exactly, as the grid's
// rows and columns are: a path cover of the mesh's edges (chain_cover.h) gives a few layers of
// chains that share no particle within a layer; each pass solves every chain of each layer at
// once, kLanes chains side by side in the lanes of a vector (their recurrences run across
// chains, as the grid's rows do), and sweeps the structural springs the cover left over.
//
// A material (cloth.material; on a grid too, whose solver's kernels are for the seed's uniform
// springs) adds to that: its bending elements as constraints on the curvature vector
// (xpbd_bend), swept colour by colour after the springs; its threads' softer compression
// (xpbd_project's kSoftened); drag on the area in the prediction (Particles::area_drag); and its
// stiffness-proportional damping taken on the velocities rather than in the projections.
// XPBD's damping term γ = c/(k·h) grows as the substeps shrink, and with one sweep a substep
// leaving the constraints unconverged it shifts the rest shape: a cantilever strip at 1082
// substeps sagged 15% past its elastica, 0.14% without. On the velocities still particles feel
// nothing. Once a frame, over the frame's step: the springs' by a Gauss–Seidel sweep
// (damp_spring; every substep cost 60% more on sphere-denim at 64², 41 against 25 ms a frame,
// for the same shape, as 1/(1 + λ·dt) and (1 + λ·h)^−n agree where λ·dt is small and both
// remove what λ·dt ≫ 1 damps), the bending elements' by backward Euler solved exactly
// (forces::BendingDamping): a sweep over them damped only each element's own curvature rate and
// left a strip swinging and folds sliding for as long as it ran.
//
// Particles keep the cloth's own order (slot p is particle p), plus one slot that never moves
// for the lanes of chains shorter than their group's longest.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "chain_cover.h"
#include "chains.h"
#include "constraints.h"
#include "forces/bending_damping.h"
#include "lanes.h"
#include "particles.h"
#include "xpbd.h"

namespace drape::xpbd {

namespace {

// Slots a thread takes at a time in the stages over particles: a multiple of the contacts'
// runs, and enough to be worth a share.
constexpr int32_t kBlock = 256;

// The shortest chain worth an exact solve: shorter ones are swept with the left-over springs.
constexpr int kMinChain = 3;
// Layers of chains at most: a triangle mesh's edges at a vertex of valence six pair into three
// straight lines (a grid's rows, columns and diagonals); a fourth takes what bends.
constexpr int kMaxLayers = 4;

/// Calls one(k) for every k in [begin[c], begin[c + 1]), colour c by colour, inside a parallel
/// region: a colour whose items share no particle (`independent(c)`) shared out to the team
/// (with kSimd, as SIMD lanes too), any other by one thread. A thread alone runs them in order
/// without OpenMP's worksharing, whose every construct costs a few microseconds here (a small
/// cloth at many substeps spent 60% of its time in them).
template <bool kSimd, class Independent, class One>
void each_by_colour(const std::vector<int32_t>& begin, Independent independent, One one) {
  const int colours = static_cast<int>(begin.size()) - 1;
  if (team_size() == 1) {
    for (int c = 0; c < colours; ++c) {
      if (kSimd && independent(c)) {
#pragma omp simd
        for (int32_t k = begin[c]; k < begin[c + 1]; ++k) one(k);
      } else {
        for (int32_t k = begin[c]; k < begin[c + 1]; ++k) one(k);
      }
    }
    return;
  }
  for (int c = 0; c < colours; ++c) {
    const int32_t b = begin[c], e = begin[c + 1];
    if (!independent(c)) {
#pragma omp single
      for (int32_t k = b; k < e; ++k) one(k);
    } else if (kSimd) {
#pragma omp for simd schedule(static)
      for (int32_t k = b; k < e; ++k) one(k);
    } else {
#pragma omp for schedule(static)
      for (int32_t k = b; k < e; ++k) one(k);
    }
  }
}

/// Springs to sweep spring by spring, in the model's colours: a colour's springs share no
/// particle, except in a colour the model could not make independent, swept by one thread.
template <typename Real>
struct SweepSet {
  AlignedVector<int32_t> i, j;
  AlignedVector<Real> rest, inv_k, c_over_k;  ///< L, 1/k, c/k per spring
  AlignedVector<Real> compression;            ///< per spring, when `softened`
  /// c per spring, for a material, whose damping is taken on the velocities (damp_spring; its
  /// c_over_k is then 0)
  AlignedVector<Real> damping;
  bool softened = false;  ///< some spring resists compression less (a material's threads)
  std::vector<int32_t> begin;                 ///< colour c: [begin[c], begin[c + 1])
  std::vector<uint8_t> independent;           ///< per colour
  AlignedVector<Real> lambda;                 ///< per spring, with several iterations

  /// The model's springs for which keep(s) holds, with stiffness > 0 (a spring of zero
  /// stiffness has infinite compliance: no constraint).
  template <class Keep>
  void build(const ClothModel& m, Keep keep) {
    i.clear(), j.clear(), rest.clear(), inv_k.clear(), c_over_k.clear(), compression.clear();
    damping.clear();
    softened = false;
    begin.assign(1, 0);
    independent.clear();
    for (int c = 0; c < m.colours(); ++c) {
      for (int32_t k = m.colour_begin[c]; k < m.colour_begin[c + 1]; ++k) {
        const Spring& s = m.springs[k];
        if (!(s.stiffness > 0.0) || !keep(s, k)) continue;
        i.push_back(s.i);
        j.push_back(s.j);
        rest.push_back(static_cast<Real>(s.rest));
        inv_k.push_back(static_cast<Real>(1.0 / s.stiffness));
        c_over_k.push_back(m.material ? Real(0) : static_cast<Real>(s.damping / s.stiffness));
        if (m.material) damping.push_back(static_cast<Real>(s.damping));
        compression.push_back(static_cast<Real>(forces::compression_of(m, s.kind)));
        softened = softened || compression.back() < 1;
      }
      if (static_cast<int32_t>(i.size()) == begin.back()) continue;
      begin.push_back(static_cast<int32_t>(i.size()));
      independent.push_back(m.colour_is_independent(c));
    }
  }
  bool empty() const { return i.empty(); }
  int64_t bytes() const {
    return heap_bytes(i, j, rest, inv_k, c_over_k, compression, damping, begin, independent,
                      lambda);
  }

  /// Colour by colour over the springs (see drape::xpbd::each_by_colour).
  template <class One>
  void each_by_colour(One one) {
    xpbd::each_by_colour<true>(
        begin, [&](int c) { return independent[c] != 0; }, one);
  }

  /// The velocity damping (damp_spring) after a substep of h, when `damping` is set.
  void damp(Particles<Real>& p, Real h) {
    if (damping.empty()) return;
    const Real* __restrict c = damping.data();
    each_by_colour([&](int32_t k) {
      damp_spring(p.base.x.data(), p.base.y.data(), p.base.z.data(), p.move.x.data(),
                  p.move.y.data(), p.move.z.data(), p.v.x.data(), p.v.y.data(), p.v.z.data(),
                  p.inv_mass.data(), i[k], j[k], h * c[k]);
    });
  }

  /// One Gauss–Seidel sweep in a substep of h, colour by colour, shared out to the team; with
  /// `kLambda` the multipliers accumulate in `lambda` (from zero when `first`).
  template <bool kLambda>
  void sweep(Particles<Real>& p, Real h, bool first) {
    if (softened)
      sweep<kLambda, true>(p, h, first);
    else
      sweep<kLambda, false>(p, h, first);
  }
  template <bool kLambda, bool kSoftened>
  void sweep(Particles<Real>& p, Real h, bool first) {
    const Real *__restrict bx = p.base.x.data(), *__restrict by = p.base.y.data(),
                           *__restrict bz = p.base.z.data();
    Real *__restrict mx = p.move.x.data(), *__restrict my = p.move.y.data(),
                     *__restrict mz = p.move.z.data();
    const Real* __restrict w = p.inv_mass.data();
    const int32_t *__restrict si = i.data(), *__restrict sj = j.data();
    const Real *__restrict sr = rest.data(), *__restrict sk = inv_k.data(),
                           *__restrict sc = c_over_k.data();
    const Real* __restrict sq = compression.data();
    Real* __restrict sl = lambda.data();
    const Real inv_h2 = 1 / (h * h), inv_h = 1 / h;
    auto one = [&](int32_t k) {
      const Real l0 = kLambda && !first ? sl[k] : Real(0);
      const Real dl = xpbd_project<false, true, kSoftened>(bx, by, bz, mx, my, mz, w, si[k], sj[k],
                                                           sr[k], sk[k] * inv_h2, sc[k] * inv_h, l0,
                                                           kSoftened ? sq[k] : Real(1));
      if constexpr (kLambda) sl[k] = l0 + dl;
    };
    each_by_colour(one);
  }
};

/// A material's bending elements (forces/bending.h) as XPBD constraints (xpbd_bend), in colours
/// whose elements share no corner, made greedily here (a corner takes part in about a dozen
/// elements on a regular mesh); elements no colour of the first kMaxColours could take make a
/// last colour, swept by one thread.
template <typename Real>
struct BendSet {
  static constexpr int kMaxColours = 64;
  AlignedVector<int32_t> v;            ///< 4 corners per element
  AlignedVector<Real> w;               ///< 4 weights per element
  AlignedVector<Real> inv_k;           ///< 1/k per element (damped apart: BendingDamping)
  std::vector<int32_t> begin;          ///< colour c: [begin[c], begin[c + 1])
  bool last_shared = false;            ///< the last colour's elements may share corners
  AlignedVector<Real> lambda;          ///< 3 per element, with several iterations

  /// With `multipliers`, room for λ (several iterations a substep).
  void build(const ClothModel& m, bool multipliers) {
    v.clear(), w.clear(), inv_k.clear();
    std::vector<int> colour;
    std::vector<uint64_t> used(m.size(), 0);  // per particle, the colours it is in
    std::vector<int32_t> count(kMaxColours + 1, 0);
    for (const BendingElement& b : m.bending) {
      if (!(b.stiffness > 0.0)) {
        colour.push_back(-1);
        continue;
      }
      uint64_t taken = 0;
      for (int32_t p : b.v) taken |= used[p];
      const int c = taken == ~uint64_t(0) ? kMaxColours : std::countr_one(taken);
      if (c < kMaxColours)
        for (int32_t p : b.v) used[p] |= uint64_t(1) << c;
      colour.push_back(c);
      ++count[c];
    }
    begin.assign(1, 0);
    std::vector<int32_t> at;
    for (int c = 0; c <= kMaxColours; ++c) {
      at.push_back(begin.back());
      if (count[c] > 0) begin.push_back(begin.back() + count[c]);
    }
    last_shared = count[kMaxColours] > 0;
    const size_t total = begin.back();
    v.resize(4 * total), w.resize(4 * total), inv_k.resize(total);
    for (size_t e = 0; e < m.bending.size(); ++e) {
      if (colour[e] < 0) continue;
      const BendingElement& b = m.bending[e];
      const int32_t k = at[colour[e]]++;
      for (int c = 0; c < 4; ++c) v[4 * k + c] = b.v[c], w[4 * k + c] = static_cast<Real>(b.w[c]);
      inv_k[k] = static_cast<Real>(1.0 / b.stiffness);
    }
    lambda.assign(multipliers ? 3 * total : 0, Real(0));
  }
  int64_t bytes() const { return heap_bytes(v, w, inv_k, begin, lambda); }

  /// Colour by colour over the elements (see drape::xpbd::each_by_colour): all but a shared
  /// last colour are independent.
  template <class One>
  void each_by_colour(One one) {
    const int colours = static_cast<int>(begin.size()) - 1;
    xpbd::each_by_colour<false>(
        begin, [&](int c) { return c + 1 < colours || !last_shared; }, one);
  }

  /// One Gauss–Seidel sweep, as SweepSet::sweep, undamped (the damping: BendingDamping).
  template <bool kLambda>
  void sweep(Particles<Real>& p, Real h, bool first) {
    const Real *__restrict bx = p.base.x.data(), *__restrict by = p.base.y.data(),
                           *__restrict bz = p.base.z.data();
    Real *__restrict mx = p.move.x.data(), *__restrict my = p.move.y.data(),
                     *__restrict mz = p.move.z.data();
    const Real* __restrict im = p.inv_mass.data();
    const Real inv_h2 = 1 / (h * h);
    auto one = [&](int32_t k) {
      Real none[3] = {0, 0, 0};
      Real* l = kLambda ? &lambda[3 * size_t(k)] : none;
      if (kLambda && first) l[0] = l[1] = l[2] = 0;
      xpbd_bend(bx, by, bz, mx, my, mz, im, &v[4 * size_t(k)], &w[4 * size_t(k)], inv_k[k] * inv_h2,
                l);
    };
    each_by_colour(one);
  }
};

/// One layer of the chain cover, its chains in groups of kLanes side by side (longest first, so
/// that a group's chains are of about one length). Group G has `length[G]` constraints; its
/// chains' particles are slot[(first[G] + t)·L + l] for t ≤ length[G] and lane l, padded with
/// the still slot, and constraint t's rest length is rest[(first[G] + t)·L + l] (0 where a lane
/// has none); its recurrence entries are entry[G] … entry[G] + length[G] + 1 (one before the
/// first constraint and one after the last, never written, end the recurrences).
template <typename Real>
struct ChainLayer {
  using Lane = typename Lanes<Real>::Vec;
  static constexpr int L = Lanes<Real>::kLanes;
  std::vector<int32_t> first, length, entry;  ///< per group; entry: its first recurrence entry
  AlignedVector<int32_t> slot;                ///< per group, particle and lane
  AlignedVector<Real> rest;                   ///< per group, constraint and lane, m
  ChainScratch<Lane> scratch;                 ///< per recurrence entry
  AlignedVector<Lane> dl;                     ///< per recurrence entry: ω·Δλ of the last pass

  void build(std::vector<std::vector<int32_t>> chains, int32_t still,
             const std::vector<Vec3>& rest_position) {
    std::stable_sort(chains.begin(), chains.end(),
                     [](const auto& a, const auto& b) { return a.size() > b.size(); });
    first.clear(), length.clear(), entry.clear(), slot.clear();
    int32_t entries = 0;
    for (size_t c0 = 0; c0 < chains.size(); c0 += L) {
      const int32_t len = static_cast<int32_t>(chains[c0].size()) - 1;  // the longest
      first.push_back(static_cast<int32_t>(slot.size() / L));
      length.push_back(len);
      entry.push_back(entries);
      entries += len + 2;
      for (int32_t t = 0; t <= len; ++t)
        for (int l = 0; l < L; ++l) {
          const size_t c = c0 + l;
          slot.push_back(c < chains.size() && t < static_cast<int32_t>(chains[c].size())
                             ? chains[c][t]
                             : still);
        }
    }
    rest.assign(slot.size(), Real(0));
    for (size_t at = 0; at + L < slot.size(); ++at) {
      const int32_t a = slot[at], b = slot[at + L];
      if (a != still && b != still)
        rest[at] = static_cast<Real>((rest_position[b] - rest_position[a]).norm());
    }
    scratch.prepare(entries);
    dl.assign(entries, Lane{});
  }
  int groups() const { return static_cast<int>(first.size()); }
  int64_t bytes() const {
    return heap_bytes(first, length, entry, slot, rest, dl) + scratch.bytes();
  }
};

template <typename Real>
class MeshXpbd final : public Solver {
  using Lane = typename Lanes<Real>::Vec;
  static constexpr int L = Lanes<Real>::kLanes;

 public:
  void prepare(const World& w, const SolverDef& def) override {
    const ClothModel& m = w.model;
    n_ = m.size();
    still_ = n_;
    triangles_.clear();
    // The particles, the still slot, and padding to a whole block.
    slots_ = (n_ + 1 + kBlock - 1) / kBlock * kBlock;
    particles_.resize(slots_, L);
    scratch_.assign(n_, Vec3::Zero());
    iterations_ = def.iterations > 0 ? def.iterations : kDefaultIterations;
    stiff_sweeps_ = def.stiff_sweeps;
    attached_ = w.attachments.active();
    particles_.prepare_attachments(w.attachments, n_, [](int32_t i) { return i; });

    double stiffest = 0.0;
    for (const Spring& s : m.springs) stiffest = std::max(stiffest, s.stiffness);
    const bool lines = prepare_lines(w, def);
    // Line passes solve the structural springs as chains; the rest are swept as always.
    all_.build(m, [&](const Spring& s, int32_t) {
      return !(lines && s.kind == SpringKind::structural);
    });
    stiffest_.build(m, [&](const Spring& s, int32_t) {
      return lines ? s.kind == SpringKind::structural : s.stiffness >= stiffest;
    });
    all_.lambda.assign(iterations_ > 1 ? all_.i.size() : 0, 0.0);
    bend_.build(m, iterations_ > 1);
    bend_damping_.prepare(m, w.state.pinned, def.dt);
    damp_time_ = 0.0;
    particles_.area_drag(w.area_drag());
    current_ = false;
    frame_dt_ = def.dt;
    if (def.substeps > 0) {
      substeps_ = def.substeps;
      return;
    }
    substeps_ = automatic_substeps(
        w, def, [&](const Spring& s) { return !(lines && s.kind == SpringKind::structural); });
  }

  void state_changed() override { current_ = false; }

  void step_frame(World& w, double dt) override {
    // A part of a frame takes its share of the substeps, with line passes all (grid_xpbd.cpp).
    const int steps = lines_ ? substeps_ : substeps_in(dt, frame_dt_, substeps_);
    const double h = dt / steps;
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    // External acceleration, held over the frame: gravity plus the wind at the frame's start
    // (as the grid solver does: the wind does not depend on the substep's positions).
    const bool wind = w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0;
    // Drag on the area, with the frame's normals too.
    const bool area = w.area_drag();
    if (wind || area) update_normals(m, s);
    if (wind) {
      std::fill(scratch_.begin(), scratch_.end(), Vec3::Zero());
      forces::add_wind(m, s, w.forces.wind, w.time, scratch_);
    }
    const double half_rho_c = 0.5 * w.air_density() * w.forces.drag_coefficient;
    const Vec3 g = w.forces.gravity;
    const double drag = w.air_drag();
    const bool read = !current_;
    if (w.colliders_move() && triangles_.empty())
      triangles_ = triangle_slots(m, [](int32_t i) { return i; });
    const bool triangles = w.colliders_move();
    particles_.read_pins(s, w.attachments);
    const int32_t blocks = slots_ / kBlock;

#pragma omp parallel if (worth_threads(n_))
    {
      if (read || wind || area) {
#pragma omp for schedule(static)
        for (int32_t i = 0; i < n_; ++i) {
          particles_.read(s, i, i, wind ? Vec3(g + s.inv_mass[i] * scratch_[i]) : g, read);
          if (area) particles_.read_area(m, s, half_rho_c, i, i);
        }
      }
      int ran = 0;  // substeps run (all, unless the frame stops early)
      for (int k = 0; k < steps; ++k, ++ran) {
        if (!substep_begins(w, k, h, stopping_)) break;
        particles_.predict(h, drag);
        for (int it = 0; it < iterations_; ++it) {
          if (iterations_ > 1) {
            all_.template sweep<true>(particles_, h, it == 0);
            bend_.template sweep<true>(particles_, h, it == 0);
          } else {
            all_.template sweep<false>(particles_, h, true);
            bend_.template sweep<false>(particles_, h, true);
          }
        }
        if (lines_) {
          for (int pass = 0; pass < line_passes_; ++pass) {
            constrain(w.colliders, blocks);
            solve_chains(h, pass == 0, pass + 1 < line_passes_ ? relaxation_ : 1);
          }
          for (int it = 0; it < stiff_sweeps_; ++it) {
            constrain(w.colliders, blocks);
            stiffest_.template sweep<false>(particles_, h, true);
          }
        } else {
          for (int it = 0; it < stiff_sweeps_; ++it) {
            if (it % kContactEvery == 0 && !w.colliders.empty()) {
#pragma omp for schedule(static)
              for (int32_t b = 0; b < blocks; ++b)
                particles_.contacts(w.colliders, b * kBlock, (b + 1) * kBlock);
            }
            stiffest_.template sweep<false>(particles_, h, true);
          }
          if (attached_) {
#pragma omp for schedule(static)
            for (int32_t b = 0; b < blocks; ++b)
              particles_.attachments(b * kBlock, (b + 1) * kBlock);
          }
        }
        // The layers self-collision left touching, held apart before the contacts (which
        // then keep the lower layer on the ground); the triangles against moving bodies and
        // the pairs with sharp features, after them.
        if (w.held && HeldLayers::due(k, steps)) {
#pragma omp single
          particles_.held_layers(*w.held, [](int32_t i) { return i; });
        }
        const bool after = triangles || w.features;
        if (after) {
#pragma omp for schedule(static)
          for (int32_t b = 0; b < blocks; ++b)
            particles_.contacts(w.colliders, b * kBlock, (b + 1) * kBlock);
#pragma omp single
          {
            if (triangles) particles_.triangle_contacts(w.colliders, triangles_);
            if (w.features)
              particles_.feature_contacts(*w.features, w.colliders, [](int32_t i) { return i; });
          }
        }
#pragma omp for schedule(static)
        for (int32_t b = 0; b < blocks; ++b) {
          if (!after) particles_.contacts(w.colliders, b * kBlock, (b + 1) * kBlock);
          particles_.velocities(h, b * kBlock, (b + 1) * kBlock);
        }
      }
      // A material's damping, on the velocities, once over the substeps run (see the top).
      all_.damp(particles_, ran * h);
#pragma omp single
      {
        damp_time_ += ran * h;
        damp_now_ = !bend_damping_.empty() && damp_time_ >= (1.0 - 1e-9) * bend_damping_.dt();
        if (damp_now_) damp_time_ = 0.0;
      }
      if (damp_now_)  // every thread: x, y and z shared among them
        bend_damping_.apply(particles_.v.x.data(), particles_.v.y.data(), particles_.v.z.data());
#pragma omp for schedule(static)
      for (int32_t i = 0; i < n_; ++i) particles_.write(s, i, i);
    }
    update_normals(m, s);
    current_ = true;
  }

  bool holds_layers() const override {
    return true;
  }
  int substeps() const override { return substeps_; }
  int64_t workspace_bytes() const override {
    int64_t bytes = particles_.bytes() + heap_bytes(scratch_, triangles_) + all_.bytes() +
                    stiffest_.bytes() + left_over_.bytes() + bend_.bytes() + bend_damping_.bytes();
    for (const ChainLayer<Real>& layer : layers_) bytes += layer.bytes();
    return bytes;
  }

 private:
  // Line passes: the chain cover of the structural springs, unless something is fixed that
  // attachments do not hold (a particle held by the hand: the passes pause while it is, as on
  // the grid). A chain through a fixed particle is swept spring by spring instead (between two
  // pins it is a taut string, whose exact solve is near singular), as are the springs the cover
  // leaves over. Returns whether the passes run.
  bool prepare_lines(const World& w, const SolverDef& def) {
    const ClothModel& m = w.model;
    line_passes_ = def.line_passes;
    relaxation_ = static_cast<Real>(def.line_relaxation);
    layers_.clear();
    left_over_ = {};
    int32_t fixed = 0;
    for (int32_t i = 0; i < n_; ++i) fixed += w.state.inv_mass[i] == 0.0;
    const bool held = fixed > static_cast<int32_t>(w.attachments.pins().size());
    lines_ = line_passes_ > 0 && !held;
    if (!lines_) return false;
    std::vector<std::pair<int32_t, int32_t>> edges;
    std::vector<int32_t> spring_of;  // the model's spring for each edge
    for (int32_t k = 0; k < static_cast<int32_t>(m.springs.size()); ++k) {
      const Spring& s = m.springs[k];
      if (s.kind != SpringKind::structural || !(s.stiffness > 0.0)) continue;
      edges.push_back({s.i, s.j});
      spring_of.push_back(k);
    }
    const ChainCover cover = cover_with_chains(m.rest_position, edges, kMaxLayers, kMinChain);
    std::vector<uint8_t> swept(m.springs.size(), 0);
    for (int32_t e : cover.left_over) swept[spring_of[e]] = 1;
    std::map<std::pair<int32_t, int32_t>, int32_t> spring_at;  // particle pair → spring
    for (size_t e = 0; e < edges.size(); ++e)
      spring_at[{std::min(edges[e].first, edges[e].second),
                 std::max(edges[e].first, edges[e].second)}] = spring_of[e];
    for (const auto& chains : cover.layers) {
      std::vector<std::vector<int32_t>> solved;
      for (const std::vector<int32_t>& chain : chains) {
        const bool through_fixed = std::any_of(chain.begin(), chain.end(), [&](int32_t p) {
          return w.state.inv_mass[p] == 0.0;
        });
        if (!through_fixed) {
          solved.push_back(chain);
          continue;
        }
        for (size_t t = 0; t + 1 < chain.size(); ++t)
          swept[spring_at.at({std::min(chain[t], chain[t + 1]),
                              std::max(chain[t], chain[t + 1])})] = 1;
      }
      if (solved.empty()) continue;
      layers_.emplace_back();
      layers_.back().build(std::move(solved), still_, m.rest_position);
    }
    left_over_.build(m, [&](const Spring&, int32_t k) { return swept[k] != 0; });
    // Every structural spring of the cover has the scene's one stiffness, rest length aside;
    // each chain constraint keeps its own rest length.
    structural_ = {};
    for (const Spring& s : m.springs)
      if (s.kind == SpringKind::structural && s.stiffness > 0.0) {
        structural_ = {s.stiffness, s.damping};
        break;
      }
    return true;
  }

  // The attachments and contacts, as each pass and each stiff sweep after them starts.
  void constrain(const std::vector<Collider>& colliders, int32_t blocks) {
    if (!attached_ && colliders.empty()) return;
#pragma omp for schedule(static)
    for (int32_t b = 0; b < blocks; ++b) {
      if (attached_) particles_.attachments(b * kBlock, (b + 1) * kBlock);
      particles_.contacts(colliders, b * kBlock, (b + 1) * kBlock);
    }
  }

  // One pass over the chains, layer by layer (block Gauss–Seidel between layers), every pass but
  // the last over-relaxed by ω, as the grid's; then the left-over structural springs, swept.
  void solve_chains(Real h, bool first, Real omega) {
    const Compliance<Real> compliance_h =
        Compliance<Real>::of(structural_.stiffness, structural_.damping, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    for (ChainLayer<Real>& layer : layers_) {
#pragma omp for schedule(static)
      for (int G = 0; G < layer.groups(); ++G)
        solve_group(layer, G, alpha_tilde, gamma, first, omega);
    }
    if (!left_over_.empty()) left_over_.template sweep<false>(particles_, h, true);
  }

  // The chains of group G: each constraint's row from the particles (gathered lane by lane),
  // eliminated as it comes; the substitution back; the moves, lane by lane.
  void solve_group(ChainLayer<Real>& layer, int G, Real alpha_tilde, Real gamma, bool first,
                   Real omega) {
    const Real *__restrict bx = particles_.base.x.data(), *__restrict by = particles_.base.y.data(),
                           *__restrict bz = particles_.base.z.data();
    Real *__restrict mx = particles_.move.x.data(), *__restrict my = particles_.move.y.data(),
                     *__restrict mz = particles_.move.z.data();
    const Real* __restrict w = particles_.inv_mass.data();
    ChainScratch<Lane>& cs = layer.scratch;
    Lane *__restrict nx = cs.n.x.data(), *__restrict ny = cs.n.y.data(),
                     *__restrict nz = cs.n.z.data();
    Lane *__restrict fe = cs.f.data(), *__restrict g = cs.g.data(),
                     *__restrict inv_beta = cs.inv_beta.data(), *__restrict lambda = cs.lambda.data();
    const int32_t* __restrict slot = layer.slot.data() + size_t(layer.first[G]) * L;
    const Real* __restrict rest = layer.rest.data() + size_t(layer.first[G]) * L;
    const int len = layer.length[G], e0 = layer.entry[G];
    const Real keep = first ? Real(0) : Real(1);
    // Particle t of every lane, gathered.
    struct Ends {
      Lane bx, by, bz, mx, my, mz, w;
    };
    auto gather = [&](int t) {
      Ends e;
      for (int l = 0; l < L; ++l) {
        const int32_t p = slot[t * L + l];
        e.bx[l] = bx[p], e.by[l] = by[p], e.bz[l] = bz[p];
        e.mx[l] = mx[p], e.my[l] = my[p], e.mz[l] = mz[p];
        e.w[l] = w[p];
      }
      return e;
    };
    Ends a = gather(0);
    for (int t = 0; t < len; ++t) {
      const Ends b = gather(t + 1);
      // chain_row's arithmetic on lanes: direction, diagonal, right-hand side (zero where both
      // ends are still: padding lanes, whose Δλ then stays zero).
      const Lane rx = b.mx - a.mx, ry = b.my - a.my, rz = b.mz - a.mz;
      const Lane dx = (b.bx - a.bx) + rx, dy = (b.by - a.by) + ry, dz = (b.bz - a.bz) + rz;
      Lane len2 = dx * dx + dy * dy + dz * dz, length;
      for (int l = 0; l < L; ++l) length[l] = std::sqrt(len2[l]);
      Lane r0;
      std::memcpy(&r0, rest + t * L, sizeof(Lane));
      // A lane past its chain's end holds no constraint (rest length 0): no direction, so it is
      // coupled to nothing, and no right-hand side, so its Δλ stays zero.
      const Lane inv = r0 > 0 && length > 0 ? Lane{} + 1 / length : Lane{};
      const Lane ux = dx * inv, uy = dy * inv, uz = dz * inv, wsum = a.w + b.w;
      const ChainRowOf<Lane> c{
          ux, uy, uz, (1 + gamma) * wsum + alpha_tilde,
          r0 > 0 && wsum > 0 ? -(length - r0) - gamma * (ux * rx + uy * ry + uz * rz) : Lane{}};
      const int q = e0 + t + 1;
      eliminate<Lane>(c, a.w, gamma, alpha_tilde * keep * lambda[q], nx, ny, nz, fe, g, inv_beta,
                      q - 1, q, q);
      a = b;
    }
    for (int t = len - 1; t >= 0; --t) {
      const int q = e0 + t + 1;
      layer.dl[q] = omega * substitute<Lane>(g, inv_beta, lambda, keep, omega, q, fe[q + 1],
                                             g[q + 1]);
    }
    // The moves: constraint t pulls particle t back and t + 1 on along its direction, lane by
    // lane (a layer's chains share no particle; the still slot takes no move).
    for (int t = 0; t < len; ++t) {
      const int q = e0 + t + 1;
      for (int l = 0; l < L; ++l) {
        const int32_t i = slot[t * L + l], j = slot[(t + 1) * L + l];
        if (i == still_ || j == still_) continue;
        const Real s = layer.dl[q][l], sx = nx[q][l], sy = ny[q][l], sz = nz[q][l];
        mx[i] -= w[i] * s * sx;
        my[i] -= w[i] * s * sy;
        mz[i] -= w[i] * s * sz;
        mx[j] += w[j] * s * sx;
        my[j] += w[j] * s * sy;
        mz[j] += w[j] * s * sz;
      }
    }
  }

  int32_t n_ = 0, slots_ = 0, still_ = 0;
  // Whether the arrays hold the state as the last frame left it (see the grid solver).
  bool stopping_ = false;  ///< the frame stops early (shared by the threads)
  bool current_ = false;
  int substeps_ = 1;
  double frame_dt_ = 0.0;
  int iterations_ = kDefaultIterations;
  int stiff_sweeps_ = 0;
  bool attached_ = false;
  Particles<Real> particles_;
  std::vector<Triangle> triangles_;  ///< built when a collider first moves
  std::vector<Vec3> scratch_;  ///< wind forces, AoS as forces.h writes them
  SweepSet<Real> all_;         ///< every spring (with line passes: all but the structural)
  SweepSet<Real> stiffest_;    ///< the stiffest springs (with line passes: the structural)
  BendSet<Real> bend_;         ///< a material's bending elements
  forces::BendingDamping bend_damping_;  ///< their damping, over a frame's step
  double damp_time_ = 0.0;  ///< s stepped since bend_damping_ last ran (a frame's parts add up)
  bool damp_now_ = false;   ///< this frame's part runs it (set by one thread for the team)
  // Line passes (solver.line_passes).
  int line_passes_ = 0;
  Real relaxation_ = 1;
  bool lines_ = false;
  SpringParams structural_;                     ///< the chains' springs' stiffness and damping
  std::vector<ChainLayer<Real>> layers_;        ///< the chain cover's layers
  SweepSet<Real> left_over_;                    ///< structural springs in no solved chain
};

}  // namespace

}  // namespace drape::xpbd

namespace drape {

std::unique_ptr<Solver> make_mesh_xpbd(Precision precision) {
  if (precision == Precision::f32) return std::make_unique<xpbd::MeshXpbd<float>>();
  return std::make_unique<xpbd::MeshXpbd<double>>();
}

}  // namespace drape
