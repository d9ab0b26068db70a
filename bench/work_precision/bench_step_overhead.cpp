// Per-step overhead of the fdem TS types on the smallest problem there is:
// one degree of freedom (x'' = -x, the scheme study's oscillator), where the
// force costs nothing and a step's time is all bookkeeping. In one process,
// interleaved rounds (the order rotates every round), it times TSSolve of
// -steps steps for
//   -ts_type cd                         (default Inf/NaN check every 10 steps)
//   -ts_type cd -ts_fdem_check_interval 1
//   -ts_type basicsymplectic -ts_basicsymplectic_type 2   (PETSc's velocity Verlet)
//   -ts_type pv, pefrl, pc3
// and prints microseconds per step (min and median over -rounds) and the
// ratio to basicsymplectic 2. Usage: bench_step_overhead [-steps 200000] [-rounds 7]
#include <fdem.h>
#include <petsctime.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {

PetscErrorCode RHSPosition(TS, PetscReal, Vec v, Vec dx, void *) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(v, dx));
  PetscFunctionReturn(0);
}
PetscErrorCode RHSMomentum(TS, PetscReal, Vec x, Vec a, void *) {
  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, a));
  PetscCall(VecScale(a, -1.0));
  PetscFunctionReturn(0);
}

struct Variant {
  const char         *label, *type, *prefix;
  std::vector<double> us; // microseconds per step, one per round
};

PetscErrorCode TimeOne(const Variant &v, PetscInt steps, double *us) {
  TS             ts;
  Vec            U;
  IS             isq, isp;
  PetscLogDouble t0, t1;
  PetscFunctionBeginUser;
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(TSSetOptionsPrefix(ts, v.prefix));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2, &U));
  PetscCall(VecSetValue(U, 1, 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(U));
  PetscCall(VecAssemblyEnd(U));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 0, 1, &isq));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, 1, 1, 1, &isp));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, nullptr));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, nullptr));
  PetscCall(TSSetType(ts, v.type));
  PetscCall(TSSetTimeStep(ts, 0.01));
  PetscCall(TSSetMaxSteps(ts, steps));
  PetscCall(TSSetMaxTime(ts, 1e300));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSetSolution(ts, U));
  PetscCall(TSSetUp(ts));
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, U));
  PetscCall(PetscTime(&t1));
  *us = 1e6 * (t1 - t0) / steps;
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscFunctionReturn(0);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

} // namespace

int main(int argc, char **argv) {
  PetscInt steps = 200000, rounds = 7;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Per-step overhead on one degree of freedom", "");
  PetscCall(PetscOptionsInt("-steps", "Steps per timed TSSolve", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsInt("-rounds", "Interleaved rounds (the order rotates every round)", "", rounds, &rounds, nullptr));
  PetscOptionsEnd();
  PetscCheck(steps >= 1 && rounds >= 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-steps and -rounds must be >= 1");
  std::vector<Variant> v = {{"basicsymplectic 2", "basicsymplectic", "bs_", {}},
                            {"cd (check every 10 steps, default)", "cd", "cd10_", {}},
                            {"cd -ts_fdem_check_interval 1", "cd", "cd1_", {}},
                            {"pv", "pv", "pv_", {}},
                            {"pefrl", "pefrl", "pefrl_", {}},
                            {"pc3", "pc3", "pc3_", {}}};
  PetscCall(PetscOptionsSetValue(nullptr, "-bs_ts_basicsymplectic_type", "2"));
  PetscCall(PetscOptionsSetValue(nullptr, "-cd1_ts_fdem_check_interval", "1"));
  for (PetscInt r = 0; r < rounds; ++r)
    for (size_t j = 0; j < v.size(); ++j) {
      Variant &x = v[(j + r) % v.size()];
      double   us;
      PetscCall(TimeOne(x, steps, &us));
      x.us.push_back(us);
    }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "1 degree of freedom, %d steps per TSSolve, %d interleaved rounds\n%-38s %10s %10s %12s %12s\n", (int)steps, (int)rounds, "variant", "min [us]",
                        "median [us]", "min / bs2", "median / bs2"));
  const double bmin = *std::min_element(v[0].us.begin(), v[0].us.end()), bmed = Median(v[0].us);
  for (auto &x : v) {
    const double mn = *std::min_element(x.us.begin(), x.us.end()), md = Median(x.us);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-38s %10.3f %10.3f %12.3f %12.3f\n", x.label, mn, md, mn / bmin, md / bmed));
  }
  PetscCall(PetscFinalize());
  return 0;
}
