// Tests of the mass-property kernels (include/fdem/kernels/massprops.hpp).
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/rotation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

using namespace fdem::kernels;
using Tets = std::vector<std::array<int, 4>>;

namespace {
constexpr double kPi = 3.14159265358979323846;
double MaxAbs(const Vec3 &a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }
double MaxAbs(const Mat3 &A) {
  double e = 0;
  for (auto &r : A.m)
    for (double v : r) e = std::max(e, std::fabs(v));
  return e;
}
// Expect ComputeMassProperties to throw InputError whose message contains all the given pieces.
void ExpectInputError(const std::vector<Vec3> &nodes, const Tets &tets, double rho, const std::string &name,
                      const std::vector<std::string> &pieces) {
  try {
    ComputeMassProperties(nodes, tets, rho, name);
    ADD_FAILURE() << "no InputError for " << name;
  } catch (const InputError &e) {
    const std::string msg = e.what();
    std::printf("[error message] %s\n", msg.c_str());
    for (const auto &p : pieces) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
  }
}
} // namespace

TEST(MassProps, UnitCubeAndBox) {
  std::vector<Vec3> nodes;
  Tets tets;
  MakeBoxTets({0, 0, 0}, {1, 1, 1}, 1, 1, 1, nodes, tets);
  EXPECT_EQ(tets.size(), 6u);
  auto mp = ComputeMassProperties(nodes, tets, 2.0, "cube");
  EXPECT_NEAR(mp.volume, 1.0, 1e-15);
  EXPECT_NEAR(mp.mass, 2.0, 1e-15);
  EXPECT_LT(MaxAbs(mp.com - Vec3{0.5, 0.5, 0.5}), 1e-15);
  EXPECT_LT(MaxAbs(mp.inertia_com - Mat3::diag(1.0 / 3, 1.0 / 3, 1.0 / 3)), 1e-15); // m (1+1)/12
  EXPECT_LT(MaxAbs(mp.principal_moments - Vec3{1.0 / 3, 1.0 / 3, 1.0 / 3}), 1e-15);
  EXPECT_NEAR(det(mp.principal_axes), 1.0, 1e-14);

  // Box a x b x c = 1 x 2 x 3 at an offset, meshed 3 x 4 x 5: exact integrals on any mesh.
  MakeBoxTets({-1, 2, 10}, {0, 4, 13}, 3, 4, 5, nodes, tets);
  EXPECT_EQ(tets.size(), 6u * 60);
  const double rho = 7.5, m = rho * 6.0;
  mp = ComputeMassProperties(nodes, tets, rho, "box");
  EXPECT_NEAR(mp.volume, 6.0, 1e-13);
  EXPECT_NEAR(mp.mass, m, 1e-12);
  EXPECT_LT(MaxAbs(mp.com - Vec3{-0.5, 3, 11.5}), 1e-13);
  const Vec3 Iex{m * (4 + 9) / 12, m * (1 + 9) / 12, m * (1 + 4) / 12};
  EXPECT_LT(MaxAbs(mp.inertia_com - Mat3::diag(Iex.x, Iex.y, Iex.z)), 1e-12 * m);
  // Sorted ascending: (1+4), (1+9), (4+9); axes z, y, x up to sign, right-handed.
  EXPECT_LT(MaxAbs(mp.principal_moments - Vec3{Iex.z, Iex.y, Iex.x}), 1e-12 * m);
  EXPECT_NEAR(std::fabs(mp.principal_axes(2, 0)), 1.0, 1e-14);
  EXPECT_NEAR(std::fabs(mp.principal_axes(1, 1)), 1.0, 1e-14);
  EXPECT_NEAR(std::fabs(mp.principal_axes(0, 2)), 1.0, 1e-14);
  EXPECT_NEAR(det(mp.principal_axes), 1.0, 1e-14);
  // The boundary of a 3x4x5 box: 2*(12+15+20) quads = 2 triangles each.
  EXPECT_EQ(BoundaryFaces(tets).size(), 2u * 2 * (12 + 15 + 20));
}

