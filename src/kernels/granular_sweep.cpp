// The sweep over sphere-sphere pairs (kernels/granular_sweep.hpp). SpherePairLaw is
// GranularForce's arithmetic written without branches; this file is compiled with
// -fno-math-errno -fno-trapping-math (CMakeLists.txt), so that a square root is one
// instruction. No pair computes a division by zero or the root of a negative number, so the
// options change no result and -fp_trap stays usable. The sweep is compiled twice, for
// x86-64 (SSE2) and for x86-64-v3 (AVX2, FMA), and the loader picks the one the processor runs.
#include "fdem/kernels/granular_sweep.hpp"

#include <type_traits>

namespace fdem::kernels {

namespace {
template <bool Hertz, bool Roll>
inline __attribute__((always_inline)) void Touching(const GranularPair &p, double dt, const SphereState &A, const SphereState &B, const SpherePairConst &c, Vec3 &s, SphereSum &sa, SphereSum &sb, double &energy) {
  const Vec3          d = A.x - B.x, dv = A.v - B.v;
  const SpherePairIn  in{d[0], d[1], d[2], A.r, B.r, dv[0], dv[1], dv[2], A.w[0], A.w[1], A.w[2], B.w[0], B.w[1], B.w[2], c.mstar, c.cn};
  const SpherePairOut o = SpherePairLaw<Hertz, Roll>(p, dt, in, s[0], s[1], s[2]);
  sa.f[0] += o.fx, sa.f[1] += o.fy, sa.f[2] += o.fz;
  sa.t[0] += o.tax, sa.t[1] += o.tay, sa.t[2] += o.taz;
  sb.f[0] -= o.fx, sb.f[1] -= o.fy, sb.f[2] -= o.fz;
  sb.t[0] += o.tbx, sb.t[1] += o.tby, sb.t[2] += o.tbz;
  energy += o.energy;
}

// Four touching pairs j[0..3] of one law side by side; their sums added in their order, as
// four calls of Touching would.
template <bool Hertz, bool Roll>
inline __attribute__((always_inline)) void Touching4(const GranularPair &p, double dt, const SphereState *s, const SpherePair *pairs, const SpherePairConst *pc, Vec3 *springs, const int *j, SphereSum *sum, double &energy) {
  const SphereState *A[4], *B[4];
  for (int k = 0; k < 4; ++k) A[k] = &s[pairs[j[k]].a], B[k] = &s[pairs[j[k]].b];
  auto lanes = [&](auto get) { return Lanes4{get(0), get(1), get(2), get(3)}; };
  SpherePairInT<Lanes4> in;
  in.dx    = lanes([&](int k) { return A[k]->x.x - B[k]->x.x; });
  in.dy    = lanes([&](int k) { return A[k]->x.y - B[k]->x.y; });
  in.dz    = lanes([&](int k) { return A[k]->x.z - B[k]->x.z; });
  in.ra    = lanes([&](int k) { return A[k]->r; });
  in.rb    = lanes([&](int k) { return B[k]->r; });
  in.vx    = lanes([&](int k) { return A[k]->v.x - B[k]->v.x; });
  in.vy    = lanes([&](int k) { return A[k]->v.y - B[k]->v.y; });
  in.vz    = lanes([&](int k) { return A[k]->v.z - B[k]->v.z; });
  in.wax   = lanes([&](int k) { return A[k]->w.x; });
  in.way   = lanes([&](int k) { return A[k]->w.y; });
  in.waz   = lanes([&](int k) { return A[k]->w.z; });
  in.wbx   = lanes([&](int k) { return B[k]->w.x; });
  in.wby   = lanes([&](int k) { return B[k]->w.y; });
  in.wbz   = lanes([&](int k) { return B[k]->w.z; });
  in.mstar = lanes([&](int k) { return pc[j[k]].mstar; });
  in.cn    = lanes([&](int k) { return pc[j[k]].cn; });
  Lanes4 sx = lanes([&](int k) { return springs[j[k]].x; });
  Lanes4 sy = lanes([&](int k) { return springs[j[k]].y; });
  Lanes4 sz = lanes([&](int k) { return springs[j[k]].z; });
  const SpherePairOutT<Lanes4> o = SpherePairLaw<Hertz, Roll>(p, dt, in, sx, sy, sz);
  for (int k = 0; k < 4; ++k) {
    const SpherePair &q = pairs[j[k]];
    springs[j[k]]       = Vec3(sx[k], sy[k], sz[k]);
    SphereSum &sa = sum[q.a], &sb = sum[q.b];
    sa.f[0] += o.fx[k], sa.f[1] += o.fy[k], sa.f[2] += o.fz[k];
    sa.t[0] += o.tax[k], sa.t[1] += o.tay[k], sa.t[2] += o.taz[k];
    sb.f[0] -= o.fx[k], sb.f[1] -= o.fy[k], sb.f[2] -= o.fz[k];
    sb.t[0] += o.tbx[k], sb.t[1] += o.tby[k], sb.t[2] += o.tbz[k];
    energy += o.energy[k];
  }
}

// The law of pairs j[0..m) of law p: four at a time if m is 4, one at a time otherwise.
inline __attribute__((always_inline)) void Law(const GranularPair &p, double dt, const SphereState *s, const SpherePair *pairs, const SpherePairConst *pc, Vec3 *springs, const int *j, int m, SphereSum *sum, double &energy) {
  const bool hertz = p.law == GranularLaw::Hertz, roll = p.mu_roll > 0;
  if (m == 4) {
    if (hertz) roll ? Touching4<true, true>(p, dt, s, pairs, pc, springs, j, sum, energy) : Touching4<true, false>(p, dt, s, pairs, pc, springs, j, sum, energy);
    else roll ? Touching4<false, true>(p, dt, s, pairs, pc, springs, j, sum, energy) : Touching4<false, false>(p, dt, s, pairs, pc, springs, j, sum, energy);
    return;
  }
  for (int k = 0; k < m; ++k) {
    const SpherePair &q = pairs[j[k]];
    const SphereState &A = s[q.a], &B = s[q.b];
    if (hertz) roll ? Touching<true, true>(p, dt, A, B, pc[j[k]], springs[j[k]], sum[q.a], sum[q.b], energy) : Touching<true, false>(p, dt, A, B, pc[j[k]], springs[j[k]], sum[q.a], sum[q.b], energy);
    else roll ? Touching<false, true>(p, dt, A, B, pc[j[k]], springs[j[k]], sum[q.a], sum[q.b], energy) : Touching<false, false>(p, dt, A, B, pc[j[k]], springs[j[k]], sum[q.a], sum[q.b], energy);
  }
}
} // namespace

// The touching pairs wait in groups of four of one law; a group is run when it is full, when
// a pair of another law comes, and at the end.
__attribute__((target_clones("arch=x86-64-v3", "default"))) void SphereContactSweep(const GranularPair *laws, double dt, const SphereState *s, const SpherePair *pairs, const SpherePairConst *pc, Vec3 *springs, int n, SphereSum *sum, SphereSweep &out) {
  out.touching.clear();
  out.started.clear();
  out.opened.clear();
  out.bad.clear();
  constexpr int kChunk = 128;
  int           pick[kChunk], group[4], m = 0;
  double        energy = 0;
  for (int j0 = 0; j0 < n; j0 += kChunk) {
    const int j1 = j0 + kChunk < n ? j0 + kChunk : n;
    int       np = 0;
    for (int j = j0; j < j1; ++j) { // the distance test without a branch: a dense packing's candidates touch at random
      const SpherePair &q = pairs[j];
      const Vec3        d  = s[q.a].x - s[q.b].x;
      const double      rr = s[q.a].r + s[q.b].r, d2 = dot(d, d);
      const bool        touch = d2 < rr * rr, bad = touch & ((q.law < 0) | !(d2 > 0));
      pick[np] = j;
      np += touch & !bad;
      if ((!touch & (q.slot >= 0)) | bad) (bad ? out.bad : out.opened).push_back(j); // rare: a contact that opened, or an error
    }
    for (int i = 0; i < np; ++i) {
      const int         j = pick[i];
      const SpherePair &q = pairs[j];
      if (q.slot < 0) {
        springs[j] = Vec3();
        out.started.push_back(j);
      }
      out.touching.push_back(j);
      if (m > 0 && pairs[group[0]].law != q.law) Law(laws[pairs[group[0]].law], dt, s, pairs, pc, springs, group, m, sum, energy), m = 0;
      group[m++] = j;
      if (m == 4) Law(laws[q.law], dt, s, pairs, pc, springs, group, m, sum, energy), m = 0;
    }
  }
  if (m > 0) Law(laws[pairs[group[0]].law], dt, s, pairs, pc, springs, group, m, sum, energy);
  out.energy = energy;
}

} // namespace fdem::kernels
