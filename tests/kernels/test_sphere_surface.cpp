// A sphere against a triangulated surface (fdem/kernels/sphere_surface.hpp,
// doc/spheres.md): the closest point of a triangle against a brute-force search; one
// contact per touched feature on a cube's skin (face, edge, vertex), with an overlap
// and a normal that stay continuous as the sphere rolls over an edge and around a
// vertex; no second contact from an edge next to the face the sphere is over; two
// contacts in a concave corner.
#include <fdem/kernels/granular.hpp>
#include <fdem/kernels/sphere_surface.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace fdem::kernels;

namespace {
// The unit cube's skin, 12 triangles (2 per face).
void Cube(std::vector<Vec3> &nodes, std::vector<std::array<int, 3>> &tris) {
  nodes.clear();
  for (int k = 0; k < 8; ++k) nodes.push_back(Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  tris.clear();
  for (const auto &q : quads) {
    tris.push_back({q[0], q[1], q[2]});
    tris.push_back({q[0], q[2], q[3]});
  }
}
std::vector<int> All(std::size_t n) {
  std::vector<int> c(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = (int)i;
  return c;
}
} // namespace

TEST(SphereSurface, ClosestPointMatchesBruteForce) {
  std::mt19937_64                        rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const Vec3                             a(0, 0, 0), b(1, 0.1, 0), c(0.3, 0.9, 0.2);
  for (int i = 0; i < 2000; ++i) {
    const Vec3            x(u(rng), u(rng), u(rng));
    const TriangleClosest q = ClosestPointOnTriangle(x, a, b, c);
    // brute force: the best of a fine barycentric grid, refined around it
    double best = 1e300;
    const int n = 400;
    for (int k = 0; k <= n; ++k)
      for (int l = 0; l <= n - k; ++l) {
        const Vec3 p = a + ((double)k / n) * (b - a) + ((double)l / n) * (c - a);
        best         = std::fmin(best, norm(x - p));
      }
    EXPECT_LE(norm(x - q.p), best + 1e-12) << "point " << i;
    EXPECT_GE(norm(x - q.p), best - 5e-3) << "point " << i; // the grid's spacing bounds its error
  }
  // the features of a few points
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(-1, -1, 0), a, b, c).feature, TriFeature::VertexA);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(0.5, -1, 0.3), a, b, c).feature, TriFeature::EdgeAB);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(0.4, 0.3, 1), a, b, c).feature, TriFeature::Face);
  // a degenerate triangle: the closest point of its longest edge
  const TriangleClosest d = ClosestPointOnTriangle(Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0));
  EXPECT_NEAR(norm(d.p - Vec3(0.5, 0, 0)), 0, 1e-15);
}

TEST(SphereSurface, OneContactPerFeatureOnACube) {
  std::vector<Vec3>               nodes;
  std::vector<std::array<int, 3>> tris;
  Cube(nodes, tris);
  const double r = 0.2, delta = 0.01;
  // over the top face: on its diagonal (the edge of its two triangles), near it, and near
  // a cube edge (the sphere also overlaps that edge)
  for (const Vec3 &x : {Vec3(0.5, 0.5, 1 + r - delta), Vec3(0.3, 0.31, 1 + r - delta), Vec3(0.95, 0.5, 1 + r - delta)}) {
    const auto cs = SphereSurfaceContacts(x, r, nodes, tris, All(tris.size()));
    ASSERT_EQ(cs.size(), 1u) << "at " << x.x << " " << x.y;
    EXPECT_NEAR(cs[0].overlap, delta, 1e-14);
    EXPECT_NEAR(norm(cs[0].n - Vec3(0, 0, 1)), 0, 1e-14);
    if (x.x != x.y) EXPECT_EQ(cs[0].feature, TriFeature::Face) << "at " << x.x << " " << x.y << " tri " << cs[0].tri; // on the diagonal: the edge both triangles share, once
  }
}

