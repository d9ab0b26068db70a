// The internal-force kernel's batched loop (cst.cpp), shared with the stresses of cst_stress.cpp:
// one copy per translation unit (an anonymous namespace), so that a new use of the loop in
// another file leaves the force kernel's compiled code as it was (gcc decides what to inline
// per file, and what it inlines decides where multiply-adds fuse).
#pragma once
#include <fdem/kernels/cst.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <fdem/kernels/gather.hpp>

#include "materials/table.hpp"

namespace fdem::kernels {

// ---------------------------------------------------------------- the batched loop
// The constitutive models live in materials/ (one file each) and are listed in
// materials/table.hpp; symmetric tensors are stored as (xx, yy, zz, xy, yz, xz).
namespace {

// Diagnostics written by Core.
struct Extra {
  double F[9], L[9], D[6], J;
};

// An element's kinematics from the positions alone: the current edge matrix
// C = [x1-x0, x2-x0, x3-x0] (row-major), its adjugate A (C^-1 = A / det C;
// row a of C^-1 is grad N_{a+1}, current), det C, J = det F and the model's
// scalar functions of J (Model::Prepare, when J > 0 or the model is
// small-strain). The one-element path (Core) keeps it; the batched loop makes
// the same values a block at a time.
struct Kin {
  double c[9], A[9], detC, J, pre[2];
};

// C, its adjugate and det C from the four corners X = (x0, x1, x2, x3).
inline void EdgeMatrix(const double *X, double *C, double *A, double &detC) {
  const double *x0 = X, *x1 = X + 3, *x2 = X + 6, *x3 = X + 9;
  const double c00 = x1[0] - x0[0], c01 = x2[0] - x0[0], c02 = x3[0] - x0[0];
  const double c10 = x1[1] - x0[1], c11 = x2[1] - x0[1], c12 = x3[1] - x0[1];
  const double c20 = x1[2] - x0[2], c21 = x2[2] - x0[2], c22 = x3[2] - x0[2];
  C[0] = c00, C[1] = c01, C[2] = c02;
  C[3] = c10, C[4] = c11, C[5] = c12;
  C[6] = c20, C[7] = c21, C[8] = c22;
  const double A00 = c11 * c22 - c12 * c21, A01 = c02 * c21 - c01 * c22, A02 = c01 * c12 - c02 * c11;
  const double A10 = c12 * c20 - c10 * c22, A11 = c00 * c22 - c02 * c20, A12 = c02 * c10 - c00 * c12;
  const double A20 = c10 * c21 - c11 * c20, A21 = c01 * c20 - c00 * c21, A22 = c00 * c11 - c01 * c10;
  A[0] = A00, A[1] = A01, A[2] = A02;
  A[3] = A10, A[4] = A11, A[5] = A12;
  A[6] = A20, A[7] = A21, A[8] = A22;
  detC = c00 * A00 + c01 * A10 + c02 * A20;
}

template <class Model>
inline void Kinematics(const TetElement &el, const double *__restrict x, Kin &k) {
  double X[12];
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j) X[3 * a + j] = x[3 * el.n[a] + j];
  EdgeMatrix(X, k.c, k.A, k.detC);
  k.J = k.detC * el.inv6V0;
  k.pre[0] = k.pre[1] = 0;
  if (Model::kSmallStrain || k.J > 0) Model::Prepare(k.J, k.pre);
}

// R = P Q, all three 3x3 and row-major.
inline void Product33(const double *P, const double *Q, double *R) {
  const double p00 = P[0], p01 = P[1], p02 = P[2];
  const double p10 = P[3], p11 = P[4], p12 = P[5];
  const double p20 = P[6], p21 = P[7], p22 = P[8];
  R[0] = p00 * Q[0] + p01 * Q[3] + p02 * Q[6];
  R[1] = p00 * Q[1] + p01 * Q[4] + p02 * Q[7];
  R[2] = p00 * Q[2] + p01 * Q[5] + p02 * Q[8];
  R[3] = p10 * Q[0] + p11 * Q[3] + p12 * Q[6];
  R[4] = p10 * Q[1] + p11 * Q[4] + p12 * Q[7];
  R[5] = p10 * Q[2] + p11 * Q[5] + p12 * Q[8];
  R[6] = p20 * Q[0] + p21 * Q[3] + p22 * Q[6];
  R[7] = p20 * Q[1] + p21 * Q[4] + p22 * Q[7];
  R[8] = p20 * Q[2] + p21 * Q[5] + p22 * Q[8];
}

// F = C Xref^-1 (eqs 4.209-4.211); C and Xi row-major.
inline void DeformationGradient(const double *C, const double *Xi, double *F) { Product33(C, Xi, F); }

// Nodal forces f_a = -vol T grad N_a (eq 4.221 with the 1/3 face split:
// equals T a_a / 3, a_a the outward area vector of the face opposite a);
// A = adj(C), Xi = Xref^-1, V0 the reference volume.
template <class Model>
inline void NodalForces(const double *T, const double *A, const double *Xi, double V0, double *fe) {
  double g[9];
  if constexpr (Model::kSmallStrain) {
    const double s = -V0;  // reference volume times reference gradients
    for (int i = 0; i < 9; ++i) g[i] = s * Xi[i];
  } else {
    (void)Xi, (void)V0;
    const double s = -1.0 / 6.0;  // vol * C^-1 = adj(C) / 6
    for (int i = 0; i < 9; ++i) g[i] = s * A[i];
  }
  double s0 = 0, s1 = 0, s2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double gx = g[3 * a], gy = g[3 * a + 1], gz = g[3 * a + 2];
    const double fx = T[0] * gx + T[3] * gy + T[5] * gz;
    const double fy = T[3] * gx + T[1] * gy + T[4] * gz;
    const double fz = T[5] * gx + T[4] * gy + T[2] * gz;
    fe[3 * (a + 1)] = fx, fe[3 * (a + 1) + 1] = fy, fe[3 * (a + 1) + 2] = fz;
    s0 += fx, s1 += fy, s2 += fz;
  }
  fe[0] = -s0, fe[1] = -s1, fe[2] = -s2;
}

