// Deformable-body throughput through the PETSc path (FDEMDeformable):
//  - set-up: METIS partition on rank 0, DMPlex creation and distribution;
//  - internal forces alone: G2L scatter of x, the CST kernel over the local
//    cells, L2G ADD assembly (FDEMDeformableComputeForces);
//  - a whole explicit step: -ts_type cd (one force evaluation per step + drift/kick).
// Prints tetrahedra per second per core. Options: -n 55 (box cells per side,
// 6 n^3 tetrahedra: 998 250 for 55) -repeats 5 -steps 20 -model munjiza_cst -visc 0
#include <fdem.h>
#include <fdem/deformable.h>

#include <cmath>

static PetscErrorCode Perturb(PetscInt id, const PetscReal X[3], PetscReal x[3], void *) {
  for (int k = 0; k < 3; ++k) x[k] = X[k] * (1 + 1e-3 * k) + 1e-4 * std::sin(0.37 * id + k);
  return 0;
}
static PetscErrorCode Shake(PetscInt id, const PetscReal[3], PetscReal v[3], void *) {
  for (int k = 0; k < 3; ++k) v[k] = 1e-3 * std::cos(0.73 * id + k);
  return 0;
}

int main(int argc, char **argv) {
  PetscInt          n = 55, repeats = 5, steps = 20;
  PetscReal         visc = 0;
  FDEMMaterialModel model = FDEM_MATERIAL_MUNJIZA_CST;
  PetscMPIInt       size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Deformable bench", "");
  PetscCall(PetscOptionsInt("-n", "box cells per side", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-repeats", "force evaluations timed (best taken)", "", repeats, &repeats, nullptr));
  PetscCall(PetscOptionsInt("-steps", "cd steps timed", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsEnum("-model", "material model", "", FDEMMaterialModels, (PetscEnum)model, (PetscEnum *)&model, nullptr));
  PetscCall(PetscOptionsReal("-visc", "viscosity mu", "", visc, &visc, nullptr));
  PetscOptionsEnd();

  FDEMDeformable d;
  PetscLogDouble t0, t1;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1.0, 0.25, 1.0, visc, model));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, n, n));
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t0));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t1));
  PetscInt cl, cg, no, ng, cmin, cmax;
  PetscCall(FDEMDeformableGetSizes(d, &cl, &cg, &no, &ng));
  PetscCall(MPIU_Allreduce(&cl, &cmin, 1, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  PetscCall(MPIU_Allreduce(&cl, &cmax, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ranks %d: %d tetrahedra, %d nodes, cells per rank %d..%d; %s%s\n", size, (int)cg, (int)ng, (int)cmin, (int)cmax, FDEMMaterialModels[model], visc > 0 ? " + viscosity" : ""));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "set-up (METIS + DMPlex create/distribute + element data + masses): %.2f s\n", t1 - t0));
  PetscCall(FDEMDeformableSetPositionField(d, Perturb, nullptr));
  PetscCall(FDEMDeformableSetVelocityField(d, Shake, nullptr));

  Vec x, F;
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(VecDuplicate(x, &F));
  double best = 1e300;
  for (PetscInt r = 0; r < repeats + 1; ++r) {
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t0));
    PetscCall(FDEMDeformableComputeForces(d, 0.0, nullptr, F));
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t1));
    if (r > 0) best = std::fmin(best, t1 - t0);
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "internal forces (scatter + kernel + ADD assembly): %.4f s per evaluation, %.3g tet/s, %.3g tet/s/core\n", best, cg / best, cg / best / size));

  TS  ts;
  Vec U;
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, 0.2 / n / 1.2));
  PetscCall(TSSetMaxSteps(ts, 1));
  PetscCall(TSSetMaxTime(ts, 1e30));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSolve(ts, U)); // warm-up (set-up, first force)
  PetscCall(TSSetMaxSteps(ts, 1 + steps));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, U));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t1));
  const double per = (t1 - t0) / steps;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "whole explicit step (-ts_type cd): %.4f s per step, %.3g tet/s, %.3g tet/s/core\n", per, cg / per, cg / per / size));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "RESULT ranks=%d tets=%d force_s=%.5f step_s=%.5f\n", size, (int)cg, best, per));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&F));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(PetscFinalize());
  return 0;
}