TEST(SphereSurface, RollingOverAnEdgeAndAroundAVertexIsContinuous) {
  std::vector<Vec3>               nodes;
  std::vector<std::array<int, 3>> tris;
  Cube(nodes, tris);
  const double r = 0.2, delta = 0.01, rho = r - delta; // the centre keeps its distance rho from the cube
  GranularPair p;
  p.law = GranularLaw::Hertz, p.estar = 1e9, p.gstar = 4e8, p.alpha = 0;
  // the path: over the top face (y = 0.5) towards the edge x = 1, z = 1, around it on a
  // quarter circle, then down the side face x = 1
  Vec3   prev_f;
  bool   first = true;
  double worst_jump = 0;
  const int n = 400;
  for (int i = 0; i <= n; ++i) {
    const double s = 3.0 * i / n; // 0..1 top, 1..2 around the edge, 2..3 down the side
    Vec3         x;
    if (s < 1) x = Vec3(0.7 + 0.3 * s, 0.5, 1 + rho);
    else if (s < 2) {
      const double th = 0.5 * M_PI * (s - 1);
      x               = Vec3(1 + rho * std::sin(th), 0.5, 1 + rho * std::cos(th));
    } else x = Vec3(1 + rho, 0.5, 1 - 0.3 * (s - 2));
    const auto cs = SphereSurfaceContacts(x, r, nodes, tris, All(tris.size()));
    ASSERT_EQ(cs.size(), 1u) << "s = " << s;
    EXPECT_NEAR(cs[0].overlap, delta, 1e-12) << "s = " << s;
    Vec3                 shear(0, 0, 0);
    const GranularResult f = GranularForce(p, {cs[0].n, cs[0].overlap, Vec3(0, 0, 0), Vec3(0, 0, 0), r, 1.0}, 1e-6, shear);
    if (!first) worst_jump = std::fmax(worst_jump, norm(f.fn - prev_f) / norm(f.fn));
    prev_f = f.fn, first = false;
  }
  // the normal turns by at most (pi/2)/(n/3) per step over the edge: the force's change is that angle
  EXPECT_LT(worst_jump, 1.01 * 0.5 * M_PI / (n / 3.0));
  // around the vertex (1, 1, 1): every direction of its octant at distance rho gives one contact
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double th = 0.5 * M_PI * i / 20, ph = 0.5 * M_PI * j / 20;
      const Vec3   dir(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      const auto   cs = SphereSurfaceContacts(Vec3(1, 1, 1) + rho * dir, r, nodes, tris, All(tris.size()));
      ASSERT_EQ(cs.size(), 1u) << "direction " << i << " " << j;
      EXPECT_NEAR(cs[0].overlap, delta, 1e-12);
      EXPECT_NEAR(norm(cs[0].n - dir), 0, 1e-12);
    }
}

TEST(SphereSurface, ConcaveCornerTouchesBothFaces) {
  // an L: the floor z = 0 (x in [0, 1]) and a wall x = 0 (z in [0, 1]), y in [0, 1]
  const std::vector<Vec3>               nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}};
  const std::vector<std::array<int, 3>> tris  = {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}};
  const double                          r = 0.2;
  const auto                            cs = SphereSurfaceContacts(Vec3(0.19, 0.5, 0.18), r, nodes, tris, All(tris.size()));
  ASSERT_EQ(cs.size(), 2u);
  double overlaps[2] = {cs[0].overlap, cs[1].overlap};
  std::sort(overlaps, overlaps + 2);
  EXPECT_NEAR(overlaps[0], 0.01, 1e-14);
  EXPECT_NEAR(overlaps[1], 0.02, 1e-14);
  // apart: nothing; a candidate list restricts the triangles
  EXPECT_TRUE(SphereSurfaceContacts(Vec3(0.5, 0.5, 0.5), r, nodes, tris, All(tris.size())).empty());
  EXPECT_EQ(SphereSurfaceContacts(Vec3(0.19, 0.5, 0.18), r, nodes, tris, {0, 1}).size(), 1u);
}

