// Sphere bodies in the rigid model's DMSwarm and TS, in contact through the contact
// engine (doc/spheres.md):
//  1. Two Hertz spheres, head-on, no damping: peak force and contact duration against
//     Hertz's theory within 2%, and with restitution 0.8 the rebound speed within 2%.
//  2. The same with the Hooke law: the contact time and restitution of the damped
//     oscillator within 2%.
//  3. A sphere dropped on a fixed rigid cube's face, edge and vertex (no gravity, head-on
//     along the normal, the diagonal of the edge, the body diagonal): one contact each, so
//     the contact duration is Hertz's for a sphere on a flat (R* = r) within 2%, and the
//     restitution 0.5 within 2%.
//  3b. A sphere on a 30 degree incline rolls without slipping at (5/7) g sin(theta) for a
//     large friction and slides at g (sin - mu cos) for a small one (2%).
//  3c. An oblique impact in gross sliding: the tangential speed drops by 2 mu v_n and the
//     spin becomes 5 mu v_n / r (2%).
//  4. 27 spheres with friction and rolling resistance thrown at a floor of fixed cubes, with
//     gravity: solved on PETSC_COMM_WORLD (slabs, migration every 10 steps) and on
//     PETSC_COMM_SELF in the same process; final positions and velocities agree to 1e-9 m
//     and 1e-7 m/s (sums in another order), and without damping or friction the energy
//     (kinetic + gravity + contact) stays within 1e-3 of the initial.
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>
#include <fdem/kernels/granular.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "../common/check.hpp"

namespace {
const PetscReal R0 = 0.01, RHO = 2500, E = 5e9, NU = 0.25;

struct Record {
  PetscInt  a = 0, b = 1;       // the two bodies watched (b < 0: a against a fixed body along -n)
  PetscReal n[3] = {1, 0, 0};   // direction of approach of a
  PetscReal vmin = 1e300;       // relative normal speed at the end
  PetscReal t_in = -1, t_out = -1, dmax = 0, vend = 0;
  PetscReal gap0 = 0;           // a's distance to the surface at the start (b < 0)
  PetscReal x0[3] = {0, 0, 0};
};

// The overlap of a and b (spheres: r_a + r_b - distance; a against a surface: gap0 - travel along n).
PetscErrorCode Monitor(FDEMRigid rb, PetscInt, PetscReal t, void *ctx) {
  Record            *r = (Record *)ctx;
  FDEMRigidBodyState A, B;
  PetscReal          ov, vn = 0;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetBodyState(rb, r->a, &A));
  if (r->b >= 0) {
    PetscCall(FDEMRigidGetBodyState(rb, r->b, &B));
    PetscReal d = 0;
    for (int k = 0; k < 3; ++k) d += PetscSqr(A.x[k] - B.x[k]);
    ov = 2 * R0 - PetscSqrtReal(d);
    for (int k = 0; k < 3; ++k) vn += (A.v[k] - B.v[k]) * r->n[k];
  } else {
    PetscReal travel = 0;
    for (int k = 0; k < 3; ++k) travel += (A.x[k] - r->x0[k]) * r->n[k];
    ov = travel - r->gap0;
    for (int k = 0; k < 3; ++k) vn += A.v[k] * r->n[k];
  }
  if (ov > 0 && r->t_in < 0) r->t_in = t;
  if (ov <= 0 && r->t_in >= 0 && r->t_out < 0) r->t_out = t;
  r->dmax = std::max(r->dmax, ov);
  r->vend = vn;
  PetscFunctionReturn(0);
}

PetscErrorCode Material(FDEMRigid rb, FDEMGranularLaw law, PetscReal e, PetscReal mu, PetscReal mu_roll, PetscInt *m, const char *name = "glass", PetscReal young = E) {
  FDEMGranularMaterial g;
  PetscFunctionBeginUser;
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law     = law;
  g.law_set = PETSC_TRUE;
  g.young   = young;
  g.poisson = NU;
  g.kn      = 2e5;
  g.kt      = 2e5 * 2.0 / 7.0;
  if (e > 0) g.restitution = e;
  g.friction         = mu;
  g.rolling_friction = mu_roll;
  PetscCall(FDEMRigidAddGranularMaterial(rb, name, &g, m));
  PetscFunctionReturn(0);
}

