// Work-precision benchmark on a nonlinear many-DOF problem: the FPU-beta chain
// (examples/common/fpu_chain.hpp) with N particles and unequal masses, started
// from a rough state so that the quartic springs matter (problem.hpp).
//
// In one process and from one initial state it runs
//   - fdem schemes (-ts_type cd, pv, omf30, fr, pefrl, chin, omf32, t16, ...)
//   - PETSc's -ts_type basicsymplectic with -ts_basicsymplectic_type 1, 2, 3, 4
//   - PETSc's -ts_type rk -ts_rk_type 4 on one combined RHS
// over a ladder of step sizes to the final time T, and records for each run
//   wall time   PetscTime() around TSSolve, best (and median) of -repeats runs
//   RHS evals   momentum-RHS (force) calls counted inside the RHS functions,
//               plus force-Jacobian products (t16 -gradient jvp) counted apiece
//   error       max_i |x_i - x_ref,i| at T against a reference run of
//               -ref_scheme (pefrl) with -ref_steps steps, whose own error is
//               estimated (Richardson, order 4) from a run with half the steps
//               and cross-checked against omf32 with half the steps.
// Output: CSV (-csv doc/bench/work_precision.csv) and, at the end, the two
// headline figures:
//   (1) wall time per step of -ts_type cd against basicsymplectic type 2,
//       interleaved runs, with -ts_fdem_check_interval 1 and 10 (the default), plus a timing
//       of the pieces of one step (the per-step overhead budget);
//   (2) at equal wall time, the error of omf32 against basicsymplectic type 4.
//
// Options: -N 1000000 -T 4 -amp 0.25 -repeats 3 -schemes cd,pv,... -levels 5
//          -ref_steps 1024 -csv FILE -summary FILE -hl_steps 100 -hl_repeats 9
//          -skip_headline1 -skip_work_precision (+ PETSc options; every TS has the
//          options prefix wp_, e.g. -wp_ts_fdem_check_interval 10)
#include <fdem.h>
#include "problem.hpp"

#include <petscts.h>
#include <petsctime.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdarg>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Spec {
  std::string label;    // name in the CSV and the plots
  std::string type;     // TS type
  std::string subtype;  // basicsymplectic type or rk type
  std::string gradient; // fdem gradient type ("" = the scheme's default)
  int         order;
  int         n0;       // steps of the coarsest run
  int         levels;   // runs with n0, 2 n0, 4 n0, ...
  std::string family;   // "fdem" or "petsc"
};

struct Result {
  Spec     spec;
  PetscInt nsteps = 0;
  double   h = 0, wall_min = 0, wall_med = 0;
  int      repeats = 0;
  PetscInt nforce = 0, njvp = 0;
  double   err = 0, energy_err = 0;
  bool     ref_limited = false;
};

struct Problem {
  fpu::Chain chain;
  PetscReal  T = 4;
  Vec        U0 = nullptr, U = nullptr, Uref = nullptr, xwork = nullptr;
  PetscReal  E0 = 0;
};

// Creates a TS for spec with n steps of size T/n, set up on U (not timed).
PetscErrorCode MakeTS(Problem &P, const Spec &s, PetscInt n, const char *prefix, TS *out) {
  TS  ts;
  fpu::Chain *c = &P.chain;
  PetscFunctionBeginUser;
  PetscCall(TSCreate(c->comm, &ts));
  PetscCall(TSSetOptionsPrefix(ts, prefix));
  if (s.type == "rk") {
    TSAdapt adapt;
    PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
    PetscCall(TSSetRHSFunction(ts, nullptr, fpu::RHSCombined, c));
    PetscCall(TSSetType(ts, TSRK));
    PetscCall(TSRKSetType(ts, s.subtype.c_str()));
    PetscCall(TSGetAdapt(ts, &adapt));
    PetscCall(TSAdaptSetType(adapt, TSADAPTNONE));
  } else {
    PetscCall(fpu::SetUpTS(c, ts));
    if (s.type == "basicsymplectic") {
      PetscCall(TSSetType(ts, TSBASICSYMPLECTIC));
      PetscCall(TSBasicSymplecticSetType(ts, s.subtype.c_str()));
    } else {
      PetscCall(FDEMTSSetForceJacobianProduct(ts, fpu::JacobianProductCounted, c));
      PetscCall(TSSetType(ts, s.type.c_str()));
      if (!s.gradient.empty()) {
        const FDEMGradientType g = s.gradient == "jvp" ? FDEM_GRADIENT_JVP : (s.gradient == "fd" ? FDEM_GRADIENT_FD : FDEM_GRADIENT_SHIFTED);
        PetscCall(FDEMTSSetGradientType(ts, g));
      }
    }
  }
  PetscCall(TSSetTimeStep(ts, P.T / n));
  PetscCall(TSSetMaxSteps(ts, n));
  PetscCall(TSSetMaxTime(ts, 2 * P.T)); // the step count ends the run: no trimmed last step
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_STEPOVER));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSetSolution(ts, P.U));
  PetscCall(TSSetUp(ts));
  *out = ts;
  PetscFunctionReturn(0);
}

