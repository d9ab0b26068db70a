// The cohesive law of a fracture joint; see fdem/kernels/joint.hpp and doc/fracture.md.
#include <fdem/kernels/joint.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <fdem/kernels/error.hpp>

namespace fdem::kernels {

double JointSoftening(double D) {
  D = std::clamp(D, 0.0, 1.0);
  const double a = kJointA, b = kJointB, c = kJointC, ab = a + b;
  const double e = std::exp(D * (a + c * b) / (ab * (1.0 - ab)));
  const double r = 1.0 - D, r2 = r * r;
  static_assert(kJointC == 6.0, "r^c is multiplied out for c = 6");
  return (1.0 - (ab - 1.0) / ab * e) * (a * r + b * (r2 * r2 * r2));
}

void JointState::SetDamage(double damage) {
  D         = damage;
  softening = damage >= 1 ? 0.0f : damage > 0 ? (float)JointSoftening(damage) : 1.0f;
}

double JointSofteningIntegral() {
  static const double Z = [] {
    const int n = 4096; // even
    double s = JointSoftening(0) + JointSoftening(1);
    for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * JointSoftening((double)i / n);
    return s / (3.0 * n);
  }();
  return Z;
}

namespace {
std::string Num(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}
// Critical value from the peak value, the strength and the energy: the whole
// area (2/3 strength peak + strength (crit - peak) Z) equals the energy.
double Critical(double peak, double strength, double G) { return peak + (G - 2.0 / 3.0 * strength * peak) / (strength * JointSofteningIntegral()); }
// The hardening shape: 2x - x^2 up to the peak (x = 1), then 1.
double Hardening(double x) { return x < 1 ? x * (2.0 - x) : 1.0; }
// Its integral from 0 to x: x^2 - x^3/3 up to the peak, then 2/3 + (x - 1).
double HardeningIntegral(double x) { return x < 1 ? x * x * (1.0 - x / 3.0) : x - 1.0 / 3.0; }
// The normal branch without damage at opening dn: penalty in compression, hardening in tension.
double NormalUndamaged(const JointLaw &L, double dn) { return dn <= 0 ? 2.0 * L.ft * dn / L.dn_peak : L.ft * Hardening(dn / L.dn_peak); }
// The part of psi that z(D) scales (J/m^2): the tension term.
double TensionEnergy(const JointLaw &L, double dn) { return dn > 0 ? L.ft * L.dn_peak * HardeningIntegral(dn / L.dn_peak) : 0.0; }
// The shear damage at which the secant (1 - w) K s meets the law z f_s h(x) at x = s / s_peak:
// since K s = 2 f_s x, w = 1 - z h(x) / (2x), i.e. 1 - z (1 - x/2) below the peak and
// 1 - z / (2x) beyond it (x/2 exactly when z = 1). Independent of f_s but through x.
double SecantShearDamage(double z, double x) { return x < 1 ? 1.0 - z + z * (0.5 * x) : 1.0 - z / (2.0 * x); }
// The energy per area dissipated by raising the shear damage from w0 to w1: the release of psi
// at fixed separation, (w1 - w0) psi_s, with psi_s the shear's K s^2 / 2 at the step's mean
// separation (JointState::last_shear). On the hardening branch at a fixed f_s the integral
// along the branch, (2/3) K s_peak^2 (w1^3 - w0^3), would be exact, but f_s follows the normal
// traction, and under a changing compression that formula is first order in the step.
double ShearDissipated(double w0, double w1, double psi_s) { return w1 > w0 ? (w1 - w0) * psi_s : 0.0; }
} // namespace

double JointStoredEnergy(const JointLaw &L, double dn, double s, const JointState &st) {
  if (st.broken()) return 0;
  const double z = st.softening;
  return (dn < 0 ? L.ft * dn * dn / L.dn_peak : 0.0) + z * TensionEnergy(L, dn) + (1.0 - st.shear_damage) * 0.5 * L.shear_stiffness * s * s;
}

JointLaw MakeJointLaw(const JointMaterial &m, double h) {
  const std::string who = "fracture material '" + m.name + "'";
  auto positive = [&](double v, const char *what) {
    if (!(v > 0) || !std::isfinite(v)) throw InputError(who + ": " + what + " = " + Num(v) + " must be positive and finite");
  };
  positive(m.tensile_strength, "tensile_strength");
  positive(m.cohesion, "cohesion");
  positive(m.GI, "G_I");
  positive(m.GII, "G_II");
  positive(m.penalty, "joint_penalty");
  if (!(m.friction_angle >= 0 && m.friction_angle < 90))
    throw InputError(who + ": friction_angle = " + Num(m.friction_angle) + " degrees must be in [0, 90)");
  if (!(h > 0) || !std::isfinite(h)) throw InputError(who + ": the element size h = " + Num(h) + " must be positive and finite");
  JointLaw L;
  L.ft = m.tensile_strength, L.c = m.cohesion, L.tan_phi = std::tan(m.friction_angle * M_PI / 180.0);
  L.GI = m.GI, L.GII = m.GII, L.penalty = m.penalty, L.h = h;
  L.dn_peak = 2.0 * h * L.ft / L.penalty;
  if (2.0 / 3.0 * L.ft * L.dn_peak >= L.GI)
    throw InputError(who + ": joint_penalty = " + Num(m.penalty) + " is too small for elements of size " + Num(h) + ": the peak opening 2 h f_t / p = " + Num(L.dn_peak) +
                     " m would store 2/3 f_t dn_peak = " + Num(2.0 / 3.0 * L.ft * L.dn_peak) + " J/m^2 before softening, more than G_I = " + Num(L.GI) +
                     "; raise the penalty above " + Num(4.0 / 3.0 * h * L.ft * L.ft / L.GI) + " Pa");
  if (2.0 / 3.0 * L.c * (2.0 * h * L.c / L.penalty) >= L.GII)
    throw InputError(who + ": joint_penalty = " + Num(m.penalty) + " is too small for elements of size " + Num(h) + " in shear: 2/3 c s_peak = " +
                     Num(2.0 / 3.0 * L.c * (2.0 * h * L.c / L.penalty)) + " J/m^2 exceeds G_II = " + Num(L.GII) + "; raise the penalty above " +
                     Num(4.0 / 3.0 * h * L.c * L.c / L.GII) + " Pa");
  L.dn_crit = Critical(L.dn_peak, L.ft, L.GI);
  L.inv_dn_peak       = 1.0 / L.dn_peak;
  L.slip_per_strength = 2.0 * h / L.penalty;
  L.shear_stiffness   = L.penalty / h;
  const double sp0 = 2.0 * h * L.c / L.penalty;
  L.s_span    = Critical(sp0, L.c, L.GII) - sp0;
  return L;
}

void JointSlipLimits(const JointLaw &L, double sigma, double *s_peak, double *s_crit) {
  // Mohr-Coulomb with tension positive: compression (sigma < 0) raises the shear strength.
  const double fs = std::max(L.c - sigma * L.tan_phi, 0.0);
  const double sp = 2.0 * L.h * fs / L.penalty;
  if (s_peak) *s_peak = sp;
  // The softening span in slip is that of pure shear (fs = c: energy G_II);
  // under compression the strength, and so the energy to rupture, grow.
  if (s_crit) *s_crit = sp + L.s_span;
}

void JointSeparationFor(const JointLaw &L, double sigma, double tau, double *dn0, double *s0) {
  // x with h(x) = 2x - x^2 = y on [0, 1]: 1 - sqrt(1 - y), written without the cancellation
  auto branch = [](double y) {
    y = std::min(std::max(y, 0.0), 1.0);
    return y / (1.0 + std::sqrt(1.0 - y));
  };
  *dn0 = sigma >= 0 ? L.dn_peak * branch(sigma / L.ft) : 0.5 * sigma * L.dn_peak / L.ft; // the compression penalty 2 f_t dn / dn_peak
  double sp;
  JointSlipLimits(L, std::min(sigma, 0.0), &sp, nullptr); // as JointTractionAt takes it
  const double fs = std::max(L.c - std::min(sigma, 0.0) * L.tan_phi, 0.0);
  *s0             = fs > 0 ? sp * branch(tau / fs) : 0.0;
}

JointTraction JointTractionAt(const JointLaw &L, double dn, double s, JointState &state) {
  JointTraction t;
  if (state.broken()) {
    t.D = 1;
    return t; // the faces are contact surfaces now
  }
  s = std::fabs(s);
  const double sigma0 = NormalUndamaged(L, dn);
  double sp, sc;
  JointSlipLimits(L, std::min(sigma0, 0.0), &sp, &sc); // the friction gain comes from compression
  const double DI  = dn > L.dn_peak ? (dn - L.dn_peak) / (L.dn_crit - L.dn_peak) : 0.0;
  const double DII = s > sp ? (s - sp) / (sc - sp) : 0.0;
  const double D0  = state.D;
  const float  w0  = state.shear_damage;
  state.D = std::max(state.D, std::min(1.0, std::sqrt(DI * DI + DII * DII)));
  t.D = state.D;
  const double z0 = state.softening; // z(D0), kept with D0
  if (state.D > D0) state.SetDamage(state.D);
  const double z = state.softening;
  // the shear secant: w rises to the law's where that is larger (1 once broken)
  state.shear_damage = state.D >= 1 ? 1.0f : std::max(w0, (float)SecantShearDamage(z, s / sp));
  // The growth releases psi at fixed separation. The tractions' work over the step, which the
  // schemes take as the trapezoidal rule, leaves over the release at the step's mean
  // separation: the state keeps the energies of the last evaluation (at this one's separation
  // where it has none: a fresh state, or one set from its damage).
  const double psi_t = TensionEnergy(L, dn), psi_s = 0.5 * L.shear_stiffness * s * s;
  const double mean_t = state.last_tension >= 0 ? 0.5 * ((double)state.last_tension + psi_t) : psi_t;
  const double mean_s = state.last_shear >= 0 ? 0.5 * ((double)state.last_shear + psi_s) : psi_s;
  t.dissipated = (z0 - z) * mean_t + ShearDissipated(w0, state.shear_damage, mean_s);
  state.last_tension = (float)psi_t, state.last_shear = (float)psi_s;
  if (state.broken()) return t;
  t.sigma = dn <= 0 ? sigma0 : z * sigma0; // compression is never softened
  t.tau   = (1.0 - state.shear_damage) * (L.shear_stiffness * s);
  return t;
}

} // namespace fdem::kernels

