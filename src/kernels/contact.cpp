// Munjiza's potential contact force between two tetrahedra (book 2.6,
// eqs 2.35-2.55; doc/book.md C). Written from the equations, see
// doc/contact.md for the derivation of every weight used here.
#include "fdem/kernels/contact.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "fdem/kernels/error.hpp"
#include "fdem/kernels/tetmesh.hpp"

namespace fdem::kernels {
namespace {

// Barycentric coordinates closer to zero than this are taken as exactly zero,
// so that touching and coincident faces give exactly zero force.
constexpr double kSnap = 1e-13;

// The three vertices of the face opposite vertex k (orientation is fixed later).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

using Frame = TetFrame;

void MakeFrame(const Tet4 &t, const char *name, Frame &f) {
  const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], e3 = t[3] - t[0];
  const Vec3 c23 = cross(e2, e3), c31 = cross(e3, e1), c12 = cross(e1, e2);
  const double d = dot(e1, c23); // 6 V, signed
  const double s = dot(e1, e1) * dot(e2, e2) * dot(e3, e3);
  if (!std::isfinite(d) || !std::isfinite(s))
    throw InputError(std::string("PotentialContactForce: tetrahedron ") + name + " has non-finite coordinates");
  if (!(d * d > 1e-24 * s))
    throw InputError(std::string("PotentialContactForce: tetrahedron ") + name +
                     " is degenerate (zero volume relative to its edge lengths)");
  const double inv = 1.0 / d;
  f.o = t[0];
  f.g[1] = inv * c23;
  f.g[2] = inv * c31;
  f.g[3] = inv * c12;
  f.g[0] = -(f.g[1] + f.g[2] + f.g[3]);
  f.centroid = 0.25 * (t[0] + t[1] + t[2] + t[3]);
  f.vol = std::fabs(d) / 6.0;
}

inline void Barycentric(const Frame &f, const Vec3 &p, double lam[4]) {
  const Vec3 r = p - f.o;
  lam[1] = dot(f.g[1], r);
  lam[2] = dot(f.g[2], r);
  lam[3] = dot(f.g[3], r);
  lam[0] = 1.0 - lam[1] - lam[2] - lam[3];
}

// A polygon vertex in a face of the contactor: where it lies in the face, (u, v), the face's
// shape functions of its second and third vertices (the first's is 1 - u - v), and the values
// n[0..3] of the linear functions that clip it, carried along so that a vertex on a clipping
// plane has exactly 0 there: t's barycentric coordinates, or a sub-tetrahedron's shape
// functions of its base nodes and (n[3]) of the centroid. Positions are never needed.
struct PV {
  double n[4];
  double u, v;
};

// Sutherland-Hodgman clip of a convex polygon to n[k] >= 0.
inline int Clip(const PV *in, int nin, PV *out, int k) {
  int nout = 0;
  for (int i = 0; i < nin; ++i) {
    const PV &p = in[i];
    const PV &q = in[i + 1 == nin ? 0 : i + 1];
    const double dp = p.n[k], dq = q.n[k];
    const bool pin = dp >= 0, qin = dq >= 0;
    if (pin) out[nout++] = p;
    if (pin != qin) {
      const double s = dp / (dp - dq);
      PV &r = out[nout++];
      for (int j = 0; j < 4; ++j) r.n[j] = p.n[j] + s * (q.n[j] - p.n[j]);
      r.u = p.u + s * (q.u - p.u);
      r.v = p.v + s * (q.v - p.v);
      r.n[k] = 0.0;
    }
  }
  return nout;
}

// Does the plane n[k] = 0 cut off any of the polygon? (If not, Clip would copy it unchanged.)
inline bool Cuts(const PV *in, int nin, int k) {
  for (int i = 0; i < nin; ++i)
    if (in[i].n[k] < 0) return true;
  return false;
}

// The face's three vertices, whose barycentric coordinates in t are the rows lam[0..2].
inline void FaceVertices(const double *const lam[3], PV *face) {
  for (int m = 0; m < 3; ++m) {
    for (int k = 0; k < 4; ++k) face[m].n[k] = lam[m][k];
    face[m].u = m == 1, face[m].v = m == 2;
  }
}

// The polygon of np vertices in poly clipped to n[k] >= 0 for k < planes (a plane that cuts
// nothing is skipped); the result in poly or other, returned, np its vertex count (< 3 when
// nothing is left).
inline PV *ClipAll(PV *poly, PV *other, int &np, int planes) {
  for (int k = 0; k < planes && np > 0; ++k) {
    if (!Cuts(poly, np, k)) continue;
    np = Clip(poly, np, other, k);
    PV *tmp = poly; poly = other; other = tmp;
  }
  return poly;
}

// Twice the area of the triangle (p, q, r) in the face's (u, v): the share of the face's area.
inline double Share(const PV &p, const PV &q, const PV &r) {
  return (q.u - p.u) * (r.v - p.v) - (r.u - p.u) * (q.v - p.v);
}

struct PassResult {
  double energy = 0;   // polygon part of int phi_t dV over c cap t
  double volume3 = 0;  // polygon part of 3 * volume(c cap t)
  double frac[4] = {}; // area fraction of each contactor face lying inside t
  double area = 0;     // total polygon area
  double weight = 0;   // int phi_t dS over the polygons
  Vec3 moment{};       // int phi_t x dS over the polygons
};

// The fraction of the area of a triangle (the rows of lam: its vertices' barycentric
// coordinates in t, snapped) that lies inside t: the triangle clipped by t's four face
// planes, its area from the fan of the clipped polygon in the triangle's own coordinates.
double AreaInside(const double *const lam[3]) {
  bool allin = true;
  for (int m = 0; m < 3 && allin; ++m) allin = lam[m][0] >= 0 && lam[m][1] >= 0 && lam[m][2] >= 0 && lam[m][3] >= 0;
  if (allin) return 1;
  PV bufA[12], bufB[12];
  FaceVertices(lam, bufA);
  int np = 3;
  const PV *poly = ClipAll(bufA, bufB, np, 4);
  double D = 0;
  for (int q = 1; q + 1 < np; ++q) D += Share(poly[0], poly[q], poly[q + 1]);
  return D;
}

// One direction: the faces of contactor c inside target t, pushed by t's
// potential (penalty eps). Adds nodal forces to fc (contactor) and ft (target).
// lam[v][k]: lambda_k of t at contactor vertex v (Barycentric, snapped by SnapCoordinates).
// Only the faces in `faces` (bit f: the face opposite vertex f) are pushed; of the others
// only the area fraction inside t is found (r.frac, for the energy's base-face terms).
// Each face is clipped to t once, then split among t's sub-tetrahedra (each the part of t
// where lambda_o is the least, its potential linear); on each piece the integrals of the
// potential times the linear functions the forces need come from the piece's moments
// (its area, first and second moments in the face's (u, v)), as the potential and those
// functions are linear on the face.
// Compiled for x86-64-v3 as well, which the loader picks where the processor has it (its
// fused multiply-adds change the results by round-off).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void Pass(const Tet4 &c, const Frame &tf, const double lam[4][4], double eps, int faces, std::array<Vec3, 4> &fc,
          std::array<Vec3, 4> &ft, PassResult &r) {
  // A face plane of t with all of c strictly outside: no overlap at all.
  for (int k = 0; k < 4; ++k)
    if (lam[0][k] < 0 && lam[1][k] < 0 && lam[2][k] < 0 && lam[3][k] < 0) return;

  const double s = 0.25 * eps; // phi = s * N_centroid on every sub-tetrahedron
  PV bufA[16], bufB[16];
  PV subA[24], subB[24];
  for (int f = 0; f < 4; ++f) {
    const int *fv = kFace[f];
    const double *tri[3] = {lam[fv[0]], lam[fv[1]], lam[fv[2]]};
    // Skip a face with all three nodes strictly outside one face plane of t.
    bool out = false;
    for (int k = 0; k < 4 && !out; ++k) out = tri[0][k] < 0 && tri[1][k] < 0 && tri[2][k] < 0;
    if (out) continue;
    if (!(faces >> f & 1)) {
      // A face in a face plane of t is pushed all the same: the energy counts such a polygon
      // once, from t's side (on_base below), so its terms in the two tetrahedra sharing it
      // no longer cancel.
      bool in_plane = false;
      for (int k = 0; k < 4 && !in_plane; ++k) in_plane = tri[0][k] == 0 && tri[1][k] == 0 && tri[2][k] == 0;
      if (!in_plane) {
        r.frac[f] = AreaInside(tri);
        continue;
      }
    }

    Vec3 av = 0.5 * cross(c[fv[1]] - c[fv[0]], c[fv[2]] - c[fv[0]]); // area vector, made outward
    if (dot(c[f] - c[fv[0]], av) > 0) av = -av;
    const double dA = dot(c[fv[0]] - tf.centroid, av); // (distance of face plane from t's centroid) * area

    // The face clipped to t once (its vertices carry t's four barycentric coordinates)
    FaceVertices(tri, bufA);
    int       nf   = 3;
    const PV *face = ClipAll(bufA, bufB, nf, 4);
    if (nf < 3) continue;
    double wT[4] = {0, 0, 0, 0}, wC[3] = {0, 0, 0}, frac = 0, en = 0, vol3 = 0;
    for (int o = 0; o < 4; ++o) { // target sub-tetrahedron: base = face opposite o, apex = centroid
      const int *tv = kFace[o];
      // the polygon in the sub-tetrahedron's shape functions (2.48), N_I = lambda_I - lambda_o
      // for its base nodes and N_C = 4 lambda_o; it misses the sub-tetrahedron when one of
      // them is negative at every vertex
      PV  *poly = subA;
      bool skip[3] = {true, true, true}, allin = true;
      for (int i = 0; i < nf; ++i) {
        const double *lv = face[i].n;
        const double lo = lv[o];
        PV &q = poly[i];
        for (int k = 0; k < 3; ++k) {
          const double nk = lv[tv[k]] - lo;
          q.n[k]  = nk;
          skip[k] = skip[k] && nk < 0;
          allin   = allin && nk >= 0;
        }
        q.n[3] = 4.0 * lo;
        q.u    = face[i].u;
        q.v    = face[i].v;
      }
      if (skip[0] || skip[1] || skip[2]) continue;
      // Polygon in the base plane of t with the same outward normal: its
      // energy/volume share is counted once, from t's side (doc/contact.md).
      const bool on_base = tri[0][o] == 0 && tri[1][o] == 0 && tri[2][o] == 0 && dA > 0;
      int np = nf;
      if (!allin) {
        poly = ClipAll(poly, subB, np, 3);
        if (np < 3) continue;
      }
      // The piece's moments about its first vertex p0, over the fan of triangles from p0, as
      // shares of the face's area: with d = (u, v) - p0, over a triangle (p0, p1, p2) of share S,
      // int d = S/3 (d1 + d2) and int d d^T = S/12 (d1 d1^T + d2 d2^T + (d1 + d2)(d1 + d2)^T)
      // (the 1/3 and 1/12 applied once, below). A linear g is g(p0) + grad g . d on the face.
      double S0 = 0, Su = 0, Sv = 0, Suu = 0, Suv = 0, Svv = 0;
      const PV &p0 = poly[0];
      for (int q = 1; q + 1 < np; ++q) {
        const PV &p1 = poly[q], &p2 = poly[q + 1];
        const double u1 = p1.u - p0.u, v1 = p1.v - p0.v, u2 = p2.u - p0.u, v2 = p2.v - p0.v;
        const double S = u1 * v2 - u2 * v1, su = u1 + u2, sv = v1 + v2;
        S0 += S;
        Su += S * su;
        Sv += S * sv;
        Suu += S * (u1 * u1 + u2 * u2 + su * su);
        Suv += S * (u1 * v1 + u2 * v2 + su * sv);
        Svv += S * (v1 * v1 + v2 * v2 + sv * sv);
      }
      constexpr double k3 = 1.0 / 3.0, k12 = 1.0 / 12.0;
      const double Mu = k3 * Su, Mv = k3 * Sv, Muu = k12 * Suu, Muv = k12 * Suv, Mvv = k12 * Svv;
      // N_C = 4 lambda_o: W0 = int N_C, (Wu, Wv) = int N_C d; then int N_C g = g(p0) W0 + grad g . (Wu, Wv)
      const double c0 = p0.n[3], cu = 4 * (tri[1][o] - tri[0][o]), cv = 4 * (tri[2][o] - tri[0][o]);
      const double W0 = c0 * S0 + cu * Mu + cv * Mv;
      const double Wu = c0 * Mu + cu * Muu + cv * Muv;
      const double Wv = c0 * Mv + cu * Muv + cv * Mvv;
      for (int k = 0; k < 3; ++k) {
        const int I = tv[k];
        wT[I] += p0.n[k] * W0 + (tri[1][I] - tri[1][o] - tri[0][I] + tri[0][o]) * Wu + (tri[2][I] - tri[2][o] - tri[0][I] + tri[0][o]) * Wv;
      }
      const double cq = 0.25 * (c0 * W0 + cu * Wu + cv * Wv); // the centroid's share, 1/4 to each node
      for (double &w : wT) w += cq;
      wC[0] += (1 - p0.u - p0.v) * W0 - Wu - Wv; // the face's shape functions 1 - u - v, u and v
      wC[1] += p0.u * W0 + Wu;
      wC[2] += p0.v * W0 + Wv;
      frac += S0;
      if (!on_base) {
        // int_{c cap t_o} phi dV = 1/4 oint (x - centroid).n (phi + eps/12) dS; the
        // sub-tetrahedron's side faces pass through the centroid and drop out.
        en += dA * (s * W0 + eps * k12 * S0);
        vol3 += dA * S0;
      }
    }
    if (frac == 0) continue;
    for (int k = 0; k < 4; ++k) ft[k] += (s * wT[k]) * av;
    for (int m = 0; m < 3; ++m) fc[fv[m]] -= (s * wC[m]) * av;
    const double af = norm(av);
    const double phiS = s * af * (wC[0] + wC[1] + wC[2]);
    r.energy += 0.25 * en;
    r.volume3 += vol3;
    r.frac[f] = frac;
    r.area += af * frac;
    r.weight += phiS;
    r.moment += (s * af) * (wC[0] * c[fv[0]] + wC[1] * c[fv[1]] + wC[2] * c[fv[2]]);
  }
}

