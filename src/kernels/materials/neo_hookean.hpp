// Material neo_hookean: compressible neo-Hookean with an isochoric/volumetric
// split, for stretches beyond ~20%; doc/element.md. One home for its stress,
// strain energy and partition weight; the row in table.hpp registers it.
#pragma once
#include "tensor.hpp"

#include <cmath>

#include <fdem/kernels/cst.hpp>

namespace fdem::kernels {

//   T = G/J dev(J^(-2/3) B) + K/2 (J - 1/J) I + 2 mu D.
struct NeoHookean {
  static constexpr const char *kName = "neo_hookean";
  static constexpr bool kSmallStrain = false;
  static constexpr int kCost = 2; // relative kernel cost (bench/cst_kernel), the METIS element weight
  // pre[0] = J^(-1/3), pre[1] = 1/J (see MunjizaCST::Prepare)
  static constexpr int kPre = 2;
  static inline void Prepare(double J, double *pre) {
    pre[0] = InvCbrt(J);
    pre[1] = 1.0 / J;
  }
  static inline void PrepareBlock(const double *J, double *pre0, double *pre1, std::size_t n) {
    InvCbrtBlock(J, pre0, n);
    for (std::size_t b = 0; b < n; ++b) pre1[b] = 1.0 / J[b];
  }
  static inline void Stress(const MaterialCoeffs &c, const double *F, double J, const double *pre, const double *D, double *T) {
    double B[6];
    LeftCauchyGreen(F, B);
    const double B0 = B[0], B1 = B[1], B2 = B[2], B3 = B[3], B4 = B[4], B5 = B[5];
    const double w3 = pre[0];  // J^(-1/3)
    const double iJ = pre[1];
    const double g = c.G * iJ * (w3 * w3);  // G / J * J^(-2/3)
    const double tr3 = (B0 + B1 + B2) * (1.0 / 3.0);
    const double p = 0.5 * c.K * (J - iJ) - g * tr3;
    const double w = c.c_visc;
    T[0] = g * B0 + p + w * D[0];
    T[1] = g * B1 + p + w * D[1];
    T[2] = g * B2 + p + w * D[2];
    T[3] = g * B3 + w * D[3];
    T[4] = g * B4 + w * D[4];
    T[5] = g * B5 + w * D[5];
  }
  // Strain energy per reference volume: G/2 (I1 / J^(2/3) - 3) + K/2 ((J^2 - 1)/2 - ln J); NaN if J <= 0.
  static double Energy(const MaterialCoeffs &c, const Mat3 &F) {
    const double J = det(F);
    if (!(J > 0)) return NAN;
    double I1 = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) I1 += F(i, j) * F(i, j);
    return 0.5 * c.G * (I1 / std::cbrt(J * J) - 3) + 0.5 * c.K * (0.5 * (J * J - 1) - std::log(J));
  }
};

} // namespace fdem::kernels
