// Joint force kernel speed (doc/fracture.md): the joint forces of N joints (3 integration
// points each) of a field of slightly opened, slipped and partly damaged joints gathered
// from a node array and scattered back, as a fracturable mesh would; points per second
// per core (CPU time of the thread), best of the repeats. Two kernels in interleaved repeats: JointBlockForces (a
// block of joints at a time, as the deformable model calls it) and, for comparison, the
// per-joint kernel it replaced (commit 0c5057f, kept below as Reference); their forces are
// compared (largest difference relative to the largest force). Printed next to it, in the
// same process: the CST internal-force kernel on N tetrahedra, so that the ratio says what
// joints add to a step (a split mesh has about 2 interior faces, so 2 joints, per tetrahedron).
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/joint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <time.h>
#include <vector>

using namespace fdem::kernels;

static double CpuSeconds() { // of this thread: what a shared machine's other load does not add
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

namespace {
// The per-joint kernel of commit 0c5057f (JointElementForces before blocks), with the shear secant since, for timing and
// comparing against; only here.
double Reference(const JointLaw &L, const double xa[3][3], const double xb[3][3], JointState state[3], double fa[3][3], double fb[3][3]) {
  double n[3], w, dn[3], sv[3][3], s[3];
  {
    double m[3][3], d[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) m[i][k] = 0.5 * (xa[i][k] + xb[i][k]), d[i][k] = xb[i][k] - xa[i][k];
    const double e1[3] = {m[1][0] - m[0][0], m[1][1] - m[0][1], m[1][2] - m[0][2]};
    const double e2[3] = {m[2][0] - m[0][0], m[2][1] - m[0][1], m[2][2] - m[0][2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double twiceA = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(twiceA > 0)) return 0;
    const double inv = 1.0 / twiceA;
    for (double &c : n) c *= inv;
    w = twiceA / 6.0;
    for (int q = 0; q < 3; ++q) {
      const int i = q, j = (q + 1) % 3;
      double    sep[3];
      for (int k = 0; k < 3; ++k) sep[k] = 0.5 * (d[i][k] + d[j][k]);
      dn[q] = sep[0] * n[0] + sep[1] * n[1] + sep[2] * n[2];
      for (int k = 0; k < 3; ++k) sv[q][k] = sep[k] - dn[q] * n[k];
      s[q] = std::sqrt(sv[q][0] * sv[q][0] + sv[q][1] * sv[q][1] + sv[q][2] * sv[q][2]);
    }
  }
  double        Dmax = 0;
  JointTraction t3[3];
  for (int q = 0; q < 3; ++q) {
    JointTraction &t = t3[q];
    if (state[q].D == 0 && dn[q] <= L.dn_peak && !state[q].broken()) {
      const double x = dn[q] * L.inv_dn_peak;
      const double sigma0 = dn[q] <= 0 ? 2.0 * L.ft * x : L.ft * x * (2.0 - x);
      const double fs     = dn[q] <= 0 ? L.c - sigma0 * L.tan_phi : L.c;
      const double sp     = fs * L.slip_per_strength;
      if (s[q] <= sp) {
        const double y = s[q] / sp;
        state[q].shear_damage = std::max(state[q].shear_damage, (float)(0.5 * y)); // the hardening branch's secant
        t                     = JointTraction();
        t.sigma               = sigma0;
        t.tau                 = (1.0 - state[q].shear_damage) * (L.shear_stiffness * s[q]);
      } else t = JointTractionAt(L, dn[q], s[q], state[q]);
    } else t = JointTractionAt(L, dn[q], s[q], state[q]);
    Dmax = std::max(Dmax, t.D);
  }
  const bool all_broken = JointBroken(state);
  for (int q = 0; q < 3; ++q) {
    const int     i = q, j = (q + 1) % 3;
    JointTraction t = t3[q];
    if (all_broken) break;
    if (state[q].broken()) t.sigma = dn[q] < 0 ? 2.0 * L.ft * dn[q] / L.dn_peak : 0.0, t.tau = 0;
    double tr[3];
    for (int k = 0; k < 3; ++k) tr[k] = t.sigma * n[k] + (s[q] > 0 ? t.tau * sv[q][k] / s[q] : 0.0);
    for (int k = 0; k < 3; ++k) {
      const double f = 0.5 * w * tr[k];
      fa[i][k] += f, fa[j][k] += f;
      fb[i][k] -= f, fb[j][k] -= f;
    }
  }
  return Dmax;
}

struct Result {
  double best_ref = 1e30, best_new = 1e30, dsum_ref = 0, dsum_new = 0, maxdiff = 0, maxf = 0;
};

// n joints over a node field: triangle A's nodes 6j..6j+2, B's 6j+3..6j+5, B displaced at
// random by up to `spread` peak openings per component; each kernel starts from intact
// joints, on a copy of their history (every repeat the same)
Result TimeJoints(const JointLaw &L, long n, int repeats, double spread) {
  std::mt19937_64                        rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double>                    x(18 * n), f_ref(18 * n, 0.0), f_new(18 * n, 0.0);
  for (long j = 0; j < n; ++j) {
    const double o[3]    = {0.01 * (j % 100), 0.01 * ((j / 100) % 100), 0.01 * (j / 10000)};
    const double P[3][3] = {{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        x[18 * j + 3 * i + k]     = o[k] + P[i][k];
        x[18 * j + 9 + 3 * i + k] = o[k] + P[i][k] + spread * L.dn_peak * u(rng);
      }
  }
  std::vector<std::array<JointState, 3>> state(n);
  std::vector<JointLaw>                  laws(n, L); // one law per joint, as in the model
  Result                                 R;
  for (int r = 0; r < repeats; ++r) {
    std::fill(f_ref.begin(), f_ref.end(), 0.0);
    std::fill(f_new.begin(), f_new.end(), 0.0);
    double t0 = CpuSeconds();
    for (long j = 0; j < n; ++j) {
      double xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) xa[i][k] = x[18 * j + 3 * i + k], xb[i][k] = x[18 * j + 9 + 3 * i + k];
      JointState st[3] = {state[j][0], state[j][1], state[j][2]};
      R.dsum_ref += Reference(laws[j], xa, xb, st, fa, fb);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) f_ref[18 * j + 3 * i + k] += fa[i][k], f_ref[18 * j + 9 + 3 * i + k] += fb[i][k];
    }
    R.best_ref = std::min(R.best_ref, CpuSeconds() - t0);
    t0         = CpuSeconds();
    JointBlock B;
    JointState st[kJointBlock][3];
    for (long j0 = 0; j0 < n; j0 += kJointBlock) {
      B.n = (int)std::min<long>(kJointBlock, n - j0);
      for (int b = 0; b < B.n; ++b) {
        const long j = j0 + b;
        for (int c = 0; c < 9; ++c) B.xa[c][b] = x[18 * j + c], B.xb[c][b] = x[18 * j + 9 + c];
        B.law[b] = &laws[j], st[b][0] = state[j][0], st[b][1] = state[j][1], st[b][2] = state[j][2];
        B.state[b] = st[b], B.dissipated[b] = nullptr;
      }
      JointBlockForces(B);
      for (int b = 0; b < B.n; ++b) {
        const long j = j0 + b;
        R.dsum_new += B.Dmax[b];
        for (int c = 0; c < 9; ++c) f_new[18 * j + c] += B.fa[c][b], f_new[18 * j + 9 + c] -= B.fa[c][b];
      }
    }
    R.best_new = std::min(R.best_new, CpuSeconds() - t0);
  }
  for (long i = 0; i < 18 * n; ++i) R.maxdiff = std::max(R.maxdiff, std::fabs(f_new[i] - f_ref[i])), R.maxf = std::max(R.maxf, std::fabs(f_ref[i]));
  R.dsum_ref += f_ref[0], R.dsum_new += f_new[0];
  return R;
}
} // namespace

int main(int argc, char **argv) {
  const long n       = argc > 1 ? std::atol(argv[1]) : 200000;
  const int  repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  if (n <= 0 || repeats <= 0) {
    std::fprintf(stderr, "usage: bench_joint [joints > 0] [repeats > 0]\n");
    return 2;
  }
  JointMaterial m;
  m.name = "bench", m.tensile_strength = 1e6, m.cohesion = 3e6, m.friction_angle = 30, m.GI = 10, m.GII = 50, m.penalty = 1e10;
  const JointLaw L = MakeJointLaw(m, 0.01);
  const Result   intact = TimeJoints(L, n, repeats, 0.3), damaged = TimeJoints(L, n, repeats, 1.5);
  JointLaw       Lface = L; // the model's default: the compression over the face (the reference kernel has the points' rule)
  Lface.face_compression = 1;
  const Result   face    = TimeJoints(Lface, n, repeats, 0.3);
  // the CST kernel on n tetrahedra in the same process (a lattice of cubes, 6 tets each)
  const int side = std::max(1, (int)std::cbrt(n / 6.0));
  std::vector<Vec3> X;
  for (int k = 0; k <= side; ++k)
    for (int jj = 0; jj <= side; ++jj)
      for (int i = 0; i <= side; ++i) X.push_back({0.01 * i, 0.01 * jj, 0.01 * k});
  auto id = [&](int i, int jj, int k) { return i + (side + 1) * (jj + (side + 1) * k); };
  std::vector<std::array<int, 4>> tets;
  for (int k = 0; k < side; ++k)
    for (int jj = 0; jj < side; ++jj)
      for (int i = 0; i < side; ++i) {
        const int c[8] = {id(i, jj, k), id(i + 1, jj, k), id(i + 1, jj + 1, k), id(i, jj + 1, k), id(i, jj, k + 1), id(i + 1, jj, k + 1), id(i + 1, jj + 1, k + 1), id(i, jj + 1, k + 1)};
        const int T[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        for (auto &t : T) tets.push_back({c[t[0]], c[t[1]], c[t[2]], c[t[3]]});
      }
  Material mat;
  mat.name = "bench", mat.E = 1e9, mat.nu = 0.2, mat.rho = 2000;
  const ElementData ed = BuildElementData(X, tets, {mat}, {}, {});
  std::vector<double> xs(3 * X.size()), fs(3 * X.size());
  for (size_t i = 0; i < X.size(); ++i)
    for (int k = 0; k < 3; ++k) xs[3 * i + k] = X[i][k] * (1 + 1e-4 * (k + 1));
  double cbest = 1e30;
  for (int r = 0; r < repeats; ++r) {
    std::fill(fs.begin(), fs.end(), 0.0);
    const double t0 = CpuSeconds();
    ComputeInternalForces(ed, xs.data(), nullptr, fs.data());
    cbest = std::min(cbest, CpuSeconds() - t0);
  }
  std::printf("joint kernel, %ld joints (3 points each), best of %d interleaved repeats, points/s/core (target 2e7):\n", n, repeats);
  std::printf("  intact (within the hardening branch): blocks %.3g, per joint (0c5057f) %.3g, ratio %.2f\n", 3.0 * n / intact.best_new, 3.0 * n / intact.best_ref, intact.best_ref / intact.best_new);
  std::printf("  damaged (half the points softening):   blocks %.3g, per joint (0c5057f) %.3g, ratio %.2f\n", 3.0 * n / damaged.best_new, 3.0 * n / damaged.best_ref, damaged.best_ref / damaged.best_new);
  std::printf("  intact, the face rule (the default):  blocks %.3g, per joint (0c5057f, the points' rule) %.3g, ratio %.2f\n", 3.0 * n / face.best_new, 3.0 * n / face.best_ref, face.best_ref / face.best_new);
  std::printf("  forces, blocks against per joint: largest difference / largest force %.3g (intact), %.3g (damaged)\n", intact.maxdiff / intact.maxf, damaged.maxdiff / damaged.maxf);
  std::printf("CST kernel (same process): %zu tetrahedra, %.3g tets/s/core\n", tets.size(), tets.size() / cbest);
  std::printf("cost of 2 intact joints per tetrahedron relative to the tetrahedron's own force: %.2f (checksums %.17g %.17g; per joint %.17g %.17g)\n", 2.0 * (intact.best_new / n) / (cbest / tets.size()),
              intact.dsum_new, damaged.dsum_new, intact.dsum_ref, damaged.dsum_ref);
  return 0;
}