void CheckPenalty(double p, const char *name) {
  if (!(p >= 0) || !std::isfinite(p))
    throw InputError(std::string("PotentialContactForce: penalty_") + name +
                     " must be finite and >= 0, got " + std::to_string(p));
}

} // namespace

// True when every vertex of t lies strictly outside one face plane of the tetrahedron of f
// (a barycentric coordinate negative at all four): the two convex tetrahedra are then
// disjoint and every integral of the pair is zero. Most candidate pairs of a search end here.
// lam[v]: the barycentric coordinates of t's vertex v in f (kept for Pass).
static bool SeparatedByFace(const Frame &f, const Tet4 &t, double lam[4][4]) {
  for (int v = 0; v < 4; ++v) Barycentric(f, t[v], lam[v]);
  for (int k = 0; k < 4; ++k)
    if (lam[0][k] < 0 && lam[1][k] < 0 && lam[2][k] < 0 && lam[3][k] < 0) return true;
  return false;
}

void MakeTetFrame(const Tet4 &t, const char *name, TetFrame &f) { MakeFrame(t, name, f); }

// The two passes' barycentric coordinates, snapped once for both: each within kSnap of 0 is 0,
// so that a vertex on a face plane is on it exactly. And a face of a lying in a face plane of
// b is a face of b's in a face plane of a: the two passes must agree on it. A polygon of a's face in the base plane of one of b's sub-tetrahedra is
// left out of the energy (on_base in Pass), as b's base-face term counts it from the
// fraction of b's face inside a that the other pass finds; if only one pass found the faces
// coplanar (each snaps its own barycentric coordinates, and the two tetrahedra's sizes
// differ), the polygon's share of the energy was lost or counted twice: a shallow overlap of
// a ball's tetrahedron with a plate, whose faces met in one plane, reported -0.45 J instead
// of +0.20 J. So face f of a and face o of b are taken as coplanar in both passes when either
// pass sees them within kSnap and the other within a looser 1e-9, which their different
// sizes can need: the coordinates of both are then 0.
static void SnapCoordinates(double a_in_b[4][4], double b_in_a[4][4]) {
  for (int f = 0; f < 4; ++f)
    for (int o = 0; o < 4; ++o) {
      // almost always some vertex is well off the plane: the first of each face says so
      if (!(std::fabs(a_in_b[kFace[f][0]][o]) < 1e-9 && std::fabs(b_in_a[kFace[o][0]][f]) < 1e-9)) continue;
      double ma = 0, mb = 0; // a's face f from b's face plane o, b's face o from a's face plane f
      for (int m = 0; m < 3; ++m) {
        ma = std::max(ma, std::fabs(a_in_b[kFace[f][m]][o]));
        mb = std::max(mb, std::fabs(b_in_a[kFace[o][m]][f]));
      }
      if (!((ma < kSnap && mb < 1e-9) || (mb < kSnap && ma < 1e-9))) continue;
      for (int m = 0; m < 3; ++m) a_in_b[kFace[f][m]][o] = 0, b_in_a[kFace[o][m]][f] = 0;
    }
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 4; ++k) {
      if (std::fabs(a_in_b[v][k]) < kSnap) a_in_b[v][k] = 0;
      if (std::fabs(b_in_a[v][k]) < kSnap) b_in_a[v][k] = 0;
    }
}

