// Contact between rigid bodies through the whole pipeline (rigid model + TS +
// halo + cell search + potential contact force):
//  1. two cubes, head-on and oblique: linear and angular momentum conserved to
//     1e-12; kinetic energy returns after separation, error shrinking with h;
//     no force while apart
//  2. a cube dropped on a fixed plate: elastic rebound; damped: comes to rest
//     without sinking through
//  3. a block on an incline: slides when tan(angle) > mu, sticks otherwise
//  4. bad input: a missing penalty, negative values, deep initial interpenetration
// Runs on 1 or 2 ranks (bodies cross the slab boundary between the ranks).
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

using fdem::kernels::Vec3;

#include "../common/check.hpp"

struct Mesh {
  std::vector<PetscReal> nodes;
  std::vector<PetscInt>  tets;
};
static Mesh Box(Vec3 half, int n) {
  std::vector<Vec3>               X;
  std::vector<std::array<int, 4>> T;
  fdem::kernels::MakeBoxTets(-1.0 * half, half, n, n, n, X, T);
  Mesh m;
  for (auto &p : X) m.nodes.insert(m.nodes.end(), {p.x, p.y, p.z});
  for (auto &t : T) m.tets.insert(m.tets.end(), {t[0], t[1], t[2], t[3]});
  return m;
}

struct Scene {
  FDEMRigid   rb = nullptr;
  FDEMContact c  = nullptr;
};
static PetscErrorCode SceneCreate(MPI_Comm comm, Scene *s, PetscReal penalty, const PetscReal lo[3], const PetscReal hi[3]) {
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(comm, &s->rb));
  PetscCall(FDEMRigidSetDomain(s->rb, lo, hi));
  PetscCall(FDEMContactCreate(s->rb, &s->c));
  PetscCall(FDEMContactSetPenalty(s->c, penalty));
  PetscFunctionReturn(0);
}
static PetscErrorCode SceneDestroy(Scene *s) {
  PetscFunctionBeginUser;
  PetscCall(FDEMContactDestroy(&s->c));
  PetscCall(FDEMRigidDestroy(&s->rb));
  PetscFunctionReturn(0);
}

struct Watch {
  PetscReal P0[3], L0[3], E0;
  PetscReal dP = 0, dL = 0, scaleP = 0, scaleL = 0;
  std::function<PetscErrorCode(FDEMRigid, PetscInt, PetscReal)> extra;
};
static PetscErrorCode WatchMonitor(FDEMRigid rb, PetscInt step, PetscReal t, void *ctx) {
  Watch    *w = (Watch *)ctx;
  PetscReal P[3], L[3], E;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetInvariants(rb, P, L, &E));
  if (step == 0) {
    for (int k = 0; k < 3; ++k) {
      w->P0[k] = P[k];
      w->L0[k] = L[k];
    }
    w->E0 = E;
  }
  for (int k = 0; k < 3; ++k) {
    w->dP = std::fmax(w->dP, std::fabs(P[k] - w->P0[k]));
    w->dL = std::fmax(w->dL, std::fabs(L[k] - w->L0[k]));
  }
  if (w->extra) PetscCall(w->extra(rb, step, t));
  PetscFunctionReturn(0);
}

