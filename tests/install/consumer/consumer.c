/* Links an installed libfdem, registers its TS types and runs omf32 on
   x'' = -x for one period: |x(2 pi)| must be tiny. */
#include <fdem.h>
#include <math.h>

static PetscErrorCode Fq(TS ts, PetscReal t, Vec v, Vec dx, void *ctx) { return VecCopy(v, dx); }
static PetscErrorCode Fp(TS ts, PetscReal t, Vec x, Vec a, void *ctx) {
  PetscCall(VecCopy(x, a));
  return VecScale(a, -1.0);
}

int main(int argc, char **argv) {
  TS             ts;
  Vec            U;
  IS             isq, isp;
  PetscScalar   *u;
  PetscReal      err;
  FDEMSchemeInfo info;
  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(FDEMInitializePackage());
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, &U));
  PetscCall(VecSetValue(U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(U));
  PetscCall(VecAssemblyEnd(U));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &isq));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 1, 1, &isp));
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(TSSetType(ts, TSFDEMOMF32));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", NULL, Fq, NULL));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", NULL, Fp, NULL));
  PetscCall(TSSetTimeStep(ts, 2 * M_PI / 20));
  PetscCall(TSSetMaxTime(ts, 2 * M_PI));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMTSGetSchemeInfo(ts, &info));
  PetscCall(VecGetArray(U, &u));
  err = fabs(PetscRealPart(u[0]));
  PetscCall(VecRestoreArray(U, &u));
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "installed fdem: %s (order %d), |x(2pi)| = %.2e\n", info.name, (int)info.order, (double)err));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(PetscFinalize());
  return err < 1e-6 ? 0 : 1;
}
