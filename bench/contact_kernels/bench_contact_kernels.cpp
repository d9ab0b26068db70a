// Benchmark of the contact kernels on one core.
//  narrow phase: PotentialContactForce on random overlapping tetrahedron pairs
//                (target >= 2e5 pairs/s), on touching-box but disjoint pairs, and on
//                barely overlapping neighbours of a mesh (a fracturing body, a pile);
//  broad phase:  CellSearch Build + FindPairs, time per element for
//                N = 1e3 .. 1e6 at two packing densities (target: flat within 25%).
// Usage: bench_contact_kernels [max_n]
//        bench_contact_kernels --narrow   (the narrow phase alone)
//        bench_contact_kernels --broad [rounds] [max_n]
//   --broad: broad phase only; every (N, density) cell of the table is
//   measured `rounds` times (default 5), the sizes interleaved and rotated
//   between rounds so that load from other processes hits all sizes alike.
//   Prints the median and the min-max spread of each cell, and per density the
//   ratio max/min of the medians over N (the flatness figure).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <time.h>
#include <vector>

#include "fdem/kernels/contact.hpp"
#include "fdem/kernels/nbs.hpp"

using namespace fdem::kernels;
using Clock = std::chrono::steady_clock;

namespace {

double Seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

Tet4 RandomTet(std::mt19937_64 &rng, double size) {
  std::uniform_real_distribution<double> U(-1, 1);
  for (;;) {
    Tet4 t;
    for (auto &p : t) p = Vec3{size * U(rng), size * U(rng), size * U(rng)};
    double L = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) L = std::fmax(L, norm(t[i] - t[j]));
    const double V = std::fabs(dot(t[1] - t[0], cross(t[2] - t[0], t[3] - t[0]))) / 6;
    if (V > 0.03 * L * L * L) return t;
  }
}

Vec3 Centroid(const Tet4 &t) { return 0.25 * (t[0] + t[1] + t[2] + t[3]); }

double ThreadSeconds();

// PotentialContactForce on the pairs (A[i], B[i]) over and over for at least a second: pairs
// per second, by the wall clock or by the thread's CPU time.
void TimePairs(const std::vector<Tet4> &A, const std::vector<Tet4> &B, const char *label, bool cpu) {
  const int      npairs = (int)A.size();
  const auto     now    = [cpu] { return cpu ? ThreadSeconds() : std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); };
  TetPairContact c;
  double         sink = 0;
  for (int i = 0; i < npairs; ++i) { PotentialContactForce(A[i], B[i], 1, 1, c); sink += c.energy; }
  int          reps = 0;
  const double t0   = now();
  double       el   = 0;
  do {
    for (int i = 0; i < npairs; ++i) {
      PotentialContactForce(A[i], B[i], 1, 1, c);
      sink += c.fa[0].x;
    }
    ++reps;
    el = now() - t0;
  } while (el < 1.0);
  std::printf("  %-38s %10.3g pairs/s  (%.2f us/pair%s)%s\n", label, reps * double(npairs) / el, 1e6 * el / (reps * double(npairs)), cpu ? ", thread CPU time" : "",
              sink == 12345.678 ? " " : "");
}

void Narrow(double offset, bool want_overlap, const char *label) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> U(-1, 1);
  const int npairs = 20000;
  std::vector<Tet4> A, B;
  while (static_cast<int>(A.size()) < npairs) {
    Tet4 a = RandomTet(rng, 1.0), b = RandomTet(rng, 1.0);
    Vec3 dir{U(rng), U(rng), U(rng)};
    dir = dir / norm(dir);
    const Vec3 s = Centroid(a) - Centroid(b) + offset * dir;
    for (auto &p : b) p += s;
    std::array<Vec3, 4> fa, fb;
    if (PotentialContactForce(a, b, 1, 1, fa, fb) != want_overlap) continue;
    A.push_back(a);
    B.push_back(b);
  }
  TimePairs(A, B, label, false);
}

