// The cohesive law of a fracture joint (fdem/kernels/joint.hpp, doc/fracture.md):
// Munjiza's softening curve, the traction-separation law point by point in
// pure mode I and II, the dissipated energy against G_I and G_II, damage that
// never heals, Mohr-Coulomb strengthening under compression, bad input.
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/joint.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace fdem::kernels;

namespace {
JointMaterial Mortar() {
  JointMaterial m;
  m.name = "mortar";
  m.tensile_strength = 1.0e6, m.cohesion = 3.0e6, m.friction_angle = 30, m.GI = 10, m.GII = 50, m.penalty = 1.0e10;
  return m;
}
// Work per unit area of the traction along a monotonic path 0 -> end in n
// steps (trapezoid), in mode I (normal) or II (slip).
double Work(const JointLaw &L, bool shear, double end, int n, JointState &st) {
  double w = 0, prev = 0;
  for (int i = 1; i <= n; ++i) {
    const double d = end * i / n;
    const JointTraction t = shear ? JointTractionAt(L, 0, d, st) : JointTractionAt(L, d, 0, st);
    const double cur = shear ? t.tau : t.sigma;
    w += 0.5 * (prev + cur) * (end / n);
    prev = cur;
  }
  return w;
}
} // namespace

TEST(Joint, SofteningCurveEndsAndIntegral) {
  EXPECT_NEAR(JointSoftening(0), 1.0, 1e-15);
  EXPECT_NEAR(JointSoftening(1), 0.0, 1e-15);
  for (int i = 0; i < 100; ++i) EXPECT_GT(JointSoftening(i / 100.0), JointSoftening((i + 1) / 100.0)) << "z must decrease at D = " << i / 100.0;
  // the published value of the integral, to its 4 digits, and an independent midpoint rule
  EXPECT_NEAR(JointSofteningIntegral(), 0.3863, 5e-5);
  double mid = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) mid += JointSoftening((i + 0.5) / n) / n;
  EXPECT_NEAR(JointSofteningIntegral(), mid, 1e-9);
}

TEST(Joint, ModeIFollowsTheLawPointByPoint) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  EXPECT_DOUBLE_EQ(L.dn_peak, 2 * 0.01 * 1e6 / 1e10); // 2 h f_t / p = 2e-6 m
  const double Z = JointSofteningIntegral();
  EXPECT_NEAR(L.dn_crit, L.dn_peak + (10 - 2.0 / 3.0 * 1e6 * L.dn_peak) / (1e6 * Z), 1e-18);
  JointState st;
  // hardening: 2x - x^2 of f_t, reversible (no damage)
  EXPECT_NEAR(JointTractionAt(L, 0.5 * L.dn_peak, 0, st).sigma, 0.75e6, 1e-6);
  EXPECT_NEAR(JointTractionAt(L, L.dn_peak, 0, st).sigma, 1e6, 1e-6);
  EXPECT_EQ(st.D, 0);
  // compression: the penalty 2 f_t dn / dn_peak
  EXPECT_NEAR(JointTractionAt(L, -L.dn_peak, 0, st).sigma, -2e6, 1e-6);
  // softening: z(D) f_t at D = 0.25, 0.5, 0.9
  for (double D : {0.25, 0.5, 0.9}) {
    JointState s2;
    const JointTraction t = JointTractionAt(L, L.dn_peak + D * (L.dn_crit - L.dn_peak), 0, s2);
    EXPECT_NEAR(t.D, D, 1e-12);
    EXPECT_NEAR(t.sigma, 1e6 * JointSoftening(D), 1e-6 * 1e6);
  }
  JointState s3;
  EXPECT_EQ(JointTractionAt(L, 1.0001 * L.dn_crit, 0, s3).sigma, 0);
  EXPECT_TRUE(s3.broken());
}

TEST(Joint, DissipatedEnergyEqualsTheFractureEnergies) {
  for (double h : {0.002, 0.01, 0.03}) {
    const JointLaw L = MakeJointLaw(Mortar(), h);
    JointState sI, sII;
    const double wI = Work(L, false, 1.01 * L.dn_crit, 200000, sI);
    double sp, sc;
    JointSlipLimits(L, 0, &sp, &sc);
    const double wII = Work(L, true, 1.01 * sc, 200000, sII);
    EXPECT_TRUE(sI.broken() && sII.broken());
    EXPECT_NEAR(wI / 10.0, 1.0, 0.01) << "mode I, h = " << h;
    EXPECT_NEAR(wII / 50.0, 1.0, 0.01) << "mode II, h = " << h;
  }
}

