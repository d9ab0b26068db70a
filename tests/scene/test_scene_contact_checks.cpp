// Rigid-deformable contact in FDEMScene: the halo, the initial-overlap check and the time-step check.
//  1. halo: 8 cubes in a row along x drop onto a long slab; the rigid bodies are split by the
//     rigid domain at x = 3, the mesh by METIS. On more than one rank the ranks hold fewer
//     ghost tetrahedra in all than there are contact tetrahedra (the halo is partial), and at
//     least one (the halo carries them); the run equals the same run on one rank to 1e-10 relative
//     (mesh nodes by global id, every cube's x, v, H); momentum conserved to 1e-12 relative.
//  2. a cube half sunk into the block: a collective error naming the rigid body, the deformable
//     body and the elements; a cube 1 mm in: no error, contact active.
//  3. FDEMSceneCheckTimeStep: the ratio omega_c dt / K_crit is linear in dt (2 dt -> 2 ratio),
//     above 0.5 for a large dt and below for a small one; omega_c equals the documented rigid-side
//     estimate when the mesh side is slower (a dense mesh); the automatic check at the first
//     evaluation of a TS stores the same ratio in the stats.
//  4. A state entry made NaN: a rigid body's velocity stops the run at the scheme's check, which
//     names the body and the quantity (FDEMTSSetNonFiniteReport); a mesh node's velocity at the
//     element check, which names the element and the body.
#include <fdem.h>
#include <fdem/scene.h>
#include <fdem/kernels/massprops.hpp>
#include "../common/check.hpp"
#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace {
const PetscReal TILT = 0.03;

// A cube of side 0.2 (density 500: 4 kg), tilted by TILT about y, bottom `gap` above z = ztop.
PetscErrorCode AddCube(FDEMRigid rb, PetscReal x0, PetscReal y0, PetscReal ztop, PetscReal gap, const PetscReal v[3], const PetscReal w[3], PetscInt *ntets) {
  std::vector<fdem::kernels::Vec3> cn;
  std::vector<std::array<int, 4>>  ct;
  PetscFunctionBeginUser;
  fdem::kernels::MakeBoxTets(fdem::kernels::Vec3(-0.1, -0.1, -0.1), fdem::kernels::Vec3(0.1, 0.1, 0.1), 1, 1, 1, cn, ct);
  std::vector<PetscReal> nodes;
  std::vector<PetscInt>  tets;
  for (const auto &p : cn) nodes.insert(nodes.end(), {p.x, p.y, p.z});
  for (const auto &t : ct) tets.insert(tets.end(), t.begin(), t.end());
  const PetscReal ca = std::cos(TILT), sa = std::sin(TILT);
  const PetscReal Q[9] = {ca, 0, sa, 0, 1, 0, -sa, 0, ca};
  const PetscReal x[3] = {x0, y0, ztop + 0.1 * (ca + sa) + gap};
  PetscCall(FDEMRigidAddBodyFromMesh(rb, "cube", (PetscInt)cn.size(), nodes.data(), (PetscInt)ct.size(), tets.data(), 500, x, Q, v, w, nullptr));
  if (ntets) *ntets = (PetscInt)ct.size();
  PetscFunctionReturn(0);
}

PetscErrorCode MakeSlab(MPI_Comm comm, PetscReal L, PetscInt nx, PetscReal rho, FDEMDeformable *d) {
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {L, 1, 0.25};
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, d));
  PetscCall(FDEMDeformableAddMaterial(*d, "rubber", 5e7, 0.3, rho, 0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshBox(*d, lo, hi, nx, 4, 1));
  PetscCall(FDEMDeformableSetUp(*d));
  PetscFunctionReturn(0);
}