TEST(MassProps, TetrahedronClosedForm) {
  // Unit corner tetrahedron: V = 1/6, COM = 1/4 (1,1,1); about the COM
  // I_xx = rho/80, I_xy = +rho/480 (from int x^2 = 1/60, int xy = 1/120).
  const std::vector<Vec3> nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Tets tets = {{0, 1, 2, 3}};
  const double rho = 3.0;
  auto mp = ComputeMassProperties(nodes, tets, rho, "tet");
  EXPECT_NEAR(mp.volume, 1.0 / 6, 1e-16);
  EXPECT_LT(MaxAbs(mp.com - Vec3{0.25, 0.25, 0.25}), 1e-16);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(mp.inertia_com(i, j), i == j ? rho / 80 : rho / 480, 1e-16);
  // Eigenvalues: symmetric about (1,1,1): 1/80 + 2/480 along (1,1,1)... check
  // A = a Id + b (11^T - Id) with a = 1/80, b = 1/480: eigen a + 2b (x1), a - b (x2).
  const double a = rho / 80, b = rho / 480;
  EXPECT_LT(MaxAbs(mp.principal_moments - Vec3{a - b, a - b, a + 2 * b}), 1e-16);
  EXPECT_NEAR(std::fabs(dot(mp.principal_axes.col(2), Vec3{1, 1, 1})) / std::sqrt(3.0), 1.0, 1e-14);
  // A general tetrahedron: the exact integrals are invariant under relabelling
  // (even permutations keep positive orientation) and under a translation.
  const std::vector<Vec3> g = {{0.3, -0.2, 1.0}, {2.0, 0.1, 0.7}, {0.5, 1.7, 0.2}, {0.9, 0.4, 2.6}};
  Tets gt = {{0, 1, 2, 3}};
  OrientTetsPositive(g, gt);
  const auto m1 = ComputeMassProperties(g, gt, 1.0, "g");
  const Tets gp = {{gt[0][1], gt[0][2], gt[0][0], gt[0][3]}};
  const auto m2 = ComputeMassProperties(g, gp, 1.0, "g");
  EXPECT_LT(MaxAbs(m1.inertia_com - m2.inertia_com), 1e-15);
  std::vector<Vec3> gs = g;
  for (auto &p : gs) p += Vec3{100, -50, 20};
  const auto m3 = ComputeMassProperties(gs, gt, 1.0, "g");
  EXPECT_LT(MaxAbs(m1.inertia_com - m3.inertia_com), 1e-12);
  EXPECT_LT(MaxAbs(m3.com - m1.com - Vec3{100, -50, 20}), 1e-12);
  // Split the same tetrahedron into 4 around an interior point: same result.
  std::vector<Vec3> gi = g;
  gi.push_back(0.25 * (g[0] + g[1] + g[2] + g[3]) + Vec3{0.01, -0.02, 0.03});
  Tets split = {{4, 1, 2, 3}, {0, 4, 2, 3}, {0, 1, 4, 3}, {0, 1, 2, 4}};
  for (auto &t : split)
    for (int &v : t)
      if (v < 4) v = gt[0][v];
  OrientTetsPositive(gi, split);
  const auto m4 = ComputeMassProperties(gi, split, 1.0, "g4");
  EXPECT_NEAR(m4.volume, m1.volume, 1e-15);
  EXPECT_LT(MaxAbs(m4.inertia_com - m1.inertia_com), 1e-15);
}

