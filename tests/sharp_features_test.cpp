// Sharp features of colliders (a box's and a mesh's convex edges and corners, an open mesh's
// rim) and the pushes that keep the cloth's edges and triangles out of them, against closed forms.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <tuple>
#include <utility>

#include "collision/feature_contacts.h"
#include "collision/motion.h"
#include "collision/sharp_features.h"

namespace drape {
namespace {

// A box has twelve edges, each between two faces whose normals are two of its axes, and
// eight corners pointing out along the diagonals; its faces' diagonals are not features.
TEST(SharpFeatures, ABoxHasTwelveEdgesAndEightCorners) {
  const Mat3 R = rotation_xyz(Vec3(10.0, 20.0, 30.0));
  const Vec3 centre(0.1, 0.2, 0.3), half(0.3, 0.2, 0.1);
  const SharpFeatures f = box_features(centre, half, R);
  ASSERT_EQ(f.edges.size(), 12u);
  ASSERT_EQ(f.corners.size(), 8u);
  for (const SharpFeatures::Edge& e : f.edges) {
    EXPECT_NEAR(e.n1.dot(e.n2), 0.0, 1e-12);
    // Both ends on both faces' planes, at the half extent along each normal.
    for (const Vec3& n : {e.n1, e.n2}) {
      const Vec3 local = R.transpose() * n;
      double extent = 0.0;
      for (int k = 0; k < 3; ++k) extent += std::abs(local[k]) * half[k];
      EXPECT_NEAR(n.dot(e.a - centre), extent, 1e-12);
      EXPECT_NEAR(n.dot(e.b - centre), extent, 1e-12);
    }
    const double length = (e.b - e.a).norm();
    EXPECT_TRUE(std::abs(length - 0.6) < 1e-12 || std::abs(length - 0.4) < 1e-12 ||
                std::abs(length - 0.2) < 1e-12);
  }
  for (const SharpFeatures::Corner& c : f.corners) {
    const Vec3 local = R.transpose() * (c.p - centre);
    EXPECT_TRUE(local.cwiseAbs().isApprox(half, 1e-12));
    EXPECT_TRUE((R.transpose() * c.n).isApprox(local.cwiseSign() / std::sqrt(3.0), 1e-12));
    // Its faces' normals: the three axes it lies out along (once or twice each: a face's
    // two triangles meet at two of its corners).
    ASSERT_GE(c.count, 3);
    for (int k = 0; k < c.count; ++k) {
      const Vec3 n = R.transpose() * f.face_normals[c.first + k];
      EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-12);
      EXPECT_GT(n.dot(local.cwiseSign()), 0.0);
    }
  }
}

// A closed mesh: a finely tessellated ball has no sharp features; a coarse one (an octahedral
// ball, faces turning by 45° and more) has them at every edge and corner.
TEST(SharpFeatures, ASmoothMeshHasNoneAndACoarseOneHasThem) {
  auto ball = [](int segments, int rings) {
    std::vector<Vec3> v;
    std::vector<Triangle> t;
    v.push_back(Vec3(0.0, 1.0, 0.0));
    for (int r = 1; r < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        const double theta = M_PI * r / rings, phi = 2.0 * M_PI * s / segments;
        v.push_back(Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                         -std::sin(theta) * std::sin(phi)));
      }
    v.push_back(Vec3(0.0, -1.0, 0.0));
    const int32_t bottom = int32_t(v.size()) - 1;
    auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    for (int s = 0; s < segments; ++s) t.push_back({0, at(1, s), at(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r)
      for (int s = 0; s < segments; ++s) {
        t.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
        t.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
      }
    for (int s = 0; s < segments; ++s)
      t.push_back({bottom, at(rings - 1, s + 1), at(rings - 1, s)});
    return std::make_pair(v, t);
  };
  const auto [fine_v, fine_t] = ball(96, 48);
  EXPECT_TRUE(sharp_features(TriangleShape(fine_v, fine_t), kSharpAngle).empty());
  const auto [coarse_v, coarse_t] = ball(4, 2);  // an octahedron
  const SharpFeatures f = sharp_features(TriangleShape(coarse_v, coarse_t), kSharpAngle);
  EXPECT_EQ(f.edges.size(), 12u);
  EXPECT_EQ(f.corners.size(), 6u);
  for (const SharpFeatures::Corner& c : f.corners) EXPECT_TRUE(c.n.isApprox(c.p, 1e-12));
}

// An open sheet is two-sided: its rim is a blade all round (each rim edge's faces are the two
// sides of its one triangle, and it points out across the rim in the sheet's plane), a
// square's four corners are corners, and its flat inside has no features. Folded into a tent,
// the ridge is an edge on the side it points out to, however its triangles are wound.
TEST(SharpFeatures, AnOpenSheetHasBladesAllRoundAndItsRidgesOnTheirOutside) {
  // A unit square in the x–z plane as 2 × 2 cells; `ridge` lifts its middle line x = 0.5.
  auto sheet = [](double ridge, bool mixed_winding) {
    std::vector<Vec3> v;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) v.push_back(Vec3(0.5 * i, i == 1 ? ridge : 0.0, 0.5 * j));
    std::vector<Triangle> t;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int32_t a = 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
        t.push_back({a, c, b});
        t.push_back(mixed_winding && i == 1 ? Triangle{a, c, d} : Triangle{a, d, c});
      }
    return TriangleShape(v, t);
  };
  const Vec3 middle(0.5, 0.0, 0.5);
  for (const bool mixed : {false, true}) {
    const SharpFeatures flat = sharp_features(sheet(0.0, mixed), kSharpAngle);
    ASSERT_EQ(flat.edges.size(), 8u);
    for (const SharpFeatures::Edge& e : flat.edges) {
      EXPECT_NEAR(std::abs(e.n1.y()), 1.0, 1e-12);
      EXPECT_TRUE(e.n2.isApprox(-e.n1, 1e-12));
      // Across the rim, away from the sheet: along the axis the rim's middle lies out on.
      const Vec3 rim = 0.5 * (e.a + e.b) - middle;
      const Vec3 expected =
          std::abs(rim.x()) > std::abs(rim.z()) ? Vec3(rim.x(), 0.0, 0.0) : Vec3(0.0, 0.0, rim.z());
      EXPECT_TRUE(e.out.isApprox(expected.normalized(), 1e-12));
    }
    ASSERT_EQ(flat.corners.size(), 4u);
    for (const SharpFeatures::Corner& c : flat.corners) {
      EXPECT_TRUE(c.n.isApprox((c.p - middle).normalized(), 1e-12));
      // A rim's: its two rim edges run from it along the axes, into the sheet.
      EXPECT_TRUE(c.rim);
      EXPECT_EQ(c.count, 0);
      for (const Vec3& u : c.along) {
        EXPECT_NEAR(u.y(), 0.0, 1e-12);
        EXPECT_NEAR(u.cwiseAbs().maxCoeff(), 1.0, 1e-12);
        EXPECT_LT(u.dot(c.p - middle), 0.0);
      }
    }

    // The tent: ridge 0.5 m up, its slopes at 45°. Its two ridge edges point up.
    const SharpFeatures tent = sharp_features(sheet(0.5, mixed), kSharpAngle);
    int ridges = 0;
    for (const SharpFeatures::Edge& e : tent.edges) {
      if (e.n2.isApprox(-e.n1, 1e-12)) continue;  // a blade
      ++ridges;
      EXPECT_NEAR(e.a.x(), 0.5, 1e-12);
      EXPECT_NEAR(e.n1.y(), std::sqrt(0.5), 1e-12);
      EXPECT_NEAR(e.n2.y(), std::sqrt(0.5), 1e-12);
      EXPECT_TRUE(e.out.isApprox(Vec3::UnitY(), 1e-12));
    }
    EXPECT_EQ(ridges, 2);
    // The square's corners still, and the ridge's middle vertex (its faces turn by 45° from
    // its normal, up); the ridge's ends on the rim are not (the sheet spans 180° there).
    ASSERT_EQ(tent.corners.size(), 5u);
    int up = 0;
    for (const SharpFeatures::Corner& c : tent.corners)
      if (c.n.isApprox(Vec3::UnitY(), 1e-12)) {
        ++up;
        EXPECT_TRUE(c.p.isApprox(Vec3(0.5, 0.5, 0.5)));
      }
    EXPECT_EQ(up, 1);
  }
}

