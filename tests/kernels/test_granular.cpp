// Tests of the granular contact laws (include/fdem/kernels/granular.hpp)
// against closed-form impact solutions.
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/granular.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace fdem::kernels;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Impact {
  double peak_force = 0, contact_time = 0;
  double vn_out = 0, vt_out = 0, w_out = 0; // exit normal and tangential speed, spin
};

// A sphere (radius R, mass m, moment of inertia 2/5 m R^2) hits a fixed wall
// z = 0 with velocity (vt0, 0, -vn0) and spin w0 about y. Velocity Verlet
// with the force evaluated at the half-step velocity, nsteps per nominal
// contact time tc.
Impact HitWall(const GranularPair &p, double R, double m, double vn0, double vt0, double w0, double tc, int nsteps = 4000) {
  const double dt = tc / nsteps, I = 0.4 * m * R * R;
  double z = R, x = 0, vz = -vn0, vx = vt0, w = w0;
  Vec3 shear;
  Impact out;
  bool touched = false;
  double t_in = 0;
  double fz = 0, fx = 0, torque = 0;
  for (int i = 0; i < 50 * nsteps; ++i) {
    vz += 0.5 * dt * fz / m;
    vx += 0.5 * dt * fx / m;
    w += 0.5 * dt * torque / I;
    z += dt * vz;
    x += dt * vx;
    fz = fx = torque = 0;
    const double overlap = R - z;
    if (overlap > 0) {
      if (!touched) t_in = i * dt;
      touched = true;
      GranularContact c;
      c.n = {0, 0, 1};
      c.overlap = overlap;
      // contact point at -R n: velocity v + w x (-R n); w = (0, w, 0)
      c.vrel = Vec3{vx, 0, vz} + cross(Vec3{0, w, 0}, Vec3{0, 0, -R});
      c.wrel = {0, w, 0};
      c.rstar = R;
      c.mstar = m;
      const GranularResult r = GranularForce(p, c, dt, shear);
      const Vec3 f = r.fn + r.ft;
      fz = f.z;
      fx = f.x;
      torque = cross(Vec3{0, 0, -R}, f).y + r.mroll.y;
      out.peak_force = std::fmax(out.peak_force, norm(r.fn));
    } else if (touched) {
      out.contact_time = i * dt - t_in;
      break;
    }
    vz += 0.5 * dt * fz / m;
    vx += 0.5 * dt * fx / m;
    w += 0.5 * dt * torque / I;
  }
  out.vn_out = vz;
  out.vt_out = vx;
  out.w_out = w;
  return out;
}

GranularMaterial Glass() {
  GranularMaterial g;
  g.law = GranularLaw::Hertz;
  g.law_set = true;
  g.young = 5e9;
  g.poisson = 0.25;
  g.restitution = 1.0;
  g.has_restitution = true;
  return g;
}

} // namespace

TEST(Granular, HookeRestitutionAndContactTimeMatchTheSpringDashpot) {
  GranularPair p;
  p.law = GranularLaw::Hooke;
  const double m = 2.0, kn = 1e5;
  p.kn = kn;
  p.gamma_n = HookeDampingForRestitution(0.6, kn, m);
  EXPECT_NEAR(HookeRestitution(kn, p.gamma_n, m), 0.6, 1e-14);
  const double tc = HookeContactTime(kn, p.gamma_n, m);
  for (double v : {0.1, 3.0}) {
    const Impact im = HitWall(p, 0.1, m, v, 0, 0, tc);
    EXPECT_NEAR(im.vn_out / v, 0.6, 2e-3) << "v " << v;
    EXPECT_NEAR(im.contact_time / tc, 1.0, 1e-3) << "v " << v;
  }
}