namespace {

// Every vertex of t below face plane k of f: lambda_k < 0 at all four (the arithmetic of Barycentric).
bool BelowFace(const Frame &f, const Tet4 &t, int k) {
  for (int v = 0; v < 4; ++v) {
    const Vec3   r   = t[v] - f.o;
    const double lam = k == 0 ? 1.0 - dot(f.g[1], r) - dot(f.g[2], r) - dot(f.g[3], r) : dot(f.g[k], r);
    if (!(lam < 0)) return false;
  }
  return true;
}

// The vertices of a and b apart along the cross product of edge i of a and edge j of b.
bool ApartAcrossEdges(const Tet4 &a, const Tet4 &b, int i, int j) {
  const Vec3   ea = a[kTetEdges[i][1]] - a[kTetEdges[i][0]], eb = b[kTetEdges[j][1]] - b[kTetEdges[j][0]];
  const Vec3   n  = cross(ea, eb);
  const double nn = dot(n, n), la = dot(ea, ea), lb = dot(eb, eb);
  if (!(nn > 1e-12 * la * lb)) return false; // (nearly) parallel edges: no axis
  double amin = 0, amax = 0, bmin = dot(n, b[0] - a[0]), bmax = bmin;
  for (int v = 1; v < 4; ++v) {
    const double pa = dot(n, a[v] - a[0]), pb = dot(n, b[v] - a[0]);
    amin = std::min(amin, pa), amax = std::max(amax, pa);
    bmin = std::min(bmin, pb), bmax = std::max(bmax, pb);
  }
  // apart by more than 1e-9 |n| (|ea| + |eb|), tested as gap^2 > 2e-18 |n|^2 (|ea|^2 + |eb|^2), which
  // asks at most 1.42 times more and takes no root
  const double gap = std::max(bmin - amax, amin - bmax);
  return gap > 0 && gap * gap > 2e-18 * nn * (la + lb);
}
} // namespace