namespace fdem::kernels {

namespace {
constexpr int N = kJointBlock;
// The square roots of v[0..n), in place, two an SSE2 instruction (v 16-byte aligned): the
// same IEEE roots as std::sqrt, which gcc does not vectorise (it keeps errno).
inline void SqrtInPlace(double *v, int n) {
  int i = 0;
#if defined(__SSE2__)
  for (; i + 1 < n; i += 2) _mm_store_pd(v + i, _mm_sqrt_pd(_mm_load_pd(v + i)));
#endif
  for (; i < n; ++i) v[i] = std::sqrt(v[i]);
}
// The geometry of a block of joint elements at their three points (the edge midpoints),
// component-major so that the loop runs two joints per SSE2 instruction: the unit normal
// of the mid-surface, each point's weight (a third of its area), opening, slip vector and
// slip; ok = 0 where the mid-surface has collapsed (it carries nothing).
struct BlockGeometry {
  alignas(16) double n[3][N], w[N], ok[N], dn[3][N], sv[3][3][N], s[3][N];
  // The square roots are taken apart (SqrtInPlace), so that the loops between them hold
  // only arithmetic.
  void Set(const JointBlock &B) {
    const int          nb = B.n;
    alignas(16) double nn[3][N], twiceA[N], sep[3][3][N];
    for (int b = 0; b < nb; ++b) {
      double m[9], d[9];
      for (int c = 0; c < 9; ++c) m[c] = 0.5 * (B.xa[c][b] + B.xb[c][b]), d[c] = B.xb[c][b] - B.xa[c][b];
      const double e1[3] = {m[3] - m[0], m[4] - m[1], m[5] - m[2]};
      const double e2[3] = {m[6] - m[0], m[7] - m[1], m[8] - m[2]};
      nn[0][b] = e1[1] * e2[2] - e1[2] * e2[1], nn[1][b] = e1[2] * e2[0] - e1[0] * e2[2], nn[2][b] = e1[0] * e2[1] - e1[1] * e2[0];
      twiceA[b] = nn[0][b] * nn[0][b] + nn[1][b] * nn[1][b] + nn[2][b] * nn[2][b];
      // point q is the midpoint of the edge (q, q+1): shape values 1/2, 1/2, 0
      for (int q = 0; q < 3; ++q)
        for (int k = 0; k < 3; ++k) sep[q][k][b] = 0.5 * (d[3 * q + k] + d[3 * ((q + 1) % 3) + k]);
    }
    SqrtInPlace(twiceA, nb);
    for (int b = 0; b < nb; ++b) {
      const double inv = 1.0 / twiceA[b]; // inf or NaN where collapsed: dropped through ok
      ok[b] = twiceA[b] > 0 ? 1.0 : 0.0;
      for (int k = 0; k < 3; ++k) n[k][b] = nn[k][b] * inv;
      w[b] = twiceA[b] / 6.0;
      for (int q = 0; q < 3; ++q) {
        const double o = sep[q][0][b] * n[0][b] + sep[q][1][b] * n[1][b] + sep[q][2][b] * n[2][b];
        dn[q][b]       = o;
        for (int k = 0; k < 3; ++k) sv[q][k][b] = sep[q][k][b] - o * n[k][b];
        s[q][b] = sv[q][0][b] * sv[q][0][b] + sv[q][1][b] * sv[q][1][b] + sv[q][2][b] * sv[q][2][b];
      }
    }
    for (int q = 0; q < 3; ++q) SqrtInPlace(s[q], nb);
  }
};

// ---- the face rule of the compression (JointLaw::face_compression): its geometry and integral
// The geometry of a joint element at its three points (the edge midpoints): the unit
// normal of the mid-surface, each point's weight (a third of its area), opening, slip
// vector and slip. false when the mid-surface has collapsed (it carries nothing).
struct JointPoints {
  double n[3], w, dn[3], sv[3][3], s[3], dnv[3]; // dnv: the opening at the vertices
  bool   Set(const double xa[3][3], const double xb[3][3]) {
    double m[3][3], d[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) m[i][k] = 0.5 * (xa[i][k] + xb[i][k]), d[i][k] = xb[i][k] - xa[i][k];
    const double e1[3] = {m[1][0] - m[0][0], m[1][1] - m[0][1], m[1][2] - m[0][2]};
    const double e2[3] = {m[2][0] - m[0][0], m[2][1] - m[0][1], m[2][2] - m[0][2]};
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double twiceA = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(twiceA > 0)) return false;
    const double inv = 1.0 / twiceA;
    for (double &c : n) c *= inv;
    w = twiceA / 6.0;
    for (int i = 0; i < 3; ++i) dnv[i] = d[i][0] * n[0] + d[i][1] * n[1] + d[i][2] * n[2];
    for (int q = 0; q < 3; ++q) {
      // point q is the midpoint of the edge (q, q+1): shape values 1/2, 1/2, 0
      const int i = q, j = (q + 1) % 3;
      double    sep[3];
      for (int k = 0; k < 3; ++k) sep[k] = 0.5 * (d[i][k] + d[j][k]);
      dn[q] = sep[0] * n[0] + sep[1] * n[1] + sep[2] * n[2];
      for (int k = 0; k < 3; ++k) sv[q][k] = sep[k] - dn[q] * n[k];
      s[q] = std::sqrt(sv[q][0] * sv[q][0] + sv[q][1] * sv[q][1] + sv[q][2] * sv[q][2]);
    }
    return true;
  }
};
// The joint's compression over its face: with g_i = -dn_i the overlap at vertex i (> 0 where
// B has passed through A) and g linear over the triangle of area A, the integral of
// max(g, 0)^2 (m^4) and its derivatives dI/dg_i = 2 int max(g, 0) N_i dA (N_i the linear shape
// functions). Exact, in closed form: the part of the triangle where g >= 0 is the whole
// triangle, the corner triangle at the one vertex with g >= 0, or the quadrilateral left when
// the corner at the one vertex with g < 0 is cut off. The edges are cut where g = 0, at the
// fractions t of the text below, and the part is two triangles at most, on each of which
// products of linear functions integrate as A'/12 (sum f_v h_v + sum f_v sum h_v). When every
// g_i >= 0 it is the midpoints' rule (A/3) sum_q g_q^2 exactly, and its derivatives are the
// midpoints' forces.
double OverlapSquared(const double g[3], double A, double dI[3]) {
  dI[0] = dI[1] = dI[2] = 0;
  if (!(g[0] > 0 || g[1] > 0 || g[2] > 0)) return 0;
  const int inside = (g[0] >= 0) + (g[1] >= 0) + (g[2] >= 0);
  const double k = A / 12.0;
  if (inside == 3) {
    const double sg = g[0] + g[1] + g[2];
    for (int i = 0; i < 3; ++i) dI[i] = 2.0 * k * (g[i] + sg);
    return k * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2] + sg * sg);
  }
  if (inside == 1) { // the corner at p, cut at the fractions tq, tr of its edges to q and r
    const int    p = g[0] >= 0 ? 0 : g[1] >= 0 ? 1 : 2, q = (p + 1) % 3, r = (p + 2) % 3;
    const double tq = g[p] / (g[p] - g[q]), tr = g[p] / (g[p] - g[r]);
    const double c = 2.0 * k * tq * tr * g[p]; // twice the corner's A'/12, times g_p
    dI[p] = c * (4.0 - tq - tr), dI[q] = c * tq, dI[r] = c * tr;
    return c * g[p];
  }
  // the corner at r cut off, at the fractions tp, tq of the edges from p and q to r: the
  // triangles (p, q, Q) of area tq A and (p, Q, P) of area (1 - tq) tp A, with P, Q the cuts
  const int    r = g[0] < 0 ? 0 : g[1] < 0 ? 1 : 2, p = (r + 1) % 3, q = (r + 2) % 3;
  const double tp = g[p] / (g[p] - g[r]), tq = g[q] / (g[q] - g[r]);
  const double a1 = k * tq, a2 = k * (1.0 - tq) * tp, s1 = g[p] + g[q];
  dI[p] = 2.0 * (a1 * (g[p] + s1) + a2 * g[p] * (3.0 - tp));
  dI[q] = 2.0 * (a1 * (g[q] + s1 * (2.0 - tq)) + a2 * g[p] * (1.0 - tq));
  dI[r] = 2.0 * (a1 * s1 * tq + a2 * g[p] * (tq + tp));
  return a1 * (g[p] * g[p] + g[q] * g[q] + s1 * s1) + a2 * 2.0 * g[p] * g[p];
}
// The joint's compression (J): the larger of the penalty's energy at the midpoints (w per point,
// broken points included) and its exact integral over the pressed part of the face
// (OverlapSquared, with its derivatives in dI). *face tells which.
double Compression(const JointLaw &L, const JointPoints &P, double dI[3], bool *face) {
  double mid = 0;
  for (int q = 0; q < 3; ++q)
    if (P.dn[q] < 0) mid += P.w * P.dn[q] * P.dn[q];
  const double g[3] = {-P.dnv[0], -P.dnv[1], -P.dnv[2]};
  const double I    = OverlapSquared(g, 3.0 * P.w, dI);
  *face             = I > mid * (1 + 1e-9); // equal to round-off when the whole face is pressed in: the midpoints' forces are kept
  return L.ft * L.inv_dn_peak * (*face ? I : mid);
}
// (JointElementEnergy's face rule, also for a joint whose points have all broken: the
// compression it would keep if it stayed, JointRemovedCompression)
double FaceJointEnergy(const JointLaw &L, const double xa[3][3], const double xb[3][3], const JointState state[3]) {
  JointPoints P;
  if (!P.Set(xa, xb)) return 0;
  double e = 0;
  if (L.face_compression == 0) { // the points' rule: the law at the midpoints, its compression penalty kept by broken points
    for (int q = 0; q < 3; ++q)
      if (!state[q].broken()) e += P.w * JointStoredEnergy(L, P.dn[q], P.s[q], state[q]);
      else if (P.dn[q] < 0) e += P.w * L.ft * P.dn[q] * P.dn[q] / L.dn_peak;
    return e;
  }
  for (int q = 0; q < 3; ++q) // the law's energy without its compression term, which is Compression's (JointElementForces)
    if (!state[q].broken()) e += P.w * (JointStoredEnergy(L, P.dn[q], P.s[q], state[q]) - (P.dn[q] < 0 ? L.ft * P.dn[q] * P.dn[q] / L.dn_peak : 0.0));
  double dI[3];
  bool   face;
  return e + Compression(L, P, dI, &face);
}


} // namespace