TEST(Granular, HertzElasticImpactMatchesHertzTheory) {
  const GranularPair p = MixGranular(Glass(), Glass(), "glass-glass");
  EXPECT_DOUBLE_EQ(p.estar, 5e9 / (2 * (1 - 0.25 * 0.25)));
  EXPECT_EQ(p.alpha, 0.0);
  const double R = 0.005, m = 2500 * 4.0 / 3.0 * kPi * R * R * R, v = 1.0;
  // A sphere on a wall of the same material: R* = R, m* = m.
  const double tc = HertzContactTime(p.estar, R, m, v), fmax = HertzPeakForce(p.estar, R, m, v);
  const Impact im = HitWall(p, R, m, v, 0, 0, tc);
  EXPECT_NEAR(im.peak_force / fmax, 1.0, 1e-4);
  EXPECT_NEAR(im.contact_time / tc, 1.0, 1e-3);
  EXPECT_NEAR(im.vn_out / v, 1.0, 1e-6);
}

TEST(Granular, HertzRestitutionIsReproducedAtEverySpeed) {
  for (double e : {0.3, 0.8}) {
    GranularMaterial g = Glass();
    g.restitution = e;
    const GranularPair p = MixGranular(g, g, "glass-glass");
    EXPECT_NEAR(HertzRestitution(p.alpha), e, 1e-8);
    const double R = 0.005, m = 1e-3;
    for (double v : {0.01, 1.0, 10.0}) {
      const Impact im = HitWall(p, R, m, v, 0, 0, HertzContactTime(p.estar, R, m, v));
      EXPECT_NEAR(im.vn_out / v, e, 2e-3) << "e " << e << " v " << v;
    }
  }
}

// Oblique elastic impact in gross sliding (small friction, large incidence
// angle): the tangential impulse is mu times the normal impulse 2 m vn, so
// vt' = vt - 2 mu vn and, friction acting along -x at the contact point
// (0, 0, -R), the spin about +y grows: w' = w + 5 mu vn / R. (With normal
// damping the dashpot pulls at the end of contact and the Coulomb limit,
// mu |Fn|, integrates to more than mu (1 + e) m vn, as in LAMMPS.)
TEST(Granular, ObliqueSlidingImpactMatchesTheCoulombImpulse) {
  GranularPair p;
  p.law = GranularLaw::Hooke;
  const double m = 1.0, R = 0.1, kn = 1e6, mu = 0.1;
  p.kn = kn;
  p.kt = 2.0 / 7.0 * kn;
  p.mu = mu;
  const double vn = 1.0, vt = 2.0, w0 = 3.0;
  const Impact im = HitWall(p, R, m, vn, vt, w0, HookeContactTime(kn, 0, m), 20000);
  EXPECT_NEAR(im.vn_out, vn, 1e-6);
  EXPECT_NEAR(im.vt_out, vt - 2 * mu * vn, 1e-4);
  EXPECT_NEAR(im.w_out, w0 + 5 * mu * vn / R, 1e-3);
}

TEST(Granular, StuckSpringIsLinearAndSlidingIsCappedAtCoulomb) {
  GranularPair p;
  p.law = GranularLaw::Hooke;
  p.kn = 1000;
  p.kt = 400;
  p.mu = 0.5;
  GranularContact c{{0, 0, 1}, 0.01, {0.1, 0, 0}, {}, 1.0, 1.0};
  Vec3 shear;
  GranularResult r = GranularForce(p, c, 1e-3, shear); // shear 1e-4: force 0.04 < 0.5 * 10
  EXPECT_FALSE(r.sliding);
  EXPECT_NEAR(r.ft.x, -0.04, 1e-15);
  EXPECT_NEAR(r.fn.z, 10.0, 1e-15);
  c.vrel = {100, 0, 0};
  r = GranularForce(p, c, 1.0, shear); // spring far past the limit
  EXPECT_TRUE(r.sliding);
  EXPECT_NEAR(norm(r.ft), 5.0, 1e-12);
  EXPECT_NEAR(400 * shear.x, 5.0, 1e-12); // history cut back to the limit
  // History is kept in the tangent plane when the normal turns.
  c.n = {0, 1, 0};
  c.vrel = {};
  r = GranularForce(p, c, 1.0, shear);
  EXPECT_EQ(dot(shear, c.n), 0.0);
}

