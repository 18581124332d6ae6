#include "collision/feature_contacts.h"

#include <algorithm>
#include <cmath>

namespace drape {

namespace {

// A cloth triangle nearly edge-on to a corner's direction has no clear side to be pushed to;
// the edge pairs hold it.
constexpr double kEdgeOn = 0.2;
// How far outside a triangle (in barycentric terms) a rim's corner still counts as under it:
// a cloth folded sharply over the corner has it under neither triangle of the fold, and the
// fold's edge, which passes it, cannot tell the side it must pass on.
constexpr double kRimMargin = 0.1;
// The most cells a grid has: a grid over widely spread features takes wider cells.
constexpr int64_t kMaxGridCells = int64_t{1} << 18;

// A blade (an open mesh's rim): the cloth edge p–q crossing its plane, t the place along the
// blade of its point nearest the edge, d from there to the edge's nearest point.
//  - Beside the blade (0 < t < 1), an edge with one end over the sheet passes the rim on that
//    end's side, `gap` clear of it: where it passes on the other side (it cuts into the sheet
//    before the rim) it is moved back round the rim, across the line between the two, the
//    short way for an edge lying nearly along the sheet. An edge with neither end over the
//    sheet keeps `gap` from the rim; one with its ends over it on its two sides passes
//    through the face, not the rim.
//  - At an end of the blade where the rim turns a corner (next_out), an edge that meets the
//    sheet's plane inside the corner (behind both rim edges, nearer the corner than the edge
//    is long) cuts across it: pushed out along the corner's bisector until it meets the plane
//    `gap` beyond the corner. Elsewhere it keeps `gap` from the corner.
bool blade_push(const SharpFeatures::Edge& e, const Vec3& p, const Vec3& q, double t, const Vec3& d,
                double gap, Vec3& n, double& depth) {
  const double distance = d.norm();
  if (t <= 0.0 || t >= 1.0) {
    const Vec3& corner = t <= 0.0 ? e.a : e.b;
    const Vec3& next = e.next_out[t <= 0.0 ? 0 : 1];
    const double hp = e.n1.dot(p - corner), hq = e.n1.dot(q - corner);
    const Vec3 meets = p + (hp / (hp - hq)) * (q - p);  // (the ends lie on the plane's two sides)
    const Vec3 in = meets - corner;
    if (next.squaredNorm() > 0.0 && e.out.dot(in) < 0.0 && next.dot(in) < 0.0 &&
        in.squaredNorm() < (q - p).squaredNorm()) {
      n = (e.out + next).normalized();
      depth = gap - n.dot(in);
      return true;
    }
  } else {
    const Vec3 ab = e.b - e.a;
    // An end within `gap` of the rim may have come round it (particle contacts keep it off the
    // rim, not on its side): it is not over the sheet until it is farther in.
    auto behind = [&](const Vec3& end) { return e.out.dot(end - e.a) < -gap; };
    auto over = [&](const Vec3& end) {
      const double along = (end - e.a).dot(ab);
      return behind(end) && along >= 0.0 && along <= ab.squaredNorm();
    };
    const bool p_over = over(p), q_over = over(q);
    if (p_over && q_over) return false;
    // The other end must lie past the rim's line: one behind it, past the blade's end, has the
    // edge passing another rim edge or the corner (the edge's own pairs), however near this
    // rim's line the nearest points fall. (Taken as a cut of this rim, a cloth edge by the
    // neighbouring rim was moved round this one, 30 cm in one push.)
    const bool crosses = p_over ? !behind(q) : q_over && !behind(p);
    const Vec3& over_end = p_over ? p : q;
    const double side = crosses ? (e.n1.dot(over_end - e.a) > 0.0 ? 1.0 : -1.0) : 0.0;
    if (side * e.n1.dot(d) < 0.0) {
      n = -d / distance;
      depth = gap + distance;
      return true;
    }
    if (distance == 0.0 && side != 0.0) {
      n = side * e.n1;
      depth = gap;
      return true;
    }
  }
  if (!(distance > 0.0 && distance < gap)) return false;
  n = d / distance;
  depth = gap - distance;
  return true;
}

// A rim's corner under the triangle x[0..2] (unit normal n by its winding, the corner's
// projection inside it; `side` as corner_triangle_push's). Neither the sheet nor the triangle
// has an inside, but the sheet's corner is a wedge between the rim's two edges, and the
// triangle is kept `gap` beyond the corner (n turned to that side) on the side that clears it:
//  - that of its corners over the sheet (in the wedge): passing the corner on the other side,
//    it would cut into the sheet between them (corners over it on both sides: through the
//    face, not the corner's);
//  - else the side both rim edges turn away from its plane;
//  - else (the edges leave it to different sides, or lie nearly in its plane) the side it
//    started the frame on, where that was decided;
//  - else the side its plane passes the corner on (the shorter way out).
// A triangle wholly above or below the sheet cannot meet the corner.
bool rim_corner_push(const SharpFeatures::Corner& c, const Vec3* const x[3], Vec3& n, int side,
                     double gap, double& depth) {
  const Vec3 sheet = c.along[0].cross(c.along[1]).normalized();
  const Vec3 in0 = sheet.cross(c.along[0]), in1 = c.along[1].cross(sheet);  // into the wedge
  bool above = true, below = true;
  double over_side = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 o = *x[k] - c.p;
    const double height = sheet.dot(o);
    above = above && height > 0.0;
    below = below && height < 0.0;
    if (!(in0.dot(o) > 0.0 && in1.dot(o) > 0.0)) continue;
    const double s = height > 0.0 ? 1.0 : -1.0;
    if (over_side == -s) return false;
    over_side = s;
  }
  if (above || below) return false;
  const double s1 = n.dot(c.along[0]), s2 = n.dot(c.along[1]);
  if (over_side != 0.0) {
    const double facing = over_side * n.dot(sheet);
    if (std::abs(facing) < kEdgeOn) return false;
    side = facing > 0.0 ? 1 : -1;
  } else if (s1 * s2 >= 0.0 && std::max(std::abs(s1), std::abs(s2)) >= kEdgeOn) {
    side = s1 + s2 < 0.0 ? 1 : -1;
  } else if (side == 0) {
    // Nothing tells: the side the triangle's plane passes the corner on, the shorter way out.
    side = n.dot(*x[0] - c.p) < 0.0 ? -1 : 1;
  }
  n *= side;
  depth = gap - n.dot(*x[0] - c.p);
  return depth > 0.0;
}

// Whether some part of the triangle x[0..2] lies inside every one of corner c's face planes
// (faces[0 .. c.count)): the body by the corner reaches into it. The triangle is clipped by each
// plane in turn (Sutherland–Hodgman); a corner of more faces than the buffer holds counts as
// reaching in.
bool reaches_into(const SharpFeatures::Corner& c, const Vec3* faces, const Vec3* const x[3]) {
  constexpr int kMaxPolygon = 24;
  if (3 + c.count > kMaxPolygon) return true;
  std::array<Vec3, kMaxPolygon> polygon, clipped;
  for (int k = 0; k < 3; ++k) polygon[k] = *x[k] - c.p;
  int count = 3;
  for (int f = 0; f < c.count && count > 0; ++f) {
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      const Vec3 &a = polygon[k], &b = polygon[(k + 1) % count];
      const double da = faces[f].dot(a), db = faces[f].dot(b);
      if (da <= 0.0) clipped[kept++] = a;
      if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))
        clipped[kept++] = a + (da / (da - db)) * (b - a);
    }
    polygon = clipped;
    count = kept;
  }
  return count > 0;
}

}  // namespace