TEST(MassProps, EllipsoidConvergesAtSecondOrder) {
  const Vec3 s{1.0, 2.0, 3.0};
  const double rho = 1.3;
  const double V = 4.0 / 3 * kPi * s.x * s.y * s.z, m = rho * V;
  const Vec3 Iex{m * (s.y * s.y + s.z * s.z) / 5, m * (s.x * s.x + s.z * s.z) / 5, m * (s.x * s.x + s.y * s.y) / 5};
  double ev[7], eI[7];
  for (int r = 2; r <= 6; ++r) {
    std::vector<Vec3> nodes;
    Tets tets;
    MakeEllipsoidTets(s, r, nodes, tets);
    EXPECT_EQ(tets.size(), 8u << (2 * r));
    const auto mp = ComputeMassProperties(nodes, tets, rho, "ellipsoid");
    ev[r] = std::fabs(mp.volume - V) / V;
    eI[r] = MaxAbs(mp.principal_moments - Vec3{Iex.z, Iex.y, Iex.x}) / Iex.x;
    EXPECT_LT(MaxAbs(mp.com), 1e-13);
    EXPECT_LT(mp.volume, V); // inscribed
    // Off-diagonal inertia vanishes by symmetry; axes are the coordinate axes.
    EXPECT_NEAR(std::fabs(mp.principal_axes(2, 0)), 1.0, 1e-12);
    EXPECT_NEAR(std::fabs(mp.principal_axes(0, 2)), 1.0, 1e-12);
    std::printf("[ellipsoid (1,2,3)] refinement %d (%zu tets): rel. volume error %.3e, rel. inertia error %.3e\n", r,
                tets.size(), ev[r], eI[r]);
  }
  for (int r = 3; r <= 6; ++r) {
    const double pv = std::log2(ev[r - 1] / ev[r]), pI = std::log2(eI[r - 1] / eI[r]);
    std::printf("[ellipsoid] observed order (edge length halves) r=%d: volume %.3f inertia %.3f\n", r, pv, pI);
    if (r >= 4) {
      EXPECT_NEAR(pv, 2.0, 0.1);
      EXPECT_NEAR(pI, 2.0, 0.1);
    }
  }
  EXPECT_LT(ev[6], 1e-3);
  EXPECT_LT(eI[6], 2e-3);
}

TEST(MassProps, RotatedShiftedBox) {
  std::vector<Vec3> nodes;
  Tets tets;
  MakeBoxTets({-0.5, -1.0, -1.5}, {0.5, 1.0, 1.5}, 2, 3, 4, nodes, tets);
  const auto ref = ComputeMassProperties(nodes, tets, 2.0, "box");
  const Mat3 Q = RotationMatrix({0.4, -0.9, 1.3});
  const Vec3 shift{5, -3, 8};
  for (auto &p : nodes) p = Q * p + shift;
  const auto mp = ComputeMassProperties(nodes, tets, 2.0, "rotated box");
  EXPECT_NEAR(mp.mass, ref.mass, 1e-13);
  EXPECT_LT(MaxAbs(mp.com - shift), 1e-13);
  EXPECT_LT(MaxAbs(mp.principal_moments - ref.principal_moments), 1e-12);
  // Inertia tensor transforms as Q I Q^T.
  EXPECT_LT(MaxAbs(mp.inertia_com - Q * ref.inertia_com * transpose(Q)), 1e-12);
  // Axes are the rotated box axes (z, y, x order: sides 3 > 2 > 1) up to sign.
  for (int k = 0; k < 3; ++k) {
    const Vec3 expected = Q.col(2 - k);
    EXPECT_NEAR(std::fabs(dot(mp.principal_axes.col(k), expected)), 1.0, 1e-12) << k;
  }
  EXPECT_NEAR(det(mp.principal_axes), 1.0, 1e-13);
  EXPECT_LT(OrthonormalityError(mp.principal_axes), 1e-14);
}

TEST(MassProps, SymmetricEigenRandomMatrices) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Mat3 A;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) A.m[i][j] = A.m[j][i] = U(gen) * (trial % 3 == 0 ? 1e6 : 1.0);
    if (trial % 5 == 0) A.m[0][0] = A.m[1][1]; // near-repeated eigenvalues now and then
    Vec3 lam;
    Mat3 V;
    SymmetricEigen(A, lam, V);
    const double s = MaxAbs(A);
    EXPECT_LE(lam[0], lam[1]);
    EXPECT_LE(lam[1], lam[2]);
    EXPECT_LT(OrthonormalityError(V), 1e-14);
    EXPECT_NEAR(det(V), 1.0, 1e-14);
    EXPECT_LT(MaxAbs(V * Mat3::diag(lam[0], lam[1], lam[2]) * transpose(V) - A), 1e-14 * s);
  }
}

