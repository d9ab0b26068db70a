// Granular contact force laws between a sphere and another sphere, a wall or a
// surface point (doc/spheres.md): the linear spring-dashpot with tangential
// history (the same law and parameters as LAMMPS gran/hooke/history) and
// Hertz-Mindlin with damping from a coefficient of restitution, both with a
// Coulomb limit on the tangential spring and optional constant rolling
// resistance. Pure functions on doubles; no PETSc, no MPI.
#pragma once
#include "fdem/kernels/vec3.hpp"

#include <algorithm>
#include <cmath>

namespace fdem::kernels {

enum class GranularLaw { Hooke, Hertz };

// One granular material. Unset values are NaN (see MixGranular).
struct GranularMaterial {
  GranularLaw law = GranularLaw::Hertz;
  bool law_set = false;
  double young = 0, poisson = 0; // Pa, - (Hertz)
  double kn = 0, kt = 0;         // N/m (Hooke)
  double gamma_n = 0, gamma_t = 0; // 1/s (Hooke; multiplied by the effective mass)
  double restitution = 0;        // - in (0, 1]
  double friction = 0;           // Coulomb coefficient, -
  double rolling_friction = 0;   // rolling resistance coefficient, -
  bool has_restitution = false, has_friction = false, has_rolling = false;
};

// The parameters of one pair of materials, ready for GranularForce.
struct GranularPair {
  GranularLaw law = GranularLaw::Hooke;
  // Hooke: normal/tangential stiffness (N/m) and damping rates (1/s).
  double kn = 0, kt = 0, gamma_n = 0, gamma_t = 0;
  // Hertz: effective Young's and shear moduli E*, G* (Pa) and the damping
  // number alpha (gamma = alpha sqrt(m* S) with S the current stiffness),
  // chosen so that a head-on impact gives the pair's restitution.
  double estar = 0, gstar = 0, alpha = 0;
  double restitution = 1; // the pair's restitution (Hooke without gamma_n: the damping rate for it at each contact's m*)
  double mu = 0;     // Coulomb friction coefficient
  double mu_roll = 0; // rolling resistance coefficient
};

// The geometry and kinematics of one contact seen from body i.
struct GranularContact {
  Vec3 n;          // unit normal, from j towards i
  double overlap;  // > 0 when touching (m)
  Vec3 vrel;       // velocity of i's contact point minus j's (m/s)
  Vec3 wrel;       // angular velocity of i minus j (rad/s), for rolling
  double rstar;    // effective radius r_i r_j / (r_i + r_j) (r_i for a wall)
  double mstar;    // effective mass m_i m_j / (m_i + m_j) (m_i for a fixed j)
};

// The rotational inertia, in units of m* R*^2, that bounds the rolling torque of one step: a
// solid sphere's 2/5, no more than a pair of spheres' or a clump's (doc/spheres.md).
constexpr double kRollingInertia = 0.4;

struct GranularResult {
  Vec3 fn;     // normal force on i (N); j gets -fn
  Vec3 ft;     // tangential force on i at the contact point (N); j gets -ft
  Vec3 mroll;  // rolling resistance torque on i (N m); j gets -mroll
  bool sliding = false;
};

// The force on i for one time step dt. `shear` is the contact's tangential
// spring displacement (m), zero at first touch; it is advanced by the tangential
// relative velocity times dt, kept in the tangent plane and cut back at the
// Coulomb limit (as in LAMMPS gran/hooke/history). Caller applies fn + ft at
// the contact point: the torque on i is (c - x_i) x (fn + ft) + mroll.
// Requires overlap > 0 (no force is computed for a gap).
// (Defined inline below: it is the innermost call of the pair loops.)
GranularResult GranularForce(const GranularPair &p, const GranularContact &c, double dt, Vec3 &shear);

// The elastic energy of a contact (J): the normal spring's (Hooke 1/2 kn d^2, Hertz
// 8/15 E* a d^2 with a = sqrt(R* d)) and the tangential spring's (1/2 kt s.s, Hertz kt = 8 G* a).
// SphereContactSweep (granular_sweep.hpp) computes the same in its own loop.
inline double GranularElasticEnergy(const GranularPair &p, double overlap, double rstar, const Vec3 &s) {
  if (p.law == GranularLaw::Hooke) return 0.5 * p.kn * overlap * overlap + 0.5 * p.kt * dot(s, s);
  const double a = std::sqrt(rstar * overlap);
  return (8.0 / 15.0) * p.estar * a * overlap * overlap + 0.5 * 8.0 * p.gstar * a * dot(s, s);
}

// The pair parameters for materials a and b (mixing rule, doc/spheres.md):
// Hertz E*, G* from both materials' elastic constants; Hooke stiffnesses by the
// harmonic mean and damping rates by the geometric mean; restitution, friction
// and rolling friction by the geometric mean, a value missing on one side
// taken from the other. Throws InputError naming `what` if the laws differ,
// a needed value is missing on both sides or out of range.
GranularPair MixGranular(const GranularMaterial &a, const GranularMaterial &b, const char *what);

// Damping number alpha of the Hertz law that gives restitution e in a head-on
// impact (independent of the impact speed). alpha(1) = 0.
double HertzDampingForRestitution(double e);
// Restitution of a head-on Hertz impact with damping number alpha.
double HertzRestitution(double alpha);

// The damping rate gamma_n (1/s) of the Hooke law giving restitution e for
// normal stiffness kn and effective mass mstar; and the inverse.
double HookeDampingForRestitution(double e, double kn, double mstar);
double HookeRestitution(double kn, double gamma_n, double mstar);
// Duration of a head-on Hooke contact (overlap > 0), s.
double HookeContactTime(double kn, double gamma_n, double mstar);

// The frequency (rad/s) that bounds an explicit step for contacts between two equal
// spheres of this mass and radius with the pair's law: the larger of the normal
// spring's, sqrt(kn / m*), and the tangential spring's, sqrt(3.5 kt / m*) (the spin
// makes a solid sphere's contact point 1 + m r^2 / I = 3.5 times as mobile as its
// centre), each multiplied by zeta + sqrt(1 + zeta^2) for its damping ratio zeta (the
// central-difference limit of a damped oscillator, K = 2 (sqrt(1 + zeta^2) - zeta)).
// Hertz's stiffnesses are taken at an overlap of 1% of the radius.
// A sphere of a clump (offset: its centre's distance from the clump's centre of mass,
// inertia: the clump's least principal moment) turns its whole body: its contact point is
// 1 + m offset^2 / I times as mobile along the normal and 1 + m (offset + radius)^2 / I across
// it (inertia 0: a solid sphere, exactly 1 and 3.5).
double GranularStableOmega(const GranularPair &p, double mass, double radius, double offset = 0, double inertia = 0);

// Hertz's elastic head-on impact at relative speed v: peak force and contact
// duration for E*, R*, m*.
double HertzPeakForce(double estar, double rstar, double mstar, double v);
double HertzContactTime(double estar, double rstar, double mstar, double v);

// ---- inline definition ---------------------------------------------------
inline GranularResult GranularForce(const GranularPair &p, const GranularContact &c, double dt, Vec3 &shear) {
  GranularResult r;
  const double delta = c.overlap;
  const Vec3 vn = dot(c.vrel, c.n) * c.n;
  const Vec3 vt = c.vrel - vn;

  double kn_delta, cn, kt, ct; // elastic normal force, normal damping, tangential stiffness and damping
  if (p.law == GranularLaw::Hooke) {
    kn_delta = p.kn * delta;
    cn = c.mstar * p.gamma_n;
    kt = p.kt;
    ct = c.mstar * p.gamma_t;
  } else {
    const double a = std::sqrt(c.rstar * delta);  // contact radius
    const double sn = 2.0 * p.estar * a;           // dFn/d(delta)
    kn_delta = (2.0 / 3.0) * sn * delta;           // 4/3 E* sqrt(R*) delta^{3/2}
    cn = p.alpha * std::sqrt(c.mstar * sn);
    kt = 8.0 * p.gstar * a;
    ct = p.alpha * std::sqrt(c.mstar * kt);
  }
  r.fn = kn_delta * c.n - cn * vn;

  // Tangential spring: advance, keep in the current tangent plane.
  shear += dt * vt;
  shear -= dot(shear, c.n) * c.n;
  const Vec3 damp = ct * vt;
  Vec3 ft = -(kt * shear + damp);
  const double fs2 = dot(ft, ft), fmax2 = p.mu * p.mu * dot(r.fn, r.fn);
  if (fs2 > fmax2) {
    const double fmax = std::sqrt(fmax2), fs = std::sqrt(fs2);
    if (kt > 0) {
      const double s = fmax / fs;
      // Cut the spring back so that it alone (with the damping) gives the limit.
      shear = s * (shear + (1.0 / kt) * damp) - (1.0 / kt) * damp;
      ft = s * ft;
    } else {
      ft = (fs > 0 ? fmax / fs : 0.0) * ft;
    }
    r.sliding = true;
  }
  r.ft = ft;

  if (p.mu_roll > 0) {
    const Vec3   wr = c.wrel - dot(c.wrel, c.n) * c.n;
    const double w  = norm(wr);
    // at most what stops the rolling within the step for a rotational inertia 0.4 m* R*^2
    // (no more than the pair's): near rest the torque fades with the rolling instead of
    // flipping its direction with every round-off of w
    const double cap = dt > 0 ? kRollingInertia * c.mstar * c.rstar * c.rstar * w / dt : HUGE_VAL;
    if (w > 0) r.mroll = (-std::min(p.mu_roll * c.rstar * norm(r.fn), cap) / w) * wr;
  }
  return r;
}

} // namespace fdem::kernels
