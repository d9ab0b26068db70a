// Tests of the serial sphere pair loop (include/fdem/kernels/sphere_pairs.hpp).
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/sphere_pairs.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using namespace fdem::kernels;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Spheres {
  std::vector<double> x, v, w, r, m;
  std::vector<int> mat;
  std::vector<std::int64_t> id;
  void Add(Vec3 p, Vec3 vel, double rad, double mass, std::int64_t gid) {
    for (int k = 0; k < 3; ++k) { x.push_back(p[k]); v.push_back(vel[k]); w.push_back(0); }
    r.push_back(rad);
    m.push_back(mass);
    mat.push_back(0);
    id.push_back(gid);
  }
  int n() const { return static_cast<int>(r.size()); }
  SphereArrays Arrays() const { return {n(), x.data(), v.data(), w.data(), r.data(), m.data(), mat.data(), id.data()}; }
};

// One velocity Verlet step, forces at the half-step velocities (as LAMMPS).
void Step(SpherePairLoop &loop, Spheres &s, std::vector<double> &f, std::vector<double> &t, double dt) {
  const int n = s.n();
  for (int i = 0; i < n; ++i) {
    const double I = 0.4 * s.m[i] * s.r[i] * s.r[i];
    for (int k = 0; k < 3; ++k) {
      s.v[3 * i + k] += 0.5 * dt * f[3 * i + k] / s.m[i];
      s.w[3 * i + k] += 0.5 * dt * t[3 * i + k] / I;
      s.x[3 * i + k] += dt * s.v[3 * i + k];
    }
  }
  std::fill(f.begin(), f.end(), 0.0);
  std::fill(t.begin(), t.end(), 0.0);
  loop.AddForces(s.Arrays(), dt, f.data(), t.data());
  for (int i = 0; i < n; ++i) {
    const double I = 0.4 * s.m[i] * s.r[i] * s.r[i];
    for (int k = 0; k < 3; ++k) {
      s.v[3 * i + k] += 0.5 * dt * f[3 * i + k] / s.m[i];
      s.w[3 * i + k] += 0.5 * dt * t[3 * i + k] / I;
    }
  }
}

GranularPair Glass(double e, double mu) {
  GranularMaterial g;
  g.law_set = true;
  g.young = 5e9;
  g.poisson = 0.25;
  g.restitution = e;
  g.has_restitution = true;
  g.friction = mu;
  g.has_friction = true;
  return MixGranular(g, g, "glass-glass");
}

} // namespace

TEST(SpherePairs, HeadOnImpactOfTwoSpheresMatchesHertz) {
  const GranularPair p = Glass(1.0, 0.3);
  SpherePairLoop loop;
  loop.SetPairTable({p}, 1);
  const double R = 0.005, m = 2500 * 4.0 / 3.0 * kPi * R * R * R, v = 0.5;
  Spheres s;
  s.Add({-R - 1e-9, 0, 0}, {v, 0, 0}, R, m, 7);
  s.Add({R + 1e-9, 0, 0}, {-v, 0, 0}, R, m, 3);
  const double tc = HertzContactTime(p.estar, R / 2, m / 2, 2 * v), fmax = HertzPeakForce(p.estar, R / 2, m / 2, 2 * v);
  const double dt = tc / 4000;
  std::vector<double> f(6, 0.0), t(6, 0.0);
  double peak = 0, t_in = -1, t_out = -1;
  for (int i = 0; i < 20000 && t_out < 0; ++i) {
    Step(loop, s, f, t, dt);
    peak = std::fmax(peak, std::fabs(f[0]));
    if (loop.NumContacts() == 1 && t_in < 0) t_in = i * dt;
    if (loop.NumContacts() == 0 && t_in >= 0) t_out = i * dt;
  }
  EXPECT_NEAR(peak / fmax, 1.0, 1e-3);
  EXPECT_NEAR((t_out - t_in) / tc, 1.0, 1e-3);
  EXPECT_NEAR(s.v[0], -v, 1e-6 * v);
  EXPECT_NEAR(s.v[3], v, 1e-6 * v);
}

