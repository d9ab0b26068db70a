// Small tensor pieces shared by the materials (symmetric tensors as
// (xx, yy, zz, xy, yz, xz), F row-major).
#pragma once
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>

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
// from the exponent bits (the bits of J^(-1/3) are about 4/3 of the bits of
// 1.0 minus a third of J's; 3.5% off at worst), then two steps of the
// fourth-order iteration w <- w (1 + e/3 + 2e^2/9 + 14e^3/81), e = 1 - J w^3
// (the series of (1 - e)^(-1/3)): 3.5e-2 -> ~1e-7 -> round-off. About a
// quarter of the cost of std::cbrt plus a division, which was a third of the
// deformable step. Outside the normal range (J subnormal or infinite):
// 1 / std::cbrt(J).
inline double InvCbrt(double J) {
  if (!(J >= DBL_MIN && J <= DBL_MAX)) return 1.0 / std::cbrt(J);
  std::uint64_t i;
  std::memcpy(&i, &J, sizeof i);
  i = 0x553ef0ff289dd796ULL - i / 3;
  double w;
  std::memcpy(&w, &i, sizeof w);
  for (int k = 0; k < 2; ++k) {
    const double e = 1.0 - J * (w * w * w);
    w = w + w * (e * (1.0 / 3.0 + e * (2.0 / 9.0 + e * (14.0 / 81.0))));
  }
  return w;
}
} // namespace fdem::kernels