TEST(MassProps, ConvexPolyhedra) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> U(0.05, 0.95);
  // Cube corners plus interior points: the hull is the cube.
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  for (int i = 0; i < 50; ++i) pts.push_back({U(gen), U(gen), U(gen)});
  std::shuffle(pts.begin(), pts.end(), gen);
  std::vector<Vec3> nodes;
  Tets tets;
  MakeConvexPolyhedronTets(pts, nodes, tets);
  EXPECT_EQ(nodes.size(), 9u); // 8 corners + centroid
  auto mp = ComputeMassProperties(nodes, tets, 1.0, "hull cube");
  EXPECT_NEAR(mp.volume, 1.0, 1e-14);
  EXPECT_LT(MaxAbs(mp.com - Vec3{0.5, 0.5, 0.5}), 1e-14);
  EXPECT_LT(MaxAbs(mp.principal_moments - Vec3{1.0 / 6, 1.0 / 6, 1.0 / 6}), 1e-14);

  // Octahedron |x|+|y|+|z| <= 1: V = 4/3, int x^2 = 2/15, so I = 4/15 rho.
  pts = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0.1, 0.2, -0.1}, {0, 0, 0}};
  MakeConvexPolyhedronTets(pts, nodes, tets);
  mp = ComputeMassProperties(nodes, tets, 3.0, "octahedron");
  EXPECT_NEAR(mp.volume, 4.0 / 3, 1e-14);
  EXPECT_LT(MaxAbs(mp.inertia_com - Mat3::diag(0.8, 0.8, 0.8)), 1e-14);

  // 300 random points on a sphere: closed hull, volume below 4/3 pi and
  // inertia close to isotropic (2/5 m r^2).
  std::normal_distribution<double> N(0, 1);
  pts.clear();
  for (int i = 0; i < 300; ++i) {
    Vec3 p{N(gen), N(gen), N(gen)};
    pts.push_back(p / norm(p));
  }
  MakeConvexPolyhedronTets(pts, nodes, tets);
  EXPECT_EQ(nodes.size(), 301u); // every point is a hull vertex
  EXPECT_EQ(tets.size(), 2u * 300 - 4); // Euler: F = 2V - 4 for a triangulated sphere
  mp = ComputeMassProperties(nodes, tets, 1.0, "pebble");
  std::printf("[hull of 300 sphere points] volume %.5f (ball %.5f), moments %.4f %.4f %.4f (2/5 m = %.4f)\n", mp.volume,
              4.0 / 3 * kPi, mp.principal_moments.x, mp.principal_moments.y, mp.principal_moments.z, 0.4 * mp.mass);
  EXPECT_LT(mp.volume, 4.0 / 3 * kPi);
  EXPECT_GT(mp.volume, 0.9 * 4.0 / 3 * kPi);
  EXPECT_LT(MaxAbs(mp.principal_moments - Vec3{1, 1, 1} * (0.4 * mp.mass)), 0.05 * mp.mass);
  // The hull contains every input point: each lies on the inner side of every face.
  for (const auto &f : BoundaryFaces(tets)) {
    const Vec3 n = cross(nodes[f[1]] - nodes[f[0]], nodes[f[2]] - nodes[f[0]]);
    for (const auto &p : pts) EXPECT_LE(dot(p - nodes[f[0]], n), 1e-12);
  }

  EXPECT_THROW(MakeConvexPolyhedronTets({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.2, 0}}, nodes, tets),
               InputError);
  EXPECT_THROW(MakeConvexPolyhedronTets({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, nodes, tets), InputError);
}

