// Material small_strain_linear: the linear tetrahedron; doc/element.md. One
// home for its stress, strain energy and partition weight; the row in
// table.hpp registers it.
#pragma once
#include <fdem/kernels/cst.hpp>

namespace fdem::kernels {

// eps = sym(F) - I, T = lambda tr(eps) I + 2G eps + 2 mu sym(Fdot).
// Forces use the reference geometry (f = -K u). Not objective: a rigid rotation strains it.
struct SmallStrainLinear {
  static constexpr const char *kName = "small_strain_linear";
  static constexpr bool kSmallStrain = true;
  static constexpr int kCost = 1; // relative kernel cost (bench/cst_kernel), the METIS element weight
  static constexpr int kPre = 0; // no scalar functions of J (see MunjizaCST::Prepare)
  static inline void Prepare(double, double *) {}
  static inline void PrepareBlock(const double *, double *, double *, std::size_t) {}
  static inline void Stress(const MaterialCoeffs &c, const double *F, double /*J*/, const double * /*pre*/, const double *D, double *T) {
    const double e0 = F[0] - 1.0, e1 = F[4] - 1.0, e2 = F[8] - 1.0;
    const double G2 = 2.0 * c.G, lt = c.lambda * (e0 + e1 + e2), w = c.c_visc;
    T[0] = G2 * e0 + lt + w * D[0];
    T[1] = G2 * e1 + lt + w * D[1];
    T[2] = G2 * e2 + lt + w * D[2];
    T[3] = c.G * (F[1] + F[3]) + w * D[3];
    T[4] = c.G * (F[5] + F[7]) + w * D[4];
    T[5] = c.G * (F[2] + F[6]) + w * D[5];
  }
  // Strain energy per reference volume: lambda/2 tr(eps)^2 + G eps:eps (exact for this law).
  static double Energy(const MaterialCoeffs &c, const Mat3 &F) {
    double e[3][3], tr = 0, ee = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) e[i][j] = 0.5 * (F(i, j) + F(j, i)) - (i == j ? 1 : 0);
    for (int i = 0; i < 3; ++i) tr += e[i][i];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ee += e[i][j] * e[i][j];
    return 0.5 * c.lambda * tr * tr + c.G * ee;
  }
};

} // namespace fdem::kernels
