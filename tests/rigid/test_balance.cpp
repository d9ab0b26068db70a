// The partition weighs each body by its contact work (FDEMRigidMigrate, doc/rigid.md "Parallel"):
// a dense block of 512 touching spheres beside a dilute gas of 512 spheres that touch nothing, at
// rest. Weighted by contact primitives alone (-fdem_rigid_partition_pairs false) the bisection
// cuts between the block and the gas: one rank computes every contact. Weighted by the pairs
// measured at the last search (the default), the cut moves into the block and the ranks' work
// (primitives plus pairs, summed from the swarm field "work") is balanced to 15%. Run on 2 ranks
// and more; on one rank it only checks that nothing moves.
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>

#include <algorithm>
#include <cmath>

#include "../common/check.hpp"

namespace {
const PetscReal R0 = 0.01, RHO = 2500;

// max over ranks / mean over ranks of each rank's work (bodies + pairs).
PetscErrorCode Imbalance(PetscBool pairs, PetscReal *ratio, PetscReal *moved) {
  FDEMRigid            rb;
  FDEMContact          c;
  FDEMGranularMaterial g;
  PetscInt             m, id;
  PetscMPIInt          size;
  const PetscReal      lo[3] = {-0.2, -0.1, -0.1}, hi[3] = {0.7, 0.1, 0.1};
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsSetValue(nullptr, "-fdem_rigid_partition_pairs", pairs ? "true" : "false"));
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law     = FDEM_GRANULAR_HERTZ;
  g.law_set = PETSC_TRUE;
  g.young   = 5e9;
  g.poisson = 0.25;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "glass", &g, &m));
  for (int i = 0; i < 8; ++i) // the block: a cubic lattice of touching spheres, x in [-0.16, 0)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) {
        const PetscReal x[3] = {-0.15 + 2 * R0 * i, -0.07 + 2 * R0 * j, -0.07 + 2 * R0 * k};
        PetscCall(FDEMRigidAddSphere(rb, "block", R0, RHO, m, x, nullptr, nullptr, &id));
      }
  for (int i = 0; i < 32; ++i) // the gas: 16 spheres per layer, 0.02 m apart along x, 0.05 across
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        const PetscReal x[3] = {0.03 + 0.02 * i, -0.075 + 0.05 * j, -0.075 + 0.05 * k};
        PetscCall(FDEMRigidAddSphere(rb, "gas", 0.4 * R0, RHO, m, x, nullptr, nullptr, &id));
      }
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(FDEMRigidSolve(rb, 0, 30 * 1e-6, 1e-6, 10, nullptr, nullptr)); // three migrations
  DM         sw;
  PetscInt   n;
  PetscReal *w, *x, mine = 0, mx, sum, dmax = 0;
  PetscCall(FDEMRigidGetDM(rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, "work", nullptr, nullptr, (void **)&w));
  PetscCall(DMSwarmGetField(sw, "v", nullptr, nullptr, (void **)&x));
  for (PetscInt b = 0; b < n; ++b) {
    mine += 1 + w[b];
    for (int k = 0; k < 3; ++k) dmax = std::max(dmax, std::fabs(x[3 * b + k]));
  }
  PetscCall(DMSwarmRestoreField(sw, "v", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmRestoreField(sw, "work", nullptr, nullptr, (void **)&w));
  PetscCallMPI(MPI_Allreduce(&mine, &mx, 1, MPIU_REAL, MPI_MAX, PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Allreduce(&mine, &sum, 1, MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Allreduce(&dmax, moved, 1, MPIU_REAL, MPI_MAX, PETSC_COMM_WORLD));
  *ratio = mx / (sum / size);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscReal   by_pairs, by_count, v1, v2;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(Imbalance(PETSC_TRUE, &by_pairs, &v1));
  PetscCall(Imbalance(PETSC_FALSE, &by_count, &v2));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d ranks: busiest rank's work / mean, weighted by pairs %.3f, by primitives %.3f; largest speed %.2e m/s\n", size, (double)by_pairs, (double)by_count, (double)std::max(v1, v2)));
  CHECK(std::max(v1, v2) < 1e-3, "the spheres at rest moved (%g m/s): they overlap", (double)std::max(v1, v2));
  if (size > 1) {
    CHECK(by_pairs < 1.15, "weighted by the pairs, the busiest rank has %.3f times the mean work", (double)by_pairs);
    CHECK(by_count > 1.3, "weighted by the primitives alone the partition should cut between the block and the gas (busiest rank %.3f of the mean): the test no longer tells the two apart", (double)by_count);
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