// The face rule of the compression over a block, for JointBlockForces (after the points' laws):
// the compression is the larger of the penalty's energy at the midpoints (the points' tractions)
// and its exact integral over the part of the face pressed in (OverlapSquared), whose forces are
// then added in place of the points' compression. Only a face pressed in at a vertex and open
// at another can have the integral larger: where no vertex is pressed in neither has
// compression, and where none is open the two are equal. Sets face[b] = 1 where the integral
// is taken, its derivatives in dI, drops the points' compression (and a broken point's
// tractions) there from sigma and tau, and returns whether any joint has it. A function of its
// own so that its arrays do not crowd the registers of the points' path (the points' rule alone
// ran 1.3 times slower in bench_joint with this code inline).
__attribute__((target_clones("arch=x86-64-v3", "default"), noinline)) int FaceRule(const JointBlock &B, const BlockGeometry &G, double (*__restrict sigma)[N], double (*__restrict tau)[N], double *__restrict face, double (*__restrict dI)[N]) {
  const int nb = B.n;
  int                any_face = 0, any_rule = 0;
  alignas(32) double g[3][N], mixed[N], I[N], face_rule[N], broken[3][N];
  for (int b = 0; b < nb; ++b) {
    face[b] = 0, face_rule[b] = B.law[b]->face_compression != 0 ? 1.0 : 0.0;
    any_rule |= face_rule[b] != 0;
  }
  if (!any_rule) return 0; // the points' rule (-fdem_joint_face_compression false)
  for (int b = 0; b < nb; ++b)
    for (int q = 0; q < 3; ++q) broken[q][b] = B.state[b][q].broken() ? 1.0 : 0.0; // after the laws above
  for (int b = 0; b < nb; ++b) {
    for (int v = 0; v < 3; ++v) { // the overlap at the vertices, -(opening)
      double gv = 0;
      for (int k = 0; k < 3; ++k) gv -= (B.xb[3 * v + k][b] - B.xa[3 * v + k][b]) * G.n[k][b];
      g[v][b] = G.ok[b] != 0 ? gv : 0.0; // a collapsed mid-surface has no normal
    }
    // factors, not bools: gcc vectorises a loop of doubles alone
    const double in  = std::max(std::max(g[0][b] > 0 ? 1.0 : 0.0, g[1][b] > 0 ? 1.0 : 0.0), g[2][b] > 0 ? 1.0 : 0.0);
    const double out = std::max(std::max(g[0][b] < 0 ? 1.0 : 0.0, g[1][b] < 0 ? 1.0 : 0.0), g[2][b] < 0 ? 1.0 : 0.0);
    mixed[b]         = in * out * face_rule[b];
  }
  // OverlapSquared's I and dI for the mixed joints (0 for the others), branch-free: both
  // of its cases run on every lane, on the vertices rotated so that the one whose sign
  // differs from the other two comes first, and each lane keeps its own. The other lanes
  // run on a harmless overlap, so that no lane divides by 0.
  int any_mixed = 0; // none in many blocks: skip the integral
  for (int b = 0; b < nb; ++b) any_mixed |= mixed[b] != 0;
  for (int b = 0; b < nb && any_mixed; ++b) {
    // each choice as a blend with the factors 1 and 0 (as in JointBlockForces), on finite values
    const double m = mixed[b], o = 1.0 - m;
    const double g0 = m * g[0][b] + o, g1 = m * g[1][b] - o, g2 = m * g[2][b] - o;
    const double i0 = g0 >= 0 ? 1.0 : 0.0, i1 = g1 >= 0 ? 1.0 : 0.0, i2 = g2 >= 0 ? 1.0 : 0.0;
    const double s0 = (i0 != i1 ? 1.0 : 0.0) * (i0 != i2 ? 1.0 : 0.0), s1 = (i1 != i0 ? 1.0 : 0.0) * (i1 != i2 ? 1.0 : 0.0), s2 = 1.0 - s0 - s1; // the odd vertex
    // the vertices from the odd one on: u = g[s], v = g[s + 1], x = g[s + 2]
    const double u = s0 * g0 + s1 * g1 + s2 * g2, v = s0 * g1 + s1 * g2 + s2 * g0, x = s0 * g2 + s1 * g0 + s2 * g1;
    const double k = 3.0 * G.w[b] / 12.0;
    // the odd vertex alone pressed in: the corner at p = s
    const double tq = u / (u - v), tr = u / (u - x);
    const double cc = 2.0 * k * tq * tr * u;
    const double I1 = cc * u, d1s = cc * (4.0 - tq - tr), d1v = cc * tq, d1x = cc * tr;
    // the odd vertex alone open: the corner at r = s cut off, p = s + 1, q = s + 2
    const double tp = v / (v - u), tq2 = x / (x - u);
    const double a1 = k * tq2, a2 = k * (1.0 - tq2) * tp, s12 = v + x;
    const double d2v = 2.0 * (a1 * (v + s12) + a2 * v * (3.0 - tp));
    const double d2x = 2.0 * (a1 * (x + s12 * (2.0 - tq2)) + a2 * v * (1.0 - tq2));
    const double d2s = 2.0 * (a1 * s12 * tq2 + a2 * v * (tq2 + tp));
    const double I2  = a1 * (v * v + x * x + s12 * s12) + a2 * 2.0 * v * v;
    const double one = m * (u >= 0 ? 1.0 : 0.0), two = m - one; // lanes not mixed keep 0
    const double ds = one * d1s + two * d2s, dv = one * d1v + two * d2v, dx = one * d1x + two * d2x;
    I[b]     = one * I1 + two * I2;
    dI[0][b] = s0 * ds + s1 * dx + s2 * dv;
    dI[1][b] = s0 * dv + s1 * ds + s2 * dx;
    dI[2][b] = s0 * dx + s1 * dv + s2 * ds;
  }
  for (int b = 0; b < nb && any_mixed; ++b) {
    double mid = 0;
    for (int q = 0; q < 3; ++q) mid += (G.dn[q][b] < 0 ? 1.0 : 0.0) * (G.w[b] * G.dn[q][b] * G.dn[q][b]);
    face[b] = mixed[b] * (I[b] > mid * (1 + 1e-9) ? 1.0 : 0.0);
    any_face |= face[b] != 0;
    for (int q = 0; q < 3; ++q) { // the points keep their tension and shear; the face has their compression
      sigma[q][b] *= 1.0 - face[b] * std::max(G.dn[q][b] <= 0 ? 1.0 : 0.0, broken[q][b]);
      tau[q][b] *= 1.0 - face[b] * broken[q][b];
    }
  }
  return any_face;
}