TEST(MassProps, BadInputsNameTheBodyAndElement) {
  std::vector<Vec3> nodes;
  Tets tets;
  MakeBoxTets({0, 0, 0}, {1, 1, 1}, 2, 2, 2, nodes, tets);
  ExpectInputError(nodes, tets, 0.0, "rockA", {"rockA", "density"});
  ExpectInputError(nodes, tets, -1.0, "rockA", {"rockA", "density"});
  ExpectInputError(nodes, {}, 1.0, "rockB", {"rockB", "no tetrahedra"});
  // Inverted element 5.
  Tets bad = tets;
  std::swap(bad[5][2], bad[5][3]);
  ExpectInputError(nodes, bad, 1.0, "rockC", {"rockC", "tetrahedron 5", "negative signed volume", "OrientTetsPositive"});
  EXPECT_EQ(OrientTetsPositive(nodes, bad), 1);
  EXPECT_NO_THROW(ComputeMassProperties(nodes, bad, 1.0, "rockC"));
  // Degenerate (flat) element 7.
  std::vector<Vec3> flat = nodes;
  flat.push_back({0.1, 0.1, 0.0});
  flat.push_back({0.3, 0.1, 0.0});
  flat.push_back({0.1, 0.4, 0.0});
  flat.push_back({0.2, 0.2, 0.0});
  bad = tets;
  bad[7] = {27, 28, 29, 30};
  ExpectInputError(flat, bad, 1.0, "rockD", {"rockD", "tetrahedron 7", "degenerate"});
  // Node index out of range.
  bad = tets;
  bad[3][1] = 1000;
  ExpectInputError(nodes, bad, 1.0, "rockE", {"rockE", "tetrahedron 3", "1000"});
  // Not closed: a hole (one tetrahedron removed from the interior is still a
  // closed boundary, so instead two tetrahedra touching along one edge only).
  const std::vector<Vec3> bow = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}};
  Tets bt = {{0, 1, 2, 3}, {0, 4, 5, 3}};
  OrientTetsPositive(bow, bt);
  ExpectInputError(bow, bt, 1.0, "bowtie", {"bowtie", "closed 2-manifold", "edge (0, 3)", "4 boundary faces"});
  // A duplicated element: its faces are then used three times.
  bad = tets;
  bad.push_back(tets[10]);
  ExpectInputError(nodes, bad, 1.0, "rockF", {"rockF", "tetrahedron 48", "repeats tetrahedron 10"});
  // A lone tetrahedron given twice (was accepted with twice the mass).
  const std::vector<Vec3> one = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  ExpectInputError(one, {{0, 1, 2, 3}, {0, 2, 3, 1}}, 1.0, "rockG", {"rockG", "tetrahedron 1 (nodes 0, 2, 3, 1) repeats tetrahedron 0"});
  // A hanging node: one cube split into 6 tets next to a cube whose shared
  // face is split differently (by a node in its centre) -> boundary edges used once.
  {
    std::vector<Vec3> hn;
    Tets ht;
    MakeBoxTets({0, 0, 0}, {1, 1, 1}, 1, 1, 1, hn, ht);
    // Second part: pyramid over the face x = 1 with apex (2, 0.5, 0.5), its
    // base split into 4 triangles through the face centre (node 8).
    hn.push_back({1, 0.5, 0.5});
    hn.push_back({2, 0.5, 0.5});
    auto id = [&](double y, double z) {
      for (int i = 0; i < 8; ++i)
        if (hn[i].x == 1 && hn[i].y == y && hn[i].z == z) return i;
      return -1;
    };
    const int c00 = id(0, 0), c10 = id(1, 0), c11 = id(1, 1), c01 = id(0, 1);
    ht.push_back({8, c00, c10, 9});
    ht.push_back({8, c10, c11, 9});
    ht.push_back({8, c11, c01, 9});
    ht.push_back({8, c01, c00, 9});
    OrientTetsPositive(hn, ht);
    ExpectInputError(hn, ht, 1.0, "hanging", {"hanging", "closed 2-manifold"});
  }
  // Degenerate inertia: a needle 1 x 5e-7 x 5e-7 (I_min / I_max = 5e-13).
  MakeBoxTets({0, 0, 0}, {1, 5e-7, 5e-7}, 1, 1, 1, nodes, tets);
  ExpectInputError(nodes, tets, 1.0, "needle", {"needle", "degenerate inertia"});
  // ... while a 1 x 1e-5 x 1e-5 rod is accepted.
  MakeBoxTets({0, 0, 0}, {1, 1e-5, 1e-5}, 1, 1, 1, nodes, tets);
  EXPECT_NO_THROW(ComputeMassProperties(nodes, tets, 1.0, "rod"));
}