TEST(Granular, RollingResistanceOpposesRollingWithConstantTorque) {
  GranularPair p;
  p.law = GranularLaw::Hooke;
  p.kn = 1000;
  p.mu_roll = 0.02;
  GranularContact c{{0, 0, 1}, 0.01, {}, {3, 0, 7}, 0.5, 1.0};
  Vec3 shear;
  const GranularResult r = GranularForce(p, c, 1e-3, shear);
  // Twist about the normal is not rolling; |M| = mu_r R* |Fn| against w.
  EXPECT_NEAR(r.mroll.x, -0.02 * 0.5 * 10.0, 1e-15);
  EXPECT_EQ(r.mroll.y, 0.0);
  EXPECT_EQ(r.mroll.z, 0.0);
}

// Near rest the rolling torque is bounded by what stops the rolling within the step for a
// rotational inertia 0.4 m* R*^2: a rolling of round-off size gets a torque of round-off size
// (not the full mu_r R* |Fn| in a direction set by round-off), and never one that reverses it.
TEST(Granular, RollingTorqueNearRestIsBoundedByTheStep) {
  GranularPair p;
  p.law     = GranularLaw::Hooke;
  p.kn      = 1000;
  p.mu_roll = 0.02;
  const double dt = 1e-3, mstar = 1.0, rstar = 0.5, full = 0.02 * 0.5 * 10.0; // mu_r R* |Fn|
  for (double w : {3.0, 1e-2, 1e-6, 1e-18}) {
    GranularContact c{{0, 0, 1}, 0.01, {}, {w, 0, 7}, rstar, mstar};
    Vec3            shear;
    const GranularResult r   = GranularForce(p, c, dt, shear);
    const double         cap = kRollingInertia * mstar * rstar * rstar * w / dt;
    EXPECT_NEAR(r.mroll.x, -std::min(full, cap), 1e-15 * full) << "rolling " << w;
    EXPECT_LE(std::fabs(r.mroll.x) * dt, kRollingInertia * mstar * rstar * rstar * w * (1 + 1e-15)) << "rolling " << w;
  }
}

TEST(Granular, MixingRule) {
  GranularMaterial a = Glass(), b = Glass();
  a.restitution = 0.9;
  b.restitution = 0.4;
  a.friction = 0.3;
  a.has_friction = true;
  b.has_friction = false; // a rigid body's material without granular keys
  b.has_restitution = true;
  b.young = 2e11;
  b.poisson = 0.3;
  b.law_set = false;
  const GranularPair p = MixGranular(a, b, "glass-steel");
  EXPECT_EQ(p.law, GranularLaw::Hertz);
  EXPECT_DOUBLE_EQ(p.mu, 0.3);
  EXPECT_NEAR(HertzRestitution(p.alpha), 0.6, 1e-8);
  EXPECT_DOUBLE_EQ(p.estar, 1.0 / ((1 - 0.0625) / 5e9 + (1 - 0.09) / 2e11));
  EXPECT_DOUBLE_EQ(p.gstar, 1.0 / (2 * 1.75 * 1.25 / 5e9 + 2 * 1.7 * 1.3 / 2e11));

  GranularMaterial h;
  h.law = GranularLaw::Hooke;
  h.law_set = true;
  h.kn = 2000;
  h.kt = 2000.0 * 2 / 7;
  h.gamma_n = 50;
  const GranularPair q = MixGranular(h, h, "chute");
  EXPECT_DOUBLE_EQ(q.kn, 2000);
  EXPECT_DOUBLE_EQ(q.gamma_n, 50);
  EXPECT_EQ(q.gamma_t, 0.0);

  try {
    MixGranular(a, h, "glass-chute");
    FAIL() << "no error";
  } catch (const InputError &err) {
    EXPECT_EQ(std::string(err.what()),
              "granular contact glass-chute: the two materials name different contact laws (hertz and hooke)");
  }
  a.restitution = 1.5;
  try {
    MixGranular(a, a, "bad");
    FAIL() << "no error";
  } catch (const InputError &err) {
    EXPECT_EQ(std::string(err.what()), "granular contact bad: restitution 1.500000 is not in (0, 1]");
  }
}

