// Periodic boundaries for rigid bodies and spheres (FDEMRigidSetPeriodic, doc/contact_engine.md):
//  1. Two Hertz spheres on a line in a cell periodic along x, elastic: they collide across the
//     boundary, pass through it and collide again, several times. The same pair started half a
//     period further on (colliding first in the middle of the cell) must give the same motion
//     shifted by half a period: velocities to 1e-9 m/s, positions to 1e-9 m modulo the period.
//     Momentum is conserved to round-off, energy to 3e-5 (elastic; about 100 steps per contact), and the unwrapped centres
//     (x + image L, the periods counted by the migrations) move as the centre of mass does.
//  1b. A free rigid cube strikes a sphere across the boundary (sphere-surface contact with an
//     image of the cube's skin): the same as in the middle of the cell, to 1e-9, and the
//     sphere leaves at the speed of an elastic head-on impact (0.1%).
//  2. 64 spheres with restitution, friction and rolling resistance in a cell periodic along x
//     and y, no walls, no gravity: solved on PETSC_COMM_WORLD and on PETSC_COMM_SELF in the same
//     process; final positions and velocities agree to 1e-9 m and 1e-7 m/s, momentum is
//     conserved to 1e-12 of its scale, and some spheres end a period away from their start.
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "../common/check.hpp"

namespace {
const PetscReal R0 = 0.01, RHO = 2500, E = 5e9, NU = 0.25, L = 0.1;

PetscErrorCode Glass(FDEMRigid rb, PetscReal e, PetscReal mu, PetscReal mu_roll, PetscInt *m) {
  FDEMGranularMaterial g;
  PetscFunctionBeginUser;
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law     = FDEM_GRANULAR_HERTZ;
  g.law_set = PETSC_TRUE;
  g.young   = E;
  g.poisson = NU;
  if (e > 0) g.restitution = e;
  g.friction         = mu;
  g.rolling_friction = mu_roll;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "glass", &g, m));
  PetscFunctionReturn(0);
}

struct State {
  std::vector<PetscReal> x, v, xu; // per body id: centre, velocity, unwrapped centre
  PetscReal              P[3], K;
  PetscInt               crossed = 0; // bodies with a nonzero image count
};

