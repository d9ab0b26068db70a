// The fdem TS types under bad step sizes, divergence, PETSc's re-set-up
// pattern and long runs: exact K_crit in messages and -ts_view, the last
// checked state returned after an Inf/NaN stop, clear errors for dt <= 0, NaN
// and -ts_exact_final_time interpolate, -help offering only working gradient
// forms, Gear/Taylor history kept across TSReset, and no PETSc object created
// per step. CTest also runs it with -malloc_dump: every error path here must
// release what it took.
#include <fdem.h>
#include <fdem/kernels/schemes.hpp>
#include "oscillator.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <unistd.h>

#include "../common/check.hpp"

namespace {

PetscErrorCode MakeTS(osc::Oscillator *o, const char *type, PetscReal h, TS *ts, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(TSCreate(PETSC_COMM_SELF, ts));
  PetscCall(osc::SetUp(o, *ts, U));
  PetscCall(VecSetValue(*U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(*U));
  PetscCall(VecAssemblyEnd(*U));
  PetscCall(TSSetType(*ts, type));
  PetscCall(TSSetTimeStep(*ts, h));
  PetscCall(TSSetMaxTime(*ts, 1e300));
  PetscCall(TSSetExactFinalTime(*ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscFunctionReturn(0);
}
PetscErrorCode Free(osc::Oscillator *o, TS *ts, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(TSDestroy(ts));
  PetscCall(VecDestroy(U));
  PetscCall(osc::Destroy(o));
  PetscFunctionReturn(0);
}

std::string captured;
PetscErrorCode Capture(MPI_Comm, const char *fmt, ...) {
  char    buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  captured += buf;
  return 0;
}
std::string ViewText(TS ts) {
  // a file of this process's own: ctest runs the test's variants side by side in one folder
  const std::string name = "test_robustness_view." + std::to_string((long long)getpid()) + ".txt";
  const char       *path = name.c_str();
  PetscViewer       v;
  if (PetscViewerASCIIOpen(PETSC_COMM_SELF, path, &v) || TSView(ts, v) || PetscViewerDestroy(&v)) return "";
  std::string text;
  char        line[512];
  FILE       *fp = std::fopen(path, "r");
  while (fp && std::fgets(line, sizeof line, fp)) text += line;
  if (fp) std::fclose(fp);
  std::remove(path);
  return text;
}

// Ids of PETSc objects count every object created: the id of a probe Vec
// made now, minus that of one made before, is the number created in between.
PetscErrorCode NextId(PetscObjectId *id) {
  Vec probe;
  PetscFunctionBeginUser;
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 1, &probe));
  PetscCall(PetscObjectGetId((PetscObject)probe, id));
  PetscCall(VecDestroy(&probe));
  PetscFunctionReturn(0);
}
PetscErrorCode ObjectsCreatedBySolve(const char *type, PetscInt nsteps, PetscBool keep_good, PetscObjectId *created) {
  osc::Oscillator o;
  TS              ts;
  Vec             U;
  PetscObjectId   a, b;
  PetscFunctionBeginUser;
  PetscCall(MakeTS(&o, type, 0.01, &ts, &U));
  PetscCall(TSSetMaxSteps(ts, nsteps));
  PetscCall(TSSetErrorIfStepFails(ts, keep_good ? PETSC_FALSE : PETSC_TRUE));
  PetscCall(TSSetSolution(ts, U));
  PetscCall(TSSetUp(ts));
  PetscCall(NextId(&a));
  PetscCall(TSSolve(ts, U));
  PetscCall(NextId(&b));
  *created = b - a - 1;
  PetscCall(Free(&o, &ts, &U));
  PetscFunctionReturn(0);
}

// x(T) with TSReset between segments of `seg` steps (PETSc's re-set-up pattern), the
// momentum-RHS evaluations, and the solution of the same run without resets.
struct SegmentRun {
  double   x = 0, x_plain = 0;
  PetscInt nforce = 0, nforce_plain = 0;
  bool     same = false;
};
PetscErrorCode RunSegments(const char *type, PetscReal h, PetscInt nsteps, PetscInt seg, SegmentRun *r) {
  osc::Oscillator o, o2;
  TS              ts, ts2;
  Vec             U, U2;
  PetscBool       eq;
  PetscFunctionBeginUser;
  PetscCall(MakeTS(&o, type, h, &ts, &U));
  for (PetscInt done = 0; done < nsteps; done += seg) {
    PetscCall(TSSetMaxSteps(ts, PetscMin(done + seg, nsteps)));
    PetscCall(TSSolve(ts, U));
    PetscCall(TSReset(ts));
    PetscCall(osc::SetSplits(&o, ts));
  }
  PetscCall(MakeTS(&o2, type, h, &ts2, &U2));
  PetscCall(TSSetMaxSteps(ts2, nsteps));
  PetscCall(TSSolve(ts2, U2));
  PetscCall(VecEqual(U, U2, &eq));
  const PetscScalar *u, *u2;
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(U2, &u2));
  r->x       = PetscRealPart(u[0]);
  r->x_plain = PetscRealPart(u2[0]);
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(U2, &u2));
  r->nforce       = o.nforce;
  r->nforce_plain = o2.nforce;
  r->same   = eq;
  PetscCall(Free(&o, &ts, &U));
  PetscCall(Free(&o2, &ts2, &U2));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());

  // 1. K_crit printed exactly: -ts_view and the Inf/NaN message carry the step-map limit to 6 decimals
  for (const char *type : {"pefrl", "omf32", "t16", "pc5"}) {
    char exact[32];
    PetscCall(PetscSNPrintf(exact, sizeof exact, "K_crit = (omega h)_crit = %.6f", fdem::kernels::SchemeCriticalK(type)));
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, type, 0.1, &ts, &U));
    PetscCall(TSSetMaxSteps(ts, 2));
    PetscCall(TSSolve(ts, U));
    const std::string text = ViewText(ts);
    CHECK(text.find(exact) != std::string::npos, "-ts_view of %s lacks \"%s\":\n%s", type, exact, text.c_str());
    PetscCall(Free(&o, &ts, &U));
  }
  {
    // PEFRL: exact 2.989450 (it blows up at 2.9897), not 2.9900
    char needle[64];
    PetscCall(PetscSNPrintf(needle, sizeof needle, "K_crit = %.6f", fdem::kernels::SchemeCriticalK("pefrl")));
    PetscCall(ExpectError("PEFRL past its limit", needle, [&]() -> PetscErrorCode {
      osc::Oscillator o;
      TS              ts;
      Vec             U;
      PetscCall(MakeTS(&o, "pefrl", 3.2, &ts, &U));
      PetscCall(TSSetMaxSteps(ts, 100000));
      PetscErrorCode ierr = TSSolve(ts, U);
      PetscCall(Free(&o, &ts, &U));
      return ierr;
    }));
  }

  // 2. with -ts_error_if_step_fails false an Inf/NaN stop returns the last checked state
  //    (bitwise the state of a run of that many steps) and counts one rejected step
  for (const char *type : {"cd", "omf32", "pc3", "t112"}) {
    FDEMSchemeInfo info;
    PetscBool      found;
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    PetscReal h = 1.05 * info.kcrit;
    while (fdem::kernels::SchemeSpectralRadius(type, h) < 1.1) h *= 1.05;
    osc::Oscillator o, o2;
    TS              ts, ts2;
    Vec             U, U2;
    PetscInt        steps, rejects;
    PetscReal       t;
    PetscCall(MakeTS(&o, type, h, &ts, &U));
    PetscCall(TSSetMaxSteps(ts, 100000));
    PetscCall(TSSetErrorIfStepFails(ts, PETSC_FALSE));
    PetscCall(TSSolve(ts, U));
    PetscCall(TSGetStepNumber(ts, &steps));
    PetscCall(TSGetTime(ts, &t));
    PetscCall(TSGetStepRejections(ts, &rejects));
    PetscReal nrm;
    PetscCall(VecNorm(U, NORM_INFINITY, &nrm));
    CHECK(!PetscIsInfOrNanReal(nrm) && rejects == 1 && steps % 10 == 0 && std::fabs(t - steps * h) <= 1e-9 * t,
          "%s at omega h = %.3f: returned |U| = %g after %d steps at t = %g, %d rejected steps (expected a finite state at a check, 1 rejection)", type, (double)h, (double)nrm, (int)steps, (double)t,
          (int)rejects);
    PetscCall(MakeTS(&o2, type, h, &ts2, &U2));
    PetscCall(TSSetMaxSteps(ts2, steps));
    PetscCall(TSSolve(ts2, U2));
    PetscBool eq;
    PetscCall(VecEqual(U, U2, &eq));
    CHECK(eq, "%s: the returned state is not that of a run of %d steps", type, (int)steps);
    const std::string text = ViewText(ts);
    CHECK(text.find("total number of rejected steps=1") != std::string::npos, "%s: -ts_view does not report the rejected step:\n%s", type, text.c_str());
    if (eq && rejects == 1) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: %s at omega h = %.3f returns the finite state of step %d and 1 rejected step\n", type, (double)h, (int)steps));
    PetscCall(Free(&o, &ts, &U));
    PetscCall(Free(&o2, &ts2, &U2));
  }

  // 3. time steps that are not positive finite numbers, for each family, at set-up and at a step
  for (const char *type : {"cd", "omf32", "pc3", "t16", "d112"})
    for (PetscReal h : {0.0, -0.1, (PetscReal)NAN, (PetscReal)INFINITY})
      for (bool after_setup : {false, true}) {
        if (after_setup && std::isinf(h)) continue; // TSSolve trims an infinite step to the final time
        char what[128];
        PetscCall(PetscSNPrintf(what, sizeof what, "%s with h = %g set %s", type, (double)h, after_setup ? "after TSSetUp" : "before the solve"));
        PetscCall(ExpectError(what, "the time step (-ts_dt, TSSetTimeStep) is", [&]() -> PetscErrorCode {
          osc::Oscillator o;
          TS              ts;
          Vec             U;
          PetscCall(MakeTS(&o, type, 0.1, &ts, &U));
          PetscCall(TSSetMaxSteps(ts, 10));
          if (after_setup) {
            PetscCall(TSSetSolution(ts, U));
            PetscCall(TSSetUp(ts));
          }
          PetscCall(TSSetTimeStep(ts, h));
          PetscErrorCode ierr = TSSolve(ts, U);
          PetscCall(Free(&o, &ts, &U));
          return ierr;
        }));
      }

  // 4. -ts_exact_final_time interpolate: the fdem types end with matchstep
  for (const char *type : {"cd", "pc5", "t16"})
    PetscCall(ExpectError("interpolate past the final time", "end exactly at the final time with -ts_exact_final_time matchstep", [&]() -> PetscErrorCode {
      osc::Oscillator o;
      TS              ts;
      Vec             U;
      PetscCall(MakeTS(&o, type, 0.03, &ts, &U));
      PetscCall(TSSetMaxTime(ts, 0.1));
      PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_INTERPOLATE));
      PetscErrorCode ierr = TSSolve(ts, U);
      PetscCall(Free(&o, &ts, &U));
      return ierr;
    }));

  // 5. a divergent tangent solve with errors on (the step fails while the state is taken)
  PetscCall(ExpectError("t112 tangent solve divergence", "the tangent solve", [&]() -> PetscErrorCode {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, "t112", 3.6, &ts, &U));
    PetscCall(TSSetMaxSteps(ts, 100));
    PetscErrorCode ierr = TSSolve(ts, U);
    PetscCall(Free(&o, &ts, &U));
    return ierr;
  }));

  // 6. -help lists only the gradient forms a type has
  for (const char *type : {"t16", "t112", "omf32"}) {
    osc::Oscillator o;
    TS              ts;
    Vec             U;
    PetscCall(MakeTS(&o, type, 0.1, &ts, &U));
    PetscCall(TSSetOptionsPrefix(ts, type)); // -help prints a block once per prefix
    PetscErrorCode (*saved)(MPI_Comm, const char[], ...) = PetscHelpPrintf;
    captured.clear();
    PetscHelpPrintf = Capture;
    PetscCall(PetscOptionsSetValue(nullptr, "-help", nullptr));
    PetscErrorCode ierr = TSSetFromOptions(ts);
    PetscCall(PetscOptionsClearValue(nullptr, "-help"));
    PetscHelpPrintf = saved;
    PetscCall(ierr);
    const std::string opt  = std::string("ts_") + type + "_gradient";
    const size_t      at   = captured.find(opt);
    const std::string line = at == std::string::npos ? "" : captured.substr(at, captured.find('\n', at) - at);
    const bool        want = std::string(type) == "omf32";
    CHECK(!line.empty() && (line.find("shifted") != std::string::npos) == want && line.find("fd") != std::string::npos, "-help for %s: \"%s\" should %s offer shifted", type, line.c_str(),
          want ? "" : "not");
    PetscCall(Free(&o, &ts, &U));
  }

  // 7. TSReset between segments (PETSc's DMSwarm pattern): Gear and Taylor keep their history
  //    when the splits and the state are unchanged: the same solution as an uninterrupted run
  //    (bitwise), one start-up in all, and the design order
  for (const char *type : {"pc3", "pc5", "t112", "t16", "d112"}) {
    const PetscInt n = 40;
    SegmentRun     r1, r2;
    PetscCall(RunSegments(type, 1.0 / n, n, 1, &r1));
    PetscCall(RunSegments(type, 0.5 / n, 2 * n, 1, &r2));
    const double e1 = std::fabs(r1.x - std::sin(1.0)), e2 = std::fabs(r2.x - std::sin(1.0)), order = std::log2(e1 / e2);
    FDEMSchemeInfo info;
    PetscBool      found;
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    CHECK(r2.same && r1.same, "%s: a TSReset every step changes the solution (x = %.17g vs %.17g without resets)", type, r2.x, r2.x_plain);
    CHECK(order > info.order - 0.3, "%s with TSReset every step: order %.2f, design %d", type, order, (int)info.order);
    // the start-up (PEFRL substeps) once, as without resets: the same force evaluations
    CHECK(r2.nforce == r2.nforce_plain, "%s with TSReset every step: %d force evaluations for %d steps, %d without resets (a restart every step)", type, (int)r2.nforce, (int)(2 * n),
          (int)r2.nforce_plain);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s with TSReset every step: order %.2f, %d RHS evaluations for %d steps (%d without resets), same solution: %s\n", type, order, (int)r2.nforce, (int)(2 * n),
                          (int)r2.nforce_plain, r2.same ? "yes" : "no"));
  }

  // 8. no PETSc object (Vec) created per step: 10 and 1000 steps create the same number
  for (const char *type : {"cd", "omf32", "pefrl", "pc5", "t16", "t112"})
    for (PetscBool keep : {PETSC_FALSE, PETSC_TRUE}) {
      PetscObjectId c10, c1000;
      PetscCall(ObjectsCreatedBySolve(type, 10, keep, &c10));
      PetscCall(ObjectsCreatedBySolve(type, 1000, keep, &c1000));
      CHECK(c10 == c1000, "%s%s: TSSolve creates %d objects in 10 steps, %d in 1000", type, keep ? " (error-if-step-fails false)" : "", (int)c10, (int)c1000);
    }

  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
