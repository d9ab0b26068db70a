// Tests of the constant-strain tetrahedron (book section 4.8, doc/book.md E).
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace fdem::kernels;

namespace {

const double kPi = std::acos(-1.0);

Material Mat(double E = 1.0, double nu = 0.3, double rho = 2.0, double mu = 0.0, int model = kMunjizaCST) {
  return Material{"rock", E, nu, rho, mu, model};
}

double MaxAbs(const Mat3 &A) {
  double m = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(A(r, c)));
  return m;
}

Mat3 Rotation(Vec3 axis, double angle) {
  axis = axis / norm(axis);
  const double c = std::cos(angle), s = std::sin(angle);
  Mat3 K;
  K(0, 1) = -axis.z, K(0, 2) = axis.y, K(1, 0) = axis.z, K(1, 2) = -axis.x, K(2, 0) = -axis.y, K(2, 1) = axis.x;
  return Mat3::identity() + s * K + (1 - c) * (K * K);
}

// Unit box, 4x4x4 cells, interior nodes jittered by up to 0.2 h in each direction.
TetMesh JitteredBox(int n = 4) {
  TetMesh m = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, n, n, n);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-0.2 / n, 0.2 / n);
  for (auto &p : m.nodes) {
    const bool interior = p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9 && p.z > 1e-9 && p.z < 1 - 1e-9;
    if (interior) p += Vec3{u(rng), u(rng), u(rng)};
  }
  return m;
}

bool Interior(const Vec3 &p) {
  return p.x > 1e-9 && p.x < 1 - 1e-9 && p.y > 1e-9 && p.y < 1 - 1e-9 && p.z > 1e-9 && p.z < 1 - 1e-9;
}

std::vector<double> Flat(const std::vector<Vec3> &p) {
  std::vector<double> a;
  for (const auto &q : p) a.insert(a.end(), {q.x, q.y, q.z});
  return a;
}
Vec3 At(const std::vector<double> &a, int i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }

// Book eq 4.220 for F = diag(a, b, c), written out independently.
Mat3 BookDiag(const Material &m, double a, double b, double c) {
  const double J = a * b * c, j23 = std::pow(J, 2.0 / 3.0);
  const double lam[3] = {a, b, c};
  Mat3 T;
  for (int i = 0; i < 3; ++i)
    T(i, i) = m.E / (1 + m.nu) * 0.5 * (lam[i] * lam[i] / j23 - 1) / j23 + m.E / (1 - 2 * m.nu) * 0.5 * (j23 - 1) / j23;
  return T;
}

Mat3 Hooke(const Material &m, const Mat3 &eps) {
  const double G = m.E / (2 * (1 + m.nu)), lam = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu));
  return lam * trace(eps) * Mat3::identity() + 2 * G * eps;
}

struct PatchResult {
  double max_stress_err = 0;    // max over elements of |T_e - T_expected|
  double max_interior_f = 0;    // max |f| at interior nodes
  double max_boundary_err = 0;  // max |f_node + sum_faces T m /3| at boundary nodes
  double max_side_err = 0;      // max |sum_side T m - T J F^-T N A0| over the six sides
};

