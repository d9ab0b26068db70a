// Small tensor pieces shared by the materials (symmetric tensors as
// (xx, yy, zz, xy, yz, xz), F row-major).
#pragma once

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
} // namespace fdem::kernels
