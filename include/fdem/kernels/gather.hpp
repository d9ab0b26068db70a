// Gathering the 3-vectors of scattered nodes into component-major blocks, four nodes at a
// time with AVX2 (the element and joint kernels' inputs). Internal to the library.
#pragma once

#if defined(__x86_64__)
#include <immintrin.h>

namespace fdem::kernels {

// Whether the processor has AVX2 for GatherRows4, found once.
inline const bool kHasAVX2 = [] {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") != 0;
}();

// The vectors of nodes n[0..3] of the node array x (node i at x[3 i .. 3 i + 2]) into
// dx[0..3], dy[0..3], dz[0..3]: a node's three values loaded as one 4-double row
// (x[3 n - 1 .. 3 n + 2], its predecessor's z first, so that no load reads past the array's
// end; node 0 is built from scalars), the four rows transposed. The same values as four
// scalar gathers. Call it from a function compiled for AVX2, which inlines it.
__attribute__((target("avx2"), always_inline)) inline void GatherRows4(const double *x, const int n[4], double *dx, double *dy, double *dz) {
  __m256d r[4];
  for (int i = 0; i < 4; ++i) r[i] = n[i] > 0 ? _mm256_loadu_pd(x + 3 * n[i] - 1) : _mm256_set_pd(x[2], x[1], x[0], 0.0);
  const __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]); // (-, -, y0, y1), (x0, x1, z0, z1)
  const __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
  _mm256_storeu_pd(dx, _mm256_permute2f128_pd(t1, t3, 0x20));
  _mm256_storeu_pd(dy, _mm256_permute2f128_pd(t0, t2, 0x31));
  _mm256_storeu_pd(dz, _mm256_permute2f128_pd(t1, t3, 0x31));
}

} // namespace fdem::kernels
#endif