// x = F X + t, v = W x; checks every element's stress against T_expected and
// the assembled nodal forces against the face tractions.
PatchResult Patch(const TetMesh &mesh, const Material &mat, const Mat3 &F, const Mat3 &T_expected,
                  const Mat3 *W = nullptr) {
  const ElementData d = BuildElementData(mesh, {mat}, {0});
  std::vector<Vec3> xc;
  for (const auto &X : mesh.nodes) xc.push_back(F * X + Vec3{0.3, -2.0, 1.5});
  const std::vector<double> x = Flat(xc);
  std::vector<double> v;
  if (W)
    for (const auto &p : xc) {
      const Vec3 q = (*W) * p;
      v.insert(v.end(), {q.x, q.y, q.z});
    }
  std::vector<double> f(x.size(), 0.0);
  EXPECT_EQ(ComputeInternalForces(d, x.data(), W ? v.data() : nullptr, f.data()), -1);
  PatchResult r;
  for (std::size_t e = 0; e < d.size(); ++e) {
    TetState s;
    EXPECT_TRUE(EvaluateTet(d, e, x.data(), W ? v.data() : nullptr, s));
    r.max_stress_err = std::max(r.max_stress_err, MaxAbs(s.T - T_expected));
  }
  // Boundary faces: each gives T m / 3 of external traction to each of its nodes.
  const SurfaceInfo surf = SurfaceTets(mesh);
  std::vector<Vec3> traction(mesh.nodes.size());
  std::map<int, Vec3> side_force;  // side id (axis*2 + (max?1:0)) -> sum T m
  for (const auto &fc : surf.faces) {
    const Vec3 m = 0.5 * cross(xc[fc[1]] - xc[fc[0]], xc[fc[2]] - xc[fc[0]]);
    const Vec3 t = T_expected * m;
    for (int n : fc) traction[n] += t / 3.0;
    const Vec3 N = cross(mesh.nodes[fc[1]] - mesh.nodes[fc[0]], mesh.nodes[fc[2]] - mesh.nodes[fc[0]]);
    for (int ax = 0; ax < 3; ++ax)
      if (std::fabs(N[ax]) > 0.5 * norm(N)) side_force[2 * ax + (N[ax] > 0)] += t;
  }
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    const Vec3 fi = At(f, static_cast<int>(i));
    if (Interior(mesh.nodes[i])) r.max_interior_f = std::max(r.max_interior_f, norm(fi));
    else r.max_boundary_err = std::max(r.max_boundary_err, norm(fi + traction[i]));
  }
  // Nanson: the current area vector of a unit side with normal N is J F^-T N.
  const Mat3 cof = det(F) * transpose(inverse(F));
  EXPECT_EQ(side_force.size(), 6u);
  for (const auto &kv : side_force) {
    Vec3 N;
    N[kv.first / 2] = kv.first % 2 ? 1.0 : -1.0;
    r.max_side_err = std::max(r.max_side_err, norm(kv.second - T_expected * (cof * N)));
  }
  return r;
}

// scale: max(|T|, E). The law forms B/J^(2/3) - I, so at strain 1e-5 the
// stress carries an absolute rounding error ~ E * 1e-16, not |T| * 1e-16.
void ExpectPatch(const PatchResult &r, double scale, const char *what) {
  EXPECT_LT(r.max_stress_err, 1e-12 * scale) << what;
  EXPECT_LT(r.max_interior_f, 1e-10) << what;
  EXPECT_LT(r.max_boundary_err, 1e-12 * scale) << what;
  EXPECT_LT(r.max_side_err, 1e-12 * scale) << what;
}

} // namespace

TEST(CST, JitteredMeshIsValid) {
  const TetMesh m = JitteredBox();
  double vmin = 1e300, vmax = 0;
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) {
    vmin = std::min(vmin, TetSignedVolume(m, t));
    vmax = std::max(vmax, TetSignedVolume(m, t));
  }
  EXPECT_GT(vmin, 0.0);
  EXPECT_GT(vmax / vmin, 1.5);  // really irregular
  EXPECT_NEAR(TotalVolume(m), 1.0, 1e-14);
}

TEST(CST, PatchUniformStretchSmallAndFinite) {
  const TetMesh mesh = JitteredBox();
  const Material mat = Mat();
  for (double s : {1e-5, 0.3}) {
    const Mat3 F = Mat3::diag(1 + s, 1 - 0.4 * s, 1 + 0.2 * s);
    const Mat3 T = BookDiag(mat, F(0, 0), F(1, 1), F(2, 2));
    EXPECT_GT(T(0, 0), 0.0);
    ExpectPatch(Patch(mesh, mat, F, T), std::max(MaxAbs(T), mat.E), s < 1e-3 ? "small stretch" : "finite stretch");
  }
}

TEST(CST, PatchCompressionSmallAndFinite) {
  const TetMesh mesh = JitteredBox();
  const Material mat = Mat(3.0, 0.25);
  for (double s : {1e-5, 0.25}) {
    const Mat3 F = Mat3::diag(1 - s, 1 - 0.5 * s, 1 - 0.8 * s);
    const Mat3 T = BookDiag(mat, F(0, 0), F(1, 1), F(2, 2));
    EXPECT_LT(T(0, 0), 0.0);
    ExpectPatch(Patch(mesh, mat, F, T), std::max(MaxAbs(T), mat.E), s < 1e-3 ? "small compression" : "finite compression");
  }
}