TEST(Joint, DamageNeverHealsAndMixedModeAddsUp) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  JointState st;
  const double d = L.dn_peak + 0.5 * (L.dn_crit - L.dn_peak);
  const double peak = JointTractionAt(L, d, 0, st).sigma;
  // unloading to the peak opening keeps D = 0.5: the traction is z(0.5) f_t, not f_t
  const JointTraction back = JointTractionAt(L, L.dn_peak, 0, st);
  EXPECT_NEAR(back.D, 0.5, 1e-12);
  EXPECT_NEAR(back.sigma, JointSoftening(0.5) * 1e6, 1e6 * 6e-8); // z(D) is kept as a float (JointState::softening)
  EXPECT_NEAR(back.sigma, peak, 1e-3); // same damage, both beyond the hardening branch
  // mode I and II damage of 0.6 each combine to sqrt(0.72)
  double sp, sc;
  JointSlipLimits(L, 0, &sp, &sc);
  JointState m;
  const JointTraction t = JointTractionAt(L, L.dn_peak + 0.6 * (L.dn_crit - L.dn_peak), sp + 0.6 * (sc - sp), m);
  EXPECT_NEAR(t.D, std::sqrt(0.72), 1e-12);
}

TEST(Joint, CompressionRaisesTheShearStrengthByMohrCoulomb) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  const double dn = -0.5 * L.dn_peak; // sigma = -f_t
  double sp, sc;
  JointSlipLimits(L, -1e6, &sp, &sc);
  JointState st;
  const JointTraction t = JointTractionAt(L, dn, sp, st);
  EXPECT_NEAR(t.sigma, -1e6, 1e-6);
  EXPECT_NEAR(t.tau, 3e6 + 1e6 * std::tan(M_PI / 6), 1e-3); // c - sigma tan(phi)
  EXPECT_EQ(st.D, 0);
}

// The energy split: along any path, the work done on a joint point equals its stored
// energy plus the sum of the dissipated energy of its evaluations. Paths: pure mode I
// and II to rupture (all of G is dissipated, nothing stored), an opening with unloading
// and reloading, and a mixed path with compression and slip.
namespace {
struct PathEnergy {
  double work = 0, dissipated = 0, stored = 0;
};
PathEnergy Walk(const JointLaw &L, double (*path)(double, double *), int n) {
  PathEnergy e;
  JointState st;
  double     s_prev = 0, dn_prev = path(0, &s_prev), sig_prev = 0, tau_prev = 0;
  {
    const JointTraction t0 = JointTractionAt(L, dn_prev, s_prev, st); // the first separation (0 on most paths)
    sig_prev = t0.sigma, tau_prev = t0.tau, e.dissipated = t0.dissipated;
    e.stored = JointStoredEnergy(L, dn_prev, s_prev, st);
  }
  for (int i = 1; i <= n; ++i) {
    double              s;
    const double        dn = path((double)i / n, &s);
    const JointTraction t  = JointTractionAt(L, dn, s, st);
    e.work += 0.5 * (sig_prev + t.sigma) * (dn - dn_prev) + 0.5 * (tau_prev + t.tau) * (s - s_prev);
    e.dissipated += t.dissipated;
    dn_prev = dn, s_prev = s, sig_prev = t.sigma, tau_prev = t.tau;
  }
  e.stored = JointStoredEnergy(L, dn_prev, s_prev, st) - e.stored; // the change from the first separation
  return e;
}
const JointLaw &Law() {
  static const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  return L;
}
} // namespace

TEST(Joint, EnergyOfModeIAndIIToRuptureIsDissipatedAsG) {
  const JointLaw &L = Law();
  double          sp, sc;
  JointSlipLimits(L, 0, &sp, &sc);
  static double crit_n, crit_s;
  crit_n = L.dn_crit, crit_s = sc;
  const PathEnergy I  = Walk(L, [](double u, double *s) { *s = 0; return 1.05 * crit_n * u; }, 20000);
  const PathEnergy II = Walk(L, [](double u, double *s) { *s = 1.05 * crit_s * u; return 0.0; }, 20000);
  EXPECT_NEAR(I.dissipated, L.GI, 1e-3 * L.GI);
  EXPECT_NEAR(II.dissipated, L.GII, 1e-3 * L.GII);
  EXPECT_EQ(I.stored, 0); // broken: nothing stored
  EXPECT_EQ(II.stored, 0);
  EXPECT_NEAR(I.work, L.GI, 1e-3 * L.GI);
}