// The velocity gradient L and the rate of deformation D = sym(L) (stored as T is) of an
// element from its corners' velocities V = (v0, v1, v2, v3): with W = [v1-v0, v2-v0, v3-v0],
// L = W Xref^-1 small-strain, else L = W C^-1 = W adj(C) / det C = Fdot F^-1 (eq 4.212).
template <class Model>
inline void VelocityGradient(const double *V, const double *A, double detC, const double *Xi, double *L, double *D) {
  const double W[9] = {V[3] - V[0], V[6] - V[0], V[9] - V[0], V[4] - V[1], V[7] - V[1], V[10] - V[1], V[5] - V[2], V[8] - V[2], V[11] - V[2]};
  if constexpr (Model::kSmallStrain) {
    (void)A, (void)detC;
    Product33(W, Xi, L);
  } else {
    (void)Xi;
    Product33(W, A, L);
    const double id = 1.0 / detC;
    for (int k = 0; k < 9; ++k) L[k] *= id;
  }
  D[0] = L[0];
  D[1] = L[4];
  D[2] = L[8];
  D[3] = 0.5 * (L[1] + L[3]);
  D[4] = 0.5 * (L[5] + L[7]);
  D[5] = 0.5 * (L[2] + L[6]);
}

// Status: 0 ok, 1 inverted and force skipped, 2 inverted but force computed.
template <class Model, bool Visc>
inline int Forces(const TetElement &el, const MaterialCoeffs &c, const Kin &k, const double *__restrict v,
                  double *__restrict T, double *__restrict fe, Extra *ex) {
  const double *Xi = el.Xinv;
  double F[9];
  DeformationGradient(k.c, Xi, F);
  const double detC = k.detC;
  const double J = k.J;
  int status = 0;
  if (!(J > 0)) {
    if constexpr (!Model::kSmallStrain) {
      ex->J = J;
      return 1;
    }
    status = 2;
  }
  double D[6] = {0, 0, 0, 0, 0, 0};
  double L[9];
  if constexpr (Visc) {
    double V[12];
    for (int a = 0; a < 4; ++a)
      for (int j = 0; j < 3; ++j) V[3 * a + j] = v[3 * el.n[a] + j];
    VelocityGradient<Model>(V, k.A, detC, Xi, L, D);
  } else {
    (void)v;
    for (double &l : L) l = 0;
  }
  Model::Stress(c, F, J, k.pre, D, T);
  for (int i = 0; i < 9; ++i) ex->F[i] = F[i], ex->L[i] = L[i];
  for (int i = 0; i < 6; ++i) ex->D[i] = D[i];
  ex->J = J;
  NodalForces<Model>(T, k.A, Xi, el.V0, fe);
  return status;
}

// One element, kinematics and forces (diagnostics: EvaluateTet).
template <class Model, bool Visc>
inline int Core(const TetElement &el, const MaterialCoeffs &c, const double *__restrict x, const double *__restrict v,
                double *__restrict T, double *__restrict fe, Extra *ex) {
  Kin k;
  Kinematics<Model>(el, x, k);
  return Forces<Model, Visc>(el, c, k, v, T, fe, ex);
}