TEST(CST, PatchSimpleShearMatchesClosedForm) {
  // F = I + g e_x e_y: J = 1, B - I = [[g^2, g, 0], [g, 0, 0], [0, 0, 0]] so
  // T = G (B - I): T_xy = G g exactly, T_xx = G g^2.
  const TetMesh mesh = JitteredBox();
  const Material mat = Mat(5.0, 0.2);
  const double G = mat.E / (2 * (1 + mat.nu));
  for (double g : {1e-5, 0.5}) {
    Mat3 F = Mat3::identity();
    F(0, 1) = g;
    Mat3 T;
    T(0, 1) = T(1, 0) = G * g;
    T(0, 0) = G * g * g;
    ExpectPatch(Patch(mesh, mat, F, T), std::max(MaxAbs(T), mat.E), g < 1e-3 ? "small shear" : "finite shear");
  }
}

TEST(CST, PatchGeneralDeformationAllModels) {
  const TetMesh mesh = JitteredBox(3);
  Mat3 F;
  F.m = {{{1.1, 0.2, -0.05}, {0.03, 0.95, 0.1}, {-0.1, 0.07, 1.02}}};
  for (int model : {kMunjizaCST, kNeoHookean, kSmallStrainLinear}) {
    const Material mat = Mat(2.0, 0.35, 1.0, 0.0, model);
    const Mat3 T = CauchyStress(mat, F);
    if (model == kSmallStrainLinear) {
      // The linear element's forces use the reference geometry: check stress and equilibrium only.
      const ElementData d = BuildElementData(mesh, {mat}, {0});
      std::vector<double> x;
      for (const auto &X : mesh.nodes) {
        const Vec3 p = F * X;
        x.insert(x.end(), {p.x, p.y, p.z});
      }
      std::vector<double> f(x.size(), 0.0);
      ComputeInternalForces(d, x.data(), nullptr, f.data());
      for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
        if (Interior(mesh.nodes[i])) {
          EXPECT_LT(norm(At(f, static_cast<int>(i))), 1e-10);
        }
      const Mat3 eps = 0.5 * (F + transpose(F)) - Mat3::identity();
      EXPECT_LT(MaxAbs(T - Hooke(mat, eps)), 1e-14);
      continue;
    }
    ExpectPatch(Patch(mesh, mat, F, T), std::max(MaxAbs(T), mat.E), MaterialModels()[model].name);
  }
}

// The book's split reduces to Hooke's law: the error of T(I + eps) against
// lambda tr(eps) I + 2 G eps is second order in |eps| (ratio 4 on halving).
TEST(CST, SmallStrainLimitIsHookesLaw) {
  Mat3 dir;
  dir.m = {{{0.8, 0.3, -0.2}, {0.3, -0.5, 0.6}, {-0.2, 0.6, 0.4}}};
  for (int model : {kMunjizaCST, kNeoHookean}) {
    for (double nu : {0.0, 0.3, 0.45, -0.5}) {
      const Material mat = Mat(7.0, nu, 1.0, 0.0, model);
      double prev = 0;
      for (double d : {1e-3, 5e-4, 2.5e-4}) {
        const Mat3 eps = d * dir;
        const Mat3 H = Hooke(mat, eps);
        const double err = MaxAbs(CauchyStress(mat, Mat3::identity() + eps) - H) / MaxAbs(H);
        EXPECT_LT(err, 5 * d) << "model " << model << " nu " << nu;
        if (prev > 0) {
          EXPECT_NEAR(prev / err, 2.0, 0.2) << "relative error must be O(d)";
        }
        prev = err;
      }
    }
  }
}