PetscErrorCode MakeScene(MPI_Comm comm, FDEMRigid rb, FDEMDeformable d, PetscReal dt, FDEMScene *sc, TS *ts, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(FDEMSceneCreate(comm, sc));
  PetscCall(FDEMSceneSetRigid(*sc, rb));
  PetscCall(FDEMSceneSetDeformable(*sc, d));
  PetscCall(FDEMSceneSetContact(*sc, 5e8, 0, 0, -1));
  PetscCall(TSCreate(comm, ts));
  PetscCall(TSSetType(*ts, "cd"));
  PetscCall(FDEMSceneSetUpTS(*sc, *ts, U));
  PetscCall(TSSetTimeStep(*ts, dt));
  PetscCall(TSSetExactFinalTime(*ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ 1. halo
constexpr int NB = 8;
struct HaloResult {
  PetscReal              P0[3], P1[3];
  PetscInt               ghosts, primitives, max_active; // ghost and contact tetrahedra, all ranks
  std::vector<PetscReal> cubes; // x, v, H of every cube (all ranks)
  std::vector<PetscReal> nodes; // on rank 0 of comm: (x, v) by global id
};

PetscErrorCode Halo(MPI_Comm comm, HaloResult &res) {
  FDEMRigid      rb;
  FDEMDeformable d;
  FDEMScene      sc;
  TS             ts;
  Vec            U;
  PetscFunctionBeginUser;
  PetscCall(MakeSlab(comm, 4, 16, 1000, &d));
  const PetscReal dlo[3] = {0, 0, 0}, dhi[3] = {6, 1, 1}; // rigid slabs along x: [0, 3) and [3, 6) on 2 ranks
  PetscCall(FDEMRigidCreate(comm, &rb));
  PetscCall(FDEMRigidSetDomain(rb, dlo, dhi));
  for (int i = 0; i < NB; ++i) {
    const PetscReal v[3] = {0.05 * (i % 3 - 1), 0.02 * (i % 2), -1}, w[3] = {0.5, 0.3 * (i % 3), 0.1 * i};
    PetscCall(AddCube(rb, 0.25 + 0.5 * i, 0.45 + 0.02 * i, 0.25, 0.002 * (i % 4), v, w, nullptr));
  }
  PetscCall(MakeScene(comm, rb, d, 1e-4, &sc, &ts, &U));
  PetscReal E[4], L[3];
  PetscCall(FDEMSceneGetInvariants(sc, U, 0, res.P0, L, E));
  res.max_active = 0;
  for (PetscInt s = 10; s <= 100; s += 10) {
    FDEMSceneContactStats st;
    PetscCall(TSSetMaxSteps(ts, s));
    PetscCall(TSSetMaxTime(ts, 1e9));
    PetscCall(TSSolve(ts, U));
    PetscCall(FDEMSceneGetContactStats(sc, &st));
    res.max_active = std::max(res.max_active, st.active_pairs);
  }
  FDEMSceneContactStats st;
  PetscCall(FDEMSceneGetContactStats(sc, &st));
  res.ghosts     = st.ghosts;
  res.primitives = st.primitives;
  PetscReal t;
  PetscCall(TSGetTime(ts, &t));
  PetscCall(FDEMSceneGetInvariants(sc, U, t, res.P1, L, E));
  res.cubes.clear();
  for (PetscInt id = 0; id < NB; ++id) {
    FDEMRigidBodyState b;
    PetscCall(FDEMRigidGetBodyState(rb, id, &b));
    for (int k = 0; k < 3; ++k) res.cubes.insert(res.cubes.end(), {b.x[k], b.v[k], b.H[k]});
  }
  PetscCall(GatherNodes(comm, d, res.nodes));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

PetscErrorCode TestHalo() {
  PetscMPIInt size, rank;
  HaloResult  r;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(Halo(PETSC_COMM_WORLD, r));
  const PetscReal P0 = std::sqrt(r.P0[0] * r.P0[0] + r.P0[1] * r.P0[1] + r.P0[2] * r.P0[2]);
  PetscReal       dP = 0;
  for (int k = 0; k < 3; ++k) dP = PetscMax(dP, PetscAbsReal(r.P1[k] - r.P0[k]));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "halo: %" PetscInt_FMT " ghost tetrahedra of %" PetscInt_FMT " contact tetrahedra (all ranks), %d cubes\n", r.ghosts, r.primitives, NB));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "halo: momentum drift %.2e relative, active pairs max %" PetscInt_FMT "\n", (double)(dP / P0), r.max_active));
  CHECK(dP / P0 < 1e-12, "halo: linear momentum drifts by %g relative", (double)(dP / P0));
  CHECK(r.max_active > 0, "halo: no contact happened");
  if (size == 1) CHECK(r.ghosts == 0, "halo: one rank holds %" PetscInt_FMT " ghosts (expected 0)", r.ghosts);
  if (size > 1) {
    CHECK(r.ghosts < r.primitives, "halo: %" PetscInt_FMT " ghosts of %" PetscInt_FMT " contact tetrahedra: the halo is not partial", r.ghosts, r.primitives);
    CHECK(r.ghosts > 0, "halo: no rank holds a ghost; this scene needs some (the rigid and mesh partitions differ)");
    HaloResult s;
    if (rank == 0) PetscCall(Halo(PETSC_COMM_SELF, s));
    PetscReal diff[2] = {0, 0};
    if (rank == 0) {
      PetscReal scale = 0;
      for (size_t k = 0; k < s.nodes.size(); ++k) {
        diff[0] = PetscMax(diff[0], PetscAbsReal(s.nodes[k] - r.nodes[k]));
        scale   = PetscMax(scale, PetscAbsReal(s.nodes[k]));
      }
      diff[0] /= scale;
      scale = 0;
      for (size_t k = 0; k < s.cubes.size(); ++k) {
        diff[1] = PetscMax(diff[1], PetscAbsReal(s.cubes[k] - r.cubes[k]));
        scale   = PetscMax(scale, PetscAbsReal(s.cubes[k]));
      }
      diff[1] /= scale;
    }
    PetscCallMPI(MPI_Bcast(diff, 2, MPIU_REAL, 0, PETSC_COMM_WORLD));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "halo: %d ranks vs 1 rank: mesh nodes differ by %.3e, cubes by %.3e (relative)\n", size, (double)diff[0], (double)diff[1]));
    CHECK(diff[0] < 1e-10 && diff[1] < 1e-10, "halo: %d ranks differ from 1 rank: nodes %g, cubes %g", size, (double)diff[0], (double)diff[1]);
  }
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ 2. initial overlap
// One cube over a 1 x 1 x 0.25 block (4 x 4 x 1 cells), its lowest corner `depth` below the top.
PetscErrorCode Overlap(PetscReal depth, PetscInt *active) {
  FDEMRigid      rb;
  FDEMDeformable d;
  FDEMScene      sc;
  TS             ts;
  Vec            U;
  const PetscReal zero[3] = {0, 0, 0}, dlo[3] = {0, 0, 0}, dhi[3] = {1, 1, 1};
  PetscFunctionBeginUser;
  PetscCall(MakeSlab(PETSC_COMM_WORLD, 1, 4, 1000, &d));
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, dlo, dhi));
  PetscCall(AddCube(rb, 0.45, 0.55, 0.25, -depth, zero, zero, nullptr));
  PetscCall(MakeScene(PETSC_COMM_WORLD, rb, d, 1e-5, &sc, &ts, &U));
  PetscCall(TSSetMaxSteps(ts, 1));
  // objects are destroyed whether the solve fails or not
  PetscErrorCode ierr = TSSolve(ts, U);
  FDEMSceneContactStats st;
  if (!ierr) PetscCall(FDEMSceneGetContactStats(sc, &st));
  if (!ierr && active) *active = st.active_pairs;
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  return ierr;
}

