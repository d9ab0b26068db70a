// The sweep over sphere-sphere pairs (include/fdem/kernels/granular_sweep.hpp) against the
// one-contact law GranularForce: random contacts, both laws, sticking and sliding, with and
// without rolling resistance, forces, torques, springs and energies equal to round-off; and
// the sweep's bookkeeping: gaps, slots started and opened, pairs without a law, the sums per
// sphere.
#include <fdem/kernels/granular_sweep.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace fdem::kernels;

namespace {

struct Case {
  Vec3   d, dv, wa, wb, s;
  double ra, rb, m;
};

// One contact by the scalar law, as the contact engine did before batches: force on a, torques
// on a and b, the advanced spring and the elastic energy.
void Scalar(const GranularPair &p, double dt, const Case &k, Vec3 &F, Vec3 &Ta, Vec3 &Tb, Vec3 &s, double &energy) {
  const double    dist = norm(k.d);
  GranularContact c;
  c.n       = (1.0 / dist) * k.d;
  c.overlap = k.ra + k.rb - dist;
  c.vrel    = k.dv - cross(k.ra * k.wa + k.rb * k.wb, c.n);
  c.wrel    = k.wa - k.wb;
  c.rstar   = k.ra * k.rb / (k.ra + k.rb);
  c.mstar   = k.m;
  s         = k.s;
  const GranularResult r = GranularForce(p, c, dt, s);
  F                      = r.fn + r.ft;
  const Vec3 nxF         = cross(c.n, F);
  Ta                     = r.mroll - k.ra * nxF;
  Tb                     = -1.0 * (k.rb * nxF + r.mroll);
  energy                 = GranularElasticEnergy(p, c.overlap, c.rstar, s);
}

double Rel(const Vec3 &a, const Vec3 &b, double scale) { return norm(a - b) / scale; }

// Each case is a pair of its own two spheres (2i, 2i + 1), with a slot (its spring given) and
// the law laws[law(i)]: what the sweep sums on each sphere is the scalar law's force and torques.
void Compare(const std::vector<GranularPair> &laws, int (*law)(int), double spin, double slip, int *sliding) {
  std::mt19937                     rng(7);
  std::uniform_real_distribution<> u(-1, 1), pos(0.2, 1);
  const int                        n  = 200;
  const double                     dt = 1e-5;
  std::vector<Case>                cases(n);
  std::vector<SphereState>         s(2 * n);
  std::vector<SpherePair>          pairs(n);
  std::vector<SpherePairConst>     pc(n);
  std::vector<Vec3>                springs(n);
  std::vector<SphereSum>           sum(2 * n);
  for (int i = 0; i < n; ++i) {
    Case &k = cases[i];
    k.ra = 0.004 + 0.002 * pos(rng), k.rb = 0.004 + 0.002 * pos(rng), k.m = 1e-4 * pos(rng);
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng));
    k.d            = ((k.ra + k.rb) * (1 - 0.02 * pos(rng)) / norm(dir)) * dir;
    k.dv           = Vec3(u(rng), u(rng), u(rng));
    k.wa = spin * Vec3(u(rng), u(rng), u(rng)), k.wb = spin * Vec3(u(rng), u(rng), u(rng));
    k.s = slip * Vec3(u(rng), u(rng), u(rng));
    const Vec3 xb(u(rng), u(rng), u(rng)), vb(u(rng), u(rng), u(rng));
    s[2 * i]     = SphereState{xb + k.d, vb + k.dv, k.wa, k.ra};
    s[2 * i + 1] = SphereState{xb, vb, k.wb, k.rb};
    pairs[i]     = SpherePair{2 * i, 2 * i + 1, 0, law(i)};
    pc[i]        = SpherePairConst{1, k.m, k.m * laws[law(i)].gamma_n};
    springs[i]   = k.s;
  }
  SphereSweep out;
  SphereContactSweep(laws.data(), dt, s.data(), pairs.data(), pc.data(), springs.data(), n, sum.data(), out);
  ASSERT_EQ((int)out.touching.size(), n);
  EXPECT_TRUE(out.started.empty() && out.opened.empty() && out.bad.empty());
  double energy = 0;
  for (int i = 0; i < n; ++i) {
    const GranularPair &p = laws[law(i)];
    Vec3                Fs, Tas, Tbs, ss;
    double              es;
    // the centres went through a sum: the scalar law sees the same difference
    Case k = cases[i];
    k.d    = s[2 * i].x - s[2 * i + 1].x;
    k.dv   = s[2 * i].v - s[2 * i + 1].v;
    Scalar(p, dt, k, Fs, Tas, Tbs, ss, es);
    energy += es;
    const Vec3   Fa = sum[2 * i].f, Fb = sum[2 * i + 1].f, Tab = sum[2 * i].t, Tbb = sum[2 * i + 1].t;
    const double fscale = norm(Fs) + 1e-300, tscale = norm(Tas) + norm(Tbs) + 1e-300;
    EXPECT_LT(Rel(Fa, Fs, fscale), 1e-12) << i;
    EXPECT_LT(Rel(Fb, -1.0 * Fs, fscale), 1e-12) << i;
    EXPECT_LT(Rel(Tab, Tas, tscale), 1e-12) << i;
    EXPECT_LT(Rel(Tbb, Tbs, tscale), 1e-12) << i;
    EXPECT_LT(Rel(springs[i], ss, norm(ss) + 1e-300), 1e-12) << i;
    // sliding: the tangential force is at the Coulomb limit
    const Vec3 nrm = (1.0 / norm(k.d)) * k.d, ft = Fa - dot(Fa, nrm) * nrm;
    if (std::fabs(norm(ft) - p.mu * std::fabs(dot(Fa, nrm))) < 1e-9 * norm(Fa)) ++*sliding;
  }
  EXPECT_LT(std::fabs(out.energy - energy), 1e-12 * energy);
}