TEST(CST, RigidRotationRotatesStressAndUnstretchedIsStressFree) {
  const TetMesh mesh = JitteredBox(3);
  const Material mat = Mat(1.0, 0.3);
  const Mat3 F0 = Mat3::diag(1.2, 0.9, 1.05);
  const Mat3 T0 = BookDiag(mat, 1.2, 0.9, 1.05);
  for (const Mat3 &R : {Rotation({0, 0, 1}, kPi / 2), Rotation({1, 0, 0}, kPi), Rotation({1, 2, 3}, 2.3)}) {
    ExpectPatch(Patch(mesh, mat, R * F0, R * T0 * transpose(R)), MaxAbs(T0), "rotated stretch");
    // Unstretched: zero stress in every element and zero force at every node.
    const PatchResult r = Patch(mesh, mat, R, Mat3{});
    EXPECT_LT(r.max_stress_err, 1e-12 * mat.E);
    EXPECT_LT(r.max_interior_f, 1e-12 * mat.E);
    EXPECT_LT(r.max_boundary_err, 1e-12 * mat.E);
    // The small-strain element sees a spurious strain sym(R) - I of order one.
    const Material lin = Mat(1.0, 0.3, 1.0, 0.0, kSmallStrainLinear);
    EXPECT_GT(MaxAbs(CauchyStress(lin, R)), 0.3 * lin.E);
  }
}

TEST(CST, ViscousTermSpinIsFreeAndStretchingRateGives2MuDOverJ23) {
  const TetMesh mesh = JitteredBox(3);
  const double mu = 0.7;
  const Material mat = Mat(1.0, 0.3, 1.0, mu);
  Mat3 W;  // rigid spin
  W(0, 1) = -0.4, W(1, 0) = 0.4, W(0, 2) = 0.9, W(2, 0) = -0.9, W(1, 2) = -0.2, W(2, 1) = 0.2;
  Mat3 Dr;  // stretching rate
  Dr.m = {{{0.3, 0.1, 0.0}, {0.1, -0.2, 0.05}, {0.0, 0.05, 0.15}}};
  // Undeformed and spinning: no stress at all.
  const PatchResult spin = Patch(mesh, mat, Mat3::identity(), Mat3{}, &W);
  EXPECT_LT(spin.max_stress_err, 1e-12);
  EXPECT_LT(spin.max_interior_f, 1e-12);
  // Rotated and stretched, with v = (Dr + W) x: T = T_el + 2 mu Dr / J^(2/3).
  const Mat3 R = Rotation({1, -1, 2}, 1.1);
  const Mat3 F = R * Mat3::diag(1.1, 1.0, 0.95);
  const double J = det(F);
  const Mat3 Tel = R * BookDiag(mat, 1.1, 1.0, 0.95) * transpose(R);
  const Mat3 Lv = Dr + W;
  const Mat3 T = Tel + (2 * mu / std::pow(J, 2.0 / 3.0)) * Dr;
  ExpectPatch(Patch(mesh, mat, F, T, &Lv), std::max(MaxAbs(T), mat.E), "viscous");
  // L is the gradient with respect to CURRENT coordinates (v = Lv x gives L = Lv).
  const ElementData d = BuildElementData(mesh, {mat}, {0});
  std::vector<double> x, v;
  for (const auto &X : mesh.nodes) {
    const Vec3 p = F * X, q = Lv * p;
    x.insert(x.end(), {p.x, p.y, p.z});
    v.insert(v.end(), {q.x, q.y, q.z});
  }
  TetState s;
  ASSERT_TRUE(EvaluateTet(d, 5, x.data(), v.data(), s));
  EXPECT_LT(MaxAbs(s.L - Lv), 1e-13);
  EXPECT_LT(MaxAbs(s.D - Dr), 1e-13);
  EXPECT_NEAR(s.J, J, 1e-14);
}