PetscErrorCode TestOverlap() {
  PetscInt active = -1;
  PetscFunctionBeginUser;
  PetscCall(ExpectError("cube half sunk into the block", "deformable body 'box' and rigid body 0 start interpenetrating deeply", [&]() { return Overlap(0.1, nullptr); }));
  PetscCall(Overlap(1e-3, &active));
  CHECK(active > 0, "a cube 1 mm into the block: no active contact pair (%" PetscInt_FMT ")", active);
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ 3. time step
PetscErrorCode TestTimeStep() {
  FDEMRigid             rb;
  FDEMDeformable        d;
  FDEMScene             sc;
  TS                    ts;
  Vec                   U;
  PetscInt              ntets;
  FDEMSceneContactStats st;
  FDEMSchemeInfo        info;
  PetscBool             found;
  const PetscReal       zero[3] = {0, 0, 0}, vdown[3] = {0, 0, -1}, dlo[3] = {0, 0, 0}, dhi[3] = {1, 1, 1};
  PetscFunctionBeginUser;
  // a dense mesh (100 t/m^3): its contact cells oscillate slower than the cube
  PetscCall(MakeSlab(PETSC_COMM_WORLD, 1, 4, 1e5, &d));
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, dlo, dhi));
  PetscCall(AddCube(rb, 0.45, 0.55, 0.25, 0.01, vdown, zero, &ntets));
  PetscCall(MakeScene(PETSC_COMM_WORLD, rb, d, 2e-3, &sc, &ts, &U));
  PetscCall(FDEMSchemeInfoFind("cd", &found, &info));
  PetscReal r1, r2, rsmall, rbig;
  PetscCall(FDEMSceneCheckTimeStep(sc, "cd", 1e-5, &r1));
  PetscCall(FDEMSceneCheckTimeStep(sc, "cd", 2e-5, &r2));
  PetscCall(FDEMSceneCheckTimeStep(sc, "cd", 1e-6, &rsmall));
  PetscCall(FDEMSceneCheckTimeStep(sc, "cd", 1e-2, &rbig)); // prints the warning
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "time step: ratio %.4g (dt 1e-5), %.4g (2e-5), %.4g (1e-6), %.4g (1e-2)\n", (double)r1, (double)r2, (double)rsmall, (double)rbig));
  CHECK(PetscAbsReal(r2 - 2 * r1) < 1e-12 * r1, "time step: doubling dt takes the ratio from %g to %g, not twice", (double)r1, (double)r2);
  CHECK(rsmall < 0.5 && rbig > 0.5, "time step: ratio %g at dt 1e-6 (expected < 0.5), %g at dt 1e-2 (expected > 0.5)", (double)rsmall, (double)rbig);
  // the rigid-side estimate sqrt(penalty A / (L m)), A = (2 r)^2, L = (6 r^3 / skin tets)^(1/3)
  const PetscReal r = 0.1 * std::sqrt(3.0), m = 500 * 0.008, L = std::cbrt(6 * r * r * r / ntets), omega = std::sqrt(5e8 * 4 * r * r / (L * m));
  const PetscReal omega_c = r1 * info.kcrit / 1e-5;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "time step: omega_c %.6g, rigid-side estimate %.6g\n", (double)omega_c, (double)omega));
  CHECK(PetscAbsReal(omega_c - omega) < 1e-10 * omega, "time step: omega_c %g is not the rigid-side estimate %g", (double)omega_c, (double)omega);
  // the automatic check at the first evaluation of the TS (dt 2e-3: a warning)
  PetscCall(TSSetMaxSteps(ts, 1));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMSceneGetContactStats(sc, &st));
  PetscReal rts;
  PetscCall(FDEMSceneCheckTimeStep(sc, "cd", 2e-3, &rts));
  CHECK(st.dt_ratio > 0.5 && PetscAbsReal(st.dt_ratio - rts) < 1e-12 * rts, "time step: the automatic check stored %g, expected %g", (double)st.dt_ratio, (double)rts);
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ 4. Inf or NaN named
PetscErrorCode TestNonFinite() {
  const PetscReal zero[3] = {0, 0, 0}, dlo[3] = {0, 0, 0}, dhi[3] = {1, 1, 1};
  PetscMPIInt     rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  for (int part = 0; part < 2; ++part) {
    FDEMRigid      rb = nullptr;
    FDEMDeformable d  = nullptr;
    FDEMScene      sc;
    TS             ts;
    Vec            U;
    PetscInt       nd = 0, nr = 0;
    PetscScalar   *u;
    PetscCall(FDEMSceneCreate(PETSC_COMM_WORLD, &sc));
    if (part == 0) { // a rigid cube alone
      PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
      PetscCall(FDEMRigidSetDomain(rb, dlo, dhi));
      PetscCall(AddCube(rb, 0.45, 0.55, 0.25, 0.01, zero, zero, nullptr));
      PetscCall(FDEMSceneSetRigid(sc, rb));
      PetscCall(FDEMRigidGetNumBodies(rb, &nr, nullptr));
    } else { // a slab alone
      PetscCall(MakeSlab(PETSC_COMM_WORLD, 1, 4, 1000, &d));
      PetscCall(FDEMSceneSetDeformable(sc, d));
      PetscCall(FDEMDeformableGetSizes(d, nullptr, nullptr, &nd, nullptr));
    }
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, "cd"));
    PetscCall(FDEMSceneSetUpTS(sc, ts, &U));
    PetscCall(TSSetTimeStep(ts, 1e-5));
    PetscCall(TSSetMaxSteps(ts, 30));
    PetscCall(VecGetArray(U, &u));
    // the last rank holding some: the cube's z velocity (after x, R and v's x, y), the first owned node's x velocity
    PetscMPIInt holds = (part == 0 ? nr : nd) > 0 ? rank : -1, last;
    PetscCallMPI(MPI_Allreduce(&holds, &last, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD));
    if (rank == last) u[part == 0 ? 12 * nr + 2 : 3 * nd] = NAN;
    PetscCall(VecRestoreArray(U, &u));
    // the velocity's NaN reaches the cube's position at the step's drift, which comes first in
    // the state; a mesh's reaches its elements' corners, which the element check finds first
    if (part == 0) PetscCall(ExpectError("non-finite: a rigid body's velocity", {"became Inf or NaN", "first at rigid body 0 (its position)"}, [&]() { return TSSolve(ts, U); }));
    else PetscCall(ExpectError("non-finite: a mesh node's velocity", {"of body 'box' has corners that are Inf or NaN"}, [&]() { return TSSolve(ts, U); }));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    PetscCall(FDEMSceneDestroy(&sc));
    if (rb) PetscCall(FDEMRigidDestroy(&rb));
    if (d) PetscCall(FDEMDeformableDestroy(&d));
  }
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(TestHalo());
  PetscCall(TestOverlap());
  PetscCall(TestTimeStep());
  PetscCall(TestNonFinite());
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failure(s)\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