TEST(Joint, WorkIsStoredPlusDissipatedAlongUnloadingAndMixedPaths) {
  const JointLaw &L = Law();
  static double   pk, cr;
  pk = L.dn_peak, cr = L.dn_crit;
  // open to 40% of the softening, close to -half the peak (compression), reopen to 70%
  auto open_close = [](double u, double *s) {
    *s = 0;
    const double a = pk + 0.4 * (cr - pk), b = -0.5 * pk, c = pk + 0.7 * (cr - pk);
    return u < 1.0 / 3 ? 3 * u * a : u < 2.0 / 3 ? a + (b - a) * (3 * u - 1) : b + (c - b) * (3 * u - 2);
  };
  const PathEnergy e1 = Walk(L, open_close, 30000);
  EXPECT_GT(e1.dissipated, 0.2 * L.GI);
  EXPECT_GT(e1.stored, 0);
  EXPECT_NEAR(e1.work, e1.stored + e1.dissipated, 1e-3 * e1.work);
  // slip and opening together, to rupture: mixed-mode damage
  auto mixed = [](double u, double *s) {
    *s = 1.3 * cr * u * u;
    return 0.8 * cr * u;
  };
  const PathEnergy e2 = Walk(L, mixed, 40000);
  EXPECT_EQ(e2.stored, 0);
  EXPECT_NEAR(e2.work, e2.dissipated, 1e-3 * e2.work);
  // the stored energy's derivatives are the tractions at fixed damage and shear damage, under
  // compression too (the shear strength follows it only through the shear damage's growth)
  JointState st;
  (void)JointTractionAt(L, pk + 0.3 * (cr - pk), 0.5 * pk, st); // damage 0.3
  for (double dn : {-0.4 * pk, 0.5 * pk, 1.5 * pk}) {
    for (double s : {0.0, 0.3 * pk, 2.0 * pk}) {
      const double        h = 1e-6 * pk;
      JointState          a = st;
      const JointTraction t = JointTractionAt(L, dn, s, a);
      ASSERT_EQ(a.D, st.D) << "inside the damage surface";
      const double dtau = (JointStoredEnergy(L, dn, s + h, a) - JointStoredEnergy(L, dn, s - h, a)) / (2 * h);
      EXPECT_NEAR(dtau, t.tau, 1e-6 * L.c) << "dn " << dn << " s " << s;
      const double dsig = (JointStoredEnergy(L, dn + h, s, a) - JointStoredEnergy(L, dn - h, s, a)) / (2 * h);
      EXPECT_NEAR(dsig, t.sigma, 1e-6 * L.ft) << "dn " << dn << " s " << s;
    }
  }
}

// The balance of a step: an explicit scheme takes the tractions' work over a step as the
// trapezoidal rule, and the dissipated energy of a step is the release at the step's mean
// separation, so that work - stored - dissipated shrinks with the square of the step along any
// path (with the release at the step's end it shrinks only with the step: a scene's balance
// then drifts by a first-order error while its joints soften). Coarse walks of n and 2n steps
// to rupture in mode I, in mode II, mixed, with unloading and reloading, and below the peaks
// with a slip that comes and goes under a compression that varies (the shear strength, and so
// the hardening branch of the shear damage, follows it: the branch's integral at the strength
// of the step's end was first order there). The walk starts from the stored energy at its
// first separation.
TEST(Joint, WorkIsStoredPlusDissipatedToSecondOrderInTheStep) {
  const JointLaw &L = Law();
  double          sp, sc;
  JointSlipLimits(L, 0, &sp, &sc);
  static double pk, cr, crs;
  pk = L.dn_peak, cr = L.dn_crit, crs = sc;
  double (*paths[5])(double, double *) = {
      [](double u, double *s) { *s = 0; return 1.05 * cr * u; },
      [](double u, double *s) { *s = 1.05 * crs * u; return 0.0; },
      [](double u, double *s) { *s = 1.3 * cr * u * u; return 0.8 * cr * u; },
      [](double u, double *s) {
        *s = 0.2 * pk * u;
        const double a = pk + 0.4 * (cr - pk), b = 0.5 * pk, c = pk + 0.9 * (cr - pk);
        return u < 1.0 / 3 ? 3 * u * a : u < 2.0 / 3 ? a + (b - a) * (3 * u - 1) : b + (c - b) * (3 * u - 2);
      },
      [](double u, double *s) {
        *s = 0.9 * (2 * 0.01 * 3e6 / 1e10) * u * (1 + 0.5 * std::sin(4 * M_PI * u)); // below the shear peak of c alone
        return -pk * (1.0 + 0.8 * std::sin(6 * M_PI * u));
      }};
  const char *names[5] = {"mode I", "mode II", "mixed", "unload and reload", "slip under a varying compression"};
  for (int k = 0; k < 5; ++k) {
    double prev = 0;
    for (int n : {60, 120, 240}) {
      const PathEnergy e   = Walk(L, paths[k], n);
      const double     err = std::fabs(e.work - e.stored - e.dissipated);
      EXPECT_LT(err, 5e-3 * e.work) << names[k] << ", " << n << " steps";
      if (prev > 0) EXPECT_GT(prev / err, 3.0) << names[k] << ": the error must shrink as the step squared, from " << prev << " to " << err << " J/m^2 at " << n << " steps";
      prev = err;
    }
  }
}