// Every body's state by id on every rank (collective).
PetscErrorCode Gather(FDEMRigid rb, PetscInt nbodies, State &s) {
  DM         sw;
  PetscInt   n, *id, *image;
  PetscReal *x, *v, Lm[3], lo[3], hi[3];
  PetscBool  per[3];
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetInvariants(rb, s.P, Lm, &s.K));
  PetscCall(FDEMRigidGetPeriodic(rb, per, lo, hi));
  std::vector<PetscReal> loc(10 * nbodies, 0.0), all(10 * nbodies);
  PetscCall(FDEMRigidGetDM(rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, "id", nullptr, nullptr, (void **)&id));
  PetscCall(DMSwarmGetField(sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(sw, "v", nullptr, nullptr, (void **)&v));
  PetscCall(DMSwarmGetField(sw, "image", nullptr, nullptr, (void **)&image));
  for (PetscInt b = 0; b < n; ++b) {
    PetscReal *r = &loc[10 * id[b]];
    for (int k = 0; k < 3; ++k) r[k] = x[3 * b + k], r[3 + k] = v[3 * b + k], r[6 + k] = x[3 * b + k] + image[3 * b + k] * (hi[k] - lo[k]);
    r[9] = image[3 * b] || image[3 * b + 1] || image[3 * b + 2];
  }
  PetscCall(DMSwarmRestoreField(sw, "image", nullptr, nullptr, (void **)&image));
  PetscCall(DMSwarmRestoreField(sw, "v", nullptr, nullptr, (void **)&v));
  PetscCall(DMSwarmRestoreField(sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmRestoreField(sw, "id", nullptr, nullptr, (void **)&id));
  MPI_Comm comm;
  PetscCall(PetscObjectGetComm((PetscObject)sw, &comm));
  PetscCallMPI(MPI_Allreduce(loc.data(), all.data(), (int)all.size(), MPIU_REAL, MPI_SUM, comm));
  s.x.assign(3 * nbodies, 0), s.v.assign(3 * nbodies, 0), s.xu.assign(3 * nbodies, 0), s.crossed = 0;
  for (PetscInt i = 0; i < nbodies; ++i) {
    for (int k = 0; k < 3; ++k) s.x[3 * i + k] = all[10 * i + k], s.v[3 * i + k] = all[10 * i + 3 + k], s.xu[3 * i + k] = all[10 * i + 6 + k];
    s.crossed += all[10 * i + 9] != 0;
  }
  PetscFunctionReturn(0);
}

// Two bodies on the x axis of a cell periodic along x, for time T: body a (a sphere, or with
// `cube` a free rigid cube of side 2 R0 in six tetrahedra: sphere-surface contact through images)
// centred at x0 - (R0 + gap) moving at 15 m/s, and a sphere b at x0 + (R0 + gap) moving at -5 m/s.
PetscErrorCode Line(MPI_Comm comm, bool cube, PetscReal x0, PetscReal T, State &s) {
  FDEMRigid       rb;
  FDEMContact     c;
  PetscInt        m, id;
  const PetscReal lo[3] = {0, -0.05, -0.05}, hi[3] = {L, 0.05, 0.05};
  const PetscBool per[3] = {PETSC_TRUE, PETSC_FALSE, PETSC_FALSE};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(comm, &rb));
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMRigidSetPeriodic(rb, per));
  PetscCall(Glass(rb, -1, 0, 0, &m));
  const PetscReal gap = 0.002;
  PetscReal       xa[3] = {std::fmod(x0 - R0 - gap + L, L), 0, 0}, xb[3] = {std::fmod(x0 + R0 + gap, L), 0, 0}, va[3] = {15, 0, 0}, vb[3] = {-5, 0, 0};
  if (cube) {
    std::vector<PetscReal> X;
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 3; ++k) X.push_back(((i >> k) & 1) ? R0 : -R0);
    const int             T6[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    std::vector<PetscInt> tets;
    for (const auto &t : T6) { // positively oriented
      PetscInt  q[4] = {t[0], t[1], t[2], t[3]};
      PetscReal e1[3], e2[3], e3[3];
      for (int k = 0; k < 3; ++k) e1[k] = X[3 * q[1] + k] - X[3 * q[0] + k], e2[k] = X[3 * q[2] + k] - X[3 * q[0] + k], e3[k] = X[3 * q[3] + k] - X[3 * q[0] + k];
      if (e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0]) + e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]) < 0) std::swap(q[2], q[3]);
      tets.insert(tets.end(), q, q + 4);
    }
    PetscCall(FDEMRigidAddBodyFromMesh(rb, "cube", 8, X.data(), 6, tets.data(), RHO, xa, nullptr, va, nullptr, &id));
    PetscCall(FDEMRigidSetBodyMaterial(rb, id, m));
  } else PetscCall(FDEMRigidAddSphere(rb, "a", R0, RHO, m, xa, va, nullptr, &id));
  PetscCall(FDEMRigidAddSphere(rb, "b", R0, RHO, m, xb, vb, nullptr, &id));
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(FDEMRigidSolve(rb, 0, T, 1e-6, 40, nullptr, nullptr));
  PetscCall(Gather(rb, 2, s));
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// 64 spheres in a cell periodic along x and y, random velocities (fixed seed), dissipative.
PetscErrorCode Cloud(MPI_Comm comm, PetscInt nsteps, State &s0, State &s) {
  FDEMRigid       rb;
  FDEMContact     c;
  PetscInt        m, id;
  const PetscReal lo[3] = {0, 0, -0.05}, hi[3] = {L, L, 0.05};
  const PetscBool per[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(comm, &rb));
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMRigidSetPeriodic(rb, per));
  PetscCall(Glass(rb, 0.6, 0.4, 0.05, &m));
  std::mt19937                     rng(11);
  std::uniform_real_distribution<> u(-1, 1);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        const PetscReal x[3] = {(i + 0.5) * L / 4 + 0.002 * u(rng), (j + 0.5) * L / 4 + 0.002 * u(rng), (k - 1.5) * 0.021}, v[3] = {2 * u(rng), 2 * u(rng), 0.5 * u(rng)}, w[3] = {50 * u(rng), 50 * u(rng), 50 * u(rng)};
        PetscCall(FDEMRigidAddSphere(rb, "s", R0, RHO, m, x, v, w, &id));
      }
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(Gather(rb, 64, s0));
  PetscCall(FDEMRigidSolve(rb, 0, nsteps * 2e-6, 2e-6, 10, nullptr, nullptr));
  PetscCall(Gather(rb, 64, s));
  FDEMContactStats st;
  PetscCall(FDEMContactGetStats(c, &st));
  CHECK(st.active_pairs >= 0, "cloud: no statistics");
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