__attribute__((target_clones("arch=x86-64-v3", "default"))) void JointBlockForces(JointBlock &B) {
  const int     nb = B.n;
  BlockGeometry G;
  G.Set(B);
  // the law's constants and the points' history, component-major
  alignas(32) double ft[N], two_ft[N], c[N], tan_phi[N], dn_peak[N], inv_dn_peak[N], slip_per_strength[N], K[N], undamaged[3][N], w0[3][N], last_s[3][N];
  for (int b = 0; b < nb; ++b) {
    const JointLaw &L = *B.law[b];
    ft[b] = L.ft, two_ft[b] = 2.0 * L.ft, c[b] = L.c, tan_phi[b] = L.tan_phi, dn_peak[b] = L.dn_peak, inv_dn_peak[b] = L.inv_dn_peak, slip_per_strength[b] = L.slip_per_strength;
    K[b] = L.shear_stiffness;
    for (int q = 0; q < 3; ++q) undamaged[q][b] = B.state[b][q].D == 0 ? 1.0 : 0.0, w0[q][b] = B.state[b][q].shear_damage, last_s[q][b] = B.state[b][q].last_shear;
  }
  bool was_broken[N]; // broken through before this evaluation
  for (int b = 0; b < nb; ++b) was_broken[b] = JointBroken(B.state[b]);
  // The common case for every point, two joints an instruction: an undamaged point below
  // both peaks is elastic in tension, and its tractions and shear damage are those of
  // JointTractionAt, with the law's reciprocals (the same to round-off). fast = 0 marks the
  // points that need JointTractionAt (done one by one below).
  alignas(16) double sigma[3][N], tau[3][N], fast[3][N], w1[3][N], dw_energy[3][N], psi_s[3][N];
  for (int q = 0; q < 3; ++q)
    for (int b = 0; b < nb; ++b) {
      // each choice as a blend with the factors 1 and 0, exact for finite values (gcc does not
      // vectorise a choice between computed values here: it moves their arithmetic into branches)
      const double dn = G.dn[q][b], x = dn * inv_dn_peak[b];
      const double pressed  = dn <= 0 ? 1.0 : 0.0, pulled = 1.0 - pressed;
      const double sigma0   = pressed * (two_ft[b] * x) + pulled * (ft[b] * x * (2.0 - x));
      const double fs       = c[b] - pressed * (sigma0 * tan_phi[b]); // > 0: compression only adds
      const double sp       = fs * slip_per_strength[b];
      const double s        = G.s[q][b], y = s / sp;
      const double w        = std::max(w0[q][b], (double)(float)(0.5 * y)); // the secant of the hardening branch (z = 1), as the state holds it
      sigma[q][b]     = sigma0;
      tau[q][b]       = (1.0 - w) * (K[b] * s);
      w1[q][b]        = w;
      // the shear energy, kept for the next evaluation, and the release of the shear damage's
      // growth at the step's mean slip (ShearDissipated; at this slip where none is kept). The
      // tension energy is kept from a point's first damaged evaluation on (JointTractionAt):
      // an undamaged point releases none.
      psi_s[q][b]     = 0.5 * K[b] * s * s;
      const double ms = last_s[q][b] >= 0 ? 0.5 * (last_s[q][b] + psi_s[q][b]) : psi_s[q][b];
      dw_energy[q][b] = (w - w0[q][b]) * ms;
      fast[q][b]      = (undamaged[q][b] != 0) & (dn <= dn_peak[b]) & (s <= sp) ? 1.0 : 0.0;
    }
  // the fast points' shear damage and its dissipated energy (where it grew), then the other
  // points, one at a time: damage, softening, broken points
  for (int b = 0; b < nb; ++b) {
    B.Dmax[b] = 0;
    if (G.ok[b] == 0) continue; // a collapsed mid-surface carries nothing and keeps its history
    JointState *state = B.state[b];
    double      fdiss = 0;
    for (int q = 0; q < 3; ++q)
      if (fast[q][b] != 0) {
        if (w1[q][b] != w0[q][b]) state[q].shear_damage = (float)w1[q][b], fdiss += dw_energy[q][b];
        state[q].last_shear = (float)psi_s[q][b];
      }
    double diss = G.w[b] * fdiss;
    if (fast[0][b] != 0 && fast[1][b] != 0 && fast[2][b] != 0) {
      if (diss != 0 && B.dissipated[b]) *B.dissipated[b] += diss;
      continue;
    }
    const JointLaw &L = *B.law[b];
    for (int q = 0; q < 3; ++q) {
      if (fast[q][b] != 0) continue;
      const JointTraction t = JointTractionAt(L, G.dn[q][b], G.s[q][b], state[q]);
      B.Dmax[b] = std::max(B.Dmax[b], t.D);
      diss += G.w[b] * t.dissipated;
      sigma[q][b] = t.sigma, tau[q][b] = t.tau;
    }
    if (JointBroken(state)) {
      // the faces are contact surfaces now; a joint that broke through at this evaluation takes
      // the compression its broken points kept with it: dissipated, so that no energy vanishes
      // (the contact books what its faces then hold, doc/fracture.md, "The handover to contact")
      if (!was_broken[b] && B.dissipated[b]) {
        double xa[3][3], xb[3][3];
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) xa[i][k] = B.xa[3 * i + k][b], xb[i][k] = B.xb[3 * i + k][b];
        diss += JointRemovedCompression(L, xa, xb);
      }
      if (B.dissipated[b]) *B.dissipated[b] += diss;
      G.ok[b] = 0;
      continue;
    }
    if (B.dissipated[b]) *B.dissipated[b] += diss;
    // A broken point of a joint that still holds (its other points intact) is not a contact
    // surface yet: it keeps the compression penalty, so that its faces cannot pass through each
    // other and meet the contact engine deeply overlapped when the joint breaks through.
    for (int q = 0; q < 3; ++q)
      if (state[q].broken()) sigma[q][b] = G.dn[q][b] < 0 ? NormalUndamaged(L, G.dn[q][b]) : 0.0, tau[q][b] = 0;
  }
  // the face rule of the compression (JointLaw::face_compression), in a function of its own
  alignas(32) double face[N], dI[3][N];
  const int          any_face = FaceRule(B, G, sigma, tau, face, dI);
  // the nodal forces, two joints an instruction: the traction on A (towards B; it pulls the
  // faces together when they open) at point q, times half its weight, on each node of its
  // edge (q, q+1); node i gets points i and i-1
  for (int b = 0; b < nb; ++b) {
    double f[3][3];
    for (int q = 0; q < 3; ++q) {
      // the slip's direction sv / s where s > 0; a slip of 0 (sv = 0 unless its squares
      // underflowed) adds nothing: divided by 1 and dropped by the factor 0
      const double slipping = G.s[q][b] > 0 ? 1.0 : 0.0, s = slipping != 0 ? G.s[q][b] : 1.0;
      const double r = slipping * (tau[q][b] / s);
      for (int k = 0; k < 3; ++k) {
        const double tr = sigma[q][b] * G.n[k][b] + r * G.sv[q][k][b];
        f[q][k]         = 0.5 * G.w[b] * tr;
      }
    }
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) B.fa[3 * i + k][b] = f[i][k] + f[(i + 2) % 3][k];
  }
  for (int b = 0; b < nb && any_face; ++b) // the face's forces: d(compression)/d(g_v) pushes B away from A along n
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) B.fa[3 * v + k][b] -= face[b] * (ft[b] * inv_dn_peak[b] * dI[v][b] * G.n[k][b]);
  for (int b = 0; b < nb; ++b)
    if (G.ok[b] == 0)
      for (int c = 0; c < 9; ++c) B.fa[c][b] = 0; // collapsed (n not finite), or every point broken
}

