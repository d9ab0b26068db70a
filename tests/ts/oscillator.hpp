// The book's test oscillator x'' = -omega^2 x (5.116-5.118) as a TS problem:
// U = (x, v) on one rank, position/momentum splits exactly as for basicsymplectic.
#pragma once
#include <petscts.h>
#include <vector>

namespace osc {

struct Oscillator {
  PetscReal omega2 = 1.0;
  IS        isq = nullptr, isp = nullptr;
  PetscInt  nforce = 0; // momentum-RHS evaluations
};

inline PetscErrorCode RHSPosition(TS, PetscReal, Vec v, Vec dx, void *) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(v, dx));
  PetscFunctionReturn(0);
}
inline PetscErrorCode RHSMomentum(TS, PetscReal, Vec x, Vec a, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, a));
  PetscCall(VecScale(a, -((Oscillator *)ctx)->omega2));
  ((Oscillator *)ctx)->nforce++;
  PetscFunctionReturn(0);
}

// The splits of the TS (again after a TSReset, which drops them).
inline PetscErrorCode SetSplits(Oscillator *o, TS ts) {
  PetscFunctionBeginUser;
  PetscCall(TSRHSSplitSetIS(ts, "position", o->isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", o->isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, o));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, o));
  PetscFunctionReturn(0);
}

inline PetscErrorCode SetUp(Oscillator *o, TS ts, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, U));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &o->isq));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 1, 1, &o->isp));
  PetscCall(TSRHSSplitSetIS(ts, "position", o->isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", o->isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, o));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, o));
  PetscFunctionReturn(0);
}

inline PetscErrorCode Destroy(Oscillator *o) {
  PetscFunctionBeginUser;
  PetscCall(ISDestroy(&o->isq));
  PetscCall(ISDestroy(&o->isp));
  PetscFunctionReturn(0);
}

// Runs `type` with step h from x=0, v=1 for nsteps (or to time T with
// matchstep when nsteps < 0) and records x after every step.
struct Record {
  std::vector<double> x;
};
inline PetscErrorCode RecordX(TS ts) {
  Vec                U;
  const PetscScalar *u;
  Record            *rec;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &rec));
  PetscCall(TSGetSolution(ts, &U));
  PetscCall(VecGetArrayRead(U, &u));
  rec->x.push_back(PetscRealPart(u[0]));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

inline PetscErrorCode Run(const char *type, PetscReal h, PetscInt nsteps, Record *rec, TSConvergedReason *reason) {
  Oscillator o;
  TS         ts;
  Vec        U;
  PetscFunctionBeginUser;
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(SetUp(&o, ts, &U));
  PetscCall(VecSetValue(U, 0, 0.0, INSERT_VALUES));
  PetscCall(VecSetValue(U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(U));
  PetscCall(VecAssemblyEnd(U));
  PetscCall(TSSetType(ts, type));
  PetscCall(TSSetTimeStep(ts, h));
  PetscCall(TSSetMaxSteps(ts, nsteps));
  PetscCall(TSSetMaxTime(ts, 1e300));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetErrorIfStepFails(ts, PETSC_FALSE));
  PetscCall(TSSetApplicationContext(ts, rec));
  PetscCall(TSSetPostStep(ts, RecordX));
  PetscCall(TSSetFromOptions(ts));
  rec->x.clear();
  PetscCall(TSSolve(ts, U));
  PetscCall(TSGetConvergedReason(ts, reason));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscCall(Destroy(&o));
  PetscFunctionReturn(0);
}

// The book's amplification factor (5.121): A_F, A_L = max x over the first and
// last `window` steps, i_F, i_L their step indices.
// `skip` steps are left out at the start (the book uses skip = 0).
inline double AmplificationFactor(const std::vector<double> &x, size_t window, size_t skip = 0) {
  if (x.size() < 2 * window + skip) return -1;
  size_t iF = skip, iL = x.size() - window;
  for (size_t i = skip; i < skip + window; ++i)
    if (x[i] > x[iF]) iF = i;
  for (size_t i = x.size() - window; i < x.size(); ++i)
    if (x[i] > x[iL]) iL = i;
  return std::pow(x[iL] / x[iF], 1.0 / (double)(iL - iF));
}

} // namespace osc