PetscReal Periodic(PetscReal d) { return d - L * std::round(d / L); }
} // namespace

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  {
    State           across, middle;
    const PetscReal T = 0.012; // relative travel 0.24 m: the pair meets three times
    PetscCall(Line(PETSC_COMM_WORLD, false, 0.0, T, across));
    PetscCall(Line(PETSC_COMM_WORLD, false, 0.5 * L, T, middle));
    PetscReal dx = 0, dv = 0;
    for (int i = 0; i < 6; ++i) {
      dx = std::max(dx, std::fabs(Periodic(across.x[i] - middle.x[i] + (i % 3 == 0 ? 0.5 * L : 0))));
      dv = std::max(dv, std::fabs(across.v[i] - middle.v[i]));
    }
    const PetscReal m = RHO * 4.0 / 3.0 * M_PI * R0 * R0 * R0, P0 = m * (15 - 5.0), K0 = 0.5 * m * (15 * 15 + 5 * 5.0);
    const PetscReal cm = 0.5 * (across.xu[0] + across.xu[3]), cm0 = 0.5 * ((L - R0 - 0.002) + (R0 + 0.002)) + 5 * T; // a starts at L - R0 - gap, b at R0 + gap; mean speed 5 m/s
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "pair across the boundary against the pair in the middle (%d ranks): |dx| %.3e m, |dv| %.3e m/s; v_a %.9f v_b %.9f; momentum %.3e kg m/s off, energy %.3e relative; centre of mass unwrapped %.9f (expected %.9f)\n", size, (double)dx,
                          (double)dv, (double)across.v[0], (double)across.v[3], (double)(across.P[0] - P0), (double)((across.K - K0) / K0), (double)cm, (double)cm0));
    CHECK(dx < 1e-9 && dv < 1e-9, "pair: across the boundary and in the middle differ by %g m, %g m/s", (double)dx, (double)dv);
    CHECK(std::fabs(across.P[0] - P0) < 1e-14 && std::fabs(across.P[1]) + std::fabs(across.P[2]) < 1e-14, "pair: momentum %g not conserved (%g)", (double)across.P[0], (double)P0);
    CHECK(std::fabs(across.K - K0) < 3e-5 * K0, "pair: kinetic energy %g after the elastic collisions, %g before", (double)across.K, (double)K0); // dt: about 100 steps per contact
    CHECK(std::fabs(across.v[0] - 15) < 1e-2 || std::fabs(across.v[0] + 5) < 1e-2, "pair: the spheres did not exchange velocities (v_a %g)", (double)across.v[0]);
    CHECK(std::fabs(cm - cm0) < 1e-9, "pair: the unwrapped centre of mass %g, expected %g (image counts)", (double)cm, (double)cm0);
    CHECK(across.crossed >= 1, "pair: no sphere ended a period away from its start (image counts all zero)");
    for (int i = 0; i < 2; ++i) CHECK(across.x[3 * i] >= 0 && across.x[3 * i] < L, "pair: sphere %d at x = %g, outside the cell", i, (double)across.x[3 * i]);
  }
  {
    State           across, middle;
    const PetscReal T = 0.002; // one collision (the sphere, thrown forward, would catch the cube again)
    PetscCall(Line(PETSC_COMM_WORLD, true, 0.0, T, across));
    PetscCall(Line(PETSC_COMM_WORLD, true, 0.5 * L, T, middle));
    PetscReal dx = 0, dv = 0;
    for (int i = 0; i < 6; ++i) {
      dx = std::max(dx, std::fabs(Periodic(across.x[i] - middle.x[i] + (i % 3 == 0 ? 0.5 * L : 0))));
      dv = std::max(dv, std::fabs(across.v[i] - middle.v[i]));
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "cube strikes a sphere across the boundary against the same in the middle (%d ranks): |dx| %.3e m, |dv| %.3e m/s; v_cube %.6f, v_sphere %.6f\n", size, (double)dx, (double)dv, (double)across.v[0], (double)across.v[3]));
    CHECK(dx < 1e-9 && dv < 1e-9, "cube and sphere: across the boundary and in the middle differ by %g m, %g m/s", (double)dx, (double)dv);
    const PetscReal mc = RHO * 8 * R0 * R0 * R0, ms = RHO * 4.0 / 3.0 * M_PI * R0 * R0 * R0, vs = ((ms - mc) * -5.0 + 2 * mc * 15.0) / (mc + ms); // elastic, head-on on a face
    CHECK(std::fabs(across.v[3] - vs) < 1e-3 * vs, "cube and sphere: the sphere leaves at %g m/s, the elastic head-on impact gives %g", (double)across.v[3], (double)vs);
  }
  {
    State           a0, a, b0, b;
    const PetscInt  nsteps = 6000;
    PetscCall(Cloud(PETSC_COMM_WORLD, nsteps, a0, a));
    PetscCall(Cloud(PETSC_COMM_SELF, nsteps, b0, b));
    PetscReal dx = 0, dv = 0, scale = 0;
    for (size_t i = 0; i < a.x.size(); ++i) {
      dx    = std::max(dx, std::fabs(a.x[i] - b.x[i]));
      dv    = std::max(dv, std::fabs(a.v[i] - b.v[i]));
      scale = std::max(scale, std::fabs(a0.v[i]));
    }
    const PetscReal m = RHO * 4.0 / 3.0 * M_PI * R0 * R0 * R0;
    PetscReal       dP = 0;
    for (int k = 0; k < 3; ++k) dP = std::max(dP, std::fabs(a.P[k] - a0.P[k]));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "cloud in a cell periodic in x and y: %d ranks against 1: |dx| %.3e m, |dv| %.3e m/s; momentum change %.3e of %g; kinetic energy %.6e -> %.6e J; %d of 64 crossed\n", size, (double)dx, (double)dv, (double)(dP / (64 * m * scale)),
                          (double)(64 * m * scale), (double)a0.K, (double)a.K, (int)a.crossed));
    CHECK(dx < 1e-9 && dv < 1e-7, "cloud: the parallel run differs from the serial one by %g m, %g m/s", (double)dx, (double)dv);
    CHECK(dP < 1e-12 * 64 * m * scale, "cloud: momentum changed by %g", (double)dP);
    CHECK(a.K < 0.9 * a0.K, "cloud: the dissipative contacts took less than 10%% of the kinetic energy (%g -> %g): no contacts?", (double)a0.K, (double)a.K);
    CHECK(a.crossed >= 2, "cloud: only %d spheres ended a period away from their start", (int)a.crossed);
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