// A cube of side L (6 tetrahedra around its diagonal) centred at c, turned by Q (row-major; null: none), fixed.
PetscErrorCode AddCube(FDEMRigid rb, PetscReal L, const PetscReal c[3], PetscInt mat, PetscInt *id, const PetscReal *Q = nullptr) {
  std::vector<PetscReal> X;
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) X.push_back(((i >> k) & 1) ? 0.5 * L : -0.5 * L);
  const int              T6[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  std::vector<PetscInt> T;
  for (auto &t : T6) {
    std::array<int, 4> q = {t[0], t[1], t[2], t[3]};
    PetscReal          a[3], b[3], d[3];
    for (int k = 0; k < 3; ++k) a[k] = X[3 * q[1] + k] - X[3 * q[0] + k], b[k] = X[3 * q[2] + k] - X[3 * q[0] + k], d[k] = X[3 * q[3] + k] - X[3 * q[0] + k];
    const PetscReal det = a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0]);
    if (det < 0) std::swap(q[2], q[3]);
    for (int k = 0; k < 4; ++k) T.push_back(q[k]);
  }
  PetscCall(FDEMRigidAddBodyFromMesh(rb, "cube", 8, X.data(), 6, T.data(), 2500, c, Q, nullptr, nullptr, id));
  PetscCall(FDEMRigidFixBody(rb, *id));
  PetscCall(FDEMRigidSetBodyMaterial(rb, *id, mat));
  PetscFunctionReturn(0);
}

// The scene of the single-contact checks: a fixed cube of side L centred at the origin (turned by
// Q; null: none) and a Hertz sphere of radius R0 at x with velocity v, both of one material
// (restitution e, < 0: elastic; friction mu), gravity g (null: none), contact attached.
PetscErrorCode SphereOnCube(PetscReal e, PetscReal mu, PetscReal L, const PetscReal *Q, const PetscReal *g, const PetscReal x[3], const PetscReal *v, FDEMRigid *rb, FDEMContact *c, PetscInt *s) {
  PetscInt        m, cube;
  const PetscReal c0[3] = {0, 0, 0};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, rb));
  if (g) PetscCall(FDEMRigidSetGravity(*rb, g));
  PetscCall(Material(*rb, FDEM_GRANULAR_HERTZ, e, mu, 0, &m));
  PetscCall(AddCube(*rb, L, c0, m, &cube, Q));
  PetscCall(FDEMRigidAddSphere(*rb, "ball", R0, RHO, m, x, v, nullptr, s));
  PetscCall(FDEMContactCreate(*rb, c));
  PetscFunctionReturn(0);
}