// Elements of one material from elems[0] on, in blocks of kBlock: the
// kinematics of the block first (its cube roots are independent and overlap),
// then stress and forces element by element, each element's forces added to
// its nodes in element order (the same sums, in the same order, as one
// element at a time).
constexpr std::size_t kBlock = 16;

// A block's inputs, component-major: corner a's coordinate k of element b at x[3 a + k][b] (and
// its velocity at v[3 a + k][b] when the material is viscous), the rows of X^-1, V0 and 1/(6 V0).
// Gathered from the element records and the node arrays.
struct BlockInputs {
  alignas(32) double x[12][kBlock], v[12][kBlock], Xi[9][kBlock], V0[kBlock], inv6V0[kBlock];
};

// Elements b0 .. nb - 1 of the block, one value at a time (v: the node velocities, or nullptr).
void GatherColumns(const TetElement *elems, std::size_t b0, std::size_t nb, const double *x, const double *v, BlockInputs &in) {
  for (std::size_t b = b0; b < nb; ++b) {
    const TetElement &el = elems[b];
    for (int a = 0; a < 4; ++a)
      for (int j = 0; j < 3; ++j) in.x[3 * a + j][b] = x[3 * el.n[a] + j];
    if (v)
      for (int a = 0; a < 4; ++a)
        for (int j = 0; j < 3; ++j) in.v[3 * a + j][b] = v[3 * el.n[a] + j];
    for (int j = 0; j < 9; ++j) in.Xi[j][b] = el.Xinv[j];
    in.V0[b] = el.V0, in.inv6V0[b] = el.inv6V0;
  }
}

#if defined(__x86_64__)
// The corners of elements e[0..3] from the node array x into the columns b .. b + 3 of dst
// (GatherRows4, corner by corner).
__attribute__((target("avx2"))) inline void CornersAVX2(const TetElement *e, const double *x, double (*dst)[kBlock], std::size_t b) {
  for (int a = 0; a < 4; ++a) {
    const int n[4] = {e[0].n[a], e[1].n[a], e[2].n[a], e[3].n[a]};
    GatherRows4(x, n, &dst[3 * a][b], &dst[3 * a + 1][b], &dst[3 * a + 2][b]);
  }
}

// Four elements at a time with AVX2: the corners (CornersAVX2) and the constants, from three
// 4-double rows of each record (X^-1 0..3, 4..7, and X^-1 7, X^-1 8, V0, 1/(6V0)) transposed
// likewise. The same values as GatherColumns.
__attribute__((target("avx2"))) void GatherAVX2(const TetElement *elems, std::size_t nb, const double *x, const double *v, BlockInputs &in) {
  static_assert(offsetof(TetElement, inv6V0) == offsetof(TetElement, Xinv) + 10 * sizeof(double), "the record's constants in a row");
  std::size_t b = 0;
  for (; b + 4 <= nb; b += 4) {
    const TetElement *e = elems + b;
    CornersAVX2(e, x, in.x, b);
    if (v) CornersAVX2(e, v, in.v, b);
    for (int row = 0; row < 3; ++row) { // constants j0 .. j0 + 3 of the four records
      const int j0 = row == 2 ? 7 : 4 * row;
      __m256d   r[4];
      for (int i = 0; i < 4; ++i) r[i] = _mm256_loadu_pd(e[i].Xinv + j0);
      const __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
      const __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
      const __m256d c0 = _mm256_permute2f128_pd(t0, t2, 0x20), c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
      const __m256d c2 = _mm256_permute2f128_pd(t0, t2, 0x31), c3 = _mm256_permute2f128_pd(t1, t3, 0x31);
      if (row < 2) {
        _mm256_store_pd(&in.Xi[j0][b], c0), _mm256_store_pd(&in.Xi[j0 + 1][b], c1);
        _mm256_store_pd(&in.Xi[j0 + 2][b], c2), _mm256_store_pd(&in.Xi[j0 + 3][b], c3);
      } else { // c0 is X^-1 7 again
        _mm256_store_pd(&in.Xi[8][b], c1), _mm256_store_pd(in.V0 + b, c2), _mm256_store_pd(in.inv6V0 + b, c3);
      }
    }
  }
  GatherColumns(elems, b, nb, x, v, in);
}
#endif

// Asks for the cache line at p. Written out on x86-64: gcc 12's dead-code elimination drops
// some __builtin_prefetch calls without a word (a loop of them over records vanished whole
// when its count was the byte bound).
inline void PrefetchLine(const void *p) {
#if defined(__x86_64__)
  __asm__ volatile("prefetcht0 %0" : : "m"(*static_cast<const char *>(p)));
#else
  __builtin_prefetch(p);
#endif
}

