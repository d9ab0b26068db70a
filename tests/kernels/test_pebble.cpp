// Tests of the random pebble generator (fdem/kernels/pebble.hpp).
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/pebble.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace fdem::kernels;

// The semi-axes are in their ranges and every point lies on the ellipsoid, pushed in by at most 15%.
TEST(Pebble, PointsOnTheSquashedEllipsoid) {
  for (unsigned long seed = 1; seed <= 50; ++seed) {
    PebbleRandom R(seed);
    const Pebble p = RandomPebble(0.05, R);
    ASSERT_EQ(p.points.size(), 12u);
    EXPECT_EQ(p.a, 0.05);
    EXPECT_GE(p.b, 0.6 * p.a);
    EXPECT_LE(p.b, 0.9 * p.a);
    EXPECT_GE(p.c, 0.35 * p.a);
    EXPECT_LE(p.c, 0.6 * p.a);
    for (const auto &q : p.points) {
      const double e = std::sqrt((q.x / p.a) * (q.x / p.a) + (q.y / p.b) * (q.y / p.b) + (q.z / p.c) * (q.z / p.c));
      EXPECT_GT(e, 0.85 - 1e-12);
      EXPECT_LE(e, 1 + 1e-12);
    }
  }
}

// The same seed gives the same pebble bitwise; another seed another pebble; pebbles drawn one
// after the other from one stream differ, and the stream is reproducible as a whole.
TEST(Pebble, SeededAndReproducible) {
  PebbleRandom R1(7), R2(7), R3(8);
  const Pebble a = RandomPebble(1.0, R1), b = RandomPebble(1.0, R2), c = RandomPebble(1.0, R3);
  for (size_t i = 0; i < 12; ++i) {
    EXPECT_EQ(a.points[i].x, b.points[i].x);
    EXPECT_EQ(a.points[i].y, b.points[i].y);
    EXPECT_EQ(a.points[i].z, b.points[i].z);
  }
  EXPECT_NE(a.points[0].x, c.points[0].x);
  const Pebble a2 = RandomPebble(1.0, R1), b2 = RandomPebble(1.0, R2);
  EXPECT_NE(a2.points[0].x, a.points[0].x);
  EXPECT_EQ(a2.points[11].z, b2.points[11].z);
  EXPECT_EQ(R1.U(), R2.U());
}

// The hull is a valid closed convex body: positive volume below the ellipsoid's, the centre of
// mass inside the ellipsoid's central eighth.
TEST(Pebble, HullIsAValidBody) {
  for (unsigned long seed = 1; seed <= 20; ++seed) {
    PebbleRandom                    R(seed);
    const Pebble                    p = RandomPebble(0.1, R);
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> T;
    MakeConvexPolyhedronTets(p.points, X, T);
    const MassProperties mp = ComputeMassProperties(X, T, 2600, "pebble");
    EXPECT_GT(mp.volume, 0);
    EXPECT_LT(mp.volume, 4.0 / 3 * std::acos(-1.0) * p.a * p.b * p.c);
    EXPECT_LT(std::fabs(mp.com.x), 0.5 * p.a);
    EXPECT_LT(std::fabs(mp.com.y), 0.5 * p.b);
    EXPECT_LT(std::fabs(mp.com.z), 0.5 * p.c);
  }
}
