// The partition weighs each body by its contact work (FDEMRigidMigrate, doc/rigid.md "Parallel"):
// a dense block of 512 touching spheres beside a dilute gas of 512 spheres that touch nothing, at
// rest. Weighted by contact primitives alone (-fdem_rigid_partition_pairs false) the bisection
// cuts between the block and the gas: one rank computes every contact. Weighted by the pairs
// measured at the last search (the default), the cut moves into the block and the ranks' work
// (primitives plus pairs, summed from the swarm field "work") is balanced to 15%. Weighted by
// measured CPU time (-fdem_rigid_partition_timed) the costs per primitive and per pair are
// positive and finite, and in those costs the ranks' work is better balanced than by the
// primitives alone when those costs make that cut clearly unbalanced. Run on 2 ranks
// and more; on one rank it only checks that nothing moves.
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>

#include <algorithm>
#include <cmath>

#include "../common/check.hpp"

namespace {
const PetscReal R0 = 0.01, RHO = 2500;

enum class Weights { Primitives, Pairs, Timed };

// One run: this rank's bodies and pairs at the end (local[0], local[1]), the largest speed, and
// the partition's measured costs (out; 0 unless weights is Timed).
PetscErrorCode Run(Weights weights, PetscReal local[2], PetscReal *moved, PetscReal out[2]) {
  FDEMRigid            rb;
  FDEMContact          c;
  FDEMGranularMaterial g;
  PetscInt             m, id;
  PetscMPIInt          size;
  const PetscReal      lo[3] = {-0.2, -0.1, -0.1}, hi[3] = {0.7, 0.1, 0.1};
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsSetValue(nullptr, "-fdem_rigid_partition_pairs", weights != Weights::Primitives ? "true" : "false"));
  PetscCall(PetscOptionsSetValue(nullptr, "-fdem_rigid_partition_timed", weights == Weights::Timed ? "true" : "false"));
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
  PetscCall(FDEMRigidGetPartitionCosts(rb, &out[0], &out[1]));
  DM         sw;
  PetscInt   n;
  PetscReal *w, *x, dmax = 0;
  PetscCall(FDEMRigidGetDM(rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, "work", nullptr, nullptr, (void **)&w));
  PetscCall(DMSwarmGetField(sw, "v", nullptr, nullptr, (void **)&x));
  for (PetscInt b = 0; b < n; ++b) {
    local[0] += 1;
    local[1] += w[b];
    for (int k = 0; k < 3; ++k) dmax = std::max(dmax, std::fabs(x[3 * b + k]));
  }
  PetscCall(DMSwarmRestoreField(sw, "v", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmRestoreField(sw, "work", nullptr, nullptr, (void **)&w));
  PetscCallMPI(MPI_Allreduce(&dmax, moved, 1, MPIU_REAL, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

// max over ranks / mean over ranks of the work per_body bodies + per_pair pairs of a run's end.
PetscReal Imbalance(const PetscReal local[2], PetscReal per_body, PetscReal per_pair) {
  PetscMPIInt     size;
  PetscReal       mx, sum;
  const PetscReal mine = per_body * local[0] + per_pair * local[1];
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Allreduce(&mine, &mx, 1, MPIU_REAL, MPI_MAX, PETSC_COMM_WORLD);
  MPI_Allreduce(&mine, &sum, 1, MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD);
  return mx / (sum / size);
}
} // namespace

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscReal   pairs[2] = {0, 0}, count[2] = {0, 0}, timed[2] = {0, 0}, v1, v2, v3, none[2], cost[2];
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(Run(Weights::Pairs, pairs, &v1, none));
  CHECK(none[0] == 0 && none[1] == 0, "without -fdem_rigid_partition_timed nothing is measured (got %g, %g s)", (double)none[0], (double)none[1]);
  PetscCall(Run(Weights::Primitives, count, &v2, none));
  PetscCall(Run(Weights::Timed, timed, &v3, cost));
  v1 = std::max(v1, std::max(v2, v3));
  // in counts (bodies + pairs), and in the costs the timed partition measured and weighed by
  const PetscReal by_pairs[2] = {Imbalance(pairs, 1, 1), Imbalance(pairs, cost[0], cost[1])}, by_count[2] = {Imbalance(count, 1, 1), Imbalance(count, cost[0], cost[1])}, by_time[2] = {Imbalance(timed, 1, 1), Imbalance(timed, cost[0], cost[1])};
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d ranks: busiest rank's work / mean (bodies + pairs; in measured costs of %.3g s per body, %.3g s per pair), weighted by pairs %.3f, %.3f; by primitives %.3f, %.3f; by measured time %.3f, %.3f; largest speed %.2e m/s\n", size, (double)cost[0], (double)cost[1],
                        (double)by_pairs[0], (double)by_pairs[1], (double)by_count[0], (double)by_count[1], (double)by_time[0], (double)by_time[1], (double)v1));
  CHECK(v1 < 1e-3, "the spheres at rest moved (%g m/s): they overlap", (double)v1);
  if (size > 1) {
    CHECK(by_pairs[0] < 1.15, "weighted by the pairs, the busiest rank has %.3f times the mean work", (double)by_pairs[0]);
    CHECK(by_count[0] > 1.3, "weighted by the primitives alone the partition should cut between the block and the gas (busiest rank %.3f of the mean): the test no longer tells the two apart", (double)by_count[0]);
    CHECK(std::isfinite(cost[0]) && std::isfinite(cost[1]) && cost[0] > 0 && cost[1] > 0, "the measured costs per primitive and per pair must be positive: %g, %g s", (double)cost[0], (double)cost[1]);
    // in the costs it weighed by (they vary from run to run: CPU time on a shared machine): when
    // they make the cut by primitives alone clearly unbalanced (the pairs cost enough), the timed
    // partition beats it; when the measured cost per pair is small against the cost per body,
    // both cuts are near balance in them, their order is noise, and the timed one must be near
    // balance too (within the granularity of the block's layers of 64 spheres, on 3 ranks)
    if (by_count[1] > 1.2) CHECK(by_time[1] < by_count[1], "in its measured costs the partition weighted by them (%.3f of the mean) should beat the one by primitives alone (%.3f)", (double)by_time[1], (double)by_count[1]);
    else CHECK(by_time[1] < 1.25, "the measured costs make the cut by primitives alone balanced (%.3f of the mean), but the one weighted by them is not (%.3f)", (double)by_count[1], (double)by_time[1]);
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