// A cloth edge lying across a right-angled edge (along z, faces +x and +y) and passing inside
// it: its point nearest the edge, halfway, is pushed out along the diagonal to the gap.
TEST(FeaturePush, AClothEdgeAcrossABoxEdgeIsPushedOutToTheGap) {
  const SharpFeatures::Edge e{Vec3(0.0, 0.0, -1.0), Vec3(0.0, 0.0, 1.0), Vec3::UnitX(),
                              Vec3::UnitY(), Vec3(1.0, 1.0, 0.0).normalized()};
  const Vec3 p(-0.1, 0.01, 0.2), q(0.01, -0.1, 0.2);
  double s = 0.0, depth = 0.0;
  Vec3 n;
  ASSERT_TRUE(edge_edge_push(e, p, q, 0.005, s, n, depth));
  EXPECT_NEAR(s, 0.5, 1e-12);
  EXPECT_TRUE(n.isApprox(Vec3(1.0, 1.0, 0.0).normalized(), 1e-12));
  EXPECT_NEAR(depth, 0.005 + 0.09 / std::sqrt(2.0), 1e-12);
  // Outside by less than the gap: out along the line between the nearest points.
  const Vec3 lift = (0.09 / std::sqrt(2.0) + 0.003) * Vec3(1.0, 1.0, 0.0).normalized();
  ASSERT_TRUE(edge_edge_push(e, p + lift, q + lift, 0.005, s, n, depth));
  EXPECT_NEAR(depth, 0.002, 1e-12);
  // Farther than the gap, wholly beyond one face, past the edge's end, or an end inside the
  // body: nothing.
  EXPECT_FALSE(edge_edge_push(e, p + 2.0 * lift, q + 2.0 * lift, 0.005, s, n, depth));
  EXPECT_FALSE(edge_edge_push(e, Vec3(-0.1, 0.01, 0.0), Vec3(-0.2, 0.01, 0.1), 0.005, s, n, depth));
  EXPECT_FALSE(edge_edge_push(e, p + Vec3(0, 0, 1.5), q + Vec3(0, 0, 1.5), 0.005, s, n, depth));
  EXPECT_FALSE(edge_edge_push(e, Vec3(-0.1, -0.01, 0.2), q, 0.005, s, n, depth));
}

