// Granular contact force laws (include/fdem/kernels/granular.hpp,
// doc/spheres.md).
#include "fdem/kernels/granular.hpp"

#include <cmath>
#include <map>
#include <string>

#include "fdem/kernels/error.hpp"

namespace fdem::kernels {
namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void Fail(const char *what, const std::string &msg) {
  throw InputError(std::string("granular contact ") + (what ? what : "") + ": " + msg);
}

// Geometric mean of two optional values; a value missing on one side is taken
// from the other; `def` if missing on both.
double MixOptional(bool ha, double a, bool hb, double b, double def) {
  if (ha && hb) return std::sqrt(a * b);
  if (ha) return a;
  if (hb) return b;
  return def;
}

// Right-hand side of the dimensionless damped Hertz impact
// X'' = -X^{3/2} - alpha sqrt(3/2) X^{1/4} X'.
inline double HertzAccel(double x, double v, double c) {
  if (x <= 0) return 0;
  return -x * std::sqrt(x) - c * std::sqrt(std::sqrt(x)) * v;
}

} // namespace

GranularPair MixGranular(const GranularMaterial &a, const GranularMaterial &b, const char *what) {
  GranularPair p;
  if (a.law_set && b.law_set && a.law != b.law) Fail(what, "the two materials name different contact laws (hertz and hooke)");
  p.law = a.law_set ? a.law : (b.law_set ? b.law : GranularLaw::Hertz);
  const double e = MixOptional(a.has_restitution, a.restitution, b.has_restitution, b.restitution, 1.0);
  if (!(e > 0 && e <= 1)) Fail(what, "restitution " + std::to_string(e) + " is not in (0, 1]");
  p.restitution = e;
  p.mu = MixOptional(a.has_friction, a.friction, b.has_friction, b.friction, 0.0);
  p.mu_roll = MixOptional(a.has_rolling, a.rolling_friction, b.has_rolling, b.rolling_friction, 0.0);
  if (!(p.mu >= 0) || !(p.mu_roll >= 0)) Fail(what, "friction and rolling friction must be >= 0");
  if (p.law == GranularLaw::Hertz) {
    // a side without young is rigid (no compliance): a sphere against a rigid wall
    if (!(a.young > 0) && !(b.young > 0)) Fail(what, "the Hertz law needs young > 0 on at least one of the two materials");
    auto compliance = [&](const GranularMaterial &m, double &cn, double &ct) {
      cn = ct = 0;
      if (!(m.young > 0)) return;
      if (!(m.poisson > -1 && m.poisson < 0.5)) Fail(what, "the Hertz law needs poisson in (-1, 0.5)");
      cn = (1 - m.poisson * m.poisson) / m.young;
      ct = 2 * (2 - m.poisson) * (1 + m.poisson) / m.young;
    };
    double cna, cta, cnb, ctb;
    compliance(a, cna, cta);
    compliance(b, cnb, ctb);
    p.estar = 1.0 / (cna + cnb);
    p.gstar = 1.0 / (cta + ctb);
    p.alpha = HertzDampingForRestitution(e);
  } else {
    auto harmonic = [](double x, double y) { return x > 0 && y > 0 ? 2 * x * y / (x + y) : (x > 0 ? x : y); };
    p.kn = harmonic(a.kn, b.kn);
    p.kt = harmonic(a.kt, b.kt);
    if (!(p.kn > 0)) Fail(what, "the Hooke law needs kn > 0 on at least one material");
    if (!(p.kt >= 0)) Fail(what, "kt must be >= 0");
    p.gamma_n = MixOptional(a.gamma_n > 0, a.gamma_n, b.gamma_n > 0, b.gamma_n, 0.0);
    p.gamma_t = MixOptional(a.gamma_t > 0, a.gamma_t, b.gamma_t > 0, b.gamma_t, 0.0);
  }
  return p;
}

double HertzRestitution(double alpha) {
  // Integrate the dimensionless impact from X = 0, X' = 1 (RK4) until X
  // returns to zero; the exit speed is the restitution.
  const double c = alpha * std::sqrt(1.5);
  const double h = 1e-4;
  double x = 0, v = 1;
  for (int i = 0; i < 2000000; ++i) {
    const double k1x = v, k1v = HertzAccel(x, v, c);
    const double k2x = v + 0.5 * h * k1v, k2v = HertzAccel(x + 0.5 * h * k1x, k2x, c);
    const double k3x = v + 0.5 * h * k2v, k3v = HertzAccel(x + 0.5 * h * k2x, k3x, c);
    const double k4x = v + h * k3v, k4v = HertzAccel(x + h * k3x, k4x, c);
    const double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (i > 0 && xn <= 0) {
      // Crossing inside the step: linear interpolation of the speed.
      const double s = x / (x - xn);
      return -(v + s * (vn - v));
    }
    x = xn;
    v = vn;
    if (v > -1e-12 && v < 1e-12 && x > 0 && i > 100) break;
  }
  return 0; // overdamped: never leaves
}