bool edge_edge_push(const SharpFeatures::Edge& e, const Vec3& p, const Vec3& q, double gap,
                    double& s, Vec3& n, double& depth) {
  // Each end beyond a face's plane or not.
  const bool p1 = e.n1.dot(p - e.a) > 0.0, q1 = e.n1.dot(q - e.a) > 0.0;
  const bool p2 = e.n2.dot(p - e.a) > 0.0, q2 = e.n2.dot(q - e.a) > 0.0;
  // Wholly beyond one face: it cannot reach into the body past this edge. An end inside both:
  // the particle contacts' to mend, not a crossing of the edge.
  if ((p1 && q1) || (p2 && q2) || !(p1 || p2) || !(q1 || q2)) return false;
  const SegmentPoints sp = closest_between_segments(p, q, e.a, e.b);
  s = sp.s;
  const Vec3 point = p + s * (q - p), ab = e.b - e.a;
  if (e.blade) return blade_push(e, p, q, sp.t, point - (e.a + sp.t * ab), gap, n, depth);
  const double along = (point - e.a).dot(ab) / ab.squaredNorm();
  if (!(along >= 0.0 && along <= 1.0)) return false;  // past the edge's ends: the corners'
  const Vec3 d = point - (e.a + along * ab);
  const double clearance = d.dot(e.out);
  if (clearance > 0.0) {
    const double distance = d.norm();
    if (distance >= gap) return false;
    n = d / distance;
    depth = gap - distance;
  } else {  // passing inside the edge
    n = e.out;
    depth = gap - clearance;
  }
  return depth > 0.0;
}