// Pairs of tetrahedra of a mesh that share a vertex, an edge or a face, as a fracturing body
// or a settled pile hands them to the narrow phase: 2 x 2 x 2 cubes of 6 tetrahedra (Kuhn's
// split, the same in every cube), each tetrahedron with nodes of its own moved by up to `jitter`
// (the cube's side is 1), the overlapping pairs kept. shared: the number of vertices the two
// share in the unmoved mesh (1, 2 or 3).
void Neighbours(int shared, double jitter, const char *label) {
  const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<std::array<int, 4>> tets; // vertex ids of a 3 x 3 x 3 grid of points
  const auto id = [](int i, int j, int k) { return i + 3 * j + 9 * k; };
  for (int ci = 0; ci < 2; ++ci)
    for (int cj = 0; cj < 2; ++cj)
      for (int ck = 0; ck < 2; ++ck)
        for (const auto &p : perm) {
          int c[3] = {ci, cj, ck};
          std::array<int, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          ++c[p[0]], t[1] = id(c[0], c[1], c[2]);
          ++c[p[1]], t[2] = id(c[0], c[1], c[2]);
          ++c[p[2]], t[3] = id(c[0], c[1], c[2]);
          tets.push_back(t);
        }
  std::vector<std::pair<int, int>> which;
  for (std::size_t a = 0; a < tets.size(); ++a)
    for (std::size_t b = a + 1; b < tets.size(); ++b) {
      int n = 0;
      for (int u : tets[a])
        for (int v : tets[b]) n += u == v;
      if (n == shared) which.emplace_back((int)a, (int)b);
    }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const auto place = [&](const std::array<int, 4> &t) {
    Tet4 x;
    for (int v = 0; v < 4; ++v) x[v] = Vec3{double(t[v] % 3) + jitter * U(rng), double(t[v] / 3 % 3) + jitter * U(rng), double(t[v] / 9) + jitter * U(rng)};
    return x;
  };
  const int npairs = 20000;
  std::vector<Tet4> A, B;
  for (std::size_t m = 0; static_cast<int>(A.size()) < npairs; ++m) {
    const auto &w = which[m % which.size()];
    const Tet4 a = place(tets[w.first]), b = place(tets[w.second]);
    std::array<Vec3, 4> fa, fb;
    if (!PotentialContactForce(a, b, 1, 1, fa, fb)) continue;
    A.push_back(a);
    B.push_back(b);
  }
  TimePairs(A, B, label, true);
}

struct BroadResult {
  double ns_per_elem, pairs_per_elem, build_frac, cpu_ns_per_elem;
};