int One(int) { return 0; }
int Mixed(int i) { // runs of 1, 2, 3, 4, 5, 1, 2, ... pairs, the laws in turn
  int k = 0, run = 1;
  while (i >= run) i -= run, ++k, run = run % 5 + 1;
  return k % 4;
}
void Compare(const GranularPair &p, double spin, double slip, int *sliding) { Compare({p}, One, spin, slip, sliding); }

GranularPair Hooke(double mu_roll) {
  GranularPair p;
  p.law = GranularLaw::Hooke, p.kn = 2000, p.kt = 2000 * 2.0 / 7.0, p.gamma_n = 50, p.gamma_t = 25, p.mu = 0.5, p.mu_roll = mu_roll;
  return p;
}
GranularPair Hertz(double mu_roll) {
  GranularPair p;
  p.law = GranularLaw::Hertz, p.estar = 3e9, p.gstar = 1.2e9, p.alpha = 0.3, p.mu = 0.3, p.mu_roll = mu_roll;
  return p;
}
} // namespace

// A law with small springs (they stick) and with large ones and spin (they slide): both regimes occur.
static void SticksAndSlides(const GranularPair &p, double small, double large) {
  int sliding = 0;
  Compare(p, 0, small, &sliding);
  Compare(p, 10, large, &sliding);
  EXPECT_GT(sliding, 100);
  EXPECT_LT(sliding, 390);
}

TEST(GranularSweep, HookeEqualsScalar) { SticksAndSlides(Hooke(0), 1e-6, 1.0); }

TEST(GranularSweep, HertzEqualsScalar) { SticksAndSlides(Hertz(0), 1e-9, 1e-3); }

TEST(GranularSweep, RollingResistanceEqualsScalar) {
  int sliding = 0;
  Compare(Hooke(0.05), 50, 1e-4, &sliding);
  Compare(Hertz(0.05), 50, 1e-4, &sliding);
  EXPECT_GT(sliding, 0);
}

// The sweep runs touching pairs four at a time while they share a law: runs of one to five
// pairs of each of four laws (Hooke and Hertz, with and without rolling resistance) in one
// sweep, so that groups are cut short by a change of law, and rolling lanes without spin.
TEST(GranularSweep, LawsMixedInOneSweep) {
  const std::vector<GranularPair> laws{Hooke(0), Hertz(0.05), Hooke(0.05), Hertz(0)};
  int                             sliding = 0;
  Compare(laws, Mixed, 0, 1e-6, &sliding);
  Compare(laws, Mixed, 10, 1e-3, &sliding);
  EXPECT_GT(sliding, 0);
}

