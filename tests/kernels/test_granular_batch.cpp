// The batched granular law (include/fdem/kernels/granular_batch.hpp) against the
// one-contact law GranularForce: random contacts, both laws, sticking and sliding,
// with and without rolling resistance, forces, torques, springs and energies equal to
// round-off; and a batch run over a sub-range leaves the other entries alone.
#include <fdem/kernels/granular_batch.hpp>

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

void Compare(const GranularPair &p, double spin, double slip, int *sliding) {
  std::mt19937                     rng(7);
  std::uniform_real_distribution<> u(-1, 1), pos(0.2, 1);
  const int                        n = 203, lo = 3, hi = 200; // a sub-range: the rest must stay as set
  const double                     dt = 1e-5;
  std::vector<Case>                cases(n);
  GranularBatch                    B;
  B.Resize(n);
  using F = GranularBatch;
  for (int i = 0; i < n; ++i) {
    Case &k = cases[i];
    k.ra = 0.004 + 0.002 * pos(rng), k.rb = 0.004 + 0.002 * pos(rng), k.m = 1e-4 * pos(rng);
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng));
    k.d            = ((k.ra + k.rb) * (1 - 0.02 * pos(rng)) / norm(dir)) * dir;
    k.dv           = Vec3(u(rng), u(rng), u(rng));
    k.wa = spin * Vec3(u(rng), u(rng), u(rng)), k.wb = spin * Vec3(u(rng), u(rng), u(rng));
    k.s = slip * Vec3(u(rng), u(rng), u(rng));
    const double in[] = {k.d[0], k.d[1], k.d[2], k.ra, k.rb, k.dv[0], k.dv[1], k.dv[2], k.wa[0], k.wa[1], k.wa[2], k.wb[0], k.wb[1], k.wb[2], k.m, k.m * p.gamma_n, k.s[0], k.s[1], k.s[2]};
    for (int f = 0; f <= F::SZ; ++f) B[(F::Field)f][i] = in[f];
    for (int f = F::FX; f < F::kFields; ++f) B[(F::Field)f][i] = -7; // untouched outside [lo, hi)
  }
  GranularBatchForces(p, dt, B, lo, hi);
  for (int i = 0; i < n; ++i) {
    if (i < lo || i >= hi) {
      EXPECT_EQ(B[F::FX][i], -7);
      EXPECT_EQ(B[F::SX][i], cases[i].s[0]);
      continue;
    }
    Vec3   Fs, Tas, Tbs, ss;
    double es;
    Scalar(p, dt, cases[i], Fs, Tas, Tbs, ss, es);
    const Vec3 Fb(B[F::FX][i], B[F::FY][i], B[F::FZ][i]), Tab(B[F::TAX][i], B[F::TAY][i], B[F::TAZ][i]), Tbb(B[F::TBX][i], B[F::TBY][i], B[F::TBZ][i]);
    const Vec3 sb(B[F::SX][i], B[F::SY][i], B[F::SZ][i]);
    const double fscale = norm(Fs) + 1e-300, tscale = norm(Tas) + norm(Tbs) + 1e-300;
    EXPECT_LT(Rel(Fb, Fs, fscale), 1e-12) << i;
    EXPECT_LT(Rel(Tab, Tas, tscale), 1e-12) << i;
    EXPECT_LT(Rel(Tbb, Tbs, tscale), 1e-12) << i;
    EXPECT_LT(Rel(sb, ss, norm(ss) + 1e-300), 1e-12) << i;
    EXPECT_LT(std::fabs(B[F::ENERGY][i] - es), 1e-12 * es) << i;
    EXPECT_LT(std::fabs(B[F::OVERLAP][i] - (cases[i].ra + cases[i].rb - norm(cases[i].d))), 1e-15) << i;
    // sliding: the tangential force is at the Coulomb limit
    const Vec3 n = (1.0 / norm(cases[i].d)) * cases[i].d, ft = Fb - dot(Fb, n) * n;
    if (std::fabs(norm(ft) - p.mu * std::fabs(dot(Fb, n))) < 1e-9 * norm(Fb)) ++*sliding;
  }
}

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

// Both regimes occur: small springs stick, large ones slide.
TEST(GranularBatch, HookeEqualsScalar) {
  int sliding = 0;
  Compare(Hooke(0), 0, 1e-6, &sliding);
  Compare(Hooke(0), 10, 1.0, &sliding);
  EXPECT_GT(sliding, 100);
  EXPECT_LT(sliding, 397);
}

TEST(GranularBatch, HertzEqualsScalar) {
  int sliding = 0;
  Compare(Hertz(0), 0, 1e-9, &sliding);
  Compare(Hertz(0), 10, 1e-3, &sliding);
  EXPECT_GT(sliding, 100);
  EXPECT_LT(sliding, 397);
}

TEST(GranularBatch, RollingResistanceEqualsScalar) {
  int sliding = 0;
  Compare(Hooke(0.05), 50, 1e-4, &sliding);
  Compare(Hertz(0.05), 50, 1e-4, &sliding);
  EXPECT_GT(sliding, 0);
}

// Zero tangential stiffness (a law of damping only): the spring is left as advanced.
TEST(GranularBatch, NoTangentialStiffness) {
  GranularPair p = Hooke(0);
  p.kt           = 0;
  int sliding    = 0;
  Compare(p, 10, 1e-3, &sliding);
}