// Two unit cubes (density 1000) approaching at relative speed 2 v, offset b sideways (b = 0: head-on).
static PetscErrorCode TwoCubes(MPI_Comm comm, PetscReal h, PetscReal offset, PetscReal *dPrel, PetscReal *dLrel, PetscReal *dErel, PetscReal *gap_force) {
  Scene           s;
  const PetscReal lo[3] = {-3, -3, -3}, hi[3] = {3, 3, 3};
  const Mesh      m = Box(Vec3(0.5, 0.5, 0.5), 2);
  PetscFunctionBeginUser;
  PetscCall(SceneCreate(comm, &s, 1e7, lo, hi));
  const PetscReal xa[3] = {-0.7, offset, 0}, xb[3] = {0.7, -offset, 0}, va[3] = {1, 0, 0}, vb[3] = {-1, 0, 0}, wa[3] = {0, 0, 0.3}, wb[3] = {0.2, 0, 0};
  PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "cube_a", (PetscInt)m.nodes.size() / 3, m.nodes.data(), (PetscInt)m.tets.size() / 4, m.tets.data(), 1000, xa, nullptr, va, wa, nullptr));
  PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "cube_b", (PetscInt)m.nodes.size() / 3, m.nodes.data(), (PetscInt)m.tets.size() / 4, m.tets.data(), 1000, xb, nullptr, vb, wb, nullptr));
  Watch w;
  PetscReal maxF_apart = 0;
  w.extra = [&](FDEMRigid rb, PetscInt step, PetscReal t) -> PetscErrorCode {
    FDEMContactStats st;
    PetscFunctionBeginUser;
    PetscCall(FDEMContactGetStats(s.c, &st));
    if (t < 0.05) maxF_apart = std::fmax(maxF_apart, st.energy); // still 0.2 apart at t < 0.1
    PetscFunctionReturn(0);
  };
  PetscCall(FDEMRigidSolve(s.rb, 0, 0.3, h, 10, WatchMonitor, &w));
  PetscReal P[3], L[3], E;
  PetscCall(FDEMRigidGetInvariants(s.rb, P, L, &E));
  *dPrel     = w.dP / 1000.0; // |P| scale: m v = 1000
  *dLrel     = w.dL / 1000.0;
  *dErel     = std::fabs(E - w.E0) / w.E0;
  *gap_force = maxF_apart;
  PetscCall(SceneDestroy(&s));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));

  // 1. two cubes
  for (PetscReal offset : {0.0, 0.3}) {
    PetscReal dP[2], dL[2], dE[2], gap;
    int       k = 0;
    for (PetscReal h : {4e-4, 2e-4}) {
      PetscCall(TwoCubes(PETSC_COMM_WORLD, h, offset, &dP[k], &dL[k], &dE[k], &gap));
      k++;
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "two cubes (%s, %d ranks): |dP|/|P| %.2e %.2e, |dL|/|L| %.2e %.2e, KE error after separation %.2e (h) %.2e (h/2), overlap energy while apart %g\n",
                          offset == 0 ? "head-on" : "oblique", (int)size, dP[0], dP[1], dL[0], dL[1], dE[0], dE[1], gap));
    CHECK(dP[0] < 1e-12 && dP[1] < 1e-12, "linear momentum not conserved: %g %g", dP[0], dP[1]);
    CHECK(dL[0] < 1e-12 && dL[1] < 1e-12, "angular momentum not conserved: %g %g", dL[0], dL[1]);
    CHECK(dE[1] < 0.02 && dE[1] < 0.6 * dE[0] + 1e-6, "kinetic energy after separation: %g (h), %g (h/2); should be small and shrink with h", dE[0], dE[1]);
    CHECK(gap == 0, "contact energy %g while the cubes are apart", gap);
  }

  // 2. a cube dropped on a fixed plate, elastic then damped
  for (PetscReal damping : {0.0, 6e5}) {
    Scene           s;
    const PetscReal lo[3] = {-2, -2, -1}, hi[3] = {2, 2, 3};
    PetscCall(SceneCreate(PETSC_COMM_WORLD, &s, 1e7, lo, hi));
    PetscCall(FDEMContactSetDissipation(s.c, damping, 0, 0));
    const Mesh      plate = Box(Vec3(1.5, 1.5, 0.1), 3), cube = Box(Vec3(0.25, 0.25, 0.25), 2);
    const PetscReal xp[3] = {0, 0, -0.1}, xc[3] = {0.1, -0.05, 0.6}, g[3] = {0, 0, -9.81};
    PetscInt        pid;
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "plate", (PetscInt)plate.nodes.size() / 3, plate.nodes.data(), (PetscInt)plate.tets.size() / 4, plate.tets.data(), 1000, xp, nullptr, nullptr, nullptr, &pid));
    PetscCall(FDEMRigidFixBody(s.rb, pid));
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "cube", (PetscInt)cube.nodes.size() / 3, cube.nodes.data(), (PetscInt)cube.tets.size() / 4, cube.tets.data(), 1000, xc, nullptr, nullptr, nullptr, nullptr));
    PetscCall(FDEMRigidSetGravity(s.rb, g));
    PetscReal ratio;
    PetscCall(FDEMContactCheckTimeStep(s.c, "cd", 2e-4, &ratio));
    Watch     w;
    PetscReal zmin = 1e9, zmax_after = -1e9, vlast = 0;
    bool      bounced = false;
    w.extra = [&](FDEMRigid rb, PetscInt, PetscReal t) -> PetscErrorCode {
      FDEMRigidBodyState st;
      PetscFunctionBeginUser;
      PetscCall(FDEMRigidGetBodyState(rb, 1, &st));
      zmin = std::fmin(zmin, st.x[2]);
      if (st.v[2] > 0.1) bounced = true;
      if (bounced) zmax_after = std::fmax(zmax_after, st.x[2]);
      vlast = std::sqrt(st.v[0] * st.v[0] + st.v[1] * st.v[1] + st.v[2] * st.v[2]);
      PetscFunctionReturn(0);
    };
    PetscCall(FDEMRigidSolve(s.rb, 0, damping > 0 ? 1.0 : 0.75, 2e-4, 50, WatchMonitor, &w));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "cube on plate (damping %g): omega_c dt / K_crit = %.3f, lowest centre z %.4f (resting height 0.25), rebound to z %.4f (dropped from 0.6), final speed %.3e\n", (double)damping,
                          (double)ratio, (double)zmin, (double)zmax_after, (double)vlast));
    CHECK(zmin > 0.25 - 0.02, "the cube sank into the plate: centre reached z = %g (surface at 0, half size 0.25)", (double)zmin);
    if (damping == 0) CHECK(bounced && zmax_after > 0.6 - 0.03, "elastic drop: rebound height %g, expected about 0.6", (double)zmax_after);
    else CHECK(vlast < 0.02 && zmin > 0.23, "damped drop: final speed %g should be near rest", (double)vlast);
    PetscCall(SceneDestroy(&s));
  }

  // 3. a block on an incline (gravity tilted by the angle): slides iff tan(angle) > mu
  for (PetscReal angle_deg : {15.0, 35.0}) {
    Scene           s;
    const PetscReal mu = 0.5, th = angle_deg * M_PI / 180, lo[3] = {-3, -2, -1}, hi[3] = {3, 2, 2};
    PetscCall(SceneCreate(PETSC_COMM_WORLD, &s, 1e7, lo, hi));
    PetscCall(FDEMContactSetDissipation(s.c, 1e5, mu, 1e7));
    const Mesh      plate = Box(Vec3(2.5, 1.0, 0.1), 4), block = Box(Vec3(0.2, 0.2, 0.1), 2);
    const PetscReal xp[3] = {0, 0, -0.1}, xb[3] = {0, 0, 0.1}, g[3] = {9.81 * std::sin(th), 0, -9.81 * std::cos(th)};
    PetscInt        pid;
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "incline", (PetscInt)plate.nodes.size() / 3, plate.nodes.data(), (PetscInt)plate.tets.size() / 4, plate.tets.data(), 1000, xp, nullptr, nullptr, nullptr, &pid));
    PetscCall(FDEMRigidFixBody(s.rb, pid));
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "block", (PetscInt)block.nodes.size() / 3, block.nodes.data(), (PetscInt)block.tets.size() / 4, block.tets.data(), 1000, xb, nullptr, nullptr, nullptr, nullptr));
    PetscCall(FDEMRigidSetGravity(s.rb, g));
    PetscCall(FDEMRigidSolve(s.rb, 0, 0.3, 1e-4, 100, nullptr, nullptr));
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(s.rb, 1, &st));
    const PetscReal slide = 0.5 * 9.81 * (std::sin(th) - mu * std::cos(th)) * 0.09; // a t^2 / 2 at t = 0.3
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "incline %.0f deg, mu %.2f (tan %.3f): block moved %.4e down the slope; Coulomb sliding would give %.4e\n", (double)angle_deg, (double)mu, std::tan(th), (double)st.x[0],
                          (double)std::fmax(slide, 0)));
    if (std::tan(th) > mu) CHECK(std::fabs(st.x[0] - slide) < 0.1 * slide, "sliding block moved %g, expected %g", (double)st.x[0], (double)slide);
    else CHECK(std::fabs(st.x[0]) < 2e-3, "sticking block moved %g (creep of the regularised friction must stay small)", (double)st.x[0]);
    PetscCall(SceneDestroy(&s));
  }

  // 4. bad input
  {
    Scene           s;
    const PetscReal lo[3] = {-3, -3, -3}, hi[3] = {3, 3, 3};
    PetscCall(SceneCreate(PETSC_COMM_WORLD, &s, 1e7, lo, hi));
    PetscCall(ExpectError("negative penalty", "penalty", [&]() { return FDEMContactSetPenalty(s.c, -5); }));
    PetscCall(ExpectError("negative friction", "friction", [&]() { return FDEMContactSetDissipation(s.c, 0, -0.3, 0); }));
    const Mesh      m = Box(Vec3(0.5, 0.5, 0.5), 1);
    const PetscReal xa[3] = {0, 0, 0}, xb[3] = {0.3, 0.1, 0};
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "a", 8, m.nodes.data(), (PetscInt)m.tets.size() / 4, m.tets.data(), 1000, xa, nullptr, nullptr, nullptr, nullptr));
    PetscCall(FDEMRigidAddBodyFromMesh(s.rb, "b", 8, m.nodes.data(), (PetscInt)m.tets.size() / 4, m.tets.data(), 1000, xb, nullptr, nullptr, nullptr, nullptr));
    PetscCall(FDEMContactSetDissipation(s.c, 0, 0.3, 0)); // friction, no tangential viscosity: refused at the first evaluation
    PetscCall(ExpectError("friction without tangential viscosity", "needs a tangential viscosity", [&]() { return FDEMRigidSolve(s.rb, 0, 1e-3, 1e-4, 10, nullptr, nullptr); }));
    PetscCall(FDEMContactSetDissipation(s.c, 0, 0, 0));
    PetscCall(ExpectError("deep initial interpenetration", "interpenetrating", [&]() { return FDEMRigidSolve(s.rb, 0, 1e-3, 1e-4, 10, nullptr, nullptr); }));
    PetscCall(SceneDestroy(&s));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
