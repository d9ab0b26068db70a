// The fracture topology (doc/fracture.md, "Broken joints"): the time of one call of
// fdem::model::DeformableFractureTopology (fragments, free faces, node keys, broken pairs),
// which the contact adapter makes each time the number of broken joints changes, on a
// fracturable box of n^3 cubes (6 n^3 tetrahedra, about 1.9 joints each), with no joint
// broken, every third joint broken (by joint id) and every joint broken. The joint states
// are loaded like a checkpoint's (FDEMDeformableLoadJointState). Prints, per case, the
// fragments, a checksum of the answer per cell (fragment id, free faces, node keys; the same on
// any number of ranks) and the wall time, slowest rank, best of the repeats, of the topology
// (the contact's call), of FDEMDeformableGetLocalFragments (each rank its share, with their
// mass and momentum) and of FDEMDeformableGetFragments (every fragment on every rank).
// Options: -n 26 (about 1e5 tetrahedra) -repeats 3; mpiexec -n 2 for two ranks.
#include "../../src/model/deformable_impl.hpp"

#include "joint_state.hpp"

#include <fdem.h>
#include <fdem/deformable.h>

#include <algorithm>
#include <vector>

// Order-free checksum of the answer per cell, by cell and node ids.
static PetscErrorCode Checksum(FDEMDeformable d, const fdem::model::FractureTopology &t, unsigned long long *sum) {
  PetscInt nc, nl;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, nullptr, nullptr, nullptr, nullptr));
  std::vector<PetscInt> conn(4 * (size_t)nc), cgid(nc), ngid(nl);
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, conn.data(), nullptr, cgid.data(), ngid.data()));
  const auto         mix = [](unsigned long long a, unsigned long long b) { return (a * 0x9E3779B97F4A7C15ULL) ^ (b + 0x632BE59BD9B4E019ULL + (a << 6) + (a >> 2)); };
  unsigned long long loc = 0;
  for (PetscInt e = 0; e < nc; ++e) {
    loc += mix(mix(cgid[e], t.cell_fragment[e]), t.cell_free[e]);
    for (int a = 0; a < 4; ++a) loc += mix(ngid[conn[4 * e + a]], t.cell_key[4 * e + a]);
  }
  PetscCallMPI(MPI_Allreduce(&loc, sum, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, PETSC_COMM_WORLD));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscInt       n = 26, repeats = 3, joints, cells;
  FDEMDeformable d;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-n", &n, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-repeats", &repeats, nullptr));
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.25, 2000, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e6, 3e6, 30, 100, 1000, 1e10));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, n, n));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableGetJointStats(d, &joints, nullptr, nullptr));
  PetscCall(FDEMDeformableGetSizes(d, nullptr, &cells, nullptr, nullptr));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "box %" PetscInt_FMT "^3 cubes: %" PetscInt_FMT " tetrahedra, %" PetscInt_FMT " joints, %d ranks\n", n, cells, joints, size));
  const PetscInt    every[3] = {0, 3, 1};
  const char *const name[3]  = {"none broken", "every 3rd broken", "all broken"};
  for (int c = 0; c < 3; ++c) {
    PetscCall(LoadJointDamage(d, joints, every[c], "bench_topology_state.h5"));
    double             best[3] = {1e300, 1e300, 1e300};
    PetscInt           nf      = 0;
    unsigned long long sum     = 0;
    for (PetscInt r = 0; r < repeats; ++r)
      for (int k = 0; k < 3; ++k) { // the contact's call, each rank's share of the fragments, all of them on every rank
        fdem::model::FractureTopology t;
        FDEMFragment                 *f = nullptr;
        PetscInt                      n;
        PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
        const double t0 = MPI_Wtime();
        if (k == 0) PetscCall(fdem::model::DeformableFractureTopology(d, t));
        else if (k == 1) PetscCall(FDEMDeformableGetLocalFragments(d, nullptr, &n, &f));
        else PetscCall(FDEMDeformableGetFragments(d, nullptr, &n, &f));
        double dt = MPI_Wtime() - t0, slow;
        PetscCallMPI(MPI_Allreduce(&dt, &slow, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
        best[k] = std::min(best[k], slow);
        PetscCall(PetscFree(f));
        if (k == 0) PetscCall(Checksum(d, t, &sum));
        if (k == 2) nf = n;
      }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-18s fragments %8" PetscInt_FMT "  checksum %016llx  topology (the contact's call) %.4f s, each rank's fragments %.4f s, every fragment on every rank %.4f s\n", name[c], nf, sum, best[0], best[1], best[2]));
  }
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(PetscFinalize());
  return 0;
}