int corner_side(const SharpFeatures::Corner& c, const Vec3& x0, const Vec3& x1, const Vec3& x2,
                double gap) {
  const Vec3 normal = (x1 - x0).cross(x2 - x0);
  const double length = normal.norm();
  if (!(length > 0.0)) return 0;
  // Only a triangle over the corner has a side worth keeping: beside it, the corner may lie
  // beyond the triangle's plane without passing through it.
  if (!over_face(c.p, x0, x1, x2, 0.0).interior) return 0;
  const double height = normal.dot(x0 - c.p) / length;
  return height > 0.5 * gap ? 1 : height < -0.5 * gap ? -1 : 0;
}

bool corner_triangle_push(const SharpFeatures::Corner& c, const Vec3* faces, const Vec3& x0,
                          const Vec3& x1, const Vec3& x2, double gap, double reach, int side,
                          double w[3], Vec3& n, double& depth) {
  const Vec3* x[3] = {&x0, &x1, &x2};
  // As for edges: not wholly beyond one face, and every corner of the triangle outside (a
  // rim's corner has no inside: rim_corner_push).
  bool outside[3] = {c.rim, c.rim, c.rim};
  for (int f = 0; f < c.count; ++f) {
    bool beyond = true;
    for (int k = 0; k < 3; ++k) {
      const bool out = faces[f].dot(*x[k] - c.p) > 0.0;
      beyond = beyond && out;
      outside[k] = outside[k] || out;
    }
    if (beyond) return false;
  }
  if (!(outside[0] && outside[1] && outside[2])) return false;
  const TrianglePoint tp = over_face(c.p, x0, x1, x2, c.rim ? kRimMargin : 0.0);
  if (!tp.interior) return false;
  const Vec3 normal = (x1 - x0).cross(x2 - x0);
  const double area2 = normal.norm();
  if (!(area2 > 0.0)) return false;
  n = normal / area2;
  w[0] = tp.wa, w[1] = tp.wb, w[2] = tp.wc;
  if (c.rim) return rim_corner_push(c, x, n, side, gap, depth);
  const bool guessed = side == 0;
  if (guessed) {
    const double facing = n.dot(c.n);
    if (std::abs(facing) < kEdgeOn) return false;
    side = facing < 0.0 ? -1 : 1;
  }
  n *= side;
  const double height = n.dot(x0 - c.p);  // of the triangle's plane above the corner
  // A corner beyond the triangle's plane pierces it only where the body by the corner reaches
  // into the triangle: else the triangle lies beside the corner (over one of its edges, its
  // plane steep to the edge; the edge contacts' to hold). And a side guessed from the corner's
  // direction, not kept from the frame's start, holds only as deep as the corner can have come
  // in this frame, and as a corner can pass through a triangle whose corners all lie outside
  // it (about the triangle's size; twice its longest edge is allowed): deeper, the triangle
  // lies past the body's far side. Pushed across the corner, either was wrapped round it (4
  // and 27 cm in one frame, measured before this rule).
  if (height <= 0.0) {
    const double longest = std::sqrt(
        std::max({(x1 - x0).squaredNorm(), (x2 - x1).squaredNorm(), (x0 - x2).squaredNorm()}));
    if (guessed && -height > std::min(reach, 2.0 * longest)) return false;
    if (!reaches_into(c, faces, x)) return false;
  }
  depth = gap - height;
  return depth > 0.0;
}