// The next block's records (from i + kBlock on, those that exist) asked for, so that they
// arrive while this block computes: the hardware's own prefetch left the first touch of each
// record waiting on memory (doc/performance.md, "The deformable step"). Two blocks ahead was
// slower.
inline void PrefetchNextBlock(const TetElement *elems, std::size_t i, std::size_t count) {
  if (i + kBlock >= count) return;
  const char       *next  = reinterpret_cast<const char *>(elems + i + kBlock);
  const std::size_t bytes = std::min(kBlock, count - i - kBlock) * sizeof(TetElement);
  for (std::size_t off = 0; off < bytes; off += 64) PrefetchLine(next + off);
}

// Stresses (cst_stress.cpp only): instead of adding the nodal forces to f, store each element's
// Cauchy stress at f[6 i] for elems[i] (NaN where J <= 0, where CellStress answers false).
template <class Model, bool Visc, bool Stresses = false>
__attribute__((target_clones("arch=x86-64-v3", "default"))) std::int64_t Batch(const TetElement *elems, std::size_t first, std::size_t count, const MaterialCoeffs &c,
                   const double *x, const double *v, double *f, std::size_t *done) {
  std::int64_t bad = -1;
  const MaterialCoeffs cc = c;
  const int mat = count ? elems[0].material : 0;
  std::size_t i = 0;
  while (i < count) {
    // kinematics of the block, then its stresses and forces with the data component-major so
    // that the loops run several elements an instruction (the same operations per element as
    // Core; an inverted element's forces are computed from pre = 0 and dropped below)
    std::size_t nb = 0;
    alignas(16) double kc[9][kBlock], kA[9][kBlock], kd[kBlock], kJ[kBlock], kP[2][kBlock], fb[12][kBlock];
    BlockInputs in;
    auto &kx = in.x;
    auto &kX = in.Xi;
    double *kI = in.inv6V0, *kV = in.V0;
    PrefetchNextBlock(elems, i, count);
    // gather the corners (and the element constants) component-major
    while (nb < kBlock && i + nb < count && elems[i + nb].material == mat) ++nb;
    if (nb == 0) break;
    const double *vel = Visc ? v : nullptr;
#if defined(__x86_64__)
    if (kHasAVX2) GatherAVX2(elems + i, nb, x, vel, in);
    else
#endif
      GatherColumns(elems + i, 0, nb, x, vel, in);
    // kinematics as Kinematics()
    for (std::size_t b = 0; b < nb; ++b) {
      double X[12], C[9], A[9], detC;
      for (int j = 0; j < 12; ++j) X[j] = kx[j][b];
      EdgeMatrix(X, C, A, detC);
      for (int j = 0; j < 9; ++j) kc[j][b] = C[j], kA[j][b] = A[j];
      kd[b] = detC;
      kJ[b] = detC * kI[b];
    }
    Model::PrepareBlock(kJ, kP[0], kP[1], nb); // inverted elements too: their forces are dropped
    for (std::size_t b = 0; b < nb; ++b) {
      double C[9], A[9], Xi[9], pre[2] = {kP[0][b], kP[1][b]}, F[9], T[6], fe[12];
      double D[6] = {0, 0, 0, 0, 0, 0};
      for (int j = 0; j < 9; ++j) C[j] = kc[j][b], A[j] = kA[j][b], Xi[j] = kX[j][b];
      DeformationGradient(C, Xi, F);
      if constexpr (Visc) {
        double V[12], L[9];
        for (int j = 0; j < 12; ++j) V[j] = in.v[j][b];
        VelocityGradient<Model>(V, A, kd[b], Xi, L, D);
      }
      Model::Stress(cc, F, kJ[b], pre, D, T);
      if constexpr (Stresses) {
        for (int j = 0; j < 6; ++j) f[6 * (i + b) + j] = kJ[b] > 0 ? T[j] : NAN;
        continue;
      }
      NodalForces<Model>(T, A, Xi, kV[b], fe);
      for (int j = 0; j < 12; ++j) fb[j][b] = fe[j];
    }
    for (std::size_t b = 0; b < nb && !Stresses; ++b) {
      const TetElement &el = elems[i + b];
      if (!(kJ[b] > 0)) {
        if (bad < 0) bad = static_cast<std::int64_t>(first + i + b);
        if (!Model::kSmallStrain) continue;
      }
      for (int a = 0; a < 4; ++a) {
        double *fa = f + 3 * el.n[a];
        fa[0] += fb[3 * a][b];
        fa[1] += fb[3 * a + 1][b];
        fa[2] += fb[3 * a + 2][b];
      }
    }
    i += nb;
    if (nb < kBlock && i < count && elems[i].material != mat) break;
  }
  *done = i;
  return bad;
}

} // namespace
} // namespace fdem::kernels
