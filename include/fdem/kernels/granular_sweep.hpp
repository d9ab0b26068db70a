// The granular law of kernels/granular.hpp over the sphere-sphere pairs of a contact search:
// one sweep over the candidate pairs in chunks, the distance test of a chunk first (without a
// branch on its outcome), then the law of its touching pairs (Hertz or Hooke, rolling
// resistance or not), four at a time in vector lanes while they share a law, and the forces
// summed per sphere in the order of the pairs. The same arithmetic as GranularForce in another
// order: the results agree to round-off (test_granular_sweep). What the sweep cannot decide
// alone (a spring slot to take or to free, a pair with no law) it lists for the caller. Pure
// functions on doubles; no PETSc, no MPI.
#pragma once
#include "fdem/kernels/granular.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace fdem::kernels {

// The arithmetic below is written once for a number type T: double (one contact) or Lanes4
// (four contacts side by side, a GCC vector of four doubles: one AVX2 instruction on each, two
// SSE2 instructions without AVX2). Comparisons give a mask (bool, or a vector of all-ones and
// zeros per lane) and Select(mask, a, b) picks per lane, so that a contact that slides and one
// that sticks can share the four lanes; a lane not picked never computes a root of a negative
// number or a division by zero.
typedef double Lanes4 __attribute__((vector_size(32)));
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi" // Lanes4 by value, to here: all inlined, so no call passes one
inline __attribute__((always_inline)) double Splat(double a, double) { return a; }
inline __attribute__((always_inline)) Lanes4 Splat(double a, Lanes4) { return Lanes4{a, a, a, a}; }
inline __attribute__((always_inline)) double Sqrt(double a) { return std::sqrt(a); }
inline __attribute__((always_inline)) Lanes4 Sqrt(Lanes4 a) { return Lanes4{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])}; }
inline __attribute__((always_inline)) bool Any(bool m) { return m; }
template <class M> inline __attribute__((always_inline)) bool Any(M m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
template <class M> inline __attribute__((always_inline)) double Select(M m, double a, double b) { return m ? a : b; }
template <class M> inline __attribute__((always_inline)) Lanes4 Select(M m, Lanes4 a, Lanes4 b) { return m ? a : b; }

// One sphere-sphere contact's inputs and outputs (T = double), or four contacts' (T = Lanes4).
template <class T>
struct SpherePairInT {
  T dx, dy, dz;    // centre of a minus centre of b (m); must not be zero
  T ra, rb;        // radii (m)
  T vx, vy, vz;    // velocity of a minus velocity of b (m/s)
  T wax, way, waz; // angular velocity of a (rad/s)
  T wbx, wby, wbz; // angular velocity of b (rad/s)
  T mstar, cn;     // effective mass (kg); Hooke: the normal damping coefficient m* gamma_n (N s/m)
};
template <class T>
struct SpherePairOutT {
  T fx, fy, fz;    // force on a (N); b gets minus it
  T tax, tay, taz; // torque on a (N m)
  T tbx, tby, tbz; // torque on b (N m)
  T energy;        // elastic energy, normal and tangential (J)
  T overlap;       // r_a + r_b - |d| (m)
};
using SpherePairIn  = SpherePairInT<double>;
using SpherePairOut = SpherePairOutT<double>;

// The law p (Hertz or Hooke; with rolling resistance or not) for touching contacts, the
// tangential springs s advanced in place: GranularForce's arithmetic, inlined into the sweep.
template <bool Hertz, bool Roll, class T>
inline __attribute__((always_inline)) SpherePairOutT<T> SpherePairLaw(const GranularPair &p, double dt, const SpherePairInT<T> &c, T &sx, T &sy, T &sz) {
  SpherePairOutT<T> o;
  const T           one = Splat(1.0, c.dx), zero = Splat(0.0, c.dx);
  const T           d2 = c.dx * c.dx + c.dy * c.dy + c.dz * c.dz;
  const T           dist = Sqrt(d2), inv = 1.0 / dist;
  const T           nx = c.dx * inv, ny = c.dy * inv, nz = c.dz * inv;
  const T           ov = c.ra + c.rb - dist, rstar = c.ra * c.rb / (c.ra + c.rb);
  // relative velocity of the contact points: v_a - v_b - (r_a w_a + r_b w_b) x n
  const T ux = c.ra * c.wax + c.rb * c.wbx, uy = c.ra * c.way + c.rb * c.wby, uz = c.ra * c.waz + c.rb * c.wbz;
  const T rvx = c.vx - (uy * nz - uz * ny), rvy = c.vy - (uz * nx - ux * nz), rvz = c.vz - (ux * ny - uy * nx);
  const T vnn = rvx * nx + rvy * ny + rvz * nz;
  const T vnx = vnn * nx, vny = vnn * ny, vnz = vnn * nz;
  const T vtx = rvx - vnx, vty = rvy - vny, vtz = rvz - vnz;
  T       knd, cn, kt, ct, a = zero;
  if constexpr (Hertz) {
    a          = Sqrt(rstar * ov);
    const T sn = 2.0 * p.estar * a;
    knd        = (2.0 / 3.0) * sn * ov;
    cn         = p.alpha * Sqrt(c.mstar * sn);
    kt         = 8.0 * p.gstar * a;
    ct         = p.alpha * Sqrt(c.mstar * kt);
  } else {
    knd = p.kn * ov;
    cn  = c.cn;
    kt  = Splat(p.kt, c.dx);
    ct  = c.mstar * p.gamma_t;
  }
  const T fnx = knd * nx - cn * vnx, fny = knd * ny - cn * vny, fnz = knd * nz - cn * vnz;
  // the spring: advanced, kept in the tangent plane
  T       s0 = sx + dt * vtx, s1 = sy + dt * vty, s2 = sz + dt * vtz;
  const T sn = s0 * nx + s1 * ny + s2 * nz;
  s0 -= sn * nx, s1 -= sn * ny, s2 -= sn * nz;
  const T dpx = ct * vtx, dpy = ct * vty, dpz = ct * vtz;
  T       ftx = -(kt * s0 + dpx), fty = -(kt * s1 + dpy), ftz = -(kt * s2 + dpz);
  const T fs2 = ftx * ftx + fty * fty + ftz * ftz, fn2 = fnx * fnx + fny * fny + fnz * fnz, fmax2 = p.mu * p.mu * fn2;
  // Coulomb: beyond the limit the force is scaled to it and the spring cut back to match (a
  // branch: most contacts stick, and they skip two roots and two divisions)
  const auto slide = fs2 > fmax2;
  if (Any(slide)) {
    const T    scale = Select(slide, Sqrt(fmax2) / Sqrt(Select(slide, fs2, one)), one);
    const auto cut   = slide & (kt > 0);
    const T    ikt   = 1.0 / Select(cut, kt, one);
    s0               = Select(cut, scale * (s0 + ikt * dpx) - ikt * dpx, s0);
    s1               = Select(cut, scale * (s1 + ikt * dpy) - ikt * dpy, s1);
    s2               = Select(cut, scale * (s2 + ikt * dpz) - ikt * dpz, s2);
    ftx = Select(slide, ftx * scale, ftx), fty = Select(slide, fty * scale, fty), ftz = Select(slide, ftz * scale, ftz);
  }
  sx = s0, sy = s1, sz = s2;
  const T Fx = fnx + ftx, Fy = fny + fty, Fz = fnz + ftz;
  T       mx = zero, my = zero, mz = zero; // rolling resistance on a
  if constexpr (Roll) {
    const T    wx = c.wax - c.wbx, wy = c.way - c.wby, wz = c.waz - c.wbz;
    const T    wn = wx * nx + wy * ny + wz * nz;
    const T    rx = wx - wn * nx, ry = wy - wn * ny, rz = wz - wn * nz;
    const T    w = Sqrt(rx * rx + ry * ry + rz * rz);
    const auto turning = w > 0;
    const T    mr = p.mu_roll * rstar * Sqrt(fn2), cap = (kRollingInertia / dt) * c.mstar * rstar * rstar * w; // GranularForce's bound
    const T    k  = Select(turning, -Select(cap < mr, cap, mr) / Select(turning, w, one), zero);
    mx = k * rx, my = k * ry, mz = k * rz;
  }
  const T cx = ny * Fz - nz * Fy, cy = nz * Fx - nx * Fz, cz = nx * Fy - ny * Fx; // n x F
  o.fx = Fx, o.fy = Fy, o.fz = Fz;
  o.tax = mx - c.ra * cx, o.tay = my - c.ra * cy, o.taz = mz - c.ra * cz;
  o.tbx = -(c.rb * cx + mx), o.tby = -(c.rb * cy + my), o.tbz = -(c.rb * cz + mz);
  const T ss = sx * sx + sy * sy + sz * sz;
  if constexpr (Hertz) o.energy = (8.0 / 15.0) * p.estar * a * ov * ov + 4.0 * p.gstar * a * ss;
  else o.energy = 0.5 * p.kn * ov * ov + 0.5 * p.kt * ss;
  o.overlap = ov;
  return o;
}
#pragma GCC diagnostic pop

// A sphere at an evaluation, read together by a pair.
struct SphereState {
  Vec3   x, v, w; // centre (m), velocity (m/s), angular velocity (rad/s)
  double r;       // radius (m)
};
// The forces on a sphere, summed over its pairs.
struct SphereSum {
  Vec3 f, t; // force (N), torque (N m)
};
// A candidate pair: its spheres (indices into the states; a the holder of the spring), the
// slot of its spring in a's history (-1: none) and its law (an index into the table; -1: none).
struct SpherePair {
  int a, b, slot, law;
};
// What stays fixed while a pair lasts.
struct SpherePairConst {
  std::int64_t key;   // the spring's key in a's history
  double       mstar; // effective mass (kg)
  double       cn;    // Hooke: the normal damping coefficient m* gamma_n (N s/m)
};
// What a sweep leaves to its caller, as indices of pairs.
struct SphereSweep {
  std::vector<int> touching; // every touching pair (with a law), in order
  std::vector<int> started;  // touching pairs without a slot: their spring starts from zero (kept in springs[j])
  std::vector<int> opened;   // pairs with a slot that no longer touch: free it
  std::vector<int> bad;      // touching pairs without a law, or with both centres at one point: an error
  double           energy = 0; // elastic energy of the touching pairs (J)
};

// One sweep over pairs [0, n) for a step dt: a touching pair with a law runs laws[law] with
// its spring springs[j] (taken as zero when it has no slot) advanced in place, and adds its
// force and torques to sum[a] and sum[b] (sum must start zeroed; b gets minus the force).
void SphereContactSweep(const GranularPair *laws, double dt, const SphereState *s, const SpherePair *pairs, const SpherePairConst *pc, Vec3 *springs, int n, SphereSum *sum, SphereSweep &out);

} // namespace fdem::kernels
