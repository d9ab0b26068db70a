// Joint force kernel speed (doc/fracture.md): JointElementForces over N joints
// (3 integration points each) of a field of slightly opened, slipped and
// partly damaged joints gathered from a node array and scattered back, as a
// fracturable mesh would; points per second per core, best of the repeats.
// Printed next to it, in the same process: the CST internal-force kernel on N
// tetrahedra, so that the ratio says what joints add to a step (a split mesh
// has about 2 interior faces, so 2 joints, per tetrahedron).
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/joint.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

using namespace fdem::kernels;
using Clock = std::chrono::steady_clock;

int main(int argc, char **argv) {
  const long n = argc > 1 ? std::atol(argv[1]) : 200000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  if (n <= 0 || repeats <= 0) {
    std::fprintf(stderr, "usage: bench_joint [joints > 0] [repeats > 0]\n");
    return 2;
  }
  JointMaterial m;
  m.name = "bench", m.tensile_strength = 1e6, m.cohesion = 3e6, m.friction_angle = 30, m.GI = 10, m.GII = 50, m.penalty = 1e10;
  const JointLaw L = MakeJointLaw(m, 0.01);
  // joints over a node field: triangle A's nodes 6j..6j+2, B's 6j+3..6j+5,
  // B displaced at random by up to `spread` peak openings per component
  auto time_joints = [&](double spread, double *dsum_out) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> x(18 * n), f(18 * n, 0.0);
    for (long j = 0; j < n; ++j) {
      const double o[3] = {0.01 * (j % 100), 0.01 * ((j / 100) % 100), 0.01 * (j / 10000)};
      const double P[3][3] = {{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}};
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
          x[18 * j + 3 * i + k]     = o[k] + P[i][k];
          x[18 * j + 9 + 3 * i + k] = o[k] + P[i][k] + spread * L.dn_peak * u(rng);
        }
    }
    std::vector<std::array<JointState, 3>> state(n);
    double best = 1e30, dsum = 0;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = Clock::now();
      for (long j = 0; j < n; ++j) {
        double xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) xa[i][k] = x[18 * j + 3 * i + k], xb[i][k] = x[18 * j + 9 + 3 * i + k];
        JointState st[3] = {state[j][0], state[j][1], state[j][2]};
        dsum += JointElementForces(L, xa, xb, st, fa, fb);
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) f[18 * j + 3 * i + k] += fa[i][k], f[18 * j + 9 + 3 * i + k] += fb[i][k];
      }
      best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    *dsum_out = dsum + f[0];
    return best;
  };
  double dsum_intact, dsum_damaged;
  const double best_intact = time_joints(0.3, &dsum_intact), best = time_joints(1.5, &dsum_damaged);
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
    const auto t0 = Clock::now();
    ComputeInternalForces(ed, xs.data(), nullptr, fs.data());
    cbest = std::min(cbest, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::printf("joint kernel, %ld joints (3 points each), best of %d:\n", n, repeats);
  std::printf("  intact (within the hardening branch): %.3g points/s/core (target 2e7)\n", 3.0 * n / best_intact);
  std::printf("  damaged (half the points softening):   %.3g points/s/core\n", 3.0 * n / best);
  std::printf("CST kernel (same process): %zu tetrahedra, %.3g tets/s/core\n", tets.size(), tets.size() / cbest);
  std::printf("cost of 2 intact joints per tetrahedron relative to the tetrahedron's own force: %.2f (checksums %.3g %.3g)\n", 2.0 * (best_intact / n) / (cbest / tets.size()), dsum_intact, dsum_damaged);
  return 0;
}
