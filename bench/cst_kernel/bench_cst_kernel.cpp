// Benchmark: ComputeInternalForces alone on a box mesh of ~1e6 tetrahedra
// (55^3 cells x 6), one core. Prints tetrahedra per second per model, with
// and without the viscous term. Target: >= 1e7 tet/s/core.
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

using namespace fdem::kernels;

int main(int argc, char **argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 55;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 5;
  const TetMesh mesh = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, n, n, n);
  const std::size_t nn = mesh.nodes.size(), ne = mesh.tets.size();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.05 / n, 0.05 / n);
  std::vector<double> x(3 * nn), v(3 * nn), f(3 * nn, 0.0);
  for (std::size_t i = 0; i < nn; ++i) {
    const Vec3 &p = mesh.nodes[i];
    x[3 * i] = 1.01 * p.x + 0.02 * p.y + u(rng);
    x[3 * i + 1] = 0.99 * p.y + u(rng);
    x[3 * i + 2] = p.z - 0.01 * p.x + u(rng);
    for (int k = 0; k < 3; ++k) v[3 * i + k] = 10 * u(rng);
  }
  std::printf("CST internal-force kernel, %zu tetrahedra, %zu nodes, best of %d runs, one core\n", ne, nn, repeats);
  std::printf("%-22s %-8s %12s %14s\n", "model", "viscous", "ns/tet", "tet/s");
  for (int model = 0; model < static_cast<int>(MaterialModels().size()); ++model)
    for (bool visc : {true, false}) {
      const ElementData d = BuildElementData(mesh, {Material{"m", 1e9, 0.25, 2500, 1e3, model}}, {0});
      double best = 1e300;
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const std::int64_t bad = ComputeInternalForces(d, x.data(), visc ? v.data() : nullptr, f.data());
        const auto t1 = std::chrono::steady_clock::now();
        if (bad >= 0) std::printf("inverted element %lld\n", static_cast<long long>(bad));
        best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
      }
      std::printf("%-22s %-8s %12.1f %14.3e\n", MaterialModels()[model].name, visc ? "yes" : "no", 1e9 * best / ne,
                  ne / best);
    }
  double s = 0;
  for (double q : f) s += q;
  std::printf("(checksum %.3e)\n", s);
  return 0;
}