// One timed solve from U0 into U with a TS made by MakeTS (reusable: the fdem
// schemes restart their caches/histories because U changed from outside).
PetscErrorCode TimedSolve(Problem &P, TS ts, PetscInt n, double *wall, PetscInt *nforce, PetscInt *njvp) {
  PetscLogDouble t0, t1;
  PetscReal      tf;
  PetscInt       steps;
  TSConvergedReason reason;
  PetscFunctionBeginUser;
  PetscCall(VecCopy(P.U0, P.U));
  PetscCall(TSSetTime(ts, 0));
  PetscCall(TSSetStepNumber(ts, 0));
  PetscCall(TSSetTimeStep(ts, P.T / n));
  P.chain.nforce   = 0;
  fpu::Count().njvp = 0;
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, P.U));
  PetscCall(PetscTime(&t1));
  *wall   = t1 - t0;
  *nforce = P.chain.nforce;
  *njvp   = fpu::Count().njvp;
  PetscCall(TSGetConvergedReason(ts, &reason));
  PetscCall(TSGetStepNumber(ts, &steps));
  PetscCall(TSGetTime(ts, &tf));
  TSType type;
  PetscCall(TSGetType(ts, &type));
  PetscCheck(reason > 0 && steps == n && std::fabs(tf - P.T) < 1e-9 * P.T, P.chain.comm, PETSC_ERR_PLIB, "%s: reason %s, %d of %d steps, t = %.17g (T = %g)", type,
             TSConvergedReasons[reason], (int)steps, (int)n, (double)tf, (double)P.T);
  PetscFunctionReturn(0);
}

PetscErrorCode RunSpec(Problem &P, const Spec &s, PetscInt n, int repeats, Result *r) {
  TS                  ts;
  std::vector<double> walls;
  PetscFunctionBeginUser;
  PetscCall(MakeTS(P, s, n, "wp_", &ts));
  for (int k = 0; k < repeats; ++k) {
    double w;
    PetscCall(TimedSolve(P, ts, n, &w, &r->nforce, &r->njvp));
    walls.push_back(w);
  }
  PetscCall(TSDestroy(&ts));
  std::sort(walls.begin(), walls.end());
  r->spec     = s;
  r->nsteps   = n;
  r->h        = P.T / n;
  r->repeats  = repeats;
  r->wall_min = walls.front();
  r->wall_med = walls[walls.size() / 2];
  PetscFunctionReturn(0);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Piecewise-linear interpolation of log(err) against log(time); NaN outside the curve.
double ErrAtTime(const std::vector<const Result *> &curve, double t) {
  std::vector<std::pair<double, double>> pts;
  for (auto *r : curve)
    if (!r->ref_limited && r->err > 0) pts.push_back({r->wall_min, r->err});
  std::sort(pts.begin(), pts.end());
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double ta = pts[i].first, tb = pts[i + 1].first;
    if (t >= ta && t <= tb) {
      const double w = std::log(t / ta) / std::log(tb / ta);
      return std::exp((1 - w) * std::log(pts[i].second) + w * std::log(pts[i + 1].second));
    }
  }
  return NAN;
}

void TimeRange(const std::vector<const Result *> &curve, double *lo, double *hi) {
  *lo = INFINITY;
  *hi = 0;
  for (auto *r : curve)
    if (!r->ref_limited && r->err > 0) {
      *lo = std::min(*lo, r->wall_min);
      *hi = std::max(*hi, r->wall_min);
    }
}

