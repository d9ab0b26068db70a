// Dense bed of spheres, serial, the kernel level only (SpherePairLoop and a
// velocity Verlet step, skin 0.1): an fcc packing of n^3 unit cells (4 n^3 spheres of
// diameter 1, mass 1) with touching nearest neighbours and small random
// velocities, gran/hooke/history 2000 NULL 50 NULL 0.5 1, dt 1e-4 in LJ
// units; the same set-up as in.bed for LAMMPS (run.sh). Prints
// particle-steps per second and the mean coordination number.
#include <fdem/kernels/sphere_pairs.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

using namespace fdem::kernels;

int main(int argc, char **argv) {
  const int cells = argc > 1 ? std::atoi(argv[1]) : 20, steps = argc > 2 ? std::atoi(argv[2]) : 1000;
  const double a = std::sqrt(2.0), dt = 1e-4, d = 1.0, mass = 1.0;
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  std::vector<double> x, v, w, r, m;
  std::vector<int> mat;
  std::vector<std::int64_t> id;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0.0, 0.1);
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k)
        for (auto &b : basis) {
          x.insert(x.end(), {(i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a});
          v.insert(v.end(), {g(rng), g(rng), g(rng)});
          w.insert(w.end(), {0, 0, 0});
          r.push_back(d / 2);
          m.push_back(mass);
          mat.push_back(0);
          id.push_back(static_cast<std::int64_t>(id.size()));
        }
  const int n = static_cast<int>(r.size());
  GranularPair p; // LAMMPS defaults: kt = 2/7 kn, gamma_t = gamma_n / 2
  p.law = GranularLaw::Hooke;
  p.kn = 2000;
  p.kt = 2000.0 * 2 / 7;
  p.gamma_n = 50;
  p.gamma_t = 25;
  p.mu = 0.5;
  SpherePairLoop loop;
  loop.SetPairTable({p}, 1);
  loop.SetSkin(0.1); // LAMMPS: neighbor 0.1 bin
  const SphereArrays s{n, x.data(), v.data(), w.data(), r.data(), m.data(), mat.data(), id.data()};
  std::vector<double> f(3 * n, 0.0), t(3 * n, 0.0);
  const double inertia = 0.4 * mass * 0.25;
  auto t0 = std::chrono::steady_clock::now();
  double coord = 0;
  for (int step = 0; step < steps; ++step) {
    for (int i = 0; i < 3 * n; ++i) {
      v[i] += 0.5 * dt * f[i] / mass;
      w[i] += 0.5 * dt * t[i] / inertia;
      x[i] += dt * v[i];
    }
    std::fill(f.begin(), f.end(), 0.0);
    std::fill(t.begin(), t.end(), 0.0);
    loop.AddForces(s, dt, f.data(), t.data());
    for (int i = 0; i < 3 * n; ++i) {
      v[i] += 0.5 * dt * f[i] / mass;
      w[i] += 0.5 * dt * t[i] / inertia;
    }
    if (step == steps - 1) coord = 2.0 * loop.NumContacts() / n;
  }
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double ke = 0;
  for (int i = 0; i < 3 * n; ++i) ke += 0.5 * mass * v[i] * v[i];
  std::printf("fdem-kernel spheres %d steps %d seconds %.3f particle-steps/s %.4g coordination %.4f ke/n %.6g searches %d\n", n,
              steps, sec, double(n) * steps / sec, coord, ke / n, loop.NumSearches());
  return 0;
}