// The same through the block kernel's common path (JointElementForces: undamaged points below
// both peaks run two joints an instruction, apart from JointTractionAt): a joint element whose
// face B slides over A under a compression that varies, the work done on it (against the
// forces on B's nodes, A held) summed by the trapezoidal rule.
TEST(Joint, ElementWorkIsStoredPlusDissipatedToSecondOrderInTheStep) {
  const JointLaw &L  = Law();
  const double    h  = 0.01, sp0 = 2 * h * L.c / L.penalty, pk = L.dn_peak;
  const double    xa[3][3] = {{0, 0, 0}, {h, 0, 0}, {0, h, 0}}; // normal +z, towards B
  double          prev = 0;
  for (int n : {60, 120, 240}) {
    JointState st[3];
    double     work = 0, diss = 0, stored0 = 0, fprev[3][3] = {}, dprev[3] = {};
    for (int i = 0; i <= n; ++i) {
      const double u = (double)i / n;
      const double d[3] = {0.9 * sp0 * u * (1 + 0.5 * std::sin(4 * M_PI * u)), 0, -pk * (1.0 + 0.8 * std::sin(6 * M_PI * u))};
      double       xb[3][3], fa[3][3] = {}, fb[3][3] = {};
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) xb[v][k] = xa[v][k] + d[k];
      JointElementForces(L, xa, xb, st, fa, fb, &diss);
      if (i == 0) stored0 = JointElementEnergy(L, xa, xb, st);
      else
        for (int v = 0; v < 3; ++v)
          for (int k = 0; k < 3; ++k) work -= 0.5 * (fprev[v][k] + fb[v][k]) * (d[k] - dprev[k]); // done on the joint: against fb
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) fprev[v][k] = fb[v][k];
      for (int k = 0; k < 3; ++k) dprev[k] = d[k];
      if (i == n) {
        for (const JointState &p : st) ASSERT_EQ(p.D, 0) << "the path stays below the peaks";
        const double err = std::fabs(work - (JointElementEnergy(L, xa, xb, st) - stored0) - diss);
        EXPECT_LT(err, 5e-3 * std::fabs(work)) << n << " steps";
        if (prev > 0) EXPECT_GT(prev / err, 3.0) << "the error must shrink as the step squared, from " << prev << " to " << err << " J at " << n << " steps";
        prev = err;
      }
    }
  }
}

