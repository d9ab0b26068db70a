// Observed order of convergence of every fdem scheme on a nonlinear problem
// with unequal masses (the FPU-beta chain), from four step sizes.
// The error of a run with step h is estimated by the difference to the run
// with h/2, so no reference solution is needed: order = log2(d(h)/d(h/2)).
// Usage: test_order [-schemes a,b,...] [-N 16] [-T 4] [-h0 0.2] (+ PETSc options)
// Fails (returns 1) if an observed order differs from the expected one.
#include <fdem.h>
#include "../../examples/common/fpu_chain.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

struct Case {
  const char *type;
  const char *gradient; // nullptr: default
  double      expected; // observed order expected on this nonlinear problem
  double      tol;
  bool        custom_drift;
  double      h0 = 0; // largest step (0: -h0); the Gear schemes need smaller steps to be asymptotic
};

static PetscErrorCode CustomDrift(TS ts, PetscReal t, PetscReal s, Vec U, void *ctx) {
  // the additive drift written by hand: exercises the engine's custom-drift path
  fpu::Chain *c = (fpu::Chain *)ctx;
  Vec         x, p, v;
  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(U, c->isq, &x));
  PetscCall(VecGetSubVector(U, c->isp, &p));
  PetscCall(VecDuplicate(x, &v));
  PetscCall(VecPointwiseMult(v, p, c->minv));
  PetscCall(VecAXPY(x, s, v));
  PetscCall(VecDestroy(&v));
  PetscCall(VecRestoreSubVector(U, c->isq, &x));
  PetscCall(VecRestoreSubVector(U, c->isp, &p));
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(fpu::Chain *c, const Case &cs, PetscReal h, PetscReal T, std::vector<double> &out, PetscInt *nforce) {
  TS  ts;
  Vec U;
  PetscFunctionBeginUser;
  PetscCall(fpu::CreateState(c, &U));
  PetscCall(fpu::Initial(c, 0.6, U));
  PetscCall(TSCreate(c->comm, &ts));
  PetscCall(fpu::SetUpTS(c, ts));
  PetscCall(FDEMTSSetForceJacobianProduct(ts, fpu::JacobianProduct, c));
  if (cs.custom_drift) PetscCall(FDEMTSSetDrift(ts, CustomDrift, c));
  PetscCall(TSSetType(ts, cs.type));
  PetscCall(TSSetFromOptions(ts));
  if (cs.gradient) {
    PetscInt g = !std::strcmp(cs.gradient, "jvp") ? FDEM_GRADIENT_JVP : (!std::strcmp(cs.gradient, "fd") ? FDEM_GRADIENT_FD : FDEM_GRADIENT_SHIFTED);
    PetscCall(FDEMTSSetGradientType(ts, (FDEMGradientType)g));
  }
  PetscCall(TSSetTimeStep(ts, h));
  PetscCall(TSSetMaxTime(ts, T));
  PetscCall(TSSetMaxSteps(ts, 100000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSolve(ts, U));
  PetscReal tf;
  PetscCall(TSGetTime(ts, &tf));
  PetscCheck(std::fabs(tf - T) < 1e-12 * T, c->comm, PETSC_ERR_PLIB, "%s ended at t = %.17g, not at the final time %g", cs.type, (double)tf, (double)T);
  PetscCall(FDEMTSGetForceEvaluations(ts, nforce));
  PetscCall(fpu::Gather(c, U, out));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscFunctionReturn(0);
}

static double MaxDiff(const std::vector<double> &a, const std::vector<double> &b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::fmax(d, std::fabs(a[i] - b[i]));
  return d;
}

int main(int argc, char **argv) {
  PetscInt  N = 16;
  PetscReal T = 4, h0 = 0.2;
  char      only[1024] = "";
  int       failures = 0;

  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-N", &N, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-T", &T, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-h0", &h0, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-schemes", only, sizeof(only), nullptr));

  // Expected observed orders on this nonlinear problem (see doc/schemes.md):
  // the Taylor-type schemes reach 4 only on linear problems and 3 here.
  const std::vector<Case> cases = {
    {"cd", nullptr, 2, 0.15, false},         {"pv", nullptr, 2, 0.15, false},         {"omf30", nullptr, 2, 0.15, false},
    {"fr", nullptr, 4, 0.25, false},         {"pefrl", nullptr, 4, 0.25, false},      {"chin", "shifted", 4, 0.25, false},
    {"chin", "fd", 4, 0.25, false},          {"chin", "jvp", 4, 0.25, false},         {"omf32", "shifted", 4, 0.3, false},
    {"omf32", "fd", 4, 0.3, false},          {"omf32", "jvp", 4, 0.3, false},         {"omf32", "shifted", 4, 0.3, true},
    {"omf32", "fd", 4, 0.3, true},           {"pefrl", nullptr, 4, 0.25, true},       {"cd", nullptr, 2, 0.15, true},
    {"t112", "fd", 3, 0.3, false},           {"t112", "jvp", 3, 0.3, false},          {"t16", "fd", 3, 0.3, false},
    {"t16", "jvp", 3, 0.3, false},           {"d112", "fd", 3, 0.3, false},           {"pc3", nullptr, 3, 0.3, false, 0.05},
    {"pc4", nullptr, 4, 0.3, false, 0.1},    {"pc5", nullptr, 5, 0.3, false, 0.05},
  };

  fpu::Chain chain;
  PetscCall(fpu::Create(PETSC_COMM_WORLD, N, 1.0, &chain));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FPU-beta chain, N = %d, unequal masses, T = %g; d(h) = max|U_h - U_{h/2}|\n", (int)N, (double)T));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-7s %-8s %-6s %6s %11s %11s %11s %7s %7s %7s %9s\n", "scheme", "gradient", "drift", "h0", "d(h0)", "d(h0/2)", "d(h0/4)", "p1", "p2", "expect", "F/step"));
  for (const Case &cs : cases) {
    if (only[0] && !std::strstr(only, cs.type)) continue;
    std::vector<std::vector<double>> sol(4);
    PetscInt                         nf[4];
    const PetscReal hc = cs.h0 > 0 ? cs.h0 : h0;
    for (int k = 0; k < 4; ++k) PetscCall(Run(&chain, cs, hc / (1 << k), T, sol[k], &nf[k]));
    double d[3], p[2];
    for (int k = 0; k < 3; ++k) d[k] = MaxDiff(sol[k], sol[k + 1]);
    for (int k = 0; k < 2; ++k) p[k] = std::log2(d[k] / d[k + 1]);
    const double steps = T / (hc / 8);
    const bool   ok = std::fabs(p[1] - cs.expected) <= cs.tol && std::fabs(p[0] - cs.expected) <= 2 * cs.tol;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-7s %-8s %-6s %6.3f %11.3e %11.3e %11.3e %7.3f %7.3f %7.1f %9.2f %s\n", cs.type, cs.gradient ? cs.gradient : "-", cs.custom_drift ? "custom" : "add", (double)hc, d[0], d[1], d[2], p[0], p[1],
                          cs.expected, nf[3] / steps, ok ? "ok" : "FAIL"));
    if (!ok) failures++;
  }
  PetscCall(fpu::Destroy(&chain));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