// A union of balls (a clump of spheres): one ball and balls apart are exact to round-off; two
// overlapping balls against the closed forms of their union (a solid of revolution).
TEST(MassProps, BallUnionExactForOneBallAndBallsApart) {
  const double rho = 2600, r = 0.04, m = rho * 4.0 / 3.0 * kPi * r * r * r, I0 = 0.4 * m * r * r;
  const auto   one = BallUnionMassProperties({{Vec3(0.3, -0.2, 1.1), r}}, rho, "pebble");
  EXPECT_NEAR(one.mass, m, 1e-13 * m);
  EXPECT_LT(MaxAbs(one.com - Vec3(0.3, -0.2, 1.1)), 1e-14);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(one.principal_moments[k], I0, 1e-12 * I0);
  // two balls 3 r apart along a skew axis: m and I of each, the parallel axis theorem across
  const Vec3 a(0.1, 0.2, 0.3), e = Vec3(1, 2, 2) / 3.0, b = a + 3 * r * e;
  const auto two = BallUnionMassProperties({{a, r}, {b, r}}, rho, "dumbbell");
  EXPECT_NEAR(two.mass, 2 * m, 1e-13 * m);
  EXPECT_LT(MaxAbs(two.com - 0.5 * (a + b)), 1e-14);
  const double Iaxis = 2 * I0, Iperp = 2 * (I0 + m * (1.5 * r) * (1.5 * r));
  EXPECT_NEAR(two.principal_moments[0], Iaxis, 1e-12 * Iperp);
  EXPECT_NEAR(two.principal_moments[1], Iperp, 1e-12 * Iperp);
  EXPECT_NEAR(two.principal_moments[2], Iperp, 1e-12 * Iperp);
  EXPECT_NEAR(std::fabs(dot(two.principal_axes.col(0), e)), 1.0, 1e-12);
}

TEST(MassProps, BallUnionOfOverlappingBallsMatchesClosedForms) {
  // balls of radius r at 0 and d on the x axis: the union's section at x is the disc of the nearer
  // centre, so V = 2 pi int_{-r}^{d/2} (r^2 - x^2) dx and I_xx = rho pi int_{-r}^{d/2} (r^2 - x^2)^2 dx
  const double rho = 1000, r = 1.0;
  for (double d : {0.3, 1.0, 1.7}) {
    const double h = 0.5 * d;
    auto         P = [&](double x) { return r * r * x - x * x * x / 3; };                                     // int (r^2 - x^2)
    auto         Q = [&](double x) { return r * r * r * r * x - 2 * r * r * x * x * x / 3 + x * x * x * x * x / 5; }; // int (r^2 - x^2)^2
    const double V = 2 * kPi * (P(h) - P(-r)), Ixx = rho * kPi * (Q(h) - Q(-r));
    // I_yy about the centre of mass: int (x - h)^2 + z^2 over the union, by sections
    auto R = [&](double t) { // an antiderivative of (r^2 - t^2)(t - h)^2
      return r * r * t * t * t / 3 - h * r * r * t * t + r * r * h * h * t - t * t * t * t * t / 5 + h * t * t * t * t / 2 - h * h * t * t * t / 3;
    };
    const double Iyy = 2 * rho * kPi * (R(h) - R(-r)) + 0.5 * Ixx; // sum of (x - h)^2 dm, plus int z^2 dm = I_xx / 2
    const auto   mp  = BallUnionMassProperties({{Vec3(0, 0, 0), r}, {Vec3(d, 0, 0), r}}, rho, "lens");
    // the grid's error at the edges of the shadow hidden inside the other ball: about 5e-5
    EXPECT_NEAR(mp.volume, V, 1e-4 * V) << "d = " << d;
    EXPECT_NEAR(mp.com.x, h, 1e-4 * r) << "d = " << d;
    EXPECT_NEAR(mp.principal_moments[0], Ixx, 1e-4 * Ixx) << "d = " << d;
    EXPECT_NEAR(mp.principal_moments[1], Iyy, 1e-4 * Iyy) << "d = " << d;
    EXPECT_NEAR(mp.principal_moments[2], Iyy, 1e-4 * Iyy) << "d = " << d;
    std::printf("d = %.1f r: volume %.3e, I_xx %.3e, I_yy %.3e relative error\n", d, mp.volume / V - 1, mp.principal_moments[0] / Ixx - 1, mp.principal_moments[1] / Iyy - 1);
  }
}