namespace {
// Two equal spheres (radius R, mass m, I = 2/5 m R^2) pressed together by forces F0 along the
// line of their centres, at rest at the overlap delta_eq F0 holds, are given a small relative
// velocity, normal and tangential (equal spins and opposite sideways velocities: no angular
// momentum, so the pair does not turn as a whole; sticking, mu is huge), and stepped nsteps times
// by central differences at dt (kick, drift, force at the half-step velocity, kick). Returns the
// largest deviation from the resting overlap or of the tangential spring, over 1e-3 delta_eq.
double PressedPairGrowth(const GranularPair &p, double R, double m, double delta_eq, double dt, int nsteps) {
  const double I = 0.4 * m * R * R, a = std::sqrt(0.5 * R * delta_eq);
  const double F0 = p.law == GranularLaw::Hooke ? p.kn * delta_eq : 4.0 / 3.0 * p.estar * std::sqrt(0.5 * R) * delta_eq * std::sqrt(delta_eq);
  const double u  = 1e-3 * delta_eq * (p.law == GranularLaw::Hooke ? std::sqrt(p.kn / m) : std::sqrt(2 * p.estar * a / m));
  Vec3 xa{0, 0, 0}, xb{2 * R - delta_eq, 0, 0}, va{u, -0.4 * u, 0}, vb{-u, 0.4 * u, 0}, wa{0, 0, u / R}, wb{0, 0, u / R}, fa, fb, ta, tb, shear;
  double worst = 0;
  for (int i = 0; i < nsteps; ++i) {
    va += (0.5 * dt / m) * fa, vb += (0.5 * dt / m) * fb, wa += (0.5 * dt / I) * ta, wb += (0.5 * dt / I) * tb;
    xa += dt * va, xb += dt * vb;
    const Vec3   d = xa - xb, n = (1.0 / norm(d)) * d;
    const double overlap = 2 * R - norm(d);
    fa = -F0 * n, fb = F0 * n, ta = tb = {};
    if (overlap > 0) {
      GranularContact c;
      c.n       = n;
      c.overlap = overlap;
      c.vrel    = (va + cross(wa, -R * n)) - (vb + cross(wb, R * n));
      c.wrel    = wa - wb;
      c.rstar   = 0.5 * R;
      c.mstar   = 0.5 * m;
      const GranularResult r = GranularForce(p, c, dt, shear);
      const Vec3           f = r.fn + r.ft;
      fa += f, fb -= f;
      ta = cross(-R * n, f) + r.mroll, tb = cross(R * n, -f) - r.mroll;
    }
    va += (0.5 * dt / m) * fa, vb += (0.5 * dt / m) * fb, wa += (0.5 * dt / I) * ta, wb += (0.5 * dt / I) * tb;
    worst = std::fmax(worst, std::fmax(std::fabs(overlap - delta_eq), norm(shear)));
    if (!(worst < 1e3 * delta_eq)) break;
  }
  return worst / (1e-3 * delta_eq);
}
} // namespace