int SeparatingAxis(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb) {
  for (int k = 0; k < 4; ++k)
    if (BelowFace(fa, b, k)) return 1 + k;
  for (int k = 0; k < 4; ++k)
    if (BelowFace(fb, a, k)) return 5 + k;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      if (ApartAcrossEdges(a, b, i, j)) return 9 + 6 * i + j;
  return 0;
}

bool SeparatedAlong(int code, const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb) {
  if (code >= 1 && code <= 4) return BelowFace(fa, b, code - 1);
  if (code >= 5 && code <= 8) return BelowFace(fb, a, code - 5);
  if (code >= 9 && code <= 44) return ApartAcrossEdges(a, b, (code - 9) / 6, (code - 9) % 6);
  return false;
}

bool PotentialContactForce(const Tet4 &a, const Tet4 &b, double penalty_a, double penalty_b, TetPairContact &out) {
  Frame fa, fb;
  CheckPenalty(penalty_a, "a");
  CheckPenalty(penalty_b, "b");
  MakeFrame(a, "a", fa);
  MakeFrame(b, "b", fb);
  return PotentialContactForce(a, fa, b, fb, penalty_a, penalty_b, out);
}

bool PotentialContactForce(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb, double penalty_a,
                           double penalty_b, TetPairContact &out) {
  return PotentialContactForce(a, fa, b, fb, penalty_a, penalty_b, 15, 15, out);
}