double JointElementForces(const JointLaw &L, const double xa[3][3], const double xb[3][3], JointState state[3], double fa[3][3], double fb[3][3], double *dissipated) {
  JointBlock B;
  B.n = 1, B.law[0] = &L, B.state[0] = state, B.dissipated[0] = dissipated;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) B.xa[3 * i + k][0] = xa[i][k], B.xb[3 * i + k][0] = xb[i][k];
  JointBlockForces(B);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) fa[i][k] += B.fa[3 * i + k][0], fb[i][k] -= B.fa[3 * i + k][0];
  return B.Dmax[0];
}

namespace {
// JointElementEnergy, also for a joint whose points have all broken (which it takes as removed)
double ElementEnergy(const JointLaw &L, const double xa[3][3], const double xb[3][3], const JointState state[3]) {
  if (L.face_compression != 0) return FaceJointEnergy(L, xa, xb, state);
  JointBlock B;
  B.n = 1;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) B.xa[3 * i + k][0] = xa[i][k], B.xb[3 * i + k][0] = xb[i][k];
  BlockGeometry G;
  G.Set(B);
  if (G.ok[0] == 0) return 0;
  double e = 0;
  for (int q = 0; q < 3; ++q)
    if (!state[q].broken()) e += G.w[0] * JointStoredEnergy(L, G.dn[q][0], G.s[q][0], state[q]);
    else if (G.dn[q][0] < 0) e += G.w[0] * L.ft * G.dn[q][0] * G.dn[q][0] / L.dn_peak; // the compression penalty it keeps
  return e;
}
} // namespace

double JointElementEnergy(const JointLaw &L, const double xa[3][3], const double xb[3][3], const JointState state[3]) {
  return JointBroken(state) ? 0.0 : ElementEnergy(L, xa, xb, state);
}

double JointRemovedCompression(const JointLaw &L, const double xa[3][3], const double xb[3][3]) {
  JointState broken[3];
  for (auto &s : broken) s.SetDamage(1);
  return ElementEnergy(L, xa, xb, broken);
}

} // namespace fdem::kernels