// A frictional, dissipative cloud of spheres colliding in free space: linear
// momentum is conserved to round-off, kinetic energy only decreases; without
// friction and damping it is conserved to O(dt^2).
TEST(SpherePairs, CloudConservesMomentumAndEnergyBalance) {
  for (int dissipative = 0; dissipative < 2; ++dissipative) {
    const GranularPair p = dissipative ? Glass(0.5, 0.5) : Glass(1.0, 0.0);
    SpherePairLoop loop;
    loop.SetPairTable({p}, 1);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    Spheres s;
    const double R = 0.005, rho = 2500;
    int id = 0;
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b)
        for (int c = 0; c < 5; ++c) {
          const double r = R * (0.8 + 0.2 * (u(rng) + 1) / 2);
          s.Add({a * 2.1 * R, b * 2.1 * R, c * 2.1 * R}, {u(rng), u(rng), u(rng)}, r, rho * 4.0 / 3.0 * kPi * r * r * r, id++);
        }
    auto momentum = [&](int k) {
      double P = 0;
      for (int i = 0; i < s.n(); ++i) P += s.m[i] * s.v[3 * i + k];
      return P;
    };
    auto energy = [&]() {
      double E = 0;
      for (int i = 0; i < s.n(); ++i) {
        const double I = 0.4 * s.m[i] * s.r[i] * s.r[i];
        for (int k = 0; k < 3; ++k) E += 0.5 * s.m[i] * s.v[3 * i + k] * s.v[3 * i + k] + 0.5 * I * s.w[3 * i + k] * s.w[3 * i + k];
      }
      // Hertz elastic energy (8/15) E* sqrt(R*) delta^{5/2} of the last contacts.
      for (auto [i, j] : loop.Contacts()) {
        const Vec3 d{s.x[3 * i] - s.x[3 * j], s.x[3 * i + 1] - s.x[3 * j + 1], s.x[3 * i + 2] - s.x[3 * j + 2]};
        const double delta = s.r[i] + s.r[j] - norm(d), rstar = s.r[i] * s.r[j] / (s.r[i] + s.r[j]);
        E += 8.0 / 15.0 * p.estar * std::sqrt(rstar) * std::pow(delta, 2.5);
      }
      return E;
    };
    const double P0[3] = {momentum(0), momentum(1), momentum(2)}, E0 = energy();
    double pscale = 0;
    for (int i = 0; i < s.n(); ++i) pscale += s.m[i];
    const double tc = HertzContactTime(p.estar, R / 2, rho * kPi * R * R * R / 3, 2.0);
    const double dt = tc / 200;
    std::vector<double> f(3 * s.n(), 0.0), t(3 * s.n(), 0.0);
    int contacts = 0;
    for (int i = 0; i < 4000; ++i) {
      Step(loop, s, f, t, dt);
      contacts += loop.NumContacts();
    }
    EXPECT_GT(contacts, 1000) << "the spheres must collide";
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(momentum(k), P0[k], 1e-13 * pscale);
    if (dissipative)
      EXPECT_LT(energy(), 0.9 * E0);
    else
      EXPECT_NEAR(energy() / E0, 1.0, 1e-6) << "contacts at end " << loop.NumContacts();
  }
}

// The answer does not depend on the order the spheres are handed over in
// (histories are keyed by global id), as a parallel layer needs, nor on the
// search skin (which only makes searches rarer).
TEST(SpherePairs, ForcesIndependentOfOrder) {
  const GranularPair p = Glass(0.7, 0.4);
  Spheres a, b;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  const double R = 0.005, m = 1e-3;
  for (int i = 0; i < 40; ++i) a.Add({2.0 * R * (i % 4) + 1e-4 * u(rng), 2.0 * R * (i / 4 % 5), 2.0 * R * (i / 20)}, {u(rng), u(rng), u(rng)}, R, m, 100 + i);
  for (int i = a.n() - 1; i >= 0; --i)
    b.Add({a.x[3 * i], a.x[3 * i + 1], a.x[3 * i + 2]}, {a.v[3 * i], a.v[3 * i + 1], a.v[3 * i + 2]}, R, m, a.id[i]);
  Spheres c = a;
  SpherePairLoop la, lb, lc;
  la.SetPairTable({p}, 1);
  lb.SetPairTable({p}, 1);
  lc.SetPairTable({p}, 1);
  lc.SetSkin(0.2 * R);
  std::vector<double> fa(3 * a.n(), 0.0), ta = fa, fb = fa, tb = fa, fc = fa, tc = fa;
  for (int s = 0; s < 200; ++s) {
    Step(la, a, fa, ta, 1e-6);
    Step(lb, b, fb, tb, 1e-6);
    Step(lc, c, fc, tc, 1e-6);
  }
  EXPECT_GT(la.NumContacts(), 0);
  EXPECT_EQ(la.NumSearches(), 200);
  EXPECT_LT(lc.NumSearches(), 10);
  for (std::size_t k = 0; k < a.x.size(); ++k) {
    EXPECT_NEAR(a.x[k], c.x[k], 1e-15);
    EXPECT_NEAR(a.w[k], c.w[k], 1e-9);
  }
  const int n = a.n();
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.x[3 * i + k], b.x[3 * (n - 1 - i) + k], 1e-12);
      EXPECT_NEAR(a.w[3 * i + k], b.w[3 * (n - 1 - i) + k], 1e-6);
    }
}

TEST(SpherePairs, BadInputIsNamed) {
  SpherePairLoop loop;
  loop.SetPairTable({Glass(1, 0)}, 1);
  Spheres s;
  s.Add({0, 0, 0}, {}, 0.01, 1, 5);
  s.Add({0.015, 0, 0}, {}, 0.01, 1, 6);
  s.mat[1] = 2;
  std::vector<double> f(6, 0.0), t(6, 0.0);
  try {
    loop.AddForces(s.Arrays(), 1e-6, f.data(), t.data());
    FAIL() << "no error";
  } catch (const InputError &e) {
    EXPECT_EQ(std::string(e.what()), "sphere 6: material index 2 is not in the pair table (1 materials)");
  }
}