// Two spheres at relative speed 1 m/s along x: contact time, peak force, rebound.
PetscErrorCode HeadOn(FDEMGranularLaw law, PetscReal e) {
  FDEMRigid   rb;
  FDEMContact c;
  PetscInt    m, a, b;
  Record      r;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
  PetscCall(Material(rb, law, e, 0, 0, &m));
  const PetscReal xa[3] = {-R0 - 1e-5, 0, 0}, xb[3] = {R0 + 1e-5, 0, 0}, va[3] = {0.5, 0, 0}, vb[3] = {-0.5, 0, 0};
  PetscCall(FDEMRigidAddSphere(rb, "a", R0, RHO, m, xa, va, nullptr, &a));
  PetscCall(FDEMRigidAddSphere(rb, "b", R0, RHO, m, xb, vb, nullptr, &b));
  PetscCall(FDEMContactCreate(rb, &c));
  const PetscReal mass = 4.0 / 3.0 * PETSC_PI * R0 * R0 * R0 * RHO, mstar = 0.5 * mass, rstar = 0.5 * R0, estar = E / (2 * (1 - NU * NU));
  PetscReal       tc, fmax = 0;
  if (law == FDEM_GRANULAR_HERTZ) {
    tc   = fdem::kernels::HertzContactTime(estar, rstar, mstar, 1.0);
    fmax = fdem::kernels::HertzPeakForce(estar, rstar, mstar, 1.0);
  } else tc = fdem::kernels::HookeContactTime(2e5, e > 0 ? fdem::kernels::HookeDampingForRestitution(e, 2e5, mstar) : 0, mstar);
  const PetscReal dt = tc / 400;
  PetscCall(FDEMRigidSolve(rb, 0, 2e-5 + 1.5 * tc, dt, 1, Monitor, &r)); // a segment per step: the monitor sees every step
  const PetscReal tcm = r.t_out - r.t_in, em = -r.vend / 1.0;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s e=%g: contact time %.6e (theory %.6e), rebound %.5f\n", law == FDEM_GRANULAR_HERTZ ? "hertz" : "hooke", (double)e, (double)tcm, (double)tc, (double)em));
  CHECK(std::fabs(em - (e > 0 ? e : 1.0)) < 0.02 * (e > 0 ? e : 1.0), "rebound speed %g, expected %g", (double)em, (double)(e > 0 ? e : 1.0));
  if (e <= 0) { // undamped: Hertz's (or the oscillator's) duration and peak
    CHECK(std::fabs(tcm - tc) < 0.02 * tc, "contact time %g, theory %g", (double)tcm, (double)tc);
    if (law == FDEM_GRANULAR_HERTZ) {
      const PetscReal fm = 4.0 / 3.0 * estar * PetscSqrtReal(rstar) * PetscPowReal(r.dmax, 1.5);
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  peak force %.6e (theory %.6e)\n", (double)fm, (double)fmax));
      CHECK(std::fabs(fm - fmax) < 0.02 * fmax, "peak force %g, theory %g", (double)fm, (double)fmax);
    }
  }
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// A sphere flying at 1 m/s along -n onto a fixed cube's face (n = z), edge (n = (x+z)/sqrt2) or vertex.
PetscErrorCode OnCube(const PetscReal n0[3], const char *what) {
  FDEMRigid   rb;
  FDEMContact c;
  PetscInt    s;
  Record      r;
  PetscFunctionBeginUser;
  const PetscReal L = 0.1, gap = 2e-5, nn = PetscSqrtReal(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
  PetscReal       n[3], x[3], v[3];
  for (int k = 0; k < 3; ++k) { // the face, edge or vertex touched is at 0.5 L n0 (n0 of 0/1 entries)
    n[k] = n0[k] / nn;
    x[k] = 0.5 * L * n0[k] + (R0 + gap) * n[k];
    v[k] = -1.0 * n[k];
  }
  PetscCall(SphereOnCube(-1, 0, L, nullptr, nullptr, x, v, &rb, &c, &s));
  r.a = s;
  r.b = -1;
  for (int k = 0; k < 3; ++k) {
    r.n[k]  = -n[k];
    r.x0[k] = x[k];
  }
  r.gap0 = gap;
  const PetscReal mass = 4.0 / 3.0 * PETSC_PI * R0 * R0 * R0 * RHO, estar = E / (2 * (1 - NU * NU));
  const PetscReal tc   = fdem::kernels::HertzContactTime(estar, R0, mass, 1.0);
  PetscCall(FDEMRigidSolve(rb, 0, 2e-5 + 1.5 * tc, tc / 400, 1, Monitor, &r));
  const PetscReal tcm = r.t_out - r.t_in, em = r.vend; // vend along -n: the rebound is negative of approach
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "sphere on a cube's %s: contact time %.6e (theory %.6e), rebound %.5f\n", what, (double)tcm, (double)tc, (double)-em));
  CHECK(std::fabs(tcm - tc) < 0.02 * tc, "%s: contact time %g, theory %g (a feature counted twice shortens it by 2^(2/5))", what, (double)tcm, (double)tc);
  CHECK(std::fabs(-em - 1.0) < 0.02, "%s: rebound speed %g, expected 1 (no damping)", what, (double)-em);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// A sphere released on an incline of 30 degrees (the top face of a fixed cube of side 1 m,
// turned about y), Hertz-Mindlin with friction mu and restitution 0.5, gravity: it rolls
// without slipping when mu >= (2/7) tan(theta), with acceleration (5/7) g sin(theta) and
// spin v / r, and slides otherwise with g (sin(theta) - mu cos(theta)). The acceleration
// along the slope from the speeds at 0.05 s and 0.15 s (after the release's transient),
// within 2%; rolling: spin within 1% of v / r.
PetscErrorCode Incline(PetscReal mu) {
  FDEMRigid          rb;
  FDEMContact        c;
  PetscInt           s;
  FDEMRigidBodyState a, b;
  PetscFunctionBeginUser;
  const PetscReal th = PETSC_PI / 6, ct = PetscCosReal(th), st = PetscSinReal(th), L = 1.0;
  // Q turns the cube about y: its top face's normal is n = (sin th, 0, cos th), and the
  // direction in the face whose z falls is +-(-cos th, 0, sin th)
  const PetscReal Q[9] = {ct, 0, st, 0, 1, 0, -st, 0, ct}, g[3] = {0, 0, -9.81};
  const PetscReal n[3] = {st, 0, ct}, down[3] = {-ct, 0, st}; // the face's normal and a direction in the face
  PetscReal       x[3];
  for (int k = 0; k < 3; ++k) x[k] = (0.5 * L + R0) * n[k];
  PetscCall(SphereOnCube(0.5, mu, L, Q, g, x, nullptr, &rb, &c, &s));
  PetscReal sgn = down[2] < 0 ? 1 : -1; // the direction along the face whose z falls
  PetscCall(FDEMRigidSolve(rb, 0, 0.05, 2e-5, 1000000, nullptr, nullptr));
  PetscCall(FDEMRigidGetBodyState(rb, s, &a));
  PetscCall(FDEMRigidSolve(rb, 0.05, 0.15, 2e-5, 1000000, nullptr, nullptr));
  PetscCall(FDEMRigidGetBodyState(rb, s, &b));
  PetscReal va = 0, vb = 0;
  for (int k = 0; k < 3; ++k) va += sgn * a.v[k] * down[k], vb += sgn * b.v[k] * down[k];
  const PetscReal acc = (vb - va) / 0.1, rolling = mu >= 2.0 / 7.0 * PetscTanReal(th);
  const PetscReal theory = rolling ? 5.0 / 7.0 * 9.81 * st : 9.81 * (st - mu * ct);
  const PetscReal w = PetscSqrtReal(b.omega_space[0] * b.omega_space[0] + b.omega_space[1] * b.omega_space[1] + b.omega_space[2] * b.omega_space[2]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "incline 30 deg, mu %g (%s): acceleration %.5f m/s^2 (theory %.5f), spin %.4f rad/s, v/r %.4f rad/s\n", (double)mu, rolling ? "rolls" : "slides", (double)acc, (double)theory, (double)w, (double)(vb / R0)));
  CHECK(std::fabs(acc - theory) < 0.02 * theory, "incline, mu %g: acceleration %g, theory %g", (double)mu, (double)acc, (double)theory);
  if (rolling) CHECK(std::fabs(w - vb / R0) < 0.01 * vb / R0, "incline, mu %g: spin %g, rolling needs v / r = %g", (double)mu, (double)w, (double)(vb / R0));
  else CHECK(w < 0.9 * vb / R0, "incline, mu %g: it should slide (spin %g below v / r = %g)", (double)mu, (double)w, (double)(vb / R0));
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// A sphere rolling down a large fixed sphere (radius 1 m; the contact holds its tangential spring
// in the sphere-sphere pairs' store), started 30 degrees from the top: after 0.1 s, solved in one
// TS and in TS segments of 10 steps (the springs must go to the swarm at the end of each segment
// and come back at the next), the same speed to 1e-6, and rolling (spin = v / r to 1%).
PetscErrorCode RollOnSphere(PetscInt every, PetscReal *speed, PetscReal *spin) {
  FDEMRigid          rb;
  FDEMContact        c;
  PetscInt           m, big, s;
  FDEMRigidBodyState b;
  PetscFunctionBeginUser;
  const PetscReal Rb = 1.0, th = PETSC_PI / 6, g[3] = {0, 0, -9.81}, c0[3] = {0, 0, 0};
  const PetscReal x[3] = {(Rb + R0) * PetscSinReal(th), 0, (Rb + R0) * PetscCosReal(th)};
  PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
  PetscCall(FDEMRigidSetGravity(rb, g));
  PetscCall(Material(rb, FDEM_GRANULAR_HERTZ, 0.5, 0.5, 0, &m));
  PetscCall(FDEMRigidAddSphere(rb, "ground", Rb, RHO, m, c0, nullptr, nullptr, &big));
  PetscCall(FDEMRigidFixBody(rb, big));
  PetscCall(FDEMRigidAddSphere(rb, "ball", R0, RHO, m, x, nullptr, nullptr, &s));
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSolve(rb, 0, 0.1, 2e-5, every, nullptr, nullptr));
  PetscCall(FDEMRigidGetBodyState(rb, s, &b));
  *speed = PetscSqrtReal(b.v[0] * b.v[0] + b.v[1] * b.v[1] + b.v[2] * b.v[2]);
  *spin  = PetscSqrtReal(b.omega_space[0] * b.omega_space[0] + b.omega_space[1] * b.omega_space[1] + b.omega_space[2] * b.omega_space[2]);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// An oblique impact in gross sliding: a sphere strikes the top face of a fixed cube at
// v_n = 1 m/s with v_t = 5 m/s, no spin, elastic (e = 1), friction mu = 0.1. It slides the
// whole contact, so the friction impulse is mu times the normal one, 2 m v_n: it leaves
// with v_t - 2 mu v_n and spin 5 mu v_n / r (I = 2/5 m r^2), v_n reversed (2%).
PetscErrorCode Oblique() {
  FDEMRigid          rb;
  FDEMContact        c;
  PetscInt           s;
  FDEMRigidBodyState st;
  PetscFunctionBeginUser;
  const PetscReal x[3] = {-0.05, 0, 0.05 + R0 + 2e-5}, v[3] = {5, 0, -1};
  PetscCall(SphereOnCube(-1, 0.1, 0.1, nullptr, nullptr, x, v, &rb, &c, &s));
  const PetscReal mass = 4.0 / 3.0 * PETSC_PI * R0 * R0 * R0 * RHO, estar = E / (2 * (1 - NU * NU)), tc = fdem::kernels::HertzContactTime(estar, R0, mass, 1.0);
  PetscCall(FDEMRigidSolve(rb, 0, 2e-5 + 1.5 * tc, tc / 400, 1000000, nullptr, nullptr));
  PetscCall(FDEMRigidGetBodyState(rb, s, &st));
  const PetscReal vt = 5 - 2 * 0.1 * 1, w = 5 * 0.1 * 1 / R0;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "oblique impact, sliding: v_t %.5f m/s (theory %.5f), spin %.4f rad/s (theory %.4f), v_n %.5f (theory 1)\n", (double)st.v[0], (double)vt, (double)st.omega_space[1], (double)w, (double)st.v[2]));
  CHECK(std::fabs(st.v[0] - vt) < 0.02 * (5 - vt), "oblique impact: tangential speed %g, theory %g", (double)st.v[0], (double)vt);
  CHECK(std::fabs(st.omega_space[1] - w) < 0.02 * w, "oblique impact: spin %g, theory %g", (double)st.omega_space[1], (double)w);
  CHECK(std::fabs(st.v[2] - 1) < 0.02, "oblique impact: normal rebound %g, theory 1", (double)st.v[2]);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// 27 spheres thrown at a floor of 9 fixed cubes: state by id after nsteps. With two materials,