TEST(CST, NodalForcesAreTAreaOverThreeAndPullInUnderTension) {
  const std::vector<Vec3> X = {{0, 0, 0}, {1, 0.1, 0}, {0.2, 0.9, 0.1}, {0.1, 0.3, 1.2}};
  const ElementData d = BuildElementData(X, {{0, 1, 2, 3}}, {Mat()});
  Mat3 F;
  F.m = {{{1.3, 0.1, 0.0}, {-0.2, 1.1, 0.1}, {0.05, 0.0, 1.2}}};
  std::vector<Vec3> xc;
  for (const auto &p : X) xc.push_back(F * p);
  const std::vector<double> x = Flat(xc);
  TetState s;
  ASSERT_TRUE(EvaluateTet(d, 0, x.data(), nullptr, s));
  static const int opp[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};  // outward faces
  Vec3 sum;
  for (int i = 0; i < 4; ++i) {
    const Vec3 a = 0.5 * cross(xc[opp[i][1]] - xc[opp[i][0]], xc[opp[i][2]] - xc[opp[i][0]]);
    EXPECT_LT(norm(s.force[i] - s.T * a / 3.0), 1e-14);
    sum += s.force[i];
  }
  EXPECT_LT(norm(sum), 1e-15);
  // Uniform dilation: tension pulls every node toward the centroid.
  std::vector<double> xd;
  for (const auto &p : X) xd.insert(xd.end(), {1.1 * p.x, 1.1 * p.y, 1.1 * p.z});
  ASSERT_TRUE(EvaluateTet(d, 0, xd.data(), nullptr, s));
  EXPECT_GT(s.T(0, 0), 0.0);
  const Vec3 c = 0.25 * (At(xd, 0) + At(xd, 1) + At(xd, 2) + At(xd, 3));
  for (int i = 0; i < 4; ++i) EXPECT_GT(dot(s.force[i], c - At(xd, i)), 0.0);
  // Batched kernel accumulates exactly these forces.
  std::vector<double> f(12, 1.0);
  EXPECT_EQ(ComputeInternalForces(d, xd.data(), nullptr, f.data()), -1);
  for (int i = 0; i < 4; ++i) EXPECT_LT(norm(At(f, i) - Vec3{1, 1, 1} - s.force[i]), 1e-15);
}

// A jittered box whose elements take three viscous materials, one of each model, in interleaved
// runs of 7, moved by up to `jitter` at random (seed) and given velocities up to 10 jitter.
struct ThreeMaterials {
  ElementData         d;
  std::vector<double> x, v;
};
ThreeMaterials ThreeMaterialBox(unsigned seed, double jitter) {
  TetMesh mesh = JitteredBox(3);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) mesh.body[t] = (t / 7) % 3;  // interleaved runs
  mesh.body_names = {"a", "b", "c"};
  const std::vector<Material> mats = {Mat(1.0, 0.3, 1.0, 0.1, kMunjizaCST), Mat(2.0, 0.2, 1.0, 0.2, kNeoHookean),
                                      Mat(3.0, 0.1, 1.0, 0.3, kSmallStrainLinear)};
  ThreeMaterials b{BuildElementData(mesh, mats, {0, 1, 2}), {}, {}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (const auto &p : mesh.nodes) b.x.insert(b.x.end(), {p.x + u(rng), p.y + u(rng), p.z + u(rng)});
  for (std::size_t i = 0; i < b.x.size(); ++i) b.v.push_back(10 * u(rng));
  return b;
}

TEST(CST, BatchedKernelEqualsElementSumAcrossMaterialsAndRanges) {
  ThreeMaterials box = ThreeMaterialBox(7, 0.02);
  const ElementData &d = box.d;
  std::vector<double> &x = box.x, &v = box.v;
  // with velocities and without, both through the blocked loop: its gathers (four elements at a
  // time where the processor has AVX2, one at a time in runs shorter than four, node 0 included)
  // and the velocity gradient of the viscous materials
  for (const double *vel : {static_cast<const double *>(v.data()), static_cast<const double *>(nullptr)}) {
    SCOPED_TRACE(vel ? "with velocities" : "without velocities");
    std::vector<double> f(x.size(), 0.0), g(x.size(), 0.0), h(x.size(), 0.0);
    EXPECT_EQ(ComputeInternalForces(d, x.data(), vel, f.data()), -1);
    double fmax = 0;
    for (std::size_t e = 0; e < d.size(); ++e) {
      TetState s;
      ASSERT_TRUE(EvaluateTet(d, e, x.data(), vel, s));
      for (int a = 0; a < 4; ++a)
        for (int k = 0; k < 3; ++k) g[3 * d.elems[e].n[a] + k] += s.force[a][k];
    }
    ComputeInternalForces(d, x.data(), vel, h.data(), 0, 100);
    ComputeInternalForces(d, x.data(), vel, h.data(), 100);
    for (std::size_t i = 0; i < f.size(); ++i) {
      fmax = std::max(fmax, std::fabs(f[i]));
      EXPECT_NEAR(f[i], g[i], 1e-14);
      EXPECT_NEAR(f[i], h[i], 1e-14);
    }
    EXPECT_GT(fmax, 1e-3);  // the deformation is not trivial
  }
}