void FeatureContacts::prepare(const ClothModel& model) {
  triangles_ = model.triangles;
  edges_ = triangle_edges(model.triangles);
  mean_edge_ = model.mean_edge;
  start_.resize(model.size());
  local_.resize(model.size());
  boost_ = 1.0;
  pairs_ = 0;
}

void FeatureContacts::Grid::build(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi,
                                  int32_t first, int32_t count, double min_cell) {
  begin.assign(1, 0);
  entries.clear();
  dims.setZero();
  if (count == 0) return;
  // Cells about as wide as the features' mean box, and never narrower than the cloth's edges.
  origin = lo[first];
  top = hi[first];
  double extent = 0.0;
  for (int32_t k = first; k < first + count; ++k) {
    origin = origin.cwiseMin(lo[k]);
    top = top.cwiseMax(hi[k]);
    extent += (hi[k] - lo[k]).maxCoeff();
  }
  cell = std::max(extent / count, min_cell);
  if (!(cell > 0.0)) cell = std::max((top - origin).maxCoeff(), 1.0);
  dims = dense_grid_dims(top - origin, cell, kMaxGridCells);
  auto index = [&](int i, int j, int l) { return (int64_t(l) * dims.y() + j) * dims.x() + i; };
  auto each_cell = [&](int32_t k, auto&& f) {
    const Eigen::Array3i a = dense_grid_cell(lo[k], origin, cell, dims);
    const Eigen::Array3i b = dense_grid_cell(hi[k], origin, cell, dims);
    for (int l = a.z(); l <= b.z(); ++l)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int i = a.x(); i <= b.x(); ++i) f(index(i, j, l));
  };
  begin.assign(dims.prod() + 1, 0);
  for (int32_t k = first; k < first + count; ++k) each_cell(k, [&](int64_t c) { ++begin[c + 1]; });
  for (size_t c = 1; c < begin.size(); ++c) begin[c] += begin[c - 1];
  entries.resize(begin.back());
  std::vector<int32_t> fill(begin.begin(), begin.end() - 1);
  for (int32_t k = first; k < first + count; ++k)
    each_cell(k, [&](int64_t c) { entries[fill[c]++] = k; });
}

FeatureContacts::Group& FeatureContacts::group_for(
    const std::shared_ptr<const SharpFeatures>& features) {
  for (Group& g : groups_)
    if (g.features == features) return g;
  Group& g = groups_.emplace_back();
  g.features = features;
  const SharpFeatures& f = *features;
  for (const SharpFeatures::Edge& e : f.edges) {
    g.lo.push_back(e.a.cwiseMin(e.b));
    g.hi.push_back(e.a.cwiseMax(e.b));
  }
  for (const SharpFeatures::Corner& c : f.corners) {
    g.lo.push_back(c.p);
    g.hi.push_back(c.p);
  }
  const int32_t edges = int32_t(f.edges.size()), corners = int32_t(f.corners.size());
  g.edge_grid.build(g.lo, g.hi, 0, edges, mean_edge_);
  g.corner_grid.build(g.lo, g.hi, edges, corners, mean_edge_);
  g.seen.assign(g.lo.size(), -1);
  g.hidden.assign(g.lo.size(), 0);
  return g;
}

const FeatureContacts::Group* FeatureContacts::find(const SharpFeatures* features) const {
  for (const Group& g : groups_)
    if (g.features.get() == features) return &g;
  return nullptr;
}

void FeatureContacts::gather(const std::vector<Collider>& colliders,
                             const std::vector<double>& travel, const ClothState& state,
                             const Vec3& gravity, double dt) {
  double fastest = 0.0;
  for (const Vec3& v : state.v) fastest = std::max(fastest, v.squaredNorm());
  allowed_ = boost_ * (2.0 * std::sqrt(fastest) * dt + gravity.norm() * dt * dt);
  std::copy(state.x.begin(), state.x.end(), start_.begin());
  pairs_ = 0;
  sheet_pairs_.clear();
  for (Group& g : groups_) {
    g.edge_pairs.clear();
    g.corner_pairs.clear();
  }
  for (size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k];
    if (!c.features || c.features->empty()) continue;
    Group& g = group_for(c.features);
    hide(colliders, k, g);
    const Mat3 back = c.pose.rotation.transpose();
    for (size_t i = 0; i < start_.size(); ++i) local_[i] = back * (start_[i] - c.pose.translation);
    g.reach = allowed_ + travel[k];
    gather(g, c.thickness + g.reach, c.thickness);
    pairs_ += int64_t(g.edge_pairs.size() + g.corner_pairs.size());
    if (c.mesh && !c.mesh->closed()) {
      const size_t before = sheet_pairs_.size();
      for (int32_t i = 0; i < int32_t(start_.size()); ++i) {
        if (state.inv_mass[i] == 0.0 || clear_of(c, start_[i], allowed_ + travel[k])) continue;
        Vec3 n;
        if (c.mesh->signed_distance(local_[i], n) < c.thickness + g.reach)
          sheet_pairs_.push_back({c.mesh.get(), i, local_[i]});
      }
      pairs_ += int64_t(sheet_pairs_.size() - before);
    }
  }
}