// every other sphere is of a second one, four times as stiff (the pairs then have three laws).
PetscErrorCode Bed(MPI_Comm comm, bool dissipative, bool two, PetscInt nsteps, std::vector<PetscReal> &out, PetscReal *E0, PetscReal *E1) {
  FDEMRigid        rb;
  FDEMContact      c;
  PetscInt         m, m2, id;
  FDEMContactStats st;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(comm, &rb));
  const PetscReal lo[3] = {-0.06, -0.06, -0.03}, hi[3] = {0.06, 0.06, 0.12}, g[3] = {0, 0, -9.81};
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMRigidSetGravity(rb, g));
  PetscCall(Material(rb, FDEM_GRANULAR_HERTZ, dissipative ? 0.6 : -1, dissipative ? 0.4 : 0, dissipative ? 0.05 : 0, &m));
  PetscCall(Material(rb, FDEM_GRANULAR_HERTZ, dissipative ? 0.6 : -1, dissipative ? 0.4 : 0, dissipative ? 0.05 : 0, &m2, "hard", 4 * E));
  const PetscReal L = 0.04;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) {
      const PetscReal cc[3] = {i * L, j * L, -0.5 * L};
      PetscCall(AddCube(rb, L, cc, m, &id));
    }
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = 0; k < 3; ++k) {
        const PetscReal x[3] = {i * 0.021 + 0.002 * k, j * 0.021 - 0.001 * i, 0.012 + k * 0.0215}, v[3] = {0.2 * j, -0.1 * k, -0.5 - 0.2 * i}, w[3] = {30.0 * k, 0, -20.0 * i};
        PetscCall(FDEMRigidAddSphere(rb, "s", R0, RHO, two && (i + j + k) % 2 ? m2 : m, x, v, w, &id));
      }
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscReal P[3], Lm[3], K;
  PetscCall(FDEMRigidGetInvariants(rb, P, Lm, &K));
  PetscReal pe = 0;
  for (PetscInt b = 9; b < 36; ++b) {
    FDEMRigidBodyState s;
    PetscCall(FDEMRigidGetBodyState(rb, b, &s));
    pe += s.mass * 9.81 * s.x[2];
  }
  *E0 = K + pe;
  PetscCall(FDEMRigidSolve(rb, 0, nsteps * 2e-6, 2e-6, 10, nullptr, nullptr));
  PetscCall(FDEMRigidGetInvariants(rb, P, Lm, &K));
  PetscCall(FDEMContactGetStats(c, &st));
  pe = 0;
  out.clear();
  for (PetscInt b = 9; b < 36; ++b) {
    FDEMRigidBodyState s;
    PetscCall(FDEMRigidGetBodyState(rb, b, &s));
    pe += s.mass * 9.81 * s.x[2];
    for (int k = 0; k < 3; ++k) out.push_back(s.x[k]);
    for (int k = 0; k < 3; ++k) out.push_back(s.v[k]);
  }
  *E1 = K + pe + st.energy;
  PetscInt    nloc, nmin;
  PetscMPIInt size;
  PetscCall(FDEMRigidGetNumBodies(rb, &nloc, nullptr));
  PetscCallMPI(MPI_Allreduce(&nloc, &nmin, 1, MPIU_INT, MPI_MIN, comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  CHECK(size == 1 || nmin > 0, "bed: a rank holds no body; the parallel run tests nothing");
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  if (size == 1) {
    PetscCall(HeadOn(FDEM_GRANULAR_HERTZ, -1));
    PetscCall(HeadOn(FDEM_GRANULAR_HERTZ, 0.8));
    PetscCall(HeadOn(FDEM_GRANULAR_HOOKE, -1));
    PetscCall(HeadOn(FDEM_GRANULAR_HOOKE, 0.8));
    const PetscReal face[3] = {0, 0, 1}, edge[3] = {1, 0, 1}, vertex[3] = {1, 1, 1};
    PetscCall(OnCube(face, "face"));
    PetscCall(OnCube(edge, "edge"));
    PetscCall(OnCube(vertex, "vertex"));
    PetscCall(Incline(0.5));
    {
      PetscReal v1, w1, v10, w10;
      PetscCall(RollOnSphere(1000000, &v1, &w1));
      PetscCall(RollOnSphere(10, &v10, &w10));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "rolling down a fixed sphere: speed %.9f m/s in one TS, %.9f in segments of 10 steps; spin %.4f rad/s, v/r %.4f\n", (double)v1, (double)v10, (double)w10, (double)(v10 / R0)));
      CHECK(std::fabs(v10 - v1) < 1e-6 * v1, "rolling down a sphere: speed %g in segments, %g in one TS (the springs are lost between segments?)", (double)v10, (double)v1);
      CHECK(std::fabs(w10 - v10 / R0) < 0.01 * v10 / R0, "rolling down a sphere: spin %g, v / r = %g", (double)w10, (double)(v10 / R0));
    }
    PetscCall(Incline(0.05));
    PetscCall(Oblique());
  }
  for (int variant = 0; variant < 3; ++variant) {
    const bool             diss = variant == 1, two = variant == 2;
    std::vector<PetscReal> a, b;
    PetscReal              e0, e1, f0, f1;
    const PetscInt         nsteps = 8000;
    PetscCall(Bed(PETSC_COMM_WORLD, diss, two, nsteps, a, &e0, &e1));
    PetscCall(Bed(PETSC_COMM_SELF, diss, two, nsteps, b, &f0, &f1));
    PetscReal dx = 0, dv = 0;
    for (size_t i = 0; i < a.size(); i += 6)
      for (int k = 0; k < 3; ++k) {
        dx = std::max(dx, std::fabs(a[i + k] - b[i + k]));
        dv = std::max(dv, std::fabs(a[i + 3 + k] - b[i + 3 + k]));
      }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "bed (%s): %d ranks against 1: max |dx| %.3e m, |dv| %.3e m/s; energy %.6e -> %.6e J\n", diss ? "restitution 0.6, friction, rolling" : two ? "elastic, frictionless, two materials" : "elastic, frictionless", size, (double)dx, (double)dv, (double)e0, (double)e1));
    CHECK(dx < 1e-9 && dv < 1e-7, "bed: the parallel run differs from the serial one by %g m, %g m/s", (double)dx, (double)dv);
    if (!diss) CHECK(std::fabs(e1 - e0) < 1e-3 * std::fabs(e0), "bed: energy %g -> %g, not conserved to 1e-3", (double)e0, (double)e1);
    else CHECK(e1 < 0.9 * e0, "bed: the dissipative contacts (only they dissipate) took less than 10%% of the energy (%g -> %g): no contacts?", (double)e0, (double)e1);
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