// CPU time of this thread: unlike the wall clock it does not count the time
// the process waits while other processes run on a shared machine.
double ThreadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// n centres uniformly in a cube holding n * spacing^3 cells of size d = 1
// (mean occupancy 1 / spacing^3 per cell). fresh: every repetition searches a
// different configuration, as a simulation would; otherwise the same one is
// searched again and again, which lets the branch predictor memorise small
// inputs.
BroadResult Broad(int n, double spacing, bool fresh, double min_seconds = 1.0) {
  const double L = std::cbrt(double(n)) * spacing;
  std::uniform_real_distribution<double> U(0, L);
  const int nsets = fresh ? std::max(2, 4000000 / n) : 1;
  std::vector<std::vector<double>> sets(nsets, std::vector<double>(3 * std::size_t(n)));
  std::mt19937_64 rng(n);
  for (auto &c : sets)
    for (double &v : c) v = U(rng);
  CellSearch cs;
  std::vector<std::pair<int, int>> pairs;
  cs.Build(sets[0].data(), nullptr, n, 1.0);
  cs.FindPairs(pairs);
  int reps = 0;
  double tb = 0, tt = 0, tc = 0, np = 0;
  do {
    const auto &c = sets[reps % nsets];
    const double c0 = ThreadSeconds();
    const auto t0 = Clock::now();
    cs.Build(c.data(), nullptr, n, 1.0);
    const auto t1 = Clock::now();
    cs.FindPairs(pairs);
    const auto t2 = Clock::now();
    tc += ThreadSeconds() - c0;
    tb += Seconds(t0, t1);
    tt += Seconds(t0, t2);
    np += double(pairs.size());
    ++reps;
  } while (tt < min_seconds || reps < 3);
  return {1e9 * tt / (double(reps) * n), np / (double(reps) * n), tb / tt, 1e9 * tc / (double(reps) * n)};
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

int BroadOnly(int rounds, int nmax) {
  std::vector<int> sizes;
  for (int n = 1000; n <= nmax; n *= 10) sizes.push_back(n);
  const double spacing[2] = {1.0, 3.0};
  for (const bool fresh : {true, false}) {
    // t[size][density] over rounds
    std::vector<std::vector<std::vector<double>>> t(sizes.size(), std::vector<std::vector<double>>(2)), tc = t;
    std::vector<std::vector<double>> pp(sizes.size(), std::vector<double>(2));
    for (int r = 0; r < rounds; ++r)
      for (std::size_t k = 0; k < sizes.size(); ++k) {
        const std::size_t s = (k + r) % sizes.size();
        for (int d = 0; d < 2; ++d) {
          const BroadResult b = Broad(sizes[s], spacing[(d + r) % 2], fresh, 0.4);
          t[s][(d + r) % 2].push_back(b.ns_per_elem);
          tc[s][(d + r) % 2].push_back(b.cpu_ns_per_elem);
          pp[s][(d + r) % 2] = b.pairs_per_elem;
        }
      }
    for (int clock = 0; clock < 2; ++clock) {
      const auto &tt = clock == 0 ? t : tc;
      std::printf("\nBroad phase: CellSearch Build + FindPairs, ns per element (%s), median of %d rounds [min-max],\n"
                  "  %s\n",
                  clock == 0 ? "wall clock" : "thread CPU time", rounds,
                  fresh ? "a fresh configuration every repetition" : "the same configuration repeated");
      std::printf("  %9s | %-30s | %-30s\n", "N", "dense (1 elem/cell)", "sparse (1/27 elem/cell)");
      double lo[2] = {1e300, 1e300}, hi[2] = {0, 0};
      for (std::size_t s = 0; s < sizes.size(); ++s) {
        std::printf("  %9d |", sizes[s]);
        for (int d = 0; d < 2; ++d) {
          const double med = Median(tt[s][d]);
          lo[d] = std::min(lo[d], med);
          hi[d] = std::max(hi[d], med);
          std::printf(" %7.1f [%6.1f-%6.1f] %5.2fp |", med, *std::min_element(tt[s][d].begin(), tt[s][d].end()),
                      *std::max_element(tt[s][d].begin(), tt[s][d].end()), pp[s][d]);
        }
        std::printf("\n");
      }
      std::printf("  max/min   | %-30.2f | %-30.2f\n", hi[0] / lo[0], hi[1] / lo[1]);
    }
  }
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  if (argc > 1 && std::string(argv[1]) == "--broad")
    return BroadOnly(argc > 2 ? std::atoi(argv[2]) : 5, argc > 3 ? std::atoi(argv[3]) : 1000000);
  const bool narrow_only = argc > 1 && std::string(argv[1]) == "--narrow";
  const int  nmax        = argc > 1 && !narrow_only ? std::atoi(argv[1]) : 1000000;
  std::printf("Narrow phase: PotentialContactForce, both directions, energy included (one core)\n");
  Narrow(0.3, true, "overlapping random pairs");
  Narrow(0.0, true, "deeply overlapping (same centroid)");
  Narrow(1.6, false, "near but disjoint pairs");
  Neighbours(1, 1e-5, "mesh neighbours sharing a vertex");
  Neighbours(2, 1e-5, "mesh neighbours sharing an edge");
  Neighbours(3, 1e-5, "mesh neighbours sharing a face");
  if (narrow_only) return 0;
  for (const bool fresh : {true, false}) {
    std::printf("\nBroad phase: CellSearch Build + FindPairs, cell d = element diameter = 1, %s\n",
                fresh ? "a fresh configuration every repetition" : "the same configuration repeated");
    std::printf("  %9s | %-32s | %-32s\n", "N", "dense (1 elem/cell)", "sparse (1/27 elem/cell)");
    std::printf("  %9s | %10s %10s %9s | %10s %10s %9s\n", "", "ns/elem", "pairs/elem", "build", "ns/elem",
                "pairs/elem", "build");
    for (int n = 1000; n <= nmax; n *= 10) {
      const BroadResult d = Broad(n, 1.0, fresh), s = Broad(n, 3.0, fresh);
      std::printf("  %9d | %10.1f %10.2f %8.0f%% | %10.1f %10.3f %8.0f%%\n", n, d.ns_per_elem, d.pairs_per_elem,
                  100 * d.build_frac, s.ns_per_elem, s.pairs_per_elem, 100 * s.build_frac);
    }
  }
  return 0;
}