std::vector<std::string> SplitList(const char *s) {
  std::vector<std::string> out;
  std::stringstream        ss(s);
  std::string              item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

struct Printer {
  FILE       *f = nullptr;
  std::string text;
  void        operator()(const char *fmt, ...) __attribute__((format(printf, 2, 3))) {
    char    buf[4096];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof(buf), fmt, ap);
    va_end(ap);
    text += buf;
    PetscCallVoid(PetscPrintf(PETSC_COMM_WORLD, "%s", buf));
  }
};

// ---------------------------------------------------------------------------
// Headline (1): cd against basicsymplectic 2, wall time per step, interleaved.
PetscErrorCode HeadlineCD(Problem &P, PetscInt nsteps, int R, Printer &out, double *ratio_med, double *ratio_min) {
  struct Variant {
    const char *label;
    Spec        spec;
    const char *prefix;
    TS          ts = nullptr;
    std::vector<double> per_step;
  };
  std::vector<Variant> v = {
    {"cd (check_interval 1)", {"cd", "cd", "", "", 2, 0, 0, "fdem"}, "hl1_"},
    {"cd (check_interval 10, default)", {"cd", "cd", "", "", 2, 0, 0, "fdem"}, "hl10_"},
    {"basicsymplectic 2", {"bs2", "basicsymplectic", "2", "", 2, 0, 0, "petsc"}, "hl10_"},
    {"pv (check_interval 10, default)", {"pv", "pv", "", "", 2, 0, 0, "fdem"}, "hl10_"},
  };
  PetscFunctionBeginUser;
  // the interval is set explicitly for both rows (a run's options may not change it)
  PetscCall(PetscOptionsSetValue(nullptr, "-hl1_ts_fdem_check_interval", "1"));
  PetscCall(PetscOptionsSetValue(nullptr, "-hl10_ts_fdem_check_interval", "10"));
  for (auto &x : v) PetscCall(MakeTS(P, x.spec, nsteps, x.prefix, &x.ts));
  for (int r = 0; r < R; ++r)
    for (size_t j = 0; j < v.size(); ++j) {
      Variant &x = v[(j + r) % v.size()]; // rotate the order every round
      double   w;
      PetscInt nf, nj;
      PetscCall(TimedSolve(P, x.ts, nsteps, &w, &nf, &nj));
      x.per_step.push_back(w / nsteps);
    }
  for (auto &x : v) PetscCall(TSDestroy(&x.ts));
  PetscCall(PetscOptionsClearValue(nullptr, "-hl1_ts_fdem_check_interval"));
  PetscCall(PetscOptionsClearValue(nullptr, "-hl10_ts_fdem_check_interval"));
  out("\n(1) wall time per step, N = %d particles (state: %d entries), %d steps of h = %g per run, %d interleaved rounds\n", (int)P.chain.N, (int)(2 * P.chain.N), (int)nsteps,
      (double)(P.T / nsteps), R);
  out("    %-32s %12s %12s %12s %10s %10s\n", "variant", "min [ms]", "median [ms]", "max [ms]", "min/bs2", "med/bs2");
  const double bmin = *std::min_element(v[2].per_step.begin(), v[2].per_step.end()), bmed = Median(v[2].per_step);
  for (auto &x : v) {
    const double mn = *std::min_element(x.per_step.begin(), x.per_step.end()), md = Median(x.per_step), mx = *std::max_element(x.per_step.begin(), x.per_step.end());
    out("    %-32s %12.4f %12.4f %12.4f %10.4f %10.4f\n", x.label, 1e3 * mn, 1e3 * md, 1e3 * mx, mn / bmin, md / bmed);
  }
  out("    cd per step, check_interval 1 minus check_interval 10: %.4f ms (median), i.e. 0.9 of an Inf/NaN check costs that much (folded into the last kick and drift)\n", 1e3 * (Median(v[0].per_step) - Median(v[1].per_step)));
  // the headline: cd as run by default (check every 10 steps)
  *ratio_min = *std::min_element(v[1].per_step.begin(), v[1].per_step.end()) / bmin;
  *ratio_med = Median(v[1].per_step) / bmed;
  PetscFunctionReturn(0);
}

