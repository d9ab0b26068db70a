// Small tensor pieces shared by the materials (symmetric tensors as
// (xx, yy, zz, xy, yz, xz), F row-major).
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstddef>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fdem::kernels {
// B = F F^T, the left Cauchy-Green tensor.
inline void LeftCauchyGreen(const double *F, double *B) {
  B[0] = F[0] * F[0] + F[1] * F[1] + F[2] * F[2];
  B[1] = F[3] * F[3] + F[4] * F[4] + F[5] * F[5];
  B[2] = F[6] * F[6] + F[7] * F[7] + F[8] * F[8];
  B[3] = F[0] * F[3] + F[1] * F[4] + F[2] * F[5];
  B[4] = F[3] * F[6] + F[4] * F[7] + F[5] * F[8];
  B[5] = F[0] * F[6] + F[1] * F[7] + F[2] * F[8];
}

// J^(-1/3) for J > 0, within 1.1 ulp of the exact value (checked against a
// long-double reference over the whole normal range; std::cbrt of glibc 2.36
// is itself up to ~4 ulp off). No library call and no division: an estimate
// from the high 32 bits of J (sign, exponent and 20 bits of mantissa: the
// bits of J^(-1/3) are about 4/3 of the bits of 1.0 minus a third of J's;
// 4% off at worst), then two steps of the fourth-order iteration
// w <- w (1 + e/3 + 2e^2/9 + 14e^3/81), e = 1 - J w^3 (the series of
// (1 - e)^(-1/3)): 4e-2 -> ~1e-6 -> round-off. About a quarter of the cost
// of std::cbrt plus a division, which was a third of the deformable step; the
// block form below runs two at once (SSE2) with the same operations.
// Outside the normal range (J subnormal or infinite): 1 / std::cbrt(J).
inline double InvCbrtEstimate(double J) {
  std::uint64_t i;
  std::memcpy(&i, &J, sizeof i);
  const std::int32_t hi = static_cast<std::int32_t>(i >> 32);
  const std::int32_t q = static_cast<std::int32_t>(static_cast<double>(hi) * (1.0 / 3.0));
  const std::uint64_t e = static_cast<std::uint64_t>(static_cast<std::uint32_t>(0x553ef0ff - q)) << 32;
  double w;
  std::memcpy(&w, &e, sizeof w);
  return w;
}
inline double InvCbrtRefine(double J, double w) {
  for (int k = 0; k < 2; ++k) {
    const double e = 1.0 - J * (w * w * w);
    w = w + w * (e * (1.0 / 3.0 + e * (2.0 / 9.0 + e * (14.0 / 81.0))));
  }
  return w;
}
inline bool InvCbrtNormal(double J) { return J >= DBL_MIN && J <= DBL_MAX; }
inline double InvCbrt(double J) {
  if (!InvCbrtNormal(J)) return 1.0 / std::cbrt(J);
  return InvCbrtRefine(J, InvCbrtEstimate(J));
}
// w[b] = InvCbrt(J[b]) for b < n, the same values, two at a time.
inline void InvCbrtBlock(const double *J, double *w, std::size_t n) {
  std::size_t b = 0;
#if defined(__SSE2__)
  for (; b + 2 <= n; b += 2) {
    const __m128d  j  = _mm_loadu_pd(J + b);
    const __m128i  hi = _mm_shuffle_epi32(_mm_castpd_si128(j), _MM_SHUFFLE(3, 1, 3, 1)); // high words in lanes 0, 1
    const __m128i  q  = _mm_cvttpd_epi32(_mm_mul_pd(_mm_cvtepi32_pd(hi), _mm_set1_pd(1.0 / 3.0)));
    const __m128i  e  = _mm_sub_epi32(_mm_set1_epi32(0x553ef0ff), q);
    const __m128i  e64 = _mm_slli_epi64(_mm_unpacklo_epi32(e, e), 32);  // (e, 0) words -> e << 32 per lane
    _mm_storeu_pd(w + b, _mm_castsi128_pd(e64));
  }
#endif
  for (; b < n; ++b) w[b] = InvCbrtEstimate(J[b]);
  for (b = 0; b < n; ++b) w[b] = InvCbrtRefine(J[b], w[b]);
  for (b = 0; b < n; ++b)
    if (!InvCbrtNormal(J[b])) w[b] = 1.0 / std::cbrt(J[b]);
}
} // namespace fdem::kernels