bool PotentialContactForce(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb, double penalty_a,
                           double penalty_b, int faces_a, int faces_b, TetPairContact &out) {
  CheckPenalty(penalty_a, "a");
  CheckPenalty(penalty_b, "b");
  for (auto &v : out.fa) v = Vec3{};
  for (auto &v : out.fb) v = Vec3{};
  double b_in_a[4][4], a_in_b[4][4];
  if (SeparatedByFace(fa, b, b_in_a) || SeparatedByFace(fb, a, a_in_b)) {
    out.energy = out.area = out.weight = 0;
    out.point = Vec3{};
    out.overlap = false;
    return false;
  }
  SnapCoordinates(a_in_b, b_in_a);
  PassResult ab, ba;
  Pass(a, fb, a_in_b, penalty_b, faces_a, out.fa, out.fb, ab); // a's faces inside b, b's potential
  Pass(b, fa, b_in_a, penalty_a, faces_b, out.fb, out.fa, ba); // b's faces inside a, a's potential
  // Base-face terms of the divergence-theorem integrals (doc/contact.md):
  // sub-tetrahedron o of t contributes 1/4 h_o (eps/12) |face_o inside c|,
  // with h_o |face_o| = 3 |V_t| / 4.
  const double fa_in_b = ab.frac[0] + ab.frac[1] + ab.frac[2] + ab.frac[3];
  const double fb_in_a = ba.frac[0] + ba.frac[1] + ba.frac[2] + ba.frac[3];
  out.energy = ab.energy + ba.energy + (penalty_b * fb.vol * fb_in_a + penalty_a * fa.vol * fa_in_b) / 64.0;
  const double volume = (ab.volume3 + 0.75 * fb.vol * fb_in_a) / 3.0;
  out.area = 0.5 * (ab.area + ba.area);
  out.weight = ab.weight + ba.weight;
  out.point = out.weight > 0 ? (1.0 / out.weight) * (ab.moment + ba.moment) : Vec3{};
  const double vmin = fa.vol < fb.vol ? fa.vol : fb.vol;
  if ((faces_a & 15) == 15 && (faces_b & 15) == 15) out.overlap = out.weight > 0 || volume > 1e-12 * vmin;
  else out.overlap = out.weight > 0 || fa_in_b > 0 || fb_in_a > 0; // the volume is not known: some face meets the other
  return out.overlap;
}