TEST(CST, CellStressIsEvaluateTetsStressToTheBit) {
  ThreeMaterials box = ThreeMaterialBox(11, 0.05);
  const ElementData &d = box.d;
  std::vector<double> &x = box.x, &v = box.v;
  x[3 * 21] += 0.9; // some elements inverted: no stress
  int inverted = 0, compared = 0;
  for (const double *vel : {static_cast<const double *>(v.data()), static_cast<const double *>(nullptr)})
    for (std::size_t e = 0; e < d.size(); ++e) {
      TetState s;
      double   T[6] = {7, 7, 7, 7, 7, 7};
      const bool ok = EvaluateTet(d, e, x.data(), vel, s);
      ASSERT_EQ(CellStress(d, e, x.data(), vel, T), ok) << "element " << e;
      if (!ok) {
        ++inverted;
        for (double t : T) EXPECT_EQ(t, 7.0); // untouched
        continue;
      }
      const double want[6] = {s.T(0, 0), s.T(1, 1), s.T(2, 2), s.T(0, 1), s.T(1, 2), s.T(0, 2)};
      for (int k = 0; k < 6; ++k) EXPECT_EQ(T[k], want[k]) << "element " << e << ", component " << k;
      ++compared;
    }
  EXPECT_GT(inverted, 1);
  EXPECT_GT(compared, 100);
}

// CellStresses (the batched loop storing stresses): CellStress's values element by element, to
// round-off (the batched loop may fuse multiply-adds), over ranges that start and end inside
// material runs; NaN where CellStress answers false (inverted elements).
TEST(CST, CellStressesAreCellStressInBlocks) {
  ThreeMaterials box = ThreeMaterialBox(11, 0.05);
  const ElementData &d = box.d;
  std::vector<double> &x = box.x, &v = box.v;
  x[3 * 21] += 0.9; // some elements inverted
  int inverted = 0, compared = 0;
  for (const double *vel : {static_cast<const double *>(v.data()), static_cast<const double *>(nullptr)})
    for (const std::array<std::size_t, 2> range : {std::array<std::size_t, 2>{0, d.size()}, std::array<std::size_t, 2>{37, d.size() - 11}}) {
      std::vector<double> S(6 * (range[1] - range[0]), 7.0);
      CellStresses(d, x.data(), vel, S.data(), range[0], range[1]);
      for (std::size_t e = range[0]; e < range[1]; ++e) {
        double     T[6];
        const bool ok = CellStress(d, e, x.data(), vel, T);
        const double *B = &S[6 * (e - range[0])];
        if (!ok) {
          ++inverted;
          for (int k = 0; k < 6; ++k) EXPECT_TRUE(std::isnan(B[k])) << "element " << e;
          continue;
        }
        double scale = 0;
        for (int k = 0; k < 6; ++k) scale = std::max(scale, std::fabs(T[k]));
        for (int k = 0; k < 6; ++k) EXPECT_NEAR(B[k], T[k], 1e-13 * scale) << "element " << e << ", component " << k;
        ++compared;
      }
    }
  EXPECT_GT(inverted, 1);
  EXPECT_GT(compared, 100);
}

