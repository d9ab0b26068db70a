// Material munjiza_cst: the finite-strain constant-strain tetrahedron of
// Munjiza's book (eq 4.220 with 4.215, 4.218, 4.219); doc/element.md.
// One home for its stress, strain energy and partition weight; the row in
// table.hpp registers it.
#pragma once
#include "neo_hookean.hpp"
#include "tensor.hpp"

#include <cmath>

#include <fdem/kernels/cst.hpp>

namespace fdem::kernels {

// J = det F > 0 here:
//   T = E/(1+nu) Ed / J^(2/3) + E/(1-2nu) Es / J^(2/3) + 2 mu D / J^(2/3)
//   Ed = (B / J^(2/3) - I) / 2,  Es = (J^(2/3) - 1) I / 2,  B = F F^T.
// Small strain: Ed -> dev(eps), Es -> tr(eps)/3 I, so T -> 2G dev(eps) + K tr(eps) I
// which is Hooke's law exactly (doc/element.md).
struct MunjizaCST {
  static constexpr const char *kName = "munjiza_cst";
  static constexpr bool kSmallStrain = false;
  // Relative cost in the internal-force kernel (bench/cst_kernel): the METIS element weight.
  static constexpr int kCost = 2;
  // The scalar functions of J that Stress needs, computed by Prepare apart
  // from Stress so that the kernel can run them for a block of elements at
  // once (independent chains overlap in the pipeline): pre[0] = J^(-1/3).
  static constexpr int kPre = 1;
  static inline void Prepare(double J, double *pre) { pre[0] = InvCbrt(J); }
  // The same for n elements: pre0[b], pre1[b] from J[b] (the same values).
  static inline void PrepareBlock(const double *J, double *pre0, double * /*pre1*/, std::size_t n) { InvCbrtBlock(J, pre0, n); }
  // Symmetric tensors are stored as (xx, yy, zz, xy, yz, xz); F row-major.
  static inline void Stress(const MaterialCoeffs &c, const double *F, double J, const double *pre, const double *D, double *T) {
    double B[6];
    LeftCauchyGreen(F, B);
    const double B0 = B[0], B1 = B[1], B2 = B[2], B3 = B[3], B4 = B[4], B5 = B[5];
    const double w3 = pre[0];                                   // J^(-1/3)
    const double j23 = J * w3, ij23 = w3 * w3;
    const double a = 0.5 * c.c_dev * ij23;                      // E/(1+nu) * (1/2) / J^(2/3)
    const double aB = a * ij23;                                  // ... times B / J^(2/3)
    const double s = 0.5 * c.c_vol * (j23 - 1.0) * ij23 - a;     // volumetric part and the -I of Ed
    const double w = c.c_visc * ij23;                            // 2 mu / J^(2/3)
    T[0] = aB * B0 + s + w * D[0];
    T[1] = aB * B1 + s + w * D[1];
    T[2] = aB * B2 + s + w * D[2];
    T[3] = aB * B3 + w * D[3];
    T[4] = aB * B4 + w * D[4];
    T[5] = aB * B5 + w * D[5];
  }
  // The law is Cauchy-elastic but not hyperelastic: no exact potential exists.
  // Reported: the neo-Hookean potential with the same G and K, equal to third
  // order in the strain (doc/deformable.md).
  static double Energy(const MaterialCoeffs &c, const Mat3 &F) { return NeoHookean::Energy(c, F); }
};

} // namespace fdem::kernels