void FeatureContacts::hide(const std::vector<Collider>& colliders, size_t k, Group& g) {
  const Collider& c = colliders[k];
  auto buried = [&](const Vec3& local) {
    const Vec3 x = c.pose.apply(local);
    Vec3 n;
    for (size_t j = 0; j < colliders.size(); ++j)
      if (j != k && !clear_of(colliders[j], x) &&
          signed_distance(colliders[j], x, n) < colliders[j].thickness)
        return true;
    return false;
  };
  const SharpFeatures& f = *g.features;
  const size_t edges = f.edges.size();
  for (size_t e = 0; e < edges; ++e) g.hidden[e] = buried(f.edges[e].a) && buried(f.edges[e].b);
  for (size_t j = 0; j < f.corners.size(); ++j) g.hidden[edges + j] = buried(f.corners[j].p);
}

void FeatureContacts::gather(Group& g, double margin, double gap) {
  const int32_t edge_features = int32_t(g.features->edges.size());
  int32_t stamp = 0;
  // The features whose boxes overlap [lo, hi], each once, to `found`.
  auto query = [&](Vec3 lo, Vec3 hi, bool edges, auto&& found) {
    lo.array() -= margin;
    hi.array() += margin;
    ++stamp;
    (edges ? g.edge_grid : g.corner_grid).query(lo, hi, [&](int32_t k) {
      if (g.seen[k] == stamp || g.hidden[k]) return;
      g.seen[k] = stamp;
      if ((g.lo[k].array() <= hi.array()).all() && (lo.array() <= g.hi[k].array()).all())
        found(edges ? k : k - edge_features);
    });
  };
  std::fill(g.seen.begin(), g.seen.end(), -1);
  for (int32_t e = 0; e < int32_t(edges_.size()); ++e) {
    const Vec3 &p = local_[edges_[e][0]], &q = local_[edges_[e][1]];
    query(p.cwiseMin(q), p.cwiseMax(q), true, [&](int32_t j) { g.edge_pairs.emplace_back(j, e); });
  }
  for (int32_t t = 0; t < int32_t(triangles_.size()); ++t) {
    const Vec3 &a = local_[triangles_[t][0]], &b = local_[triangles_[t][1]],
               &c = local_[triangles_[t][2]];
    query(a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), false, [&](int32_t j) {
      g.corner_pairs.push_back({j, t, corner_side(g.features->corners[j], a, b, c, gap)});
    });
  }
}

void FeatureContacts::check(const std::vector<Vec3>& x) {
  if (pairs_ == 0 && groups_.empty()) return;
  double farthest = 0.0;
  for (size_t i = 0; i < x.size(); ++i)
    farthest = std::max(farthest, (x[i] - start_[i]).squaredNorm());
  if (std::sqrt(farthest) > allowed_)
    boost_ = std::min(2.0 * boost_, 1024.0);
  else
    boost_ = std::max(1.0, 0.95 * boost_);
}

int64_t FeatureContacts::bytes() const {
  int64_t total = heap_bytes(edges_, triangles_, groups_, sheet_pairs_, start_, local_);
  for (const Group& g : groups_) {
    total +=
        heap_bytes(g.edge_pairs, g.corner_pairs, g.lo, g.hi, g.seen, g.hidden, g.edge_grid.begin,
                   g.edge_grid.entries, g.corner_grid.begin, g.corner_grid.entries);
  }
  return total;
}

}  // namespace drape
