// Contact with newly exposed faces (doc/fracture.md, "Speed"): a fracturable box of
// n^3 cubes (6 n^3 tetrahedra) whose joints are all broken (loaded through
// FDEMDeformableLoadJointState from a state file of damage 1), so that every tetrahedron
// is a contact primitive touching its neighbours across cracks. Times, per tetrahedron,
// the first contact evaluation (list, search, ghosts, pair loop) and a following one
// (pair loop only), for several n: a linear search keeps both flat as the count grows.
// Options: -sizes 6,12,24 -repeats 3
#include "joint_state.hpp"

#include <fdem.h>
#include <fdem/deformable.h>
#include <fdem/deformable_contact.h>

#include <algorithm>
#include <ctime>
#include <vector>

static double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static PetscErrorCode Run(PetscInt n, double *first, double *next, PetscInt *pairs, PetscInt *joints) {
  FDEMDeformable        d;
  FDEMDeformableContact c;
  Vec                   F, x;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.25, 2000, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e6, 3e6, 30, 100, 1000, 1e10));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, n, n));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableGetJointStats(d, joints, nullptr, nullptr));
  PetscCall(LoadJointDamage(d, *joints, 1, "bench_exposed_state.h5")); // every joint broken, loaded like a checkpoint's
  PetscInt broken;
  PetscCall(FDEMDeformableGetJointStats(d, nullptr, &broken, nullptr));
  PetscCheck(broken == *joints, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "bench: %" PetscInt_FMT " of %" PetscInt_FMT " joints broken", broken, *joints);
  PetscCall(FDEMDeformableContactCreate(d, &c));
  PetscCall(FDEMDeformableContactSetPenalty(c, 1e10));
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(VecDuplicate(x, &F));
  double c0 = CpuSeconds();
  PetscCall(FDEMDeformableComputeForces(d, 0, nullptr, F));
  double c1 = CpuSeconds();
  PetscCall(FDEMDeformableComputeForces(d, 0, nullptr, F));
  double c2 = CpuSeconds(), loc[2] = {c1 - c0, c2 - c1}, glob[2];
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  *first = glob[0], *next = glob[1];
  FDEMDeformableContactStats st;
  PetscCall(FDEMDeformableContactGetStats(c, &st));
  *pairs = st.candidate_pairs;
  PetscCall(VecDestroy(&F));
  PetscCall(FDEMDeformableContactDestroy(&c));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscInt  sizes[16] = {6, 12, 24}, ns = 16, repeats = 3;
  PetscBool set;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetIntArray(nullptr, nullptr, "-sizes", sizes, &ns, &set));
  if (!set) ns = 3;
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-repeats", &repeats, nullptr));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "every joint broken: CPU s per tetrahedron of a contact evaluation (busiest rank, best of %" PetscInt_FMT ")\n%10s %10s %12s %16s %16s %14s\n", repeats, "cubes", "tets", "joints", "first (search)", "next (pairs)", "pairs/tet"));
  for (PetscInt k = 0; k < ns; ++k) {
    double   best1 = 1e300, best2 = 1e300;
    PetscInt pairs = 0, nj = 0;
    for (PetscInt r = 0; r < repeats; ++r) {
      double a, b;
      PetscCall(Run(sizes[k], &a, &b, &pairs, &nj));
      best1 = std::min(best1, a), best2 = std::min(best2, b);
    }
    const double tets = 6.0 * sizes[k] * sizes[k] * sizes[k];
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%7" PetscInt_FMT "^3 %10.0f %12" PetscInt_FMT " %16.3e %16.3e %14.1f\n", sizes[k], tets, nj, best1 / tets, best2 / tets, pairs / tets));
  }
  PetscCall(PetscFinalize());
  return 0;
}