TEST(CST, InvertedElementReportedById) {
  const TetMesh mesh = JitteredBox(3);
  const ElementData d = BuildElementData(mesh, {Mat()}, {0});
  std::vector<double> x = Flat(mesh.nodes);
  // Push one interior node (index 1 + 4*(1 + 4*1) = 21) far through its neighbours.
  const int node = 21;
  ASSERT_TRUE(Interior(mesh.nodes[node]));
  x[3 * node] += 0.9;
  std::int64_t first = -1, second = -1;
  int n_inv = 0;
  for (std::size_t e = 0; e < d.size(); ++e) {
    TetState s;
    if (!EvaluateTet(d, e, x.data(), nullptr, s)) {
      EXPECT_LE(s.J, 0.0);
      if (first >= 0 && second < 0) second = static_cast<std::int64_t>(e);
      if (first < 0) first = static_cast<std::int64_t>(e);
      ++n_inv;
    }
  }
  ASSERT_GE(first, 0);
  EXPECT_GT(n_inv, 1);
  std::vector<double> f(x.size(), 0.0);
  EXPECT_EQ(ComputeInternalForces(d, x.data(), nullptr, f.data()), first);
  EXPECT_EQ(ComputeInternalForces(d, x.data(), nullptr, f.data(), first + 1, d.size()), second);
  for (double q : f) EXPECT_TRUE(std::isfinite(q));
  const std::string msg = InversionMessage(d, first, x.data());
  EXPECT_NE(msg.find("element " + std::to_string(first)), std::string::npos) << msg;
  EXPECT_NE(msg.find("body 0"), std::string::npos) << msg;
  // The linear element reports the same id but still assembles its force.
  const ElementData dl = BuildElementData(mesh, {Mat(1, 0.3, 1, 0, kSmallStrainLinear)}, {0});
  EXPECT_EQ(ComputeInternalForces(dl, x.data(), nullptr, f.data()), first);
}

TEST(CST, BadMaterialsAndElementsRejected) {
  auto expect_bad = [](Material m, const char *what) {
    m.name = "granite";
    try {
      CheckMaterial(m);
      ADD_FAILURE() << "accepted " << what;
    } catch (const InputError &e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("material 'granite'"), std::string::npos) << msg;
      EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
  };
  expect_bad(Mat(1, 0.5), "Poisson");
  expect_bad(Mat(1, 0.7), "Poisson");
  expect_bad(Mat(1, -1.0), "Poisson");
  expect_bad(Mat(0, 0.3), "Young");
  expect_bad(Mat(-2, 0.3), "Young");
  expect_bad(Mat(1, 0.3, 0.0), "density");
  expect_bad(Mat(1, 0.3, 1.0, -0.1), "viscosity");
  expect_bad(Mat(NAN, 0.3), "Young");
  expect_bad(Mat(1, 0.3, 1, 0, 42), "model");
  EXPECT_NO_THROW(CheckMaterial(Mat(1, 0.499, 1, 0, kNeoHookean)));
  EXPECT_THROW(BuildElementData(MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 1, 1, 1), {Mat(1, 0.5)}, {0}), InputError);
  // Negative reference volume names body and element.
  TetMesh m = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 1, 1, 2);
  m.body.assign(m.tets.size(), 4);
  std::swap(m.tets[9][1], m.tets[9][2]);
  try {
    BuildElementData(m, {Mat()}, {0, 0, 0, 0, 0});
    ADD_FAILURE();
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find("body 4, element 9: reference volume"), std::string::npos) << e.what();
  }
  OrientTets(m);
  EXPECT_NO_THROW(BuildElementData(m, {Mat()}, {0, 0, 0, 0, 0}));
  EXPECT_EQ(FindMaterialModel("neo_hookean"), kNeoHookean);
  EXPECT_EQ(FindMaterialModel("munjiza_cst"), kMunjizaCST);
  EXPECT_EQ(FindMaterialModel("nope"), -1);
}

TEST(CST, LumpedMassIsRhoTimesVolume) {
  TetMesh mesh = JitteredBox();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) mesh.body[t] = t < mesh.tets.size() / 3 ? 0 : 1;
  mesh.body_names = {"a", "b"};
  const ElementData d = BuildElementData(mesh, {Mat(1, 0.3, 2500.0), Mat(1, 0.3, 1000.0)}, {0, 1});
  const std::vector<double> m = NodalMasses(d, mesh.nodes.size());
  double V0 = 0, V1 = 0, total = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    (mesh.body[t] == 0 ? V0 : V1) += TetSignedVolume(mesh, static_cast<int>(t));
  for (double q : m) total += q;
  EXPECT_NEAR(total, 2500.0 * V0 + 1000.0 * V1, 1e-10);
  EXPECT_NEAR(V0 + V1, 1.0, 1e-14);
  const std::vector<double> m2 = LumpedMasses(mesh, {2500.0, 1000.0});
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_NEAR(m[i], m2[i], 1e-12);
}
