// Free rotation of a rigid body (see include/fdem/kernels/rotation.hpp and
// doc/rotation.md). Written from the book's equations (doc/book.md B), from
// Miller et al. (2002) for NO_SQUISH and from the classical Jacobi-elliptic
// solution of Euler's equations (Landau & Lifshitz, Mechanics, section 37).
#include <fdem/kernels/rotation.hpp>

#include <fdem/kernels/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

namespace fdem::kernels {
namespace {

constexpr double kPi = 3.14159265358979323846;

// sin(x)/x and (1 - cos x)/x^2 without cancellation for small x.
double Sinc(double x) {
  if (std::fabs(x) < 1e-4) return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}
double OneMinusCosOverSq(double x) {
  // 1 - cos x = 2 sin^2(x/2)  =>  (1 - cos x)/x^2 = 0.5 * sinc(x/2)^2
  const double s = Sinc(0.5 * x);
  return 0.5 * s * s;
}

Vec3 Hadamard(const Vec3 &a, const Vec3 &b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
Vec3 DivideBy(const Vec3 &a, const Vec3 &b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
Vec3 Normalized(const Vec3 &a) { return a / norm(a); }
Vec3 UnitAxis(int k) {
  Vec3 e;
  e[k] = 1.0;
  return e;
}
// Rotation about coordinate axis k by angle theta (exact plane rotation).
Mat3 AxisRotation(int k, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  Mat3 Q;
  Q.m[k][k] = 1.0;
  Q.m[i][i] = c;
  Q.m[j][j] = c;
  Q.m[i][j] = -s;
  Q.m[j][i] = s;
  return Q;
}

void CheckInertia(const Vec3 &I, const char *who) {
  for (int k = 0; k < 3; ++k)
    if (!(I[k] > 0.0) || !std::isfinite(I[k])) {
      std::ostringstream os;
      os << who << ": principal moment I" << (k + 1) << " = " << I[k] << " must be positive and finite";
      throw InputError(os.str());
    }
}

// ---------------------------------------------------------------------------
// Elliptic functions. m is the parameter, mc = 1 - m its complement (passed
// separately so that values near the separatrix keep their accuracy).

double Agm(double a, double b) {
  for (int it = 0; it < 64 && std::fabs(a - b) > 1e-16 * a; ++it) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return 0.5 * (a + b);
}

double EllipticKc(double mc) {
  if (mc <= 0.0) return std::numeric_limits<double>::infinity();
  return 0.5 * kPi / Agm(1.0, std::sqrt(mc));
}

// Carlson's symmetric integral R_F(x, y, z) by the duplication theorem
// (DLMF 19.36.1 series once the arguments agree to 1e-3).
double CarlsonRF(double x, double y, double z) {
  for (int it = 0; it < 200; ++it) {
    const double mu = (x + y + z) / 3.0;
    const double dx = 1.0 - x / mu, dy = 1.0 - y / mu, dz = 1.0 - z / mu;
    if (std::max({std::fabs(dx), std::fabs(dy), std::fabs(dz)}) < 1e-3) {
      const double e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
      return (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / std::sqrt(mu);
    }
    const double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const double lam = sx * (sy + sz) + sy * sz;
    x = 0.25 * (x + lam);
    y = 0.25 * (y + lam);
    z = 0.25 * (z + lam);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double EllipticFc(double phi, double m, double mc) {
  const double j = std::nearbyint(phi / kPi);
  const double pr = phi - j * kPi; // in [-pi/2, pi/2]
  const double s = std::sin(pr), c = std::cos(pr);
  const double f = s * CarlsonRF(c * c, c * c + mc * s * s, 1.0);
  (void)m;
  if (j == 0.0) return f;
  return 2.0 * j * EllipticKc(mc) + f;
}

void SnCnDn(double u, double m, double mc, double &sn, double &cn, double &dn) {
  if (m <= 0.0) {
    sn = std::sin(u);
    cn = std::cos(u);
    dn = 1.0;
    return;
  }
  if (mc <= 0.0) {
    sn = std::tanh(u);
    cn = dn = 1.0 / std::cosh(u);
    return;
  }
  // Descending Landen / AGM (DLMF 22.20(ii)).
  std::array<double, 40> a{}, c{};
  a[0] = 1.0;
  c[0] = std::sqrt(m);
  double b = std::sqrt(mc);
  int n = 0;
  do {
    a[n + 1] = 0.5 * (a[n] + b);
    c[n + 1] = 0.5 * (a[n] - b);
    b = std::sqrt(a[n] * b);
    ++n;
    // Stop once c_n is at the level of a_n's last bits: a_n and b_n may then stay one ulp
    // apart for ever, and a tighter bound ran the loop to its end (2^38 u into sin).
  } while (n < 38 && std::fabs(c[n]) > 4.5e-16 * a[n]);
  double phi = std::ldexp(a[n] * u, n);
  for (int k = n; k > 0; --k) phi = 0.5 * (phi + std::asin(c[k] / a[k] * std::sin(phi)));
  sn = std::sin(phi);
  cn = std::cos(phi);
  dn = std::sqrt(cn * cn + mc * sn * sn); // = sqrt(1 - m sn^2) without cancellation
}

// ---------------------------------------------------------------------------
// Torque-free solution of Euler's equations in the body frame.
//
// Asymmetric case: relabel the axes (1',2',3') = (other extreme, middle,
// circled axis) where the circled axis is the one of largest inertia when
// L^2 > 2E I_mid and of smallest inertia otherwise. Then
//   w1' = s1 A1 cn(tau), w2' = A2 sn(tau), w3' = s3 A3 dn(tau), tau = Lam t + tau0
// with all radicands written as sums of same-signed terms. If (1',2',3') is an
// odd permutation of the original axes, Euler's equations change sign in the
// new labels, which reverses the sign of Lam.
struct TorqueFree {
  enum Kind { Zero, Steady, Symmetric, Asymmetric } kind = Zero;
  Vec3 I, w0;
  // symmetric: equal pair (pi, pj), distinct axis pc, rate a
  int pi = 0, pj = 1, pc = 2;
  double a = 0;
  // asymmetric
  int p[3] = {0, 1, 2};
  double A1 = 0, A2 = 0, A3 = 0, s1 = 1, s3 = 1, Lam = 0, tau0 = 0, m = 0, mc = 1, K = 0;

  TorqueFree(const Vec3 &I_, const Vec3 &w0_) : I(I_), w0(w0_) {
    if (w0.x == 0.0 && w0.y == 0.0 && w0.z == 0.0) {
      kind = Zero;
      return;
    }
    const double imax = std::max({I.x, I.y, I.z});
    const double tol = 4.0 * std::numeric_limits<double>::epsilon() * imax;
    const bool e01 = std::fabs(I[0] - I[1]) <= tol, e12 = std::fabs(I[1] - I[2]) <= tol,
               e02 = std::fabs(I[0] - I[2]) <= tol;
    if ((e01 && e12) || (e01 && e02) || (e02 && e12)) {
      kind = Steady; // sphere: omega is constant
      return;
    }
    if (e01 || e12 || e02) {
      kind = Symmetric;
      if (e01) { pi = 0; pj = 1; pc = 2; }
      else if (e12) { pi = 1; pj = 2; pc = 0; }
      else { pi = 2; pj = 0; pc = 1; }
      // omega_i' = ((I_{i+1} - I_{i+2}) / I_i) omega_{i+1} omega_{i+2}; for i = pi
      // one of i+1, i+2 is pj and the other pc.
      const int i1 = (pi + 1) % 3, i2 = (pi + 2) % 3;
      const double coef = (I[i1] - I[i2]) / I[pi]; // multiplies w[i1] w[i2]
      a = coef * w0[pc];                           // dw_i/dt = a w_j
      (void)i1;
      (void)i2;
      return;
    }
    kind = Asymmetric;
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int x, int y) { return I[x] < I[y]; });
    const int lo = order[0], mid = order[1], hi = order[2];
    // Delta = L^2 - 2E I_mid as a sum of terms (exactly zero terms for mid).
    const double dlo = I[lo] * w0[lo] * w0[lo] * (I[lo] - I[mid]);
    const double dhi = I[hi] * w0[hi] * w0[hi] * (I[hi] - I[mid]);
    const double Delta = dlo + dhi;
    const int c3 = Delta >= 0.0 ? hi : lo;
    const int c1 = Delta >= 0.0 ? lo : hi;
    p[0] = c1;
    p[1] = mid;
    p[2] = c3;
    const bool even = ((p[1] - p[0] + 3) % 3) == 1; // (p0,p1,p2) cyclic
    const double I1 = I[p[0]], I2 = I[p[1]], I3 = I[p[2]];
    const double w1 = w0[p[0]], w2 = w0[p[1]], w3 = w0[p[2]];
    if (w1 == 0.0 && w2 == 0.0) { kind = Steady; return; } // about the circled axis
    if (w1 == 0.0 && w3 == 0.0) { kind = Steady; return; } // about the intermediate axis
    // P = 2E I3 - L^2, Q = L^2 - 2E I1, D = L^2 - 2E I2 (each with the sign of I3 - I1 etc.)
    const double P = I1 * w1 * w1 * (I3 - I1) + I2 * w2 * w2 * (I3 - I2);
    const double Q = I2 * w2 * w2 * (I2 - I1) + I3 * w3 * w3 * (I3 - I1);
    const double D = I1 * w1 * w1 * (I1 - I2) + I3 * w3 * w3 * (I3 - I2);
    A1 = std::sqrt(std::max(0.0, P / (I1 * (I3 - I1))));
    A2 = std::sqrt(std::max(0.0, P / (I2 * (I3 - I2))));
    A3 = std::sqrt(std::max(0.0, Q / (I3 * (I3 - I1))));
    const double lam = std::sqrt(std::max(0.0, (I3 - I2) * Q / (I1 * I2 * I3)));
    m = std::clamp((I2 - I1) * P / ((I3 - I2) * Q), 0.0, 1.0);
    mc = std::clamp((I3 - I1) * D / ((I3 - I2) * Q), 0.0, 1.0);
    s3 = w3 >= 0.0 ? 1.0 : -1.0;
    s1 = 1.0;
    if (mc == 0.0) s1 = w1 >= 0.0 ? 1.0 : -1.0; // on the separatrix cn = sech > 0
    const double g = I3 > I1 ? 1.0 : -1.0;
    Lam = (even ? 1.0 : -1.0) * g * s1 * s3 * lam;
    const double x = A1 > 0.0 ? s1 * w1 / A1 : 0.0; // cn(tau0)
    const double y = A2 > 0.0 ? w2 / A2 : 0.0;      // sn(tau0)
    const double phi0 = std::atan2(y, x);
    tau0 = EllipticFc(phi0, m, mc);
    K = EllipticKc(mc);
  }

  Vec3 Omega(double t) const {
    switch (kind) {
    case Zero:
      return {};
    case Steady:
      return w0;
    case Symmetric: {
      Vec3 w = w0;
      const double c = std::cos(a * t), s = std::sin(a * t);
      w[pi] = w0[pi] * c + w0[pj] * s;
      w[pj] = w0[pj] * c - w0[pi] * s;
      return w;
    }
    case Asymmetric: {
      double sn, cn, dn;
      SnCnDn(Lam * t + tau0, m, mc, sn, cn, dn);
      Vec3 w;
      w[p[0]] = s1 * A1 * cn;
      w[p[1]] = A2 * sn;
      w[p[2]] = s3 * A3 * dn;
      return w;
    }
    }
    return w0;
  }
};

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
struct GaussLegendre {
  static constexpr int n = 10;
  std::array<double, n> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::fabs(dz) < 1e-17) break;
      }
      x[i] = z;
      w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

template <class F> double GaussPanel(const F &f, double a, double b) {
  static const GaussLegendre gl;
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  double sum = 0.0;
  for (int i = 0; i < GaussLegendre::n; ++i) sum += gl.w[i] * f(c + h * gl.x[i]);
  return h * sum;
}

template <class F> double AdaptiveGauss(const F &f, double a, double b, double whole, double scale, int depth) {
  const double c = 0.5 * (a + b);
  const double l = GaussPanel(f, a, c), r = GaussPanel(f, c, b);
  if (depth >= 25 || std::fabs(l + r - whole) <= 1e-14 * scale * std::fabs(b - a)) return l + r;
  return AdaptiveGauss(f, a, c, l, scale, depth + 1) + AdaptiveGauss(f, c, b, r, scale, depth + 1);
}

Mat3 OuterSum(const Vec3 &A, const Vec3 &a, const Vec3 &B, const Vec3 &b, const Vec3 &N, const Vec3 &u) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = A[r] * a[c] + B[r] * b[c] + N[r] * u[c];
  return M;
}

Mat3 ExactRotate(const Mat3 &R, const Vec3 &I, const Vec3 &H, double s) {
  const double L = norm(H);
  if (L == 0.0 || s == 0.0) return R;
  const Vec3 Lb0 = transpose(R) * H;
  const Vec3 w0 = DivideBy(Lb0, I);
  TorqueFree sol(I, w0);
  if (sol.kind == TorqueFree::Zero) return R;
  if (sol.kind == TorqueFree::Steady) return RotateTriad(R, s * (R * w0));
  const Vec3 n = H / L;
  if (sol.kind == TorqueFree::Symmetric) {
    // Closed form: R(t) = Rot(n, L t / I_perp) R0 Rot_body(e_c, beta t),
    // beta = (1/I_c - 1/I_perp) L_c. Then omega = H / I_perp + beta R e_c.
    const double Ip = I[sol.pi], Ic = I[sol.pc];
    const double beta = (1.0 / Ic - 1.0 / Ip) * Lb0[sol.pc];
    return RotationMatrix(n * (L * s / Ip)) * R * AxisRotation(sol.pc, beta * s);
  }
  // Asymmetric: choose the reference body axis r that stays farthest from the
  // direction of L over the whole orbit (min over the orbit of L^2 - L_r^2,
  // attained where sn^2 = 0 or sn^2 = 1).
  Vec3 Lsn0, Lsn1; // squared body components at sn^2 = 0 and sn^2 = 1
  Lsn0[sol.p[0]] = std::pow(I[sol.p[0]] * sol.A1, 2);
  Lsn0[sol.p[1]] = 0.0;
  Lsn0[sol.p[2]] = std::pow(I[sol.p[2]] * sol.A3, 2);
  Lsn1[sol.p[0]] = 0.0;
  Lsn1[sol.p[1]] = std::pow(I[sol.p[1]] * sol.A2, 2);
  Lsn1[sol.p[2]] = std::pow(I[sol.p[2]] * sol.A3, 2) * sol.mc;
  int r = 0;
  double best = -1.0;
  for (int k = 0; k < 3; ++k) {
    const double v = std::min(Lsn0.x + Lsn0.y + Lsn0.z - Lsn0[k], Lsn1.x + Lsn1.y + Lsn1.z - Lsn1[k]);
    if (v > best) { best = v; r = k; }
  }
  // A step short against the wobble (|Lam s| <= 0.01, as in a settled pile): sn, cn, dn at the
  // quadrature's nodes come from their values at the step's middle by the addition theorem (DLMF
  // 22.8.1-3), with those of the small offset d = Lam (t - s/2) from their Maclaurin series (DLMF
  // 22.10.4-6, to d^7 and d^6: the first terms left out are below 1e-18 for |d| <= 0.005). Two
  // runs of the Landen recursion a step instead of 31; the same values to round-off.
  const bool   near = std::fabs(sol.Lam * s) <= 0.01 && sol.m > 0.0 && sol.mc > 0.0;
  double       snm = 0, cnm = 0, dnm = 0;
  const double m = sol.m;
  if (near) SnCnDn(sol.Lam * 0.5 * s + sol.tau0, m, sol.mc, snm, cnm, dnm);
  auto omega = [&](double t) {
    if (!near) return sol.Omega(t);
    const double d = sol.Lam * (t - 0.5 * s), d2 = d * d;
    const double sd = d * (1.0 - d2 * ((1.0 + m) / 6.0 - d2 * ((1.0 + m * (14.0 + m)) / 120.0 - d2 * (1.0 + m * (135.0 + m * (135.0 + m))) / 5040.0)));
    const double cd = 1.0 - d2 * (0.5 - d2 * ((1.0 + 4.0 * m) / 24.0 - d2 * (1.0 + m * (44.0 + 16.0 * m)) / 720.0));
    const double dd = 1.0 - m * d2 * (0.5 - d2 * ((4.0 + m) / 24.0 - d2 * (16.0 + m * (44.0 + m)) / 720.0));
    const double q = 1.0 / (1.0 - m * snm * snm * sd * sd);
    Vec3 w;
    w[sol.p[0]] = sol.s1 * sol.A1 * (cnm * cd - snm * dnm * sd * dd) * q;
    w[sol.p[1]] = sol.A2 * (snm * cd * dd + sd * cnm * dnm) * q;
    w[sol.p[2]] = sol.s3 * sol.A3 * (dnm * dd - m * snm * cnm * sd * cd) * q;
    return w;
  };
  // phi' = L * sum_{j != r} L_j^2 / I_j / sum_{j != r} L_j^2 (a weighted mean of 1/I_j).
  auto rate = [&](double t) {
    const Vec3 w = omega(t);
    double num = 0.0, den = 0.0;
    for (int j = 0; j < 3; ++j) {
      if (j == r) continue;
      const double Lj = I[j] * w[j];
      num += Lj * w[j];
      den += Lj * Lj;
    }
    return L * num / den;
  };
  const double scale = L / std::min({I.x, I.y, I.z});
  // Panels no longer than an eighth of the period of L_j^2 (2K/|Lam|).
  double panel = std::fabs(s);
  if (sol.Lam != 0.0 && std::isfinite(sol.K)) panel = std::min(panel, 0.25 * sol.K / std::fabs(sol.Lam));
  else if (sol.Lam != 0.0) panel = std::min(panel, 0.5 / std::fabs(sol.Lam));
  // A step over more than kMaxPanels eighths of that period (the body wobbling through thousands
  // of cycles in one step) resolves nothing of the motion, and its cost would grow without bound
  // (an angular velocity of 1e20 rad/s took minutes a step, its panel count past the range of int)
  constexpr double kMaxPanels = 1e5;
  const double     want       = std::ceil(std::fabs(s) / panel - 1e-12);
  if (!(want <= kMaxPanels)) {
    char msg[256];
    std::snprintf(msg, sizeof(msg), "the exact free rotation: the body wobbles through %.3g cycles of its torque-free motion in one step of %.3g s (|omega| up to %.3g rad/s)", want / 8, s, scale);
    throw InputError(std::string(msg) + "; the step cannot follow it: lower the time step or the angular velocity");
  }
  const int npanel = std::max(1, static_cast<int>(want));
  double phi = 0.0;
  for (int k = 0; k < npanel; ++k) {
    const double ta = s * k / npanel, tb = s * (k + 1) / npanel;
    phi += AdaptiveGauss(rate, ta, tb, GaussPanel(rate, ta, tb), scale, 0);
  }
  const Vec3 Lb1 = Hadamard(I, sol.Omega(s));
  const Vec3 u0 = Lb0 / L, u1 = Normalized(Lb1);
  const Vec3 er = UnitAxis(r);
  const Vec3 a0 = Normalized(er - u0[r] * u0), b0 = cross(u0, a0);
  const Vec3 a1 = Normalized(er - u1[r] * u1), b1 = cross(u1, a1);
  Vec3 A0 = R * a0;
  A0 = Normalized(A0 - dot(A0, n) * n);
  const Vec3 B0 = cross(n, A0);
  (void)b0;
  const double c = std::cos(phi), sp = std::sin(phi);
  const Vec3 A1 = c * A0 + sp * B0, B1 = c * B0 - sp * A0;
  return OuterSum(A1, a1, B1, b1, n, u1);
}

Mat3 MunjizaRotate(const Mat3 &R, const Vec3 &I, const Vec3 &H, double s) {
  // Steps 1-6 of doc/book.md B with the typos corrected and the consistent stage 1
  // (omega from H, so any impulse already added to H is seen by every stage).
  const Vec3 w1 = SpaceOmega(R, I, H);
  const Mat3 R1 = RotateTriad(R, 0.5 * s * w1);
  const Vec3 w2 = SpaceOmega(R1, I, H);
  const Mat3 R2 = RotateTriad(R, 0.5 * s * w2);
  const Vec3 w3 = SpaceOmega(R2, I, H);
  const Mat3 R3 = RotateTriad(R, s * w3);
  const Vec3 w4 = SpaceOmega(R3, I, H);
  const Vec3 wbar = (w1 + 2.0 * w2 + 2.0 * w3 + w4) / 6.0;
  return RotateTriad(R, s * wbar);
}

Mat3 NoSquishRotate(const Mat3 &R, const Vec3 &I, const Vec3 &H, double s) {
  // Symmetric splitting of T = sum_k Lk^2/(2 Ik); each factor is the exact
  // flow of one term: a rotation of the body about its own axis k by the angle
  // tau Lk / Ik, which also rotates the body-frame momentum Lb = R^T H.
  Mat3 Q = R;
  Vec3 Lb = transpose(R) * H;
  auto sub = [&](int k, double tau) {
    const Mat3 Rk = AxisRotation(k, tau * Lb[k] / I[k]);
    Q = Q * Rk;
    Lb = transpose(Rk) * Lb;
  };
  sub(2, 0.5 * s);
  sub(1, 0.5 * s);
  sub(0, s);
  sub(1, 0.5 * s);
  sub(2, 0.5 * s);
  return Q;
}

// Rounding makes a product of rotation matrices drift from orthonormality as a
// random walk (~1e-13 after 1e5 steps). When the defect exceeds a few ulps,
// one Newton-Schulz step toward the polar factor, R <- R (3 Id - R^T R) / 2,
// squares it away. The correction is O(1e-15), so it does not affect the
// order, the reversibility or the conservation properties of any variant.
Mat3 KeepOrthonormal(const Mat3 &R) {
  if (OrthonormalityError(R) <= 2e-15) return R;
  return 0.5 * (R * (3.0 * Mat3::identity() - transpose(R) * R));
}

} // namespace

namespace {
// (5.68) rearranged: e' = cos(psi) e + (1 - cos psi)/psi^2 (psi.e) psi + sin(psi)/psi (psi x e);
// the three scalar factors depend on psi alone, so a triad rotated by one psi needs them once.
struct Rodrigues {
  Vec3   psi;
  double c, a, s; // cos psi, (1 - cos psi) / psi^2, sin psi / psi
  explicit Rodrigues(const Vec3 &p) : psi(p) {
    const double ang = norm(p);
    c = std::cos(ang), a = OneMinusCosOverSq(ang), s = Sinc(ang);
  }
  Vec3 operator()(const Vec3 &e) const { return c * e + (a * dot(psi, e)) * psi + s * cross(psi, e); }
};
} // namespace

Vec3 RotateRodrigues(const Vec3 &e, const Vec3 &psi) { return Rodrigues(psi)(e); }

Mat3 RotationMatrix(const Vec3 &psi) {
  const Rodrigues rot(psi);
  return Mat3::columns(rot({1, 0, 0}), rot({0, 1, 0}), rot({0, 0, 1}));
}

Mat3 RotateTriad(const Mat3 &R, const Vec3 &psi) {
  const Rodrigues rot(psi);
  return Mat3::columns(rot(R.col(0)), rot(R.col(1)), rot(R.col(2)));
}

Vec3 SpaceOmega(const Mat3 &R, const Vec3 &I, const Vec3 &H) { return R * DivideBy(transpose(R) * H, I); }

Vec3 AngularMomentum(const Mat3 &R, const Vec3 &I, const Vec3 &omega) { return R * Hadamard(I, transpose(R) * omega); }

double RotationalKineticEnergy(const Mat3 &R, const Vec3 &I, const Vec3 &H) {
  const Vec3 Lb = transpose(R) * H;
  return 0.5 * (Lb.x * Lb.x / I.x + Lb.y * Lb.y / I.y + Lb.z * Lb.z / I.z);
}

double OrthonormalityError(const Mat3 &R) {
  // R^T R - 1 is symmetric: its six distinct entries, each the dot product of two columns
  double e = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      const double d = R.m[0][a] * R.m[0][b] + R.m[1][a] * R.m[1][b] + R.m[2][a] * R.m[2][b];
      e              = std::max(e, std::fabs(a == b ? d - 1.0 : d));
    }
  return e;
}

const char *FreeRotationName(FreeRotation kind) {
  switch (kind) {
  case FreeRotation::Munjiza: return "munjiza";
  case FreeRotation::NoSquish: return "nosquish";
  case FreeRotation::Exact: return "exact";
  }
  return "unknown";
}

Mat3 FreeRotate(FreeRotation kind, const Mat3 &R, const Vec3 &I, const Vec3 &H, double s) {
  CheckInertia(I, "FreeRotate");
  if (!std::isfinite(s) || !std::isfinite(H.x) || !std::isfinite(H.y) || !std::isfinite(H.z))
    throw InputError("FreeRotate: time step or angular momentum is not finite");
  switch (kind) {
  case FreeRotation::Munjiza: return KeepOrthonormal(MunjizaRotate(R, I, H, s));
  case FreeRotation::NoSquish: return KeepOrthonormal(NoSquishRotate(R, I, H, s));
  case FreeRotation::Exact: return KeepOrthonormal(ExactRotate(R, I, H, s));
  }
  return R;
}

void TorqueFreeOmegaBody(const Vec3 &I, const Vec3 &omega0_body, double t, Vec3 &omega_body) {
  CheckInertia(I, "TorqueFreeOmegaBody");
  omega_body = TorqueFree(I, omega0_body).Omega(t);
}

void JacobiSnCnDn(double u, double m, double &sn, double &cn, double &dn) {
  if (!(m >= 0.0 && m <= 1.0)) throw InputError("JacobiSnCnDn: parameter m = " + std::to_string(m) + " is outside [0, 1]");
  SnCnDn(u, m, 1.0 - m, sn, cn, dn);
}

double EllipticK(double m) {
  if (!(m >= 0.0 && m < 1.0)) throw InputError("EllipticK: parameter m = " + std::to_string(m) + " is outside [0, 1)");
  return EllipticKc(1.0 - m);
}

double EllipticF(double phi, double m) {
  if (!(m >= 0.0 && m <= 1.0)) throw InputError("EllipticF: parameter m = " + std::to_string(m) + " is outside [0, 1]");
  if (m == 1.0 && std::fabs(phi) >= 0.5 * kPi) return std::copysign(std::numeric_limits<double>::infinity(), phi);
  return EllipticFc(phi, m, 1.0 - m);
}

} // namespace fdem::kernels