// GranularStableOmega bounds the step: 10% below 2 / omega a pressed pair of spheres oscillates
// with a bounded amplitude, 10% above it the oscillation grows without bound. Hooke with
// kt = 2/7 kn has equal normal and tangential frequencies sqrt(kn / m*); Hertz-Mindlin's
// tangential spring, 8 G* a against 2 E* a, is the faster one (the spin makes the contact point
// 3.5 times as mobile); damping lowers the limit to 2 (sqrt(1 + zeta^2) - zeta) / omega.
TEST(Granular, StableOmegaBoundsTheStepOfAPressedPair) {
  const double R = 0.01, m = 2500 * 4.0 / 3.0 * kPi * R * R * R;
  GranularPair hooke;
  hooke.law = GranularLaw::Hooke;
  hooke.kn  = 1e5;
  hooke.kt  = 2.0 / 7.0 * hooke.kn;
  hooke.mu  = 1e9;
  EXPECT_NEAR(GranularStableOmega(hooke, m, R), std::sqrt(hooke.kn / (0.5 * m)), 1e-9 * std::sqrt(hooke.kn / (0.5 * m)));
  GranularPair hooke_damped = hooke;
  hooke_damped.gamma_n      = HookeDampingForRestitution(0.5, hooke.kn, 0.5 * m);
  hooke_damped.gamma_t      = 0.5 * hooke_damped.gamma_n;
  GranularMaterial g        = Glass();
  g.young                   = 5e8;
  g.friction                = 1e9;
  g.has_friction            = true;
  const GranularPair hertz  = MixGranular(g, g, "elastic");
  g.restitution             = 0.3;
  const GranularPair hertz_damped = MixGranular(g, g, "damped");
  const double       w_n          = std::sqrt(2 * hertz.estar * std::sqrt(0.5 * R * 0.01 * R) / (0.5 * m));
  EXPECT_NEAR(GranularStableOmega(hertz, m, R) / w_n, std::sqrt(3.5 * 4 * hertz.gstar / hertz.estar), 1e-12);
  for (const GranularPair *p : std::initializer_list<const GranularPair *>{&hooke, &hooke_damped, &hertz, &hertz_damped}) {
    const double w = GranularStableOmega(*p, m, R), delta_eq = 0.01 * R;
    EXPECT_LT(PressedPairGrowth(*p, R, m, delta_eq, 0.9 * 2 / w, 4000), 20.0) << "law " << (int)p->law << " alpha " << p->alpha << " gamma_n " << p->gamma_n;
    EXPECT_GT(PressedPairGrowth(*p, R, m, delta_eq, 1.1 * 2 / w, 4000), 1e3) << "law " << (int)p->law << " alpha " << p->alpha << " gamma_n " << p->gamma_n;
  }
  // the normal spring's undamped frequency alone would not do: Hertz-Mindlin's tangential spring
  // and Hooke's damping make a pair unstable below 2 / sqrt(kn / m*)
  EXPECT_GT(PressedPairGrowth(hertz, R, m, 0.01 * R, 0.9 * 2 / w_n, 4000), 1e3);
  EXPECT_GT(PressedPairGrowth(hooke_damped, R, m, 0.01 * R, 0.9 * 2 / std::sqrt(hooke.kn / (0.5 * m)), 4000), 1e3);
}

// A sphere of a clump: with no offset and a solid sphere's moment it is the sphere's own bound; an
// offset raises it as the contact point's mobility 1 + m d^2 / I (normal: d = offset; across:
// d = offset + radius), here for an undamped Hooke pair, where the bound is exactly sqrt(mobility k / m*).
TEST(Granular, StableOmegaOfAClumpSphereCountsItsLever) {
  GranularMaterial g;
  g.law     = GranularLaw::Hooke;
  g.law_set = true;
  g.kn      = 2.0e5;
  g.kt      = 2.0 / 7.0 * g.kn;
  const GranularPair p = MixGranular(g, g, "test");
  const double       m = 2.0, r = 0.01, I = 0.4 * m * r * r;
  EXPECT_NEAR(GranularStableOmega(p, m, r), GranularStableOmega(p, m, r, 0.0, I), 1e-14 * GranularStableOmega(p, m, r));
  EXPECT_NEAR(GranularStableOmega(p, m, r), std::sqrt(3.5 * p.kt / (0.5 * m)), 1e-12 * GranularStableOmega(p, m, r));
  const double d = 0.03, Ic = 1e-4; // a sphere 3 cm from the centre of mass of a clump of least moment 1e-4 kg m^2
  const double wn = std::sqrt((1 + m * d * d / Ic) * p.kn / (0.5 * m)), wt = std::sqrt((1 + m * (d + r) * (d + r) / Ic) * p.kt / (0.5 * m));
  EXPECT_NEAR(GranularStableOmega(p, m, r, d, Ic), std::max(wn, wt), 1e-12 * std::max(wn, wt));
  EXPECT_GT(GranularStableOmega(p, m, r, d, Ic), 2.5 * GranularStableOmega(p, m, r));
}