// Zero tangential stiffness (a law of damping only): the spring is left as advanced.
TEST(GranularSweep, NoTangentialStiffness) {
  GranularPair p = Hooke(0);
  p.kt           = 0;
  int sliding    = 0;
  Compare(p, 10, 1e-3, &sliding);
}

// The bookkeeping of one sweep over a chain of spheres 0-1-2-3-4 (each 1 apart, radius 0.6 or
// 0.4): pairs that touch with and without a slot, a gap with a slot, a pair without a law and
// one with both centres at one point; the forces of the touching pairs summed per sphere,
// in the pairs' order, equal and opposite.
TEST(GranularSweep, Bookkeeping) {
  const GranularPair       p = Hooke(0);
  std::vector<SphereState> s = {{Vec3(0, 0, 0), Vec3(), Vec3(), 0.6}, {Vec3(1, 0, 0), Vec3(), Vec3(), 0.6}, {Vec3(2, 0, 0), Vec3(), Vec3(), 0.6},
                                {Vec3(3, 0, 0), Vec3(), Vec3(), 0.4}, {Vec3(4, 0, 0), Vec3(), Vec3(), 0.6}, {Vec3(4, 0, 0), Vec3(), Vec3(), 0.6}};
  std::vector<SpherePair>  pairs = {
      {0, 1, 2, 0},   // touches, has slot 2
      {1, 2, -1, 0},  // touches, no slot yet: started
      {2, 3, 1, 0},   // 0.6 + 0.4 = 1: a gap of zero, with a slot: opened
      {3, 4, -1, 0},  // no touch, no slot: nothing
      {0, 1, 0, -1},  // touches without a law: bad
      {4, 5, 0, 0},   // one centre: bad
  };
  std::vector<SpherePairConst> pc(pairs.size(), SpherePairConst{1, 1.0, 0.0});
  std::vector<Vec3>            springs(pairs.size(), Vec3(0.007, 0.007, 0.007));
  std::vector<SphereSum>       sum(s.size());
  SphereSweep                  out;
  SphereContactSweep(&p, 1e-3, s.data(), pairs.data(), pc.data(), springs.data(), (int)pairs.size(), sum.data(), out);
  EXPECT_EQ(out.touching, (std::vector<int>{0, 1}));
  EXPECT_EQ(out.started, (std::vector<int>{1}));
  EXPECT_EQ(out.opened, (std::vector<int>{2}));
  EXPECT_EQ(out.bad, (std::vector<int>{4, 5}));
  // at rest, overlap 0.2 each: kn 0.2 along x; a spring at rest in the tangent plane keeps its
  // tangential part (0.007 in y and z: it sticks) and the started one starts from zero
  const double fn = p.kn * 0.2;
  EXPECT_DOUBLE_EQ(springs[1][1], 0.0);
  EXPECT_DOUBLE_EQ(springs[0][0], 0.0);
  EXPECT_DOUBLE_EQ(springs[0][1], 0.007);
  EXPECT_EQ(springs[3][0], 0.007); // not touching: left alone
  const double ft = p.kt * 0.007 * std::sqrt(2.0);
  ASSERT_LT(ft, p.mu * fn);
  EXPECT_NEAR(sum[0].f[0], -fn, 1e-12 * fn);
  EXPECT_NEAR(std::hypot(sum[0].f[1], sum[0].f[2]), ft, 1e-12 * fn);
  EXPECT_NEAR(sum[1].f[0], fn - fn, 1e-12 * fn);
  EXPECT_NEAR(sum[2].f[0], fn, 1e-12 * fn);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(sum[0].f[k] + sum[1].f[k] + sum[2].f[k], 0.0, 1e-12 * fn);
    EXPECT_EQ(sum[3].f[k], 0.0);
    EXPECT_EQ(sum[4].f[k], 0.0);
  }
  EXPECT_NEAR(out.energy, 2 * 0.5 * p.kn * 0.2 * 0.2 + 0.5 * p.kt * dot(springs[0], springs[0]), 1e-12);
}