// Two triangles folded along their shared edge by a tiny angle (a deformed mesh's flat
// face): a sphere over the edge feels one contact, whether the fold is convex, concave or
// flat to round-off, and the overlap is that of the flat surface; a real valley (20 degrees
// each side) still gives two. (Before, a concave fold of 1e-9 rad counted both faces: the
// force doubled across a fold no one could see.)
TEST(SphereSurface, NearlyFlatFoldGivesOneContact) {
  const double r = 0.1;
  for (double angle : {-1e-9, 0.0, 1e-9, 1e-6, -1e-4, 0.35}) {
    // edge along y through the origin; faces towards -x and +x, tilted up by `angle` (> 0: a valley)
    const double      c = std::cos(angle), s = std::sin(angle);
    std::vector<Vec3> nodes = {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-c, 0, s), Vec3(c, 0, s)};
    std::vector<std::array<int, 3>> tris = {{0, 1, 2}, {1, 0, 3}};
    for (double x : {0.0, 1e-12, -3e-10}) {
      const auto cs = SphereSurfaceContacts(Vec3(x, 0.1, 0.095), r, nodes, tris, All(tris.size()));
      if (angle < 0.3) {
        ASSERT_EQ(cs.size(), 1u) << "fold " << angle << ", centre x " << x;
        EXPECT_NEAR(cs[0].overlap, 0.005, 1e-3 * 0.005 + 0.2 * std::fabs(angle)) << "fold " << angle;
      } else {
        EXPECT_EQ(cs.size(), 2u) << "a valley of " << angle << " rad each side touches both faces";
      }
    }
  }
}

// A flat square meshed in 8 x 8 cells of two triangles each: wherever the sphere sits over it,
// one contact, along the plane's normal, of overlap r - h. Without the in-plane rule a triangle
// that shares only a vertex with the one below the centre gave a second, tilted contact on its
// own edge whenever that edge lay between sqrt(r d) and sqrt(2 r d) of the centre's foot
// (d the overlap), and a sphere near the square's edge touched that convex edge, or the
// diagonal of a side face's cell, as well.
TEST(SphereSurface, FinelyMeshedFlatFaceGivesOneContact) {
  const int                       n = 8;
  const double                    h = 1.0 / n, r = 0.12;
  std::vector<Vec3>               nodes;
  std::vector<std::array<int, 3>> tris;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) nodes.push_back(Vec3(i * h, j * h, 0));
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  // a side face along y = 0 (meshed to match), so that the square's edge there is a convex edge
  const int b0 = (int)nodes.size();
  for (int i = 0; i <= n; ++i) nodes.push_back(Vec3(i * h, 0, -0.5));
  for (int i = 0; i < n; ++i) {
    tris.push_back({id(i, 0), b0 + i, b0 + i + 1});
    tris.push_back({id(i, 0), b0 + i + 1, id(i + 1, 0)});
  }
  std::mt19937_64                        rng(11);
  std::uniform_real_distribution<double> u(0.02, 0.98), height(0.05, 0.1199);
  int                                    extra_before = 0;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 x(u(rng), u(rng), height(rng));
    const auto cs = SphereSurfaceContacts(x, r, nodes, tris, All(tris.size()));
    ASSERT_EQ(cs.size(), 1u) << "centre " << x.x << " " << x.y << " " << x.z;
    EXPECT_NEAR(cs[0].overlap, r - x.z, 1e-12);
    EXPECT_NEAR(cs[0].n.z, 1.0, 1e-12);
    // what a second contact would have needed: a touched edge point of another triangle
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const TriangleClosest q = ClosestPointOnTriangle(x, nodes[tris[t][0]], nodes[tris[t][1]], nodes[tris[t][2]]);
      const double          d = norm(x - q.p);
      if (q.feature != TriFeature::Face && d < r && norm(q.p - cs[0].point) >= std::sqrt(r * cs[0].overlap) && q.p.z == 0) {
        ++extra_before;
        break;
      }
    }
  }
  EXPECT_GT(extra_before, 0) << "no centre of the sample met the case the rule is for";
}

