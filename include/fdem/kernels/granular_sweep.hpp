// The granular law of kernels/granular.hpp over the sphere-sphere pairs of a contact search:
// one pass over the candidate pairs, the distance test, the law of each touching pair
// (Hertz or Hooke, rolling resistance or not) and the forces summed per sphere, in the order
// of the pairs. The same arithmetic as GranularForce in another order: the results agree to
// round-off (test_granular_sweep). What a pass cannot decide alone (a spring slot to take or
// to free, a pair with no law) it lists for the caller. Pure functions on doubles; no PETSc,
// no MPI.
#pragma once
#include "fdem/kernels/granular.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace fdem::kernels {

// One sphere-sphere contact's inputs and outputs.
struct SpherePairIn {
  double dx, dy, dz;    // centre of a minus centre of b (m); must not be zero
  double ra, rb;        // radii (m)
  double vx, vy, vz;    // velocity of a minus velocity of b (m/s)
  double wax, way, waz; // angular velocity of a (rad/s)
  double wbx, wby, wbz; // angular velocity of b (rad/s)
  double mstar, cn;     // effective mass (kg); Hooke: the normal damping coefficient m* gamma_n (N s/m)
};
struct SpherePairOut {
  double fx, fy, fz;    // force on a (N); b gets minus it
  double tax, tay, taz; // torque on a (N m)
  double tbx, tby, tbz; // torque on b (N m)
  double energy;        // elastic energy, normal and tangential (J)
  double overlap;       // r_a + r_b - |d| (m)
};

// The law p (Hertz or Hooke; with rolling resistance or not) for one touching contact, the
// tangential spring s advanced in place: GranularForce's arithmetic, inlined into the sweep.
template <bool Hertz, bool Roll>
inline __attribute__((always_inline)) SpherePairOut SpherePairLaw(const GranularPair &p, double dt, const SpherePairIn &c, double &sx, double &sy, double &sz) {
  SpherePairOut o;
  const double  d2 = c.dx * c.dx + c.dy * c.dy + c.dz * c.dz;
  const double  dist = std::sqrt(d2), inv = 1.0 / dist;
  const double  nx = c.dx * inv, ny = c.dy * inv, nz = c.dz * inv;
  const double  ov = c.ra + c.rb - dist, rstar = c.ra * c.rb / (c.ra + c.rb);
  // relative velocity of the contact points: v_a - v_b - (r_a w_a + r_b w_b) x n
  const double ux = c.ra * c.wax + c.rb * c.wbx, uy = c.ra * c.way + c.rb * c.wby, uz = c.ra * c.waz + c.rb * c.wbz;
  const double rvx = c.vx - (uy * nz - uz * ny), rvy = c.vy - (uz * nx - ux * nz), rvz = c.vz - (ux * ny - uy * nx);
  const double vnn = rvx * nx + rvy * ny + rvz * nz;
  const double vnx = vnn * nx, vny = vnn * ny, vnz = vnn * nz;
  const double vtx = rvx - vnx, vty = rvy - vny, vtz = rvz - vnz;
  double       knd, cn, kt, ct, a = 0;
  if constexpr (Hertz) {
    a               = std::sqrt(rstar * ov);
    const double sn = 2.0 * p.estar * a;
    knd             = (2.0 / 3.0) * sn * ov;
    cn              = p.alpha * std::sqrt(c.mstar * sn);
    kt              = 8.0 * p.gstar * a;
    ct              = p.alpha * std::sqrt(c.mstar * kt);
  } else {
    knd = p.kn * ov;
    cn  = c.cn;
    kt  = p.kt;
    ct  = c.mstar * p.gamma_t;
  }
  const double fnx = knd * nx - cn * vnx, fny = knd * ny - cn * vny, fnz = knd * nz - cn * vnz;
  // the spring: advanced, kept in the tangent plane
  double       s0 = sx + dt * vtx, s1 = sy + dt * vty, s2 = sz + dt * vtz;
  const double sn = s0 * nx + s1 * ny + s2 * nz;
  s0 -= sn * nx, s1 -= sn * ny, s2 -= sn * nz;
  const double dpx = ct * vtx, dpy = ct * vty, dpz = ct * vtz;
  double       ftx = -(kt * s0 + dpx), fty = -(kt * s1 + dpy), ftz = -(kt * s2 + dpz);
  const double fs2 = ftx * ftx + fty * fty + ftz * ftz, fn2 = fnx * fnx + fny * fny + fnz * fnz, fmax2 = p.mu * p.mu * fn2;
  // Coulomb: beyond the limit the force is scaled to it and the spring cut back to match (a
  // branch: most contacts stick, and they skip two roots and two divisions)
  if (fs2 > fmax2) {
    const double scale = std::sqrt(fmax2) / std::sqrt(fs2);
    if (kt > 0) {
      const double ikt = 1.0 / kt;
      s0 = scale * (s0 + ikt * dpx) - ikt * dpx;
      s1 = scale * (s1 + ikt * dpy) - ikt * dpy;
      s2 = scale * (s2 + ikt * dpz) - ikt * dpz;
    }
    ftx *= scale, fty *= scale, ftz *= scale;
  }
  sx = s0, sy = s1, sz = s2;
  const double Fx = fnx + ftx, Fy = fny + fty, Fz = fnz + ftz;
  double       mx = 0, my = 0, mz = 0; // rolling resistance on a
  if constexpr (Roll) {
    const double wx = c.wax - c.wbx, wy = c.way - c.wby, wz = c.waz - c.wbz;
    const double wn = wx * nx + wy * ny + wz * nz;
    const double rx = wx - wn * nx, ry = wy - wn * ny, rz = wz - wn * nz;
    const double w = std::sqrt(rx * rx + ry * ry + rz * rz);
    const double k = w > 0 ? -p.mu_roll * rstar * std::sqrt(fn2) / (w > 0 ? w : 1.0) : 0.0;
    mx = k * rx, my = k * ry, mz = k * rz;
  }
  const double cx = ny * Fz - nz * Fy, cy = nz * Fx - nx * Fz, cz = nx * Fy - ny * Fx; // n x F
  o.fx = Fx, o.fy = Fy, o.fz = Fz;
  o.tax = mx - c.ra * cx, o.tay = my - c.ra * cy, o.taz = mz - c.ra * cz;
  o.tbx = -(c.rb * cx + mx), o.tby = -(c.rb * cy + my), o.tbz = -(c.rb * cz + mz);
  const double ss = sx * sx + sy * sy + sz * sz;
  if constexpr (Hertz) o.energy = (8.0 / 15.0) * p.estar * a * ov * ov + 4.0 * p.gstar * a * ss;
  else o.energy = 0.5 * p.kn * ov * ov + 0.5 * p.kt * ss;
  o.overlap = ov;
  return o;
}

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