// Mohr-Coulomb without an energy source: a closed cycle of opening and slip never gives back
// more work than it took. The cycle slides the joint free of compression, presses it (the
// shear strength rises by f_t tan(phi) per f_t of compression), slides it back under that
// pressure and releases it. The law tau = f_s h(s / s_peak) with the strength of the moment
// would return more on the way back than it took, (p/h)^2 S^3 / 12 (1/c - 1/f_s) per unit
// area; the secant keeps the softer stiffness it reached and returns less. Repeated cycles,
// and random closed loops below the peaks, each take at least what they give.
TEST(Joint, NoClosedCycleOfOpeningAndSlipCreatesEnergy) {
  const JointLaw &L = Law();
  double          sp0, sc0;
  JointSlipLimits(L, 0, &sp0, &sc0);
  const double S = 0.9 * sp0, press = -2.0 * L.dn_peak; // sigma = -4 f_t: f_s = c + 4 f_t tan(phi)
  auto corner = [&](int k, double *dn, double *s) {      // (0,0) -> (0,S) -> (press,S) -> (press,0) -> (0,0)
    const double P[5][2] = {{0, 0}, {0, S}, {press, S}, {press, 0}, {0, 0}};
    *dn = P[k][0], *s = P[k][1];
  };
  JointState st;
  double     dn = 0, s = 0, sig = 0, tau = 0;
  const int  n  = 4000;
  double     cycle_work[3] = {0, 0, 0}, diss = 0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 4; ++k) {
      double a0, s0, a1, s1;
      corner(k, &a0, &s0), corner(k + 1, &a1, &s1);
      for (int i = 1; i <= n; ++i) {
        const double        dn1 = a0 + (a1 - a0) * i / n, s1i = s0 + (s1 - s0) * i / n;
        const JointTraction t   = JointTractionAt(L, dn1, s1i, st);
        cycle_work[c] += 0.5 * (sig + t.sigma) * (dn1 - dn) + 0.5 * (tau + t.tau) * (s1i - s);
        diss += t.dissipated;
        dn = dn1, s = s1i, sig = t.sigma, tau = t.tau;
      }
    }
  EXPECT_EQ(st.D, 0) << "the cycle stays below the peaks";
  const double K = L.shear_stiffness, fs = L.c + 4.0 * L.ft * L.tan_phi;
  const double law_gain = K * K * S * S * S / 12.0 * (1.0 / L.c - 1.0 / fs); // what the law without the secant would create
  EXPECT_GT(law_gain, 1e-3 * (0.5 * K * S * S)) << "the cycle must be one that the plain law gains on";
  // the first cycle dissipates what raising the secant to w = x/2 = 0.45 cost, and stores nothing
  // back at the origin; the later cycles are elastic on that secant and take nothing
  EXPECT_GT(cycle_work[0], 0.5 * law_gain);
  // (the dissipated energy is counted at the end of each step, the work by the trapezoid: 1e-3 for 4000 steps a leg)
  EXPECT_NEAR(cycle_work[0], diss, 1e-3 * cycle_work[0]) << "back at the origin nothing is stored: the work is what was dissipated";
  for (int c = 1; c < 3; ++c) EXPECT_NEAR(cycle_work[c], 0, 1e-9 * cycle_work[0]) << "cycle " << c;
  // random closed loops through the origin (7 corners within and around the peaks), from
  // fresh and from damaged states: the joint stores nothing at the origin whatever its
  // history, so each loop's work is what it dissipated, and that is never negative
  unsigned seed = 12345;
  auto     u    = [&] { return (seed = seed * 1664525u + 1013904223u) / 4294967296.0; };
  for (int trial = 0; trial < 200; ++trial) {
    JointState q;
    if (trial % 2) (void)JointTractionAt(L, L.dn_peak + 0.2 * u() * (L.dn_crit - L.dn_peak), 0.5 * sp0, q);
    double pts[9][2] = {};
    for (int k = 1; k < 8; ++k) pts[k][0] = (-2.0 + 2.9 * u()) * L.dn_peak, pts[k][1] = 1.2 * sp0 * u();
    double        work = 0, d = 0, pd = 0, ps = 0;
    JointTraction prev = JointTractionAt(L, 0, 0, q);
    for (int k = 0; k < 8; ++k)
      for (int i = 1; i <= 400; ++i) {
        const double        dn1 = pts[k][0] + (pts[k + 1][0] - pts[k][0]) * i / 400, s1 = pts[k][1] + (pts[k + 1][1] - pts[k][1]) * i / 400;
        const JointTraction t   = JointTractionAt(L, dn1, s1, q);
        work += 0.5 * (prev.sigma + t.sigma) * (dn1 - pd) + 0.5 * (prev.tau + t.tau) * (s1 - ps);
        d += t.dissipated;
        pd = dn1, ps = s1, prev = t;
      }
    const double scale = 0.5 * L.shear_stiffness * sp0 * sp0; // the shear energy at the peak, J/m^2
    EXPECT_EQ(JointStoredEnergy(L, 0, 0, q), 0);
    EXPECT_GE(d, 0) << "trial " << trial;
    EXPECT_NEAR(work, d, 2e-3 * scale) << "trial " << trial;
    EXPECT_GE(work, -1e-3 * scale) << "trial " << trial << ": a closed loop gave back more than it took";
  }
}