double HertzDampingForRestitution(double e) {
  if (!(e > 0 && e <= 1)) throw InputError("HertzDampingForRestitution: restitution " + std::to_string(e) + " is not in (0, 1]");
  if (e == 1) return 0;
  // a root search of some 40 integrations of the impact: each restitution once per process
  static std::map<double, double> known;
  const auto                      it0 = known.find(e);
  if (it0 != known.end()) return it0->second;
  double lo = 0, hi = 1;
  while (HertzRestitution(hi) > e) {
    hi *= 2;
    if (hi > 64) throw InputError("HertzDampingForRestitution: restitution " + std::to_string(e) + " is too small");
  }
  for (int it = 0; it < 48 && hi - lo > 1e-10 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (HertzRestitution(mid) > e ? lo : hi) = mid;
  }
  return known[e] = 0.5 * (lo + hi);
}

double HookeDampingForRestitution(double e, double kn, double mstar) {
  if (!(e > 0 && e <= 1)) throw InputError("HookeDampingForRestitution: restitution " + std::to_string(e) + " is not in (0, 1]");
  const double l = std::log(e);
  const double zeta = -l / std::sqrt(kPi * kPi + l * l);
  return 2 * zeta * std::sqrt(kn / mstar);
}

double HookeRestitution(double kn, double gamma_n, double mstar) {
  const double w0 = std::sqrt(kn / mstar), zeta = gamma_n / (2 * w0);
  if (zeta >= 1) return 0;
  return std::exp(-zeta * kPi / std::sqrt(1 - zeta * zeta));
}

double HookeContactTime(double kn, double gamma_n, double mstar) {
  const double w0 = std::sqrt(kn / mstar), zeta = gamma_n / (2 * w0);
  return kPi / (w0 * std::sqrt(1 - zeta * zeta));
}

namespace {
// Maximum overlap of an elastic Hertz impact.
double HertzMaxOverlap(double estar, double rstar, double mstar, double v) {
  return std::pow(15.0 * mstar * v * v / (16.0 * estar * std::sqrt(rstar)), 0.4);
}
} // namespace

double HertzPeakForce(double estar, double rstar, double mstar, double v) {
  const double d = HertzMaxOverlap(estar, rstar, mstar, v);
  return 4.0 / 3.0 * estar * std::sqrt(rstar) * d * std::sqrt(d);
}

double HertzContactTime(double estar, double rstar, double mstar, double v) {
  // t_c = 2 (delta_max / v) int_0^1 (1 - x^{5/2})^{-1/2} dx
  const double integral = std::tgamma(1.4) * std::sqrt(kPi) / std::tgamma(0.9);
  return 2.0 * HertzMaxOverlap(estar, rstar, mstar, v) / v * integral;
}


double GranularStableOmega(const GranularPair &p, double mass, double radius, double offset, double inertia) {
  // how much more mobile the contact point is than the centre of mass, along the normal and across
  // it: 1 + m lever^2 / I, the lever of the normal force |offset| at most and of the tangential
  // |offset| + radius (a solid sphere: 1 and 1 + m r^2 / (2/5 m r^2) = 3.5)
  const double mnormal  = inertia > 0 ? 1 + mass * offset * offset / inertia : 1;
  const double mobility = inertia > 0 ? 1 + mass * (offset + radius) * (offset + radius) / inertia : 3.5;
  const double mstar = 0.5 * mass, rstar = 0.5 * radius;
  double kn, kt, zn, zt;
  if (p.law == GranularLaw::Hooke) {
    const double gn = p.gamma_n > 0 || !(p.restitution < 1) ? p.gamma_n : HookeDampingForRestitution(p.restitution, p.kn, mstar);
    kn = p.kn;
    kt = p.kt;
    zn = kn > 0 ? 0.5 * gn * std::sqrt(mstar * mnormal / kn) : 0;
    zt = kt > 0 ? 0.5 * p.gamma_t * std::sqrt(mstar * mobility / kt) : 0;
  } else {
    const double a = std::sqrt(rstar * 0.01 * radius);
    kn = 2.0 * p.estar * a;
    kt = 8.0 * p.gstar * a;
    zn = 0.5 * p.alpha * std::sqrt(mnormal); // cn = alpha sqrt(m* kn) = 2 zn sqrt(m* kn / mnormal)
    zt = 0.5 * p.alpha * std::sqrt(mobility); // ct = alpha sqrt(m* kt) against the mobile mass m* / 3.5
  }
  const double wn = std::sqrt(mnormal * kn / mstar) * (zn + std::sqrt(1 + zn * zn));
  const double wt = std::sqrt(mobility * kt / mstar) * (zt + std::sqrt(1 + zt * zt));
  return std::max(wn, wt);
}

} // namespace fdem::kernels
