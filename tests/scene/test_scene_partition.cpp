// The partition of a combined scene counts the rigid bodies' pairs with the mesh (doc/rigid.md,
// "Parallel"): 64 spheres resting on a deformable slab (each touching it) beside 64 spheres that
// float free, at rest, no gravity. After one step and a migration on 2 ranks, weighted by
// primitives alone (-fdem_rigid_partition_pairs false) the bisection cuts between the two groups
// (64 spheres on each rank); weighted by the pairs, the resting spheres weigh more and the cut
// moves into them: the rank that holds only resting spheres has fewer than 64 (32 here: without
// the mesh's pairs in the weights it kept all 64).
#include <fdem.h>
#include <fdem/deformable.h>
#include <fdem/rigid.h>
#include <fdem/scene.h>

#include <algorithm>

#include "../common/check.hpp"

namespace {
const PetscReal R = 0.01;

// Spheres on this rank after the migration: resting ones (x < 0) and floating ones.
PetscErrorCode Partition(PetscBool pairs, PetscInt *resting, PetscInt *floating) {
  FDEMRigid            rb;
  FDEMDeformable       d;
  FDEMScene            sc;
  FDEMGranularMaterial g;
  TS                   ts;
  Vec                  U;
  PetscInt             glass, slab, id;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsSetValue(nullptr, "-fdem_rigid_partition_pairs", pairs ? "true" : "false"));
  // the slab under the resting spheres: x in [-0.2, 0], its top at z = 0
  const PetscReal slo[3] = {-0.2, -0.1, -0.04}, shi[3] = {0, 0.1, 0};
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "slab", 1e8, 0.3, 2000, 0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshBox(d, slo, shi, 10, 10, 2));
  PetscCall(FDEMDeformableSetUp(d));
  const PetscReal lo[3] = {-0.2, -0.1, -0.05}, hi[3] = {0.7, 0.1, 0.1};
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law     = FDEM_GRANULAR_HERTZ;
  g.law_set = PETSC_TRUE;
  g.young   = 5e9;
  g.poisson = 0.25;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "glass", &g, &glass));
  g.young = 1e8; // the slab's material, by its name, for the spheres' law against it
  g.poisson = 0.3;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "slab", &g, &slab));
  for (int i = 0; i < 8; ++i) // resting: 8 x 8, 1e-5 m into the slab
    for (int j = 0; j < 8; ++j) {
      const PetscReal x[3] = {-0.19 + 0.024 * i, -0.085 + 0.024 * j, R - 1e-5};
      PetscCall(FDEMRigidAddSphere(rb, "resting", R, 2500, glass, x, nullptr, nullptr, &id));
    }
  for (int i = 0; i < 16; ++i) // floating: 16 x 4, well clear of everything
    for (int j = 0; j < 4; ++j) {
      const PetscReal x[3] = {0.05 + 0.04 * i, -0.06 + 0.04 * j, 0.05};
      PetscCall(FDEMRigidAddSphere(rb, "floating", R, 2500, glass, x, nullptr, nullptr, &id));
    }
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(FDEMSceneCreate(PETSC_COMM_WORLD, &sc));
  PetscCall(FDEMSceneSetRigid(sc, rb));
  PetscCall(FDEMSceneSetDeformable(sc, d));
  PetscCall(FDEMSceneSetContact(sc, 0, 0, 0, -1));
  PetscCall(FDEMSceneSetFromOptions(sc));
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, "cd"));
  PetscCall(FDEMSceneSetUpTS(sc, ts, &U));
  PetscCall(TSSetTimeStep(ts, 1e-8));
  PetscCall(TSSetMaxSteps(ts, 2));
  PetscCall(TSSolve(ts, U));
  FDEMSceneContactStats st;
  PetscCall(FDEMSceneGetContactStats(sc, &st));
  CHECK(st.active_pairs >= 64, "the resting spheres should touch the slab: %" PetscInt_FMT " touching pairs", st.active_pairs);
  PetscCall(FDEMSceneRestoreState(sc, U));
  PetscCall(FDEMRigidMigrate(rb));
  DM         sw;
  PetscInt   n;
  PetscReal *x;
  PetscCall(FDEMRigidGetDM(rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, "x", nullptr, nullptr, (void **)&x));
  *resting = *floating = 0;
  for (PetscInt b = 0; b < n; ++b) ++(x[3 * b] < 0 ? *resting : *floating);
  PetscCall(DMSwarmRestoreField(sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscInt    r1, f1, r0, f0, fewest[2], local[2];
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(Partition(PETSC_FALSE, &r0, &f0));
  PetscCall(Partition(PETSC_TRUE, &r1, &f1));
  local[0] = r0 + f0, local[1] = r1 + f1;
  PetscCallMPI(MPI_Allreduce(local, fewest, 2, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  PetscCall(PetscSynchronizedPrintf(PETSC_COMM_WORLD, "rank spheres: by primitives %" PetscInt_FMT " resting + %" PetscInt_FMT " floating; by pairs %" PetscInt_FMT " + %" PetscInt_FMT "\n", r0, f0, r1, f1));
  PetscCall(PetscSynchronizedFlush(PETSC_COMM_WORLD, PETSC_STDOUT));
  if (size == 2) {
    CHECK(fewest[0] == 64, "weighted by primitives the 128 spheres should split 64 and 64 (fewest on a rank: %" PetscInt_FMT ")", fewest[0]);
    CHECK(fewest[1] < 64, "weighted by pairs the resting spheres (in contact with the mesh) should weigh more: a rank should hold fewer than 64 spheres, the fewest is %" PetscInt_FMT, fewest[1]);
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