TEST(Joint, BadInputIsNamed) {
  auto expect = [](JointMaterial m, double h, const std::string &text) {
    try {
      MakeJointLaw(m, h);
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError &e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  JointMaterial m = Mortar();
  m.tensile_strength = 0;
  expect(m, 0.01, "fracture material 'mortar': tensile_strength = 0 must be positive");
  m = Mortar(), m.GI = -1;
  expect(m, 0.01, "G_I = -1 must be positive");
  m = Mortar(), m.GII = NAN;
  expect(m, 0.01, "G_II = nan must be positive");
  m = Mortar(), m.friction_angle = 90;
  expect(m, 0.01, "friction_angle = 90 degrees must be in [0, 90)");
  m = Mortar(), m.penalty = 1e5; // peak opening 0.2 m for h = 0.01
  expect(m, 0.01, "joint_penalty = 100000 is too small for elements of size 0.01");
  expect(Mortar(), 0, "the element size h = 0 must be positive");
}

namespace {
// A right triangle of legs 0.1 m in the plane z = 0 (normal +z), B lifted by dz
// and shifted by dx; optionally everything rotated about x by angle.
void Pair(double dz, double dx, double angle, double xa[3][3], double xb[3][3]) {
  const double P[3][3] = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}};
  const double c = std::cos(angle), s = std::sin(angle);
  for (int i = 0; i < 3; ++i) {
    const double a[3] = {P[i][0], P[i][1], P[i][2]}, b[3] = {P[i][0] + dx, P[i][1], P[i][2] + dz};
    xa[i][0] = a[0], xa[i][1] = c * a[1] - s * a[2], xa[i][2] = s * a[1] + c * a[2];
    xb[i][0] = b[0], xb[i][1] = c * b[1] - s * b[2], xb[i][2] = s * b[1] + c * b[2];
  }
}
} // namespace

TEST(Joint, ElementForcesOfUniformOpeningAndSlip) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  const double area = 0.005;
  for (double angle : {0.0, 0.7}) {
    // mode I at half the peak opening: B pulled back by 0.75 f_t A along the normal
    double xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
    JointState st[3];
    Pair(0.5 * L.dn_peak, 0, angle, xa, xb);
    JointElementForces(L, xa, xb, st, fa, fb);
    double FB[3] = {0, 0, 0}, FA[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) FB[k] += fb[i][k], FA[k] += fa[i][k];
    const double nrm[3] = {0, -std::sin(angle), std::cos(angle)};
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(FB[k], -0.75e6 * area * nrm[k], 1e-6) << "angle " << angle;
      EXPECT_NEAR(FA[k] + FB[k], 0, 1e-9);
    }
    // mode II at the shear peak: tangential force c A opposing the slip (x)
    double ya[3][3], yb[3][3], ga[3][3] = {}, gb[3][3] = {};
    JointState s2[3];
    double sp, sc;
    JointSlipLimits(L, 0, &sp, &sc);
    Pair(0, sp, angle, ya, yb);
    JointElementForces(L, ya, yb, s2, ga, gb);
    double GB[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) GB[k] += gb[i][k];
    EXPECT_NEAR(GB[0], -3e6 * area, 1e-6);
    EXPECT_NEAR(GB[1], 0, 1e-6);
    EXPECT_NEAR(GB[2], 0, 1e-6);
  }
}

TEST(Joint, ElementForcesBalanceAndVanishForCoincidentFaces) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  // arbitrary separations: the forces on A and B cancel node by node
  double xa[3][3] = {{0, 0, 0}, {0.1, 0.01, 0}, {0.02, 0.1, 0.01}}, xb[3][3];
  const double d[3][3] = {{1e-7, -2e-7, 3e-7}, {-1e-7, 4e-7, 1e-6}, {2e-7, 1e-7, -5e-7}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) xb[i][k] = xa[i][k] + d[i][k];
  double fa[3][3] = {}, fb[3][3] = {};
  JointState st[3];
  JointElementForces(L, xa, xb, st, fa, fb);
  double mag = 0;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(fa[i][k] + fb[i][k], 0, 1e-12);
      mag += std::fabs(fa[i][k]);
    }
  EXPECT_GT(mag, 0);
  // coincident faces (an unloaded joint, however the body has moved): no force
  double ca[3][3] = {}, cb[3][3] = {};
  JointState s0[3];
  JointElementForces(L, xa, xa, s0, ca, cb);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(ca[i][k], 0);
}

namespace {
// Triangle A in the plane z = 0 (area 0.005 m^2, normal +z) and B above it, vertex i of B
// at height dz[i]: an opening that varies linearly over the face.
void Hinge(const double dz[3], double xa[3][3], double xb[3][3]) {
  const double a[3][3] = {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) xa[i][k] = a[i][k], xb[i][k] = a[i][k] + (k == 2 ? dz[i] : 0.0);
}
} // namespace

