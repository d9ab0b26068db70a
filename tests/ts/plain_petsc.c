/* A plain PETSc 3.18 program written for -ts_type basicsymplectic: it knows
   nothing of fdem and links only PETSc. With
     -dll_append /path/libfdem.so -ts_type omf32
   it runs fdem's schemes unchanged. It solves x'' = -x, x(0) = 0, v(0) = 1 to
   T = 2 with h = 0.05 and checks |x(T) - sin T| <= -tol; with -expect_type it
   also checks that the TS really is of that type. */
#include <petscts.h>
#include <math.h>

static PetscErrorCode RHSPosition(TS ts, PetscReal t, Vec v, Vec dx, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(v, dx));
  PetscFunctionReturn(0);
}
static PetscErrorCode RHSMomentum(TS ts, PetscReal t, Vec x, Vec a, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, a));
  PetscCall(VecScale(a, -1.0));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  TS          ts;
  Vec         U;
  IS          isq, isp;
  PetscReal   tol = 1e-3, err, t;
  char        expect[64] = "";
  PetscBool   same = PETSC_TRUE;
  TSType      type;
  PetscScalar *u;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-tol", &tol, NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-expect_type", expect, sizeof(expect), NULL));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, &U));
  PetscCall(VecSetValue(U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(U));
  PetscCall(VecAssemblyEnd(U));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &isq));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 1, 1, &isp));
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(TSSetType(ts, TSBASICSYMPLECTIC));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", NULL, RHSPosition, NULL));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", NULL, RHSMomentum, NULL));
  PetscCall(TSSetTimeStep(ts, 0.05));
  PetscCall(TSSetMaxTime(ts, 2.0));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSolve(ts, U));
  PetscCall(TSGetSolveTime(ts, &t));
  PetscCall(TSGetType(ts, &type));
  PetscCall(VecGetArray(U, &u));
  err = PetscAbsReal(PetscRealPart(u[0]) - sin(t));
  PetscCall(VecRestoreArray(U, &u));
  if (expect[0]) PetscCall(PetscStrcmp(expect, type, &same));
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "type %s: t = %g, |x - sin t| = %.3e (tol %.1e)%s\n", type, (double)t, (double)err, (double)tol, same ? "" : " WRONG TYPE"));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(PetscFinalize());
  return (err <= tol && same) ? 0 : 1;
}