// The cube's skin with every triangle holding copies of its nodes of its own (a fracturable
// body's split cells), each copy in the group of the node it copies: a sphere over a face
// near the diagonal that two triangles share feels the one face contact of the skin whose
// triangles share nodes (the other triangle's copy of the diagonal is hidden by the face that
// holds its group; without the groups it is a second contact), and a sphere over a corner
// touches each of the six copies of it, at the corner, with the overlap of the one contact of
// the shared skin (the copies neither hide nor merge with each other).
TEST(SphereSurface, CopiesOfAVertexOrAnEdgeAreFeaturesOfTheirOwn) {
  std::vector<Vec3>               nodes, copies;
  std::vector<std::array<int, 3>> tris, split;
  std::vector<int>                group;
  Cube(nodes, tris);
  for (const auto &t : tris) {
    std::array<int, 3> s;
    for (int m = 0; m < 3; ++m) {
      s[m] = (int)copies.size();
      copies.push_back(nodes[t[m]]);
      group.push_back(t[m]);
    }
    split.push_back(s);
  }
  const double r = 0.5;
  // over triangle (0, 2, 3) of the face z = 0, 0.05 from its diagonal (0, 3)
  const Vec3 below(0.45, 0.55, -0.45);
  const auto shared  = SphereSurfaceContacts(below, r, nodes, tris, All(tris.size()));
  std::vector<SurfaceContact> grouped, apart;
  SphereSurfaceContacts(below, r, copies, split, All(split.size()), grouped, &group);
  SphereSurfaceContacts(below, r, copies, split, All(split.size()), apart);
  ASSERT_EQ(shared.size(), 1u);
  ASSERT_EQ(grouped.size(), 1u);
  EXPECT_EQ(grouped[0].feature, TriFeature::Face);
  EXPECT_NEAR(grouped[0].overlap, shared[0].overlap, 1e-15);
  EXPECT_EQ(apart.size(), 2u); // the test needs the groups
  // over the corner (0, 0, 0), along the diagonal
  const Vec3 corner(-0.25, -0.25, -0.25);
  const auto one = SphereSurfaceContacts(corner, r, nodes, tris, All(tris.size()));
  ASSERT_EQ(one.size(), 1u);
  SphereSurfaceContacts(corner, r, copies, split, All(split.size()), grouped, &group);
  ASSERT_EQ(grouped.size(), 6u);
  for (const auto &c : grouped) {
    EXPECT_NEAR(norm(c.point), 0, 1e-15);
    EXPECT_NEAR(c.overlap, one[0].overlap, 1e-15);
  }
}

// The nearly flat fold of NearlyFlatFoldGivesOneContact with each triangle holding copies of
// its nodes (the groups the nodes): the two faces of the fold still give one contact, or, over
// the fold's edge, each triangle its copy of the edge, at one overlap (the caller weighs each
// by 1/2). (Only faces are merged there; a face and another cell's copy of an edge or a vertex
// that shares one node with it are not: driver_scene_fracture_on_clump.)
TEST(SphereSurface, CopiesOnAFoldMergeOnlyFaces) {
  const double r = 0.1;
  for (double angle : {-1e-9, 0.0, 1e-9}) {
    const double      c = std::cos(angle), s = std::sin(angle);
    std::vector<Vec3> nodes = {Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-c, 0, s), Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(c, 0, s)};
    std::vector<std::array<int, 3>> tris  = {{0, 1, 2}, {4, 3, 5}};
    std::vector<int>                group = {0, 1, 2, 0, 1, 3};
    std::vector<SurfaceContact>     cs;
    for (double x : {0.0, 1e-12, -3e-10}) {
      SphereSurfaceContacts(Vec3(x, 0.1, 0.095), r, nodes, tris, All(tris.size()), cs, &group);
      // one face, or the two copies of the shared edge (the caller weighs each by 1/2)
      ASSERT_TRUE(cs.size() == 1u || cs.size() == 2u) << "fold " << angle << ", centre x " << x;
      for (const auto &k : cs) {
        EXPECT_TRUE(cs.size() == 1u ? k.feature == TriFeature::Face : k.feature != TriFeature::Face && k.feature < TriFeature::VertexA) << "fold " << angle << ", centre x " << x;
        EXPECT_NEAR(k.overlap, 0.005, 1e-6);
      }
      if (cs.size() == 2u) EXPECT_NE(cs[0].tri, cs[1].tri);
    }
  }
}
