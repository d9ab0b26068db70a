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
inline __attribute__((always_inline)) void Touching(const GranularPair &p, double dt, const SphereState &A, const SphereState &B, const Vec3 &d, const SpherePairConst &c, Vec3 &s, SphereSum &sa, SphereSum &sb, double &energy) {
  const Vec3          dv = A.v - B.v;
  const SpherePairIn  in{d[0], d[1], d[2], A.r, B.r, dv[0], dv[1], dv[2], A.w[0], A.w[1], A.w[2], B.w[0], B.w[1], B.w[2], c.mstar, c.cn};
  const SpherePairOut o = SpherePairLaw<Hertz, Roll>(p, dt, in, s[0], s[1], s[2]);
  sa.f[0] += o.fx, sa.f[1] += o.fy, sa.f[2] += o.fz;
  sa.t[0] += o.tax, sa.t[1] += o.tay, sa.t[2] += o.taz;
  sb.f[0] -= o.fx, sb.f[1] -= o.fy, sb.f[2] -= o.fz;
  sb.t[0] += o.tbx, sb.t[1] += o.tby, sb.t[2] += o.tbz;
  energy += o.energy;
}
} // namespace

__attribute__((target_clones("arch=x86-64-v3", "default"))) void SphereContactSweep(const GranularPair *laws, double dt, const SphereState *s, const SpherePair *pairs, const SpherePairConst *pc, Vec3 *springs, int n, SphereSum *sum, SphereSweep &out) {
  out.touching.clear();
  out.started.clear();
  out.opened.clear();
  out.bad.clear();
  double energy = 0;
  for (int j = 0; j < n; ++j) {
    const SpherePair  &q = pairs[j];
    const SphereState &A = s[q.a], &B = s[q.b];
    const Vec3         d  = A.x - B.x;
    const double       rr = A.r + B.r, d2 = dot(d, d);
    if (!(d2 < rr * rr)) {
      if (q.slot >= 0) out.opened.push_back(j);
      continue;
    }
    if (q.law < 0 || !(d2 > 0)) {
      out.bad.push_back(j);
      continue;
    }
    if (q.slot < 0) {
      springs[j] = Vec3();
      out.started.push_back(j);
    }
    out.touching.push_back(j);
    const GranularPair &p = laws[q.law];
    if (p.law == GranularLaw::Hertz) {
      if (p.mu_roll > 0) Touching<true, true>(p, dt, A, B, d, pc[j], springs[j], sum[q.a], sum[q.b], energy);
      else Touching<true, false>(p, dt, A, B, d, pc[j], springs[j], sum[q.a], sum[q.b], energy);
    } else if (p.mu_roll > 0) Touching<false, true>(p, dt, A, B, d, pc[j], springs[j], sum[q.a], sum[q.b], energy);
    else Touching<false, false>(p, dt, A, B, d, pc[j], springs[j], sum[q.a], sum[q.b], energy);
  }
  out.energy = energy;
}

} // namespace fdem::kernels
