// The TS interface of the fdem schemes: final time, monitors, pre/post step,
// -ts_view facts, type switching, and clear errors for bad input.
#include <fdem.h>
#include <fdem/kernels/schemes.hpp>
#include "oscillator.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include "../common/check.hpp"

struct Counts {
  int monitor = 0, pre = 0, post = 0;
};
static PetscErrorCode Monitor(TS ts, PetscInt, PetscReal, Vec, void *ctx) {
  PetscFunctionBeginUser;
  ((Counts *)ctx)->monitor++;
  PetscFunctionReturn(0);
}
static PetscErrorCode Pre(TS ts) {
  Counts *c;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &c));
  c->pre++;
  PetscFunctionReturn(0);
}
static PetscErrorCode Post(TS ts) {
  Counts *c;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &c));
  c->post++;
  PetscFunctionReturn(0);
}

static PetscErrorCode MakeTS(osc::Oscillator *o, const char *type, TS *ts, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(TSCreate(PETSC_COMM_SELF, ts));
  PetscCall(osc::SetUp(o, *ts, U));
  PetscCall(VecSetValue(*U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(*U));
  PetscCall(VecAssemblyEnd(*U));
  PetscCall(TSSetType(*ts, type));
  PetscFunctionReturn(0);
}


int main(int argc, char **argv) {
  const char *types[] = {"cd", "pv", "t112", "t16", "d112", "pc3", "pc4", "pc5", "chin", "omf30", "omf32", "fr", "pefrl"};
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(FDEMInitializePackage()); // idempotent

  // 1. final time, steps, monitor and pre/post step, -ts_view
  for (const char *type : types) {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    Counts          c;
    PetscReal       t;
    PetscInt        steps;
    PetscCall(MakeTS(&o, type, &ts, &U));
    PetscCall(TSSetTimeStep(ts, 0.03));
    PetscCall(TSSetMaxTime(ts, 0.1));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(TSMonitorSet(ts, Monitor, &c, nullptr));
    PetscCall(TSSetApplicationContext(ts, &c));
    PetscCall(TSSetPreStep(ts, Pre));
    PetscCall(TSSetPostStep(ts, Post));
    PetscCall(TSSolve(ts, U));
    PetscCall(TSGetSolveTime(ts, &t));
    PetscCall(TSGetStepNumber(ts, &steps));
    CHECK(std::fabs(t - 0.1) < 1e-14, "%s ends at t = %.17g, not 0.1", type, (double)t);
    CHECK(steps == 4, "%s took %d steps to reach 0.1 with h = 0.03 (expected 3 + a trimmed one)", type, (int)steps);
    CHECK(c.pre == 4 && c.post == 4 && c.monitor == 5, "%s: pre %d, post %d, monitor %d calls", type, c.pre, c.post, c.monitor);
    {
      const PetscScalar *u;
      PetscCall(VecGetArrayRead(U, &u));
      CHECK(std::fabs(PetscRealPart(u[0]) - std::sin(0.1)) < 5e-5, "%s: x(0.1) = %g, exact %g", type, (double)PetscRealPart(u[0]), std::sin(0.1));
      PetscCall(VecRestoreArrayRead(U, &u));
    }
    PetscViewer sv;
    char        buf[4096] = "";
    PetscCall(PetscViewerStringOpen(PETSC_COMM_SELF, buf, sizeof(buf), &sv));
    PetscCall(PetscViewerSetType(sv, PETSCVIEWERSTRING));
    PetscCall(TSView(ts, sv));
    PetscCall(PetscViewerDestroy(&sv));
    // the string viewer is not ASCII: check the facts through the API instead
    FDEMSchemeInfo info;
    PetscCall(FDEMTSGetSchemeInfo(ts, &info));
    CHECK(!std::strcmp(info.name, type) && info.order >= 2 && info.kcrit >= 0 && info.evals >= 1, "%s: scheme info wrong", type);
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: all 13 types end exactly at the final time with h = 0.03, T = 0.1, and call monitor/pre/post step\n"));

  // 2. -ts_view prints the scheme's facts
  {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "omf32", &ts, &U));
    PetscCall(TSSetTimeStep(ts, 0.1));
    PetscCall(TSSetMaxSteps(ts, 2));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(TSSolve(ts, U));
    char        path[] = "test_interface_view.txt";
    PetscViewer v;
    PetscCall(PetscViewerASCIIOpen(PETSC_COMM_SELF, path, &v));
    PetscCall(TSView(ts, v));
    PetscCall(PetscViewerDestroy(&v));
    FILE       *fp = fopen(path, "r");
    std::string text;
    char        line[512];
    while (fp && fgets(line, sizeof(line), fp)) text += line;
    if (fp) fclose(fp);
    for (const char *needle : {"omf32", "order 4", "5 force evaluations per step", "2 gradient terms", "shifted", "K_crit = (omega h)_crit = 3.122", "3.1110"})
      CHECK(text.find(needle) != std::string::npos, "-ts_view of omf32 lacks \"%s\":\n%s", needle, text.c_str());
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
  }

  // 3. switching types keeps the problem; a drift set before survives TSSetType
  {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "cd", &ts, &U));
    PetscCall(TSSetType(ts, "pc5"));
    PetscCall(TSSetType(ts, "pefrl"));
    PetscCall(TSSetTimeStep(ts, 0.05));
    PetscCall(TSSetMaxTime(ts, 1.0));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(TSSolve(ts, U));
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(U, &u));
    CHECK(std::fabs(PetscRealPart(u[0]) - std::sin(1.0)) < 1e-6, "pefrl after type switches: x(1) = %g", (double)PetscRealPart(u[0]));
    PetscCall(VecRestoreArrayRead(U, &u));
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
  }

  // 4. bad input: clear errors
  PetscCall(ExpectError("missing momentum split", "\"momentum\" split is missing", [&]() -> PetscErrorCode {
    TS  ts;
    Vec U;
    IS  is;
    PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, &U));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &is));
    PetscCall(TSRHSSplitSetIS(ts, "position", is));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, osc::RHSPosition, nullptr));
    PetscCall(TSSetType(ts, "omf32"));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(ISDestroy(&is));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    return ierr;
  }));
  PetscCall(ExpectError("missing position RHS", "\"position\" split has no RHS function", [&]() -> PetscErrorCode {
    TS              ts;
    Vec             U;
    osc::Oscillator o;
    PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, &U));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &o.isq));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 1, 1, &o.isp));
    PetscCall(TSRHSSplitSetIS(ts, "position", o.isq));
    PetscCall(TSRHSSplitSetIS(ts, "momentum", o.isp));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, osc::RHSMomentum, &o));
    PetscCall(TSSetType(ts, "cd"));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(osc::Destroy(&o));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    return ierr;
  }));
  PetscCall(ExpectError("overlapping splits", "overlap", [&]() -> PetscErrorCode {
    TS              ts;
    Vec             U;
    osc::Oscillator o;
    PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3, &U));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 2, 0, 1, &o.isq));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 2, 1, 1, &o.isp));
    PetscCall(TSRHSSplitSetIS(ts, "position", o.isq));
    PetscCall(TSRHSSplitSetIS(ts, "momentum", o.isp));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, osc::RHSPosition, &o));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, osc::RHSMomentum, &o));
    PetscCall(TSSetType(ts, "fr"));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(osc::Destroy(&o));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    return ierr;
  }));
  PetscCall(ExpectError("split sizes that do not match", "split sizes do not match", [&]() -> PetscErrorCode {
    TS              ts;
    Vec             U;
    osc::Oscillator o;
    PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, 3, &U));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 2, 0, 1, &o.isq));
    PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 2, 1, &o.isp));
    PetscCall(TSRHSSplitSetIS(ts, "position", o.isq));
    PetscCall(TSRHSSplitSetIS(ts, "momentum", o.isp));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, osc::RHSPosition, &o));
    PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, osc::RHSMomentum, &o));
    PetscCall(TSSetType(ts, "pv"));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(osc::Destroy(&o));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    return ierr;
  }));
  PetscCall(ExpectError("a gradient option value that does not exist", "bogus", [&]() -> PetscErrorCode {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "omf32", &ts, &U));
    PetscCall(PetscOptionsSetValue(nullptr, "-ts_omf32_gradient", "bogus"));
    PetscErrorCode ierr = TSSetFromOptions(ts);
    PetscCall(PetscOptionsClearValue(nullptr, "-ts_omf32_gradient"));
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
    return ierr;
  }));
  PetscCall(ExpectError("the shifted form on a Taylor scheme", "shifted-force form exists only", [&]() -> PetscErrorCode {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "t16", &ts, &U));
    PetscErrorCode ierr = FDEMTSSetGradientType(ts, FDEM_GRADIENT_SHIFTED);
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
    return ierr;
  }));
  PetscCall(ExpectError("jvp gradient without a Jacobian product", "FDEMTSSetForceJacobianProduct", [&]() -> PetscErrorCode {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "chin", &ts, &U));
    PetscCall(FDEMTSSetGradientType(ts, FDEM_GRADIENT_JVP));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
    return ierr;
  }));
  PetscCall(ExpectError("an adaptive controller", "fixed steps", [&]() -> PetscErrorCode {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    TSAdapt         adapt;
    PetscCall(MakeTS(&o, "pefrl", &ts, &U));
    PetscCall(TSGetAdapt(ts, &adapt));
    PetscCall(TSAdaptSetType(adapt, TSADAPTBASIC));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&U));
    PetscCall(osc::Destroy(&o));
    return ierr;
  }));
  // 5. a step beyond the stability limit: Inf/NaN stops the solve naming the scheme and K_crit
  for (const char *type : {"cd", "omf32", "pc3", "t112"}) {
    FDEMSchemeInfo info;
    PetscBool      found;
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    // a step well past the limit where the exact growth per step is large (OMF32 has stable islands above K_crit)
    PetscReal h = 1.05 * info.kcrit;
    while (fdem::kernels::SchemeSpectralRadius(type, h) < 1.1) h *= 1.05;
    osc::Record       rec;
    TSConvergedReason reason;
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
    PetscErrorCode ierr = osc::Run(type, h, 100000, &rec, &reason); // error-if-step-fails off: reason < 0
    PetscCall(PetscPopErrorHandler());
    CHECK(ierr == 0 && reason < 0, "%s at omega h = %.3f: reason %d (ierr %d), expected a negative reason", type, (double)h, (int)reason, (int)ierr);
    if (ierr == 0 && reason < 0) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: %s at omega h = %.3f stops after %d steps with reason %s\n", type, (double)h, (int)rec.x.size(), TSConvergedReasons[reason]));
    char needle[64];
    PetscCall(PetscSNPrintf(needle, sizeof(needle), "K_crit = %.6f", (double)info.kcrit)); // the exact limit, 6 decimals
    PetscCall(ExpectError("divergence with error-if-step-fails on", needle, [&]() -> PetscErrorCode {
      osc::Oscillator o;
      TS              ts;
      Vec             U;
      PetscCall(MakeTS(&o, type, &ts, &U));
      PetscCall(TSSetTimeStep(ts, h));
      PetscCall(TSSetMaxSteps(ts, 100000));
      PetscErrorCode ierr = TSSolve(ts, U);
      PetscCall(TSDestroy(&ts));
      PetscCall(VecDestroy(&U));
      PetscCall(osc::Destroy(&o));
      return ierr;
    }));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