bool PotentialContactForce(const Tet4 &a, const Tet4 &b, double penalty_a, double penalty_b, std::array<Vec3, 4> &fa,
                           std::array<Vec3, 4> &fb) {
  TetPairContact c;
  const bool hit = PotentialContactForce(a, b, penalty_a, penalty_b, c);
  fa = c.fa;
  fb = c.fb;
  return hit;
}

void ContactDampingFriction(const Tet4 &a, const Tet4 &b, const std::array<Vec3, 4> &va,
                            const std::array<Vec3, 4> &vb, const TetPairContact &contact,
                            const ContactDissipation &param, std::array<Vec3, 4> &fa, std::array<Vec3, 4> &fb) {
  Frame ta, tb;
  if (contact.overlap && contact.weight > 0) {
    MakeFrame(a, "a", ta);
    MakeFrame(b, "b", tb);
  }
  ContactDampingFriction(ta, tb, va, vb, contact, param, fa, fb);
}

void ContactDampingFriction(const TetFrame &ta, const TetFrame &tb, const std::array<Vec3, 4> &va,
                            const std::array<Vec3, 4> &vb, const TetPairContact &contact,
                            const ContactDissipation &param, std::array<Vec3, 4> &fa, std::array<Vec3, 4> &fb) {
  if (!(param.normal_damping >= 0) || !(param.friction >= 0) || !(param.tangential_viscosity >= 0) ||
      !std::isfinite(param.normal_damping) || !std::isfinite(param.friction) ||
      !std::isfinite(param.tangential_viscosity))
    throw InputError("ContactDampingFriction: normal_damping, friction and tangential_viscosity must be finite and >= 0");
  for (auto &v : fa) v = Vec3{};
  for (auto &v : fb) v = Vec3{};
  if (!contact.overlap || !(contact.weight > 0)) return;
  const Vec3 F = contact.fa[0] + contact.fa[1] + contact.fa[2] + contact.fa[3];
  const double Fmag = norm(F);
  if (!(Fmag > 0)) return;
  const Vec3 n = (1.0 / Fmag) * F;
  double la[4], lb[4];
  Barycentric(ta, contact.point, la);
  Barycentric(tb, contact.point, lb);
  Vec3 v{};
  for (int k = 0; k < 4; ++k) v += la[k] * va[k] - lb[k] * vb[k];
  const double vn = dot(v, n);
  const Vec3 vt = v - vn * n;
  const double A = contact.area;
  double Fn = -param.normal_damping * A * vn;
  if (Fn < -Fmag) Fn = -Fmag; // damping never makes the contact adhesive
  Vec3 Fd = Fn * n;
  const double vtm = norm(vt);
  if (vtm > 0) {
    const double coulomb = param.friction * (Fmag + Fn);
    const double visc = param.tangential_viscosity * A * vtm;
    Fd -= ((coulomb < visc ? coulomb : visc) / vtm) * vt;
  }
  for (int k = 0; k < 4; ++k) {
    fa[k] = la[k] * Fd;
    fb[k] = -lb[k] * Fd;
  }
}

} // namespace fdem::kernels
