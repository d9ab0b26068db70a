// Material neo_hookean: compressible neo-Hookean with an isochoric/volumetric
// split, for stretches beyond ~20%; doc/element.md. One home for its stress,
// strain energy and partition weight; the row in table.hpp registers it.
#pragma once
#include <cmath>

#include <fdem/kernels/cst.hpp>

namespace fdem::kernels {

//   T = G/J dev(J^(-2/3) B) + K/2 (J - 1/J) I + 2 mu D.
struct NeoHookean {
  static constexpr const char *kName = "neo_hookean";
  static constexpr bool kSmallStrain = false;
  static constexpr int kCost = 2; // relative kernel cost (bench/cst_kernel), the METIS element weight
  static inline void Stress(const MaterialCoeffs &c, const double *F, double J, const double *D, double *T) {
    const double B0 = F[0] * F[0] + F[1] * F[1] + F[2] * F[2];
    const double B1 = F[3] * F[3] + F[4] * F[4] + F[5] * F[5];
    const double B2 = F[6] * F[6] + F[7] * F[7] + F[8] * F[8];
    const double B3 = F[0] * F[3] + F[1] * F[4] + F[2] * F[5];
    const double B4 = F[3] * F[6] + F[4] * F[7] + F[5] * F[8];
    const double B5 = F[0] * F[6] + F[1] * F[7] + F[2] * F[8];
    const double cj = std::cbrt(J);
    const double iJ = 1.0 / J;
    const double g = c.G * iJ / (cj * cj);  // G / J * J^(-2/3)
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