// A joint hinged about a line across its face (a crack opening on one side while a corner is
// pressed in) with two of its points broken: every midpoint is open, so a penalty taken at the
// midpoints lets the corner pass through B unresisted, and the contact engine finds the overlap
// when the joint breaks through (doc/fracture.md, "Broken joints"). The compression is the exact
// integral of the penalty's energy over the part of the face pressed in: the corner is pushed
// back, the forces are the gradient of JointElementEnergy along a path that closes the hinge,
// nothing changes when a point breaks, and a face pressed in all over gets the midpoints' forces.
TEST(Joint, HingedJointResistsItsPressedCornerOverTheFace) {
  JointLaw L         = MakeJointLaw(Mortar(), 0.01);
  L.face_compression = 1;
  const double   d = 0.1 * L.dn_peak, A = 0.005, w = A / 3, k = L.penalty / L.h; // corner depth, area, weight of a point, p / h
  JointState     st[3];
  st[0].SetDamage(1), st[2].SetDamage(1); // edges (0,1) and (2,0) broken; (1,2) holds
  const double dz[3] = {-d, 2 * d, 2 * d};                   // midpoints open: d/2, 2d, d/2
  double       xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
  Hinge(dz, xa, xb);
  JointState s[3] = {st[0], st[1], st[2]};
  JointElementForces(L, xa, xb, s, fa, fb);
  // the pressed part is the triangle at vertex 0 cut at a third of its edges: int g N_0 dA = 10 A d / 324
  EXPECT_NEAR(fb[0][2], k * 10 * A * d / 324, 1e-3 * k * A * d / 32); // B's corner pushed back up
  EXPECT_NEAR(fa[0][2], -fb[0][2], 1e-12);
  EXPECT_NEAR(JointElementEnergy(L, xa, xb, s), k / 2 * A * d * d / 54 + w * L.ft * L.dn_peak * (0.04 - 0.008 / 3), 1e-3 * k * A * d * d / 108);
  // work = - change of energy along a path from the open hinge to a corner pressed in by 2d
  const int n    = 2000;
  double    work = 0, fprev = 0, e0 = 0, e1 = 0;
  for (int m = 0; m <= n; ++m) {
    const double z   = 2 * d - 4 * d * m / n;
    const double p[3] = {z, 2 * d, 2 * d};
    double       ya[3][3], yb[3][3], ga[3][3] = {}, gb[3][3] = {};
    JointState   c[3] = {st[0], st[1], st[2]};
    Hinge(p, ya, yb);
    JointElementForces(L, ya, yb, c, ga, gb);
    if (m > 0) work += 0.5 * (fprev + gb[0][2]) * (-4 * d / n);
    fprev = gb[0][2];
    if (m == 0) e0 = JointElementEnergy(L, ya, yb, c);
    if (m == n) e1 = JointElementEnergy(L, ya, yb, c);
  }
  EXPECT_GT(e1 - e0, 0);
  EXPECT_NEAR(work, -(e1 - e0), 2e-3 * (e1 - e0));
  // the compression does not change when a point breaks: an intact joint pressed in at a corner
  // stores what the same joint with two broken points stores (neither has tension or slip)
  const double q[3] = {-d, 0, 0};
  double       za[3][3], zb[3][3];
  Hinge(q, za, zb);
  JointState intact[3];
  EXPECT_NEAR(JointElementEnergy(L, za, zb, intact), JointElementEnergy(L, za, zb, st), 1e-12 * k * A * d * d);
  EXPECT_NEAR(JointElementEnergy(L, za, zb, intact), k / 2 * A * d * d / 6, 1e-6 * k * A * d * d);
  // a face pressed in all over: the forces of the penalty at the midpoints, (A/12) (p/h) (2 g_i + g_j + g_k)
  const double r[3] = {-d, -2 * d, -3 * d};
  double       ra[3][3], rb[3][3], ha[3][3] = {}, hb[3][3] = {};
  Hinge(r, ra, rb);
  JointState fresh[3];
  JointElementForces(L, ra, rb, fresh, ha, hb);
  const double g[3] = {d, 2 * d, 3 * d};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(hb[i][2], A / 12 * k * (g[i] + g[0] + g[1] + g[2]), 1e-3 * A / 12 * k * d) << "vertex " << i;
}

