// The batched granular law (kernels/granular_batch.hpp). The loop body is GranularForce's
// arithmetic written without branches (a choice between two computed values instead), so
// that GCC vectorizes it; this file is compiled with -fno-math-errno -fno-trapping-math
// (CMakeLists.txt), which vectorization of sqrt and of the choices needs. No lane computes a
// division by zero or the root of a negative number, so the options change no result and
// -fp_trap stays usable. The function is compiled twice, for x86-64 (SSE2) and for
// x86-64-v3 (AVX2, FMA), and the loader picks the one the processor runs.
#include "fdem/kernels/granular_batch.hpp"

#include <cmath>

namespace fdem::kernels {

void GranularBatch::Resize(int n) {
  n_ = n;
  if (n > cap_) {
    cap_ = n + n / 4 + 16;
    data_.assign((size_t)kFields * cap_, 0.0);
  }
}

namespace {
template <bool Hertz, bool Roll>
inline __attribute__((always_inline)) void Loop(const GranularPair &p, double dt, GranularBatch &B, int begin, int end) {
  using F                  = GranularBatch;
  const double *__restrict dx = B[F::DX], *__restrict dy = B[F::DY], *__restrict dz = B[F::DZ];
  const double *__restrict ra = B[F::RA], *__restrict rb = B[F::RB];
  const double *__restrict vx = B[F::VX], *__restrict vy = B[F::VY], *__restrict vz = B[F::VZ];
  const double *__restrict wax = B[F::WAX], *__restrict way = B[F::WAY], *__restrict waz = B[F::WAZ];
  const double *__restrict wbx = B[F::WBX], *__restrict wby = B[F::WBY], *__restrict wbz = B[F::WBZ];
  const double *__restrict ms = B[F::MSTAR], *__restrict cnh = B[F::CN];
  double *__restrict sx = B[F::SX], *__restrict sy = B[F::SY], *__restrict sz = B[F::SZ];
  double *__restrict fx = B[F::FX], *__restrict fy = B[F::FY], *__restrict fz = B[F::FZ];
  double *__restrict tax = B[F::TAX], *__restrict tay = B[F::TAY], *__restrict taz = B[F::TAZ];
  double *__restrict tbx = B[F::TBX], *__restrict tby = B[F::TBY], *__restrict tbz = B[F::TBZ];
  double *__restrict en = B[F::ENERGY], *__restrict ovl = B[F::OVERLAP];
  const double mu2 = p.mu * p.mu;
#pragma GCC ivdep
  for (int i = begin; i < end; ++i) {
    const double d2 = dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i];
    const double dist = std::sqrt(d2), inv = 1.0 / dist;
    const double nx = dx[i] * inv, ny = dy[i] * inv, nz = dz[i] * inv;
    const double ov = ra[i] + rb[i] - dist, rstar = ra[i] * rb[i] / (ra[i] + rb[i]);
    // relative velocity of the contact points: v_a - v_b - (r_a w_a + r_b w_b) x n
    const double ux = ra[i] * wax[i] + rb[i] * wbx[i], uy = ra[i] * way[i] + rb[i] * wby[i], uz = ra[i] * waz[i] + rb[i] * wbz[i];
    const double rvx = vx[i] - (uy * nz - uz * ny), rvy = vy[i] - (uz * nx - ux * nz), rvz = vz[i] - (ux * ny - uy * nx);
    const double vnn = rvx * nx + rvy * ny + rvz * nz;
    const double vnx = vnn * nx, vny = vnn * ny, vnz = vnn * nz;
    const double vtx = rvx - vnx, vty = rvy - vny, vtz = rvz - vnz;
    double       knd, cn, kt, ct, a = 0;
    if constexpr (Hertz) {
      a              = std::sqrt(rstar * ov);
      const double sn = 2.0 * p.estar * a;
      knd            = (2.0 / 3.0) * sn * ov;
      cn             = p.alpha * std::sqrt(ms[i] * sn);
      kt             = 8.0 * p.gstar * a;
      ct             = p.alpha * std::sqrt(ms[i] * kt);
    } else {
      knd = p.kn * ov;
      cn  = cnh[i];
      kt  = p.kt;
      ct  = ms[i] * p.gamma_t;
    }
    const double fnx = knd * nx - cn * vnx, fny = knd * ny - cn * vny, fnz = knd * nz - cn * vnz;
    // the spring: advanced, kept in the tangent plane
    double       s0 = sx[i] + dt * vtx, s1 = sy[i] + dt * vty, s2 = sz[i] + dt * vtz;
    const double sn = s0 * nx + s1 * ny + s2 * nz;
    s0 -= sn * nx, s1 -= sn * ny, s2 -= sn * nz;
    const double dpx = ct * vtx, dpy = ct * vty, dpz = ct * vtz;
    double       ftx = -(kt * s0 + dpx), fty = -(kt * s1 + dpy), ftz = -(kt * s2 + dpz);
    const double fs2 = ftx * ftx + fty * fty + ftz * ftz, fn2 = fnx * fnx + fny * fny + fnz * fnz, fmax2 = mu2 * fn2;
    // Coulomb: beyond the limit the force is scaled to it and the spring cut back to match
    const bool   slide = fs2 > fmax2;
    const double fs = std::sqrt(fs2), scale = std::sqrt(fmax2) / (fs > 0 ? fs : 1.0);
    const double ikt = 1.0 / (kt > 0 ? kt : 1.0);
    const bool   cut = slide && kt > 0;
    sx[i]            = cut ? scale * (s0 + ikt * dpx) - ikt * dpx : s0;
    sy[i]            = cut ? scale * (s1 + ikt * dpy) - ikt * dpy : s1;
    sz[i]            = cut ? scale * (s2 + ikt * dpz) - ikt * dpz : s2;
    ftx              = slide ? scale * ftx : ftx;
    fty              = slide ? scale * fty : fty;
    ftz              = slide ? scale * ftz : ftz;
    const double Fx = fnx + ftx, Fy = fny + fty, Fz = fnz + ftz;
    double       mx = 0, my = 0, mz = 0; // rolling resistance on a
    if constexpr (Roll) {
      const double wx = wax[i] - wbx[i], wy = way[i] - wby[i], wz = waz[i] - wbz[i];
      const double wn = wx * nx + wy * ny + wz * nz;
      const double rx = wx - wn * nx, ry = wy - wn * ny, rz = wz - wn * nz;
      const double w = std::sqrt(rx * rx + ry * ry + rz * rz);
      const double k = w > 0 ? -p.mu_roll * rstar * std::sqrt(fn2) / (w > 0 ? w : 1.0) : 0.0;
      mx = k * rx, my = k * ry, mz = k * rz;
    }
    const double cx = ny * Fz - nz * Fy, cy = nz * Fx - nx * Fz, cz = nx * Fy - ny * Fx; // n x F
    fx[i] = Fx, fy[i] = Fy, fz[i] = Fz;
    tax[i] = mx - ra[i] * cx, tay[i] = my - ra[i] * cy, taz[i] = mz - ra[i] * cz;
    tbx[i] = -(rb[i] * cx + mx), tby[i] = -(rb[i] * cy + my), tbz[i] = -(rb[i] * cz + mz);
    const double ss = sx[i] * sx[i] + sy[i] * sy[i] + sz[i] * sz[i];
    if constexpr (Hertz) en[i] = (8.0 / 15.0) * p.estar * a * ov * ov + 4.0 * p.gstar * a * ss;
    else en[i] = 0.5 * p.kn * ov * ov + 0.5 * p.kt * ss;
    ovl[i] = ov;
  }
}
} // namespace

__attribute__((target_clones("arch=x86-64-v3", "default"))) void GranularBatchForces(const GranularPair &p, double dt, GranularBatch &b, int begin, int end) {
  const bool hertz = p.law == GranularLaw::Hertz, roll = p.mu_roll > 0;
  if (hertz && roll) Loop<true, true>(p, dt, b, begin, end);
  else if (hertz) Loop<true, false>(p, dt, b, begin, end);
  else if (roll) Loop<false, true>(p, dt, b, begin, end);
  else Loop<false, false>(p, dt, b, begin, end);
}

} // namespace fdem::kernels