// Marks a vector as changed (VecNorm caches its result until then).
PetscErrorCode BumpState(Vec v) {
  PetscScalar *a;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(v, &a));
  PetscCall(VecRestoreArray(v, &a));
  PetscFunctionReturn(0);
}

// The pieces of one step, timed alone (per call, best of 5 batches).
PetscErrorCode StepPieces(Problem &P, Printer &out) {
  fpu::Chain *c = &P.chain;
  Vec         x, p, q_work, p_work, a;
  const int   M = 20;
  std::map<std::string, double> best;
  PetscFunctionBeginUser;
  PetscCall(VecCopy(P.U0, P.U));
  PetscCall(VecGetSubVector(P.U, c->isq, &x));
  PetscCall(VecDuplicate(x, &q_work));
  PetscCall(VecDuplicate(x, &p_work));
  PetscCall(VecDuplicate(x, &a));
  PetscCall(VecRestoreSubVector(P.U, c->isq, &x));
  auto timeit = [&](const std::string &name, auto &&body) -> PetscErrorCode {
    PetscLogDouble t0, t1;
    PetscFunctionBeginUser;
    double b = INFINITY;
    for (int rep = 0; rep < 5; ++rep) {
      PetscCall(PetscTime(&t0));
      for (int k = 0; k < M; ++k) PetscCall(body());
      PetscCall(PetscTime(&t1));
      b = std::min(b, (t1 - t0) / M);
    }
    best[name] = b;
    PetscFunctionReturn(0);
  };
  PetscCall(timeit("force", [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(VecGetSubVector(P.U, c->isq, &x));
    PetscCall(fpu::RHSMomentum(nullptr, 0, x, a, c));
    PetscCall(VecRestoreSubVector(P.U, c->isq, &x));
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("velocity", [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(VecGetSubVector(P.U, c->isp, &p));
    PetscCall(fpu::RHSPosition(nullptr, 0, p, q_work, c));
    PetscCall(VecRestoreSubVector(P.U, c->isp, &p));
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("axpy", [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(VecAXPY(p_work, 1e-30, a));
    PetscFunctionReturn(0);
  }));
  // VecNorm caches its result until the vector changes: bump the state each call
  PetscCall(timeit("norm_inf_state", [&]() -> PetscErrorCode {
    PetscReal nrm;
    PetscFunctionBeginUser;
    PetscCall(BumpState(P.U));
    PetscCall(VecNorm(P.U, NORM_INFINITY, &nrm));
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("norm_1_state", [&]() -> PetscErrorCode {
    PetscReal nrm;
    PetscFunctionBeginUser;
    PetscCall(BumpState(P.U));
    PetscCall(VecNorm(P.U, NORM_1, &nrm));
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("norm_2_state", [&]() -> PetscErrorCode {
    PetscReal nrm;
    PetscFunctionBeginUser;
    PetscCall(BumpState(P.U));
    PetscCall(VecNorm(P.U, NORM_2, &nrm));
    PetscFunctionReturn(0);
  }));
  // what a check can cost at least: one vectorisable pass testing the exponent bits
  PetscCall(timeit("bits_check_state", [&]() -> PetscErrorCode {
    const PetscScalar *u;
    PetscInt           nloc;
    PetscFunctionBeginUser;
    PetscCall(VecGetLocalSize(P.U, &nloc));
    PetscCall(VecGetArrayRead(P.U, &u));
    std::uint64_t bad = 0;
    for (PetscInt i = 0; i < nloc; ++i) {
      std::uint64_t b;
      std::memcpy(&b, &u[i], sizeof b);
      bad |= (std::uint64_t)(((b >> 52) & 0x7ff) == 0x7ff);
    }
    PetscCall(VecRestoreArrayRead(P.U, &u));
    PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_FP, "Inf/NaN in the state");
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("state_increase", [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(BumpState(P.U));
    PetscFunctionReturn(0);
  }));
  PetscCall(timeit("getsub_pair", [&]() -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(VecGetSubVector(P.U, c->isq, &x));
    PetscCall(VecGetSubVector(P.U, c->isp, &p));
    PetscCall(VecRestoreSubVector(P.U, c->isq, &x));
    PetscCall(VecRestoreSubVector(P.U, c->isp, &p));
    PetscFunctionReturn(0);
  }));
  PetscCall(VecDestroy(&q_work));
  PetscCall(VecDestroy(&p_work));
  PetscCall(VecDestroy(&a));
  const double F = best["force"], V = best["velocity"], A = best["axpy"], Nm = best["norm_inf_state"] - best["state_increase"], G = best["getsub_pair"];
  out("    pieces, per call [ms]: force F = %.4f, velocity p/m V = %.4f, VecAXPY (N) A = %.4f, VecGetSubVector+Restore of both splits G = %.5f\n", 1e3 * F, 1e3 * V, 1e3 * A, 1e3 * G);
  out("    the Inf/NaN check on the state (2N entries): VecNorm NORM_INFINITY = %.4f ms (NORM_1 = %.4f ms, NORM_2 = %.4f ms, through this PETSc's BLAS);\n"
      "    one hand-written vectorisable pass over the state testing the exponent bits = %.4f ms\n", 1e3 * Nm, 1e3 * (best["norm_1_state"] - best["state_increase"]),
      1e3 * (best["norm_2_state"] - best["state_increase"]), 1e3 * best["bits_check_state"]);
  const double cd1 = F + V + 3 * A + G + Nm, cd10 = F + V + 3 * A + G + Nm / 10, bs2 = F + 2 * V + 3 * A + 2 * G;
  out("    model per step [ms]: cd = F + V + 3A + G + norm = %.4f (check_interval 10: %.4f); basicsymplectic 2 = F + 2V + 3A + 2G = %.4f; the norm is %.1f%% of cd's step\n", 1e3 * cd1, 1e3 * cd10,
      1e3 * bs2, 100 * Nm / cd1);
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  Problem   P;
  PetscInt  N = 1000000, levels = -1, ref_steps = 1024, hl_steps = 100, hl_repeats = 9, repeats = 3;
  PetscReal amp = 0.25;
  char      schemes_opt[1024] = "", csv[PETSC_MAX_PATH_LEN] = "doc/bench/work_precision.csv", summary[PETSC_MAX_PATH_LEN] = "doc/bench/work_precision_summary.txt";
  char      ref_scheme[64] = "pefrl";
  PetscBool skip_h1 = PETSC_FALSE, skip_wp = PETSC_FALSE;
  Printer   out;

  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Work-precision bench (bench/work_precision/README.md)", "");
  PetscCall(PetscOptionsInt("-N", "degrees of freedom of the headline problem", "", N, &N, nullptr));
  PetscCall(PetscOptionsReal("-T", "simulated time of every run", "", P.T, &P.T, nullptr));
  PetscCall(PetscOptionsReal("-amp", "amplitude of the initial displacement", "", amp, &amp, nullptr));
  PetscCall(PetscOptionsInt("-levels", "step-size levels per scheme (< 0: each scheme's default ladder)", "", levels, &levels, nullptr));
  PetscCall(PetscOptionsInt("-repeats", "timed repeats per work-precision point (the minimum is kept)", "", repeats, &repeats, nullptr));
  PetscCall(PetscOptionsInt("-ref_steps", "steps of the reference solution", "", ref_steps, &ref_steps, nullptr));
  PetscCall(PetscOptionsInt("-hl_steps", "steps of the headline cost runs", "", hl_steps, &hl_steps, nullptr));
  PetscCall(PetscOptionsInt("-hl_repeats", "repeats of the headline cost runs", "", hl_repeats, &hl_repeats, nullptr));
  PetscCall(PetscOptionsString("-schemes", "comma-separated schemes (default: all)", "", schemes_opt, schemes_opt, sizeof(schemes_opt), nullptr));
  PetscCall(PetscOptionsString("-ref_scheme", "scheme of the reference solution", "", ref_scheme, ref_scheme, sizeof(ref_scheme), nullptr));
  PetscCall(PetscOptionsString("-csv", "work-precision CSV output", "", csv, csv, sizeof(csv), nullptr));
  PetscCall(PetscOptionsString("-summary", "summary text output", "", summary, summary, sizeof(summary), nullptr));
  PetscCall(PetscOptionsBool("-skip_headline1", "skip the first headline table", "", skip_h1, &skip_h1, nullptr));
  PetscCall(PetscOptionsBool("-skip_work_precision", "skip the work-precision ladders", "", skip_wp, &skip_wp, nullptr));
  PetscOptionsEnd();
  PetscCheck(N > 0 && repeats > 0 && ref_steps > 0 && hl_steps > 0 && hl_repeats > 0 && P.T > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-N, -repeats, -ref_steps, -hl_steps, -hl_repeats and -T must be positive");

  // The ladders: n0 steps for the coarsest run (h = T/n0), then n0 2^j. The
  // coarsest steps stay inside every scheme's stability limit on this problem
  // (omega_max ~ 2 sqrt((1 + 3 r^2)/m_min) ~ 3-4 with the rough start).
  // clang-format off
  std::vector<Spec> all = {
    {"cd",    "cd",    "", "",    2, 16, 6, "fdem"},
    {"pv",    "pv",    "", "",    2, 16, 6, "fdem"},
    {"omf30", "omf30", "", "",    2, 16, 6, "fdem"},
    {"fr",    "fr",    "", "",    4, 16, 5, "fdem"},
    {"pefrl", "pefrl", "", "",    4,  8, 5, "fdem"},
    {"chin",  "chin",  "", "",    4,  8, 5, "fdem"},
    {"omf32", "omf32", "", "",    4,  8, 5, "fdem"},
    {"omf32-jvp", "omf32", "", "jvp", 4, 8, 5, "fdem"},
    {"t16",   "t16",   "", "jvp", 3, 16, 4, "fdem"},
    {"pc4",   "pc4",   "", "",    4, 32, 4, "fdem"},
    {"pc5",   "pc5",   "", "",    5, 32, 4, "fdem"},
    {"bs1",   "basicsymplectic", "1", "", 1, 16, 6, "petsc"},
    {"bs2",   "basicsymplectic", "2", "", 2, 16, 6, "petsc"},
    {"bs3",   "basicsymplectic", "3", "", 3, 16, 5, "petsc"},
    {"bs4",   "basicsymplectic", "4", "", 4, 16, 5, "petsc"},
    {"rk4",   "rk",    "4", "",   4, 16, 5, "petsc"},
  };
  // clang-format on
  std::vector<std::string> chosen = schemes_opt[0] ? SplitList(schemes_opt) : std::vector<std::string>{"cd", "pv", "omf30", "fr", "pefrl", "chin", "omf32", "t16", "bs1", "bs2", "bs3", "bs4", "rk4"};
  std::vector<Spec>        specs;
  for (auto &name : chosen) {
    bool found = false;
    for (auto &s : all)
      if (s.label == name) {
        specs.push_back(s);
        found = true;
      }
    PetscCheck(found, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "-schemes: unknown scheme %s", name.c_str());
  }
  if (levels > 0)
    for (auto &s : specs) s.levels = (int)levels;

  PetscCall(fpu::Create(PETSC_COMM_WORLD, N, 1.0, &P.chain));
  PetscCall(fpu::CreateState(&P.chain, &P.U0));
  PetscCall(VecDuplicate(P.U0, &P.U));
  PetscCall(VecDuplicate(P.U0, &P.Uref));
  {
    Vec x;
    PetscCall(VecGetSubVector(P.U0, P.chain.isq, &x));
    PetscCall(VecDuplicate(x, &P.xwork));
    PetscCall(VecRestoreSubVector(P.U0, P.chain.isq, &x));
  }
  PetscCall(fpu::InitialRough(&P.chain, amp, P.U0));
  PetscCall(fpu::Energy(&P.chain, P.U0, &P.E0));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  out("FPU-beta chain, N = %d particles (state %d entries), beta = 1, unequal masses m_i in [1, 1.75], rough start amp = %g, T = %g, E0 = %.10g, %d MPI rank(s)\n", (int)N, (int)(2 * N),
      (double)amp, (double)P.T, (double)P.E0, size);

  std::vector<Result> results;
  double              hl_ratio_med = NAN, hl_ratio_min = NAN;
  if (!skip_wp) {
    // --- reference -----------------------------------------------------------
    Spec ref{"ref", ref_scheme, "", "", 4, 0, 0, "fdem"};
    Result rr, rh, ro;
    Vec    Uhalf;
    PetscReal d_half, d_omf;
    PetscCall(VecDuplicate(P.U0, &Uhalf));
    PetscCall(RunSpec(P, ref, ref_steps, 1, &rr));
    PetscCall(VecCopy(P.U, P.Uref));
    PetscCall(RunSpec(P, ref, ref_steps / 2, 1, &rh));
    PetscCall(VecCopy(P.U, Uhalf));
    PetscCall(fpu::PositionMaxDiff(&P.chain, P.Uref, Uhalf, P.xwork, &d_half));
    Spec omf{"omf32", "omf32", "", "", 4, 0, 0, "fdem"};
    PetscCall(RunSpec(P, omf, ref_steps / 2, 1, &ro));
    PetscCall(fpu::PositionMaxDiff(&P.chain, P.Uref, P.U, P.xwork, &d_omf));
    PetscCall(VecDestroy(&Uhalf));
    const double ref_err = d_half / 15; // 4th order: e(n) ~ (e(n/2) - e(n)) / (2^4 - 1)
    PetscReal Eref;
    PetscCall(fpu::Energy(&P.chain, P.Uref, &Eref));
    out("reference: %s with %d steps (h = %.3g, %.1f s): |ref - %s(%d steps)| = %.3e -> estimated reference error %.2e; |ref - omf32(%d steps)| = %.3e; relative energy error %.2e\n", ref_scheme,
        (int)ref_steps, (double)(P.T / ref_steps), rr.wall_min, ref_scheme, (int)(ref_steps / 2), d_half, ref_err, (int)(ref_steps / 2), d_omf, std::fabs(Eref - P.E0) / P.E0);
    const double floor_err = 10 * std::max(ref_err, (double)d_omf / 15);

    // --- ladders ---------------------------------------------------------------
    out("%-10s %8s %10s %11s %11s %9s %10s %12s %12s\n", "scheme", "steps", "h", "wall [s]", "median [s]", "evals", "evals/step", "err(x)", "dE/E0");
    for (auto &s : specs) {
      for (int j = 0; j < s.levels; ++j) {
        const PetscInt n = (PetscInt)s.n0 << j;
        Result         r;
        PetscCall(RunSpec(P, s, n, (int)repeats, &r));
        PetscReal d, E;
        PetscCall(fpu::PositionMaxDiff(&P.chain, P.U, P.Uref, P.xwork, &d));
        PetscCall(fpu::Energy(&P.chain, P.U, &E));
        r.err         = d;
        r.energy_err  = std::fabs(E - P.E0) / P.E0;
        r.ref_limited = !(d > floor_err);
        out("%-10s %8d %10.5f %11.5f %11.5f %9d %10.2f %12.4e %12.4e%s\n", s.label.c_str(), (int)n, r.h, r.wall_min, r.wall_med, (int)(r.nforce + r.njvp), (double)(r.nforce + r.njvp) / n, r.err,
            r.energy_err, r.ref_limited ? "  (at the reference's accuracy: not used)" : "");
        results.push_back(r);
      }
    }
    FILE *f;
    PetscCall(PetscFOpen(PETSC_COMM_WORLD, csv, "w", &f));
    PetscCall(PetscFPrintf(PETSC_COMM_WORLD, f, "scheme,family,ts_type,subtype,gradient,order,N,T,nsteps,h,wall_s,wall_median_s,repeats,rhs_evals,force_evals,jvp_evals,err_max_x,energy_rel_err,ref_limited\n"));
    for (auto &r : results)
      PetscCall(PetscFPrintf(PETSC_COMM_WORLD, f, "%s,%s,%s,%s,%s,%d,%d,%g,%d,%.10g,%.6e,%.6e,%d,%d,%d,%d,%.6e,%.6e,%d\n", r.spec.label.c_str(), r.spec.family.c_str(), r.spec.type.c_str(),
                             r.spec.subtype.c_str(), r.spec.gradient.c_str(), r.spec.order, (int)N, (double)P.T, (int)r.nsteps, r.h, r.wall_min, r.wall_med, r.repeats, (int)(r.nforce + r.njvp),
                             (int)r.nforce, (int)r.njvp, r.err, r.energy_err, (int)r.ref_limited));
    PetscCall(PetscFClose(PETSC_COMM_WORLD, f));
    out("wrote %s\n", csv);
  }

  if (!skip_h1) {
    PetscCall(HeadlineCD(P, hl_steps, (int)hl_repeats, out, &hl_ratio_med, &hl_ratio_min));
    PetscCall(StepPieces(P, out));
  }

  // --- headline (2) and the equal-time table ------------------------------------
  double t_star = NAN, hl2 = NAN;
  if (!results.empty()) {
    std::map<std::string, std::vector<const Result *>> curves;
    std::vector<std::string>                           order;
    for (auto &r : results) {
      if (!curves.count(r.spec.label)) order.push_back(r.spec.label);
      curves[r.spec.label].push_back(&r);
    }
    if (curves.count("omf32") && curves.count("bs4")) {
      double la, ha, lb, hb;
      TimeRange(curves["omf32"], &la, &ha);
      TimeRange(curves["bs4"], &lb, &hb);
      const double lo = std::max(la, lb), hi = std::min(ha, hb);
      out("\n(2) error at equal wall time, omf32 against basicsymplectic 4 (log-log interpolation of error vs wall time)\n");
      if (lo < hi) {
        t_star = std::sqrt(lo * hi);
        out("    overlap of the two curves: %.4g .. %.4g s\n", lo, hi);
        out("    %10s %14s %14s %12s\n", "wall [s]", "err omf32", "err bs4", "bs4/omf32");
        double rmin = INFINITY, rmax = 0;
        for (int k = 0; k <= 8; ++k) {
          const double t = lo * std::pow(hi / lo, k / 8.0), eo = ErrAtTime(curves["omf32"], t), eb = ErrAtTime(curves["bs4"], t);
          out("    %10.4g %14.4e %14.4e %12.1f\n", t, eo, eb, eb / eo);
          rmin = std::min(rmin, eb / eo);
          rmax = std::max(rmax, eb / eo);
        }
        hl2 = ErrAtTime(curves["bs4"], t_star) / ErrAtTime(curves["omf32"], t_star);
        out("    at the geometric middle of the overlap, t = %.4g s: err(bs4)/err(omf32) = %.1f (range over the overlap %.1f .. %.1f)\n", t_star, hl2, rmin, rmax);
      } else out("    the curves do not overlap in wall time (omf32 %.3g..%.3g s, bs4 %.3g..%.3g s): widen the ladders (-levels)\n", la, ha, lb, hb);
    }
    if (std::isfinite(t_star)) {
      out("\nerror at equal wall time t = %.4g s (interpolated; '-' = t outside the scheme's measured range)\n", t_star);
      out("    %-10s %14s %14s\n", "scheme", "err(x)", "/ err(omf32)");
      const double eo = ErrAtTime(curves["omf32"], t_star);
      for (auto &name : order) {
        const double e = ErrAtTime(curves[name], t_star);
        if (std::isfinite(e)) out("    %-10s %14.4e %14.1f\n", name.c_str(), e, e / eo);
        else {
          double lo, hi;
          TimeRange(curves[name], &lo, &hi);
          out("    %-10s %14s %14s   (measured %.3g .. %.3g s)\n", name.c_str(), "-", "-", lo, hi);
        }
      }
    }
  }
  out("\nHEADLINE (1): wall time per step cd (default check interval) / basicsymplectic-2 = %.4f (median), %.4f (min); target <= 1.05\n", hl_ratio_med, hl_ratio_min);
  out("HEADLINE (2): at equal wall time %.4g s, err(basicsymplectic-4) / err(omf32) = %.1f; target >= 100\n", t_star, hl2);
  if (summary[0]) {
    FILE *f;
    PetscCall(PetscFOpen(PETSC_COMM_WORLD, summary, "w", &f));
    PetscCall(PetscFPrintf(PETSC_COMM_WORLD, f, "%s", out.text.c_str()));
    PetscCall(PetscFClose(PETSC_COMM_WORLD, f));
  }
  PetscCall(VecDestroy(&P.U0));
  PetscCall(VecDestroy(&P.U));
  PetscCall(VecDestroy(&P.Uref));
  PetscCall(VecDestroy(&P.xwork));
  PetscCall(fpu::Destroy(&P.chain));
  PetscCall(PetscFinalize());
  return 0;
}