// A joint that breaks through under compression (its last point torn open while a broken
// corner is pressed in) is removed, and its faces become contact surfaces: the compression its
// broken points kept goes with it. At the evaluation where it breaks, the energy it stored at
// that position is all dissipated (the opened point's by its damage, the compression by the
// removal), so nothing vanishes from the balance; afterwards it stores and dissipates nothing.
// With the compression left out of the dissipated energy (as before), the check fails by it.
TEST(Joint, BreakingThroughDissipatesTheCompressionItKept) {
  for (int rule : {1, 0}) { // the face rule (the default) and the midpoints' rule
    JointLaw L         = MakeJointLaw(Mortar(), 0.01);
    L.face_compression = rule;
    const double D = 10 * L.dn_peak, big = 4 * L.dn_crit + 3 * D;
    JointState   st[3];
    st[0].SetDamage(1), st[2].SetDamage(1); // edges (0,1) and (2,0) broken; (1,2) holds
    // edge (0,1) pressed in by D at its midpoint, edge (1,2) torn open beyond the critical opening
    const double dz[3] = {-D, -D, big};
    double       xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
    Hinge(dz, xa, xb);
    const double before = JointElementEnergy(L, xa, xb, st);
    const double kept   = JointRemovedCompression(L, xa, xb);
    EXPECT_GT(kept, 0.2 * before) << "rule " << rule; // the compression is a large part of it
    double     diss = 0;
    JointState s[3] = {st[0], st[1], st[2]};
    JointElementForces(L, xa, xb, s, fa, fb, &diss);
    ASSERT_TRUE(JointBroken(s)) << "rule " << rule;
    EXPECT_EQ(JointElementEnergy(L, xa, xb, s), 0);
    EXPECT_NEAR(diss, before, 1e-3 * before) << "rule " << rule << ": kept " << kept;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(fa[i][k], 0);
        EXPECT_EQ(fb[i][k], 0);
      }
    const double again = diss; // broken already: nothing more
    JointElementForces(L, xa, xb, s, fa, fb, &diss);
    EXPECT_EQ(diss, again);
    // the compression it would keep is that of the joint with its last point pressed in too
    const double shut[3] = {-D, -D, 0};
    Hinge(shut, xa, xb);
    JointState all[3];
    for (auto &p : all) p.SetDamage(1);
    EXPECT_EQ(JointElementEnergy(L, xa, xb, all), 0);
    JointState two[3] = {st[0], st[1], st[2]};
    EXPECT_NEAR(JointRemovedCompression(L, xa, xb), JointElementEnergy(L, xa, xb, two), 1e-6 * kept) << "rule " << rule;
  }
}

// A joint inserted into a stressed body starts at the separation whose tractions are its
// face's: the law evaluated there gives back the normal and shear tractions asked for, over
// tension, compression and shear up to the peaks, and a traction beyond a peak is taken at it.
TEST(Joint, SeparationForATractionGivesItBack) {
  const JointLaw L = MakeJointLaw(Mortar(), 0.01);
  const double   tan_phi = std::tan(30 * M_PI / 180);
  int            checked = 0;
  for (double sn : {-5e6, -1e6, -1e3, 0.0, 1e-3, 0.3e6, 0.7e6, 0.999e6}) {
    const double fs = 3e6 - std::min(sn, 0.0) * tan_phi;
    for (double share : {0.0, 1e-9, 0.2, 0.6, 0.95}) {
      const double tau = share * fs;
      double       dn, s;
      JointSeparationFor(L, sn, tau, &dn, &s);
      JointState         st;
      const JointTraction t = JointTractionAt(L, dn, s, st);
      EXPECT_NEAR(t.sigma, sn, 1e-9 * 1e6) << "sigma " << sn << " tau " << tau;
      EXPECT_NEAR(t.tau, tau, 1e-7 * fs) << "sigma " << sn << " tau " << tau; // w is a float
      EXPECT_EQ(t.D, 0);
      EXPECT_EQ(t.dissipated == 0, tau == 0); // the secant's step at the first evaluation
      EXPECT_GE(s, 0);
      EXPECT_EQ(dn > 0, sn > 0);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 40);
  // beyond the peaks: at the peaks
  double dn, s;
  JointSeparationFor(L, 2e6, 0, &dn, &s);
  EXPECT_DOUBLE_EQ(dn, L.dn_peak);
  JointSeparationFor(L, 0, 7e6, &dn, &s);
  double sp;
  JointSlipLimits(L, 0, &sp, nullptr);
  EXPECT_DOUBLE_EQ(s, sp);
  // small tractions keep their relative accuracy (no cancellation in the branch's inverse)
  JointSeparationFor(L, 1e-6, 0, &dn, &s);
  EXPECT_NEAR(dn, 0.5 * 1e-12 * L.dn_peak, 1e-12 * 1e-12 * L.dn_peak);
}