// A clump with tetrahedral symmetry has an isotropic inertia tensor, one symmetric about an axis two
// equal moments: the integration's differences (~5e-5) are snapped, so that the free rotation takes
// its closed forms (a spherical or a symmetric top).
TEST(MassProps, BallUnionSymmetricClumpsAreSymmetricTops) {
  const double c = 0.0202, r = 0.04;
  const auto   tet = BallUnionMassProperties({{Vec3(c, c, c), r}, {Vec3(-c, -c, c), r}, {Vec3(-c, c, -c), r}, {Vec3(c, -c, -c), r}}, 2600, "tetra");
  EXPECT_EQ(tet.principal_moments[0], tet.principal_moments[1]);
  EXPECT_EQ(tet.principal_moments[1], tet.principal_moments[2]);
  EXPECT_LT(MaxAbs(tet.com), 1e-6 * r);
  const auto bell = BallUnionMassProperties({{Vec3(-0.007, 0, 0), 0.009}, {Vec3(0.007, 0, 0), 0.007}}, 2500, "dumbbell");
  EXPECT_EQ(bell.principal_moments[1], bell.principal_moments[2]);
  EXPECT_LT(bell.principal_moments[0], 0.9 * bell.principal_moments[1]);
  EXPECT_NEAR(std::fabs(bell.principal_axes.col(0).x), 1.0, 1e-12);
  // and a body that is not symmetric keeps three moments
  const auto chain = BallUnionMassProperties({{Vec3(-0.01, 0, 0), 0.006}, {Vec3(0, 0, 0.003), 0.007}, {Vec3(0.01, 0, 0), 0.006}}, 2500, "chain");
  EXPECT_GT(chain.principal_moments[1] - chain.principal_moments[0], 1e-3 * chain.principal_moments[2]);
  EXPECT_GT(chain.principal_moments[2] - chain.principal_moments[1], 1e-3 * chain.principal_moments[2]);
}

TEST(MassProps, BallUnionBadInputNamesTheSphere) {
  auto expect = [](const std::vector<Ball> &balls, double rho, const std::string &piece) {
    try {
      BallUnionMassProperties(balls, rho, "clump 'c'");
      ADD_FAILURE() << "no error for " << piece;
    } catch (const InputError &e) {
      EXPECT_NE(std::string(e.what()).find("clump 'c'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(piece), std::string::npos) << e.what();
    }
  };
  expect({}, 1000, "no spheres");
  expect({{Vec3(0, 0, 0), 1}, {Vec3(1, 0, 0), -1}}, 1000, "sphere 1: radius");
  expect({{Vec3(0, 0, 0), 1}, {Vec3(NAN, 0, 0), 1}}, 1000, "sphere 1: its centre");
  expect({{Vec3(0, 0, 0), 1}}, 0, "density");
  expect({{Vec3(-1e308, 0, 0), 1}, {Vec3(1e308, 0, 0), 1}}, 1000, "too large");
}

// A clump of many spheres stays bounded in work (about 1e8 sphere tests): 20 000 spheres in a row,
// apart, so the answer is exact whatever the grid.
TEST(MassProps, BallUnionOfManySpheresIsBoundedAndExactWhenApart) {
  std::vector<Ball> balls;
  for (int k = 0; k < 20000; ++k) balls.push_back({Vec3(3.0 * k, 0, 0), 1.0});
  const auto   mp = BallUnionMassProperties(balls, 1.0, "rod");
  const double V  = 20000 * 4.0 / 3.0 * kPi;
  EXPECT_NEAR(mp.volume, V, 1e-12 * V);
  EXPECT_NEAR(mp.com.x, 1.5 * 19999, 1e-9 * 1.5 * 19999);
}