// A ridge folded flat onto itself (its faces' normals opposite, not a blade: an open sheet's
// rim is marked as one), along z, the sheet on x < 0 in the plane y = 0. A cloth edge through
// the plane beyond it is kept the gap from it; one through the sheet near it (come round it)
// is pushed out past it along the sheet; one wholly on a side has nothing to do with it.
TEST(FeaturePush, AClothEdgeAcrossAFlatFoldedRidgeIsKeptBeyondIt) {
  const SharpFeatures::Edge e{Vec3(0.0, 0.0, -1.0), Vec3(0.0, 0.0, 1.0), Vec3::UnitY(),
                              -Vec3::UnitY(), Vec3::UnitX()};
  auto across = [](double x) { return std::pair{Vec3(x, 0.1, 0.3), Vec3(x, -0.1, 0.3)}; };
  double s = 0.0, depth = 0.0;
  Vec3 n;
  auto [p, q] = across(0.003);
  ASSERT_TRUE(edge_edge_push(e, p, q, 0.005, s, n, depth));
  EXPECT_NEAR(s, 0.5, 1e-12);
  EXPECT_TRUE(n.isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_NEAR(depth, 0.002, 1e-12);
  std::tie(p, q) = across(-0.02);
  ASSERT_TRUE(edge_edge_push(e, p, q, 0.005, s, n, depth));
  EXPECT_TRUE(n.isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_NEAR(depth, 0.025, 1e-12);
  std::tie(p, q) = across(0.01);
  EXPECT_FALSE(edge_edge_push(e, p, q, 0.005, s, n, depth));
  EXPECT_FALSE(
      edge_edge_push(e, Vec3(-0.02, 0.1, 0.3), Vec3(0.02, 0.001, 0.3), 0.005, s, n, depth));
}

// A blade: an open sheet's rim along z from −1 to 1, the sheet on x < 0 in the plane y = 0.
// A cloth edge from over the sheet to past the rim, its point nearest the rim on the far side
// of the plane, cuts into the sheet before the rim: it is moved back round the rim, to the
// side its end over the sheet is on. One through the sheet 30 cm in, its other end behind the
// rim's line but past the blade's end (z < −1), is not a cut of this rim at all, though its
// nearest point lies beside the blade on the far side too: it was moved round the rim, 30 cm
// in one push, and a cloth sliding off a sheet's corner was torn.
TEST(FeaturePush, AClothEdgeCuttingPastABladeIsMovedBackRoundItsRim) {
  SharpFeatures::Edge e{Vec3(0.0, 0.0, -1.0), Vec3(0.0, 0.0, 1.0), Vec3::UnitY(), -Vec3::UnitY(),
                        Vec3::UnitX()};
  e.blade = true;
  double s = 0.0, depth = 0.0;
  Vec3 n;
  ASSERT_TRUE(
      edge_edge_push(e, Vec3(-0.02, 0.01, 0.3), Vec3(0.03, -0.02, 0.3), 0.005, s, n, depth));
  EXPECT_GT(n.y(), 0.0);  // to the upper side, where the end over the sheet is
  EXPECT_GT(depth, 0.005);
  EXPECT_LT(depth, 0.01);
  EXPECT_FALSE(
      edge_edge_push(e, Vec3(-0.3, 0.01, -0.8), Vec3(-0.299, -0.03, -1.01), 0.005, s, n, depth));
}

// A triangle through a box's corner (faces +x, +y, +z) is pushed out along its own normal to
// the gap above it, at the corner's projection (its centroid here).
TEST(FeaturePush, ATriangleOverACornerIsPushedOutAlongItsNormal) {
  SharpFeatures::Corner c{Vec3::Zero(), Vec3(1.0, 1.0, 1.0).normalized(), 0, 3};
  const Vec3 faces[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  const Vec3 sink = -0.01 * Vec3(1.0, 1.0, 1.0).normalized();
  const Vec3 a = Vec3(0.3, -0.15, -0.15) + sink, b = Vec3(-0.15, 0.3, -0.15) + sink,
             d = Vec3(-0.15, -0.15, 0.3) + sink;
  double w[3], depth = 0.0;
  Vec3 n;
  ASSERT_TRUE(corner_triangle_push(c, faces, a, b, d, 0.005, 1.0, 0, w, n, depth));
  EXPECT_TRUE(n.isApprox(Vec3(1.0, 1.0, 1.0).normalized(), 1e-12));
  EXPECT_NEAR(depth, 0.015, 1e-12);
  for (double wk : w) EXPECT_NEAR(wk, 1.0 / 3.0, 1e-12);
  // Wound the other way, the same push (the side is the corner's, not the winding's).
  ASSERT_TRUE(corner_triangle_push(c, faces, a, d, b, 0.005, 1.0, 0, w, n, depth));
  EXPECT_TRUE(n.isApprox(Vec3(1.0, 1.0, 1.0).normalized(), 1e-12));
  // A triangle that started the frame on the far side (the corner poking out beyond it, as a
  // box's foot does through the ground round it) is held there instead, at the gap.
  const Vec3 up = Vec3(1.0, 1.0, 1.0).normalized();
  EXPECT_EQ(corner_side(c, a, b, d, 0.005), -1);  // 1 cm below, by its winding's normal
  EXPECT_EQ(corner_side(c, a - sink, b - sink, d - sink, 0.005), 0);
  EXPECT_EQ(corner_side(c, a + 0.1 * up, b + 0.1 * up, d + 0.1 * up, 0.005), 1);
  EXPECT_FALSE(corner_triangle_push(c, faces, a, b, d, 0.005, 1.0, -1, w, n, depth));
  const Vec3 near = -0.002 * up - sink;  // 2 mm below
  ASSERT_TRUE(
      corner_triangle_push(c, faces, a + near, b + near, d + near, 0.005, 1.0, -1, w, n, depth));
  EXPECT_TRUE(n.isApprox(-up, 1e-12));
  EXPECT_NEAR(depth, 0.003, 1e-12);
  // Above by more than the gap, or not over the corner: nothing.
  EXPECT_FALSE(corner_triangle_push(c, faces, a - 3.0 * sink, b - 3.0 * sink, d - 3.0 * sink, 0.005,
                                    1.0, 0, w, n, depth));
  const Vec3 aside(0.5, 0.0, -0.5);
  EXPECT_FALSE(
      corner_triangle_push(c, faces, a + aside, b + aside, d + aside, 0.005, 1.0, 0, w, n, depth));
}

// A cube's corner at the origin, the body where x < 0, y > 0 and z > 0 (faces +x, −y, −z), and
// a cloth triangle draped over the edge that leaves the corner along +y, 2 to 7 cm from it
// (taken from a run where `fast` let it happen): its plane is steep to the edge, so the
// corner's projection falls inside it and the corner lies 3.4 cm beyond its plane, but no point
// of it is inside the body. It is the edge's to hold, not the corner's: pushed across the
// corner it was wrapped round to the corner's far side, the corner through its neighbours.
TEST(FeaturePush, ATriangleOverAnEdgeBesideTheCornerIsNotPushedAcrossIt) {
  SharpFeatures::Corner c{Vec3::Zero(), Vec3(1.0, -1.0, -1.0).normalized(), 0, 3};
  const Vec3 faces[3] = {Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ()};
  const Vec3 a(-0.02501, 0.01675, -0.01962), b(0.02963, 0.06972, 0.00127),
      d(0.00310, 0.02851, -0.02582);
  double w[3], depth = 0.0;
  Vec3 n;
  // As said: the corner beyond the plane, over the triangle, and no point of it in the body.
  const Vec3 normal = (b - a).cross(d - a).normalized();
  const Vec3 foot = c.p - normal.dot(c.p - a) * normal;
  EXPECT_GT(std::abs(normal.dot(c.p - a)), 0.03);
  EXPECT_TRUE(over_face(foot, a, b, d, 0.0).interior);
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; i + j <= 50; ++j) {
      const Vec3 q = a + (i / 50.0) * (b - a) + (j / 50.0) * (d - a);
      ASSERT_FALSE(q.x() < 0.0 && q.y() > 0.0 && q.z() > 0.0) << i << " " << j;
    }
  EXPECT_FALSE(corner_triangle_push(c, faces, a, b, d, 0.005, 1.0, 0, w, n, depth)) << depth;
}

// The same corner, the body above it (x < 0, y > 0, z < 0, faces +x, −y, +z), and a level
// triangle 27 cm above, round the body's far edge: the corner points away from it, 27 cm
// beyond its plane, and the body's cone by the corner reaches into it. With no side kept
// from the frame's start, a push along the corner's direction would carry it down through
// the body. Neither can the corner have come 27 cm in a frame that allowed 2 cm, nor can a
// corner be that deep through a triangle of 7 cm edges whose corners lie outside it: nothing.
TEST(FeaturePush, ACornerDeeperThanTheFrameOrTheTriangleAllowsIsNotGuessedThrough) {
  SharpFeatures::Corner c{Vec3::Zero(), Vec3(1.0, -1.0, 1.0).normalized(), 0, 3};
  const Vec3 faces[3] = {Vec3::UnitX(), -Vec3::UnitY(), Vec3::UnitZ()};
  const Vec3 a(0.02, 0.27, -0.03), b(-0.03, 0.27, 0.02), d(0.02, 0.27, 0.03);
  double w[3], depth = 0.0;
  Vec3 n;
  EXPECT_FALSE(corner_triangle_push(c, faces, a, b, d, 0.005, 0.02, 0, w, n, depth)) << depth;
  EXPECT_FALSE(corner_triangle_push(c, faces, a, b, d, 0.005, 1.0, 0, w, n, depth)) << depth;
  // The same triangle three times as large (its corners outside still) is within both.
  const Vec3 mid = (a + b + d) / 3.0;
  const Vec3 A = mid + 3.0 * (a - mid), B = mid + 3.0 * (b - mid), D = mid + 3.0 * (d - mid);
  ASSERT_TRUE(corner_triangle_push(c, faces, A, B, D, 0.005, 1.0, 0, w, n, depth));
  EXPECT_NEAR(depth, 0.275, 1e-12);
  // Kept on a side since the frame's start, it is held there however deep.
  const int up = (b - a).cross(d - a).y() > 0.0 ? 1 : -1;
  ASSERT_TRUE(corner_triangle_push(c, faces, a, b, d, 0.005, 0.02, -up, w, n, depth));
  EXPECT_NEAR(depth, 0.275, 1e-12);
}

// A sheet's rim corner at the origin (the sheet in y = 0 over x < 0, z < 0). A triangle lying
// nearly in the sheet's plane round the corner, across it (its plane s·(0.001 + 0.01x − 0.015z),
// 1 mm above or below the corner), with none of its own corners over the sheet, its rim edges
// leaving it to different sides and no side from the frame's start, is pushed the shorter way
// out along its normal, to the gap; a side from the frame's start still wins.
TEST(FeaturePush, ATriangleFlatRoundASheetsCornerIsPushedTheShorterWayOut) {
  const SharpFeatures::Corner c{Vec3::Zero(), Vec3(1.0, 0.0, 1.0).normalized(), 0, 0,
                                true,         {-Vec3::UnitX(), -Vec3::UnitZ()}};
  auto at = [](double s) {
    auto point = [s](double x, double z) { return Vec3(x, s * (0.001 + 0.01 * x - 0.015 * z), z); };
    return std::array{point(0.1, -0.12), point(-0.12, 0.1), point(0.1, 0.1)};
  };
  const double lift = 0.001 / Vec3(-0.01, 1.0, 0.015).norm();  // the plane's height at the corner
  double w[3], depth = 0.0;
  Vec3 n;
  for (const double s : {1.0, -1.0}) {
    const auto x = at(s);
    const Vec3 out = Vec3(-0.01, s, 0.015).normalized();  // its normal, turned down for s < 0
    ASSERT_TRUE(corner_triangle_push(c, nullptr, x[0], x[1], x[2], 0.005, 1.0, 0, w, n, depth))
        << s;
    EXPECT_TRUE(n.isApprox(out, 1e-12)) << s;
    EXPECT_NEAR(depth, 0.005 - lift, 1e-12);
    ASSERT_TRUE(corner_triangle_push(c, nullptr, x[0], x[2], x[1], 0.005, 1.0, 0, w, n, depth))
        << s;
    EXPECT_TRUE(n.isApprox(out, 1e-12)) << s;
  }
  const auto x = at(1.0);  // its winding's normal points up
  ASSERT_TRUE(corner_triangle_push(c, nullptr, x[0], x[1], x[2], 0.005, 1.0, -1, w, n, depth));
  EXPECT_TRUE(n.isApprox(-Vec3(-0.01, 1.0, 0.015).normalized(), 1e-12));
  EXPECT_NEAR(depth, 0.005 + lift, 1e-12);
}
}  // namespace
}  // namespace drape
