// Rigid-body benchmarks (doc/rigid.md), one process:
//
//  -mode cost   cost per body-step of each drift variant (munjiza, nosquish,
//               exact) x scheme (-schemes, default cd,pefrl,omf32) on -n bodies
//               (default 1e4) with random principal moments, orientations and
//               spins under an orientation-dependent torque; wall time of
//               TSSolve (best of -repeat runs of -steps steps) per body and
//               step, force evaluations per step, ratio to cd + nosquish.
//               -> -csv (default doc/rigid/cost_per_body_step.csv)
//  -mode error  orientation error against cost: -n bodies (default 100) with
//               the torque, to T = 2, for every rotation variant x scheme (cd,
//               pv, omf30, fr, pefrl, chin, omf32) and h = T/10 .. T/320;
//               error = max over bodies of max_ij |R_ij - R_ref,ij| against a
//               reference run (omf32 + exact rotation, h = T/1280, whose own
//               error is ~1e-15: 4th order from 7e-9 at h = T/20); cost = force evaluations per body and wall
//               time per body. -> -csv (default doc/rigid/orientation_error_vs_cost.csv)
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/rotation.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {

// torque of a constant space force F0 applied at the body point c (body frame): M = (R c) x F0
PetscErrorCode Torque(PetscInt, PetscReal, const PetscReal *, const PetscReal R[9], const PetscReal *, const PetscReal *, PetscReal *, PetscReal M[3], void *) {
  const double c[3] = {0.3, -0.2, 0.5}, F0[3] = {0, 0, -4.0};
  double       rc[3];
  for (int r = 0; r < 3; ++r) rc[r] = R[3 * r] * c[0] + R[3 * r + 1] * c[1] + R[3 * r + 2] * c[2];
  M[0] += rc[1] * F0[2] - rc[2] * F0[1];
  M[1] += rc[2] * F0[0] - rc[0] * F0[2];
  M[2] += rc[0] * F0[1] - rc[1] * F0[0];
  return 0;
}

PetscErrorCode Build(PetscInt n, FDEMRotationType rot, unsigned long seed, FDEMRigid *out) {
  FDEMRigid rb;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
  PetscCall(FDEMRigidSetRotationType(rb, rot));
  PetscCall(FDEMRigidSetForceFunction(rb, Torque, nullptr));
  std::mt19937_64                        rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (PetscInt b = 0; b < n; ++b) {
    // asymmetric tops: I1 < I2 < I3 with the triangle inequality
    const PetscReal I[3] = {1.0 + 0.1 * U(rng), 2.0 + 0.1 * U(rng), 2.5 + 0.1 * U(rng)}; // I1 + I2 >= 2.8 > 2.6 >= I3
    const Mat3      Q    = fdem::kernels::RotationMatrix(Vec3(2 * U(rng), 2 * U(rng), 2 * U(rng)));
    PetscReal       R[9], x[3] = {0, 0, 0}, w[3] = {0.8 + 0.2 * U(rng), -0.4 + 0.2 * U(rng), 1.1 + 0.2 * U(rng)};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R[3 * r + c] = Q.m[r][c];
    PetscCall(FDEMRigidAddBody(rb, "top", 1.0, I, x, R, nullptr, w, nullptr));
  }
  *out = rb;
  PetscFunctionReturn(0);
}

struct RunResult {
  double   wall = 0;
  PetscInt steps = 0, nforce = 0;
};

// runs the bodies of rb with scheme and step h for `steps` steps (or to T if steps < 0); leaves the state in rb
PetscErrorCode Run(FDEMRigid rb, const char *scheme, PetscReal h, PetscReal T, PetscInt steps, RunResult *res) {
  TS             ts;
  Vec            U;
  PetscLogDouble t0, t1;
  PetscFunctionBeginUser;
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(TSSetType(ts, scheme));
  PetscCall(FDEMRigidSetUpTS(rb, ts, &U));
  PetscCall(TSSetTimeStep(ts, h));
  if (steps > 0) {
    PetscCall(TSSetMaxSteps(ts, steps));
    PetscCall(TSSetMaxTime(ts, 1e300));
  } else {
    PetscCall(TSSetMaxSteps(ts, 100000000));
    PetscCall(TSSetMaxTime(ts, T));
  }
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetUp(ts));
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, U));
  PetscCall(PetscTime(&t1));
  res->wall = t1 - t0;
  PetscCall(TSGetStepNumber(ts, &res->steps));
  PetscCall(FDEMTSGetForceEvaluations(ts, &res->nforce));
  PetscCall(FDEMRigidRestoreState(rb, U));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscFunctionReturn(0);
}

std::vector<std::string> Split(const char *s) {
  std::vector<std::string> out;
  std::stringstream        ss(s);
  std::string              item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

const FDEMRotationType kRots[3] = {FDEM_ROTATION_MUNJIZA, FDEM_ROTATION_NOSQUISH, FDEM_ROTATION_EXACT};

PetscErrorCode CostMode(PetscInt n, PetscInt steps, PetscInt repeat, const std::vector<std::string> &schemes, const char *csv) {
  struct Row {
    std::string scheme;
    int         rot;
    double      us;
    double      forces;
  };
  std::vector<Row> rows;
  double           base = 0;
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "cost per body-step, %" PetscInt_FMT " bodies, %" PetscInt_FMT " steps of h = 0.01, best of %" PetscInt_FMT "\n%-7s %-9s %12s %10s %14s\n", n, steps, repeat, "scheme", "rotation",
                        "us/body-step", "forces/step", "ratio to cd+nosquish"));
  for (const auto &s : schemes)
    for (int r = 0; r < 3; ++r) {
      double best = 1e300, forces = 0;
      for (PetscInt k = 0; k < repeat; ++k) {
        FDEMRigid rb;
        RunResult res;
        PetscCall(Build(n, kRots[r], 11, &rb));
        PetscCall(Run(rb, s.c_str(), 0.01, 0, steps, &res));
        PetscCall(FDEMRigidDestroy(&rb));
        best   = std::fmin(best, res.wall);
        forces = (double)res.nforce / (double)res.steps;
      }
      const double us = 1e6 * best / ((double)n * (double)steps);
      if (s == "cd" && kRots[r] == FDEM_ROTATION_NOSQUISH) base = us;
      rows.push_back({s, r, us, forces});
    }
  FILE *fp = csv[0] ? std::fopen(csv, "w") : nullptr;
  if (fp) std::fprintf(fp, "scheme,rotation,bodies,steps,us_per_body_step,forces_per_step,ratio_to_cd_nosquish\n");
  for (const auto &w : rows) {
    PetscCall(PetscPrintf(PETSC_COMM_SELF, "%-7s %-9s %12.3f %10.2f %14.2f\n", w.scheme.c_str(), FDEMRotationTypes[kRots[w.rot]], w.us, w.forces, base > 0 ? w.us / base : NAN));
    if (fp) std::fprintf(fp, "%s,%s,%d,%d,%.4f,%.3f,%.3f\n", w.scheme.c_str(), FDEMRotationTypes[kRots[w.rot]], (int)n, (int)steps, w.us, w.forces, base > 0 ? w.us / base : NAN);
  }
  if (fp) std::fclose(fp);
  PetscFunctionReturn(0);
}

PetscErrorCode States(FDEMRigid rb, PetscInt n, std::vector<double> &R) {
  PetscFunctionBeginUser;
  R.resize(9 * n);
  for (PetscInt id = 0; id < n; ++id) {
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(rb, id, &st));
    for (int k = 0; k < 9; ++k) R[9 * id + k] = st.R[k];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ErrorMode(PetscInt n, const std::vector<std::string> &schemes, PetscInt nh, const char *csv) {
  const PetscReal     T = 2.0;
  std::vector<double> Rref, R;
  FDEMRigid           rb;
  RunResult           res;
  PetscFunctionBeginUser;
  PetscCall(Build(n, FDEM_ROTATION_EXACT, 5, &rb));
  PetscCall(Run(rb, "omf32", T / 1280, T, -1, &res));
  PetscCall(States(rb, n, Rref));
  PetscCall(FDEMRigidDestroy(&rb));
  FILE *fp = csv[0] ? std::fopen(csv, "w") : nullptr;
  if (fp) std::fprintf(fp, "scheme,rotation,h,steps,force_evals,wall_per_body_s,orientation_error\n");
  PetscCall(PetscPrintf(PETSC_COMM_SELF, "orientation error at T = %g vs cost, %" PetscInt_FMT " bodies, reference omf32 + exact, h = T/1280\n%-7s %-9s %10s %8s %10s %12s %12s\n", (double)T, n, "scheme", "rotation", "h", "steps", "forces",
                        "s/body", "error"));
  for (const auto &s : schemes)
    for (int r = 0; r < 3; ++r)
      for (PetscInt k = 0; k < nh; ++k) {
        const PetscReal h = T / (10.0 * (1 << k));
        PetscCall(Build(n, kRots[r], 5, &rb));
        PetscCall(Run(rb, s.c_str(), h, T, -1, &res));
        PetscCall(States(rb, n, R));
        PetscCall(FDEMRigidDestroy(&rb));
        double err = 0;
        for (size_t i = 0; i < R.size(); ++i) err = std::fmax(err, std::fabs(R[i] - Rref[i]));
        PetscCall(PetscPrintf(PETSC_COMM_SELF, "%-7s %-9s %10.5f %8" PetscInt_FMT " %10" PetscInt_FMT " %12.3e %12.3e\n", s.c_str(), FDEMRotationTypes[kRots[r]], (double)h, res.steps, res.nforce, res.wall / n, err));
        if (fp) std::fprintf(fp, "%s,%s,%.10g,%d,%d,%.6e,%.6e\n", s.c_str(), FDEMRotationTypes[kRots[r]], (double)h, (int)res.steps, (int)res.nforce, res.wall / n, err);
      }
  if (fp) std::fclose(fp);
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  char      mode[32] = "cost", schemes[256] = "", csv[PETSC_MAX_PATH_LEN] = "";
  PetscInt  n = -1, steps = 10, repeat = 3, nh = 6;
  PetscBool flg;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Rigid-body scheme bench (doc/rigid.md)", "");
  PetscCall(PetscOptionsString("-mode", "cost (time per step) or error (error against step size)", "", mode, mode, sizeof(mode), nullptr));
  PetscCall(PetscOptionsString("-schemes", "comma-separated fdem TS types (default cost: cd,pefrl,omf32; error: cd,pv,omf30,fr,pefrl,chin,omf32)", "", schemes, schemes, sizeof(schemes), &flg));
  PetscCall(PetscOptionsString("-csv", "write the results to this CSV file", "", csv, csv, sizeof(csv), nullptr));
  PetscCall(PetscOptionsInt("-n", "number of bodies (default cost 10000, error 100)", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-steps", "steps per timed run (cost mode)", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsInt("-repeat", "timed runs per scheme; the minimum is reported (cost mode)", "", repeat, &repeat, nullptr));
  PetscCall(PetscOptionsInt("-nh", "step sizes h, h/2, ... (error mode)", "", nh, &nh, nullptr));
  PetscOptionsEnd();
  PetscCheck(steps > 0 && repeat > 0 && nh > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-steps, -repeat and -nh must be positive");
  const std::string m(mode);
  if (m == "cost") PetscCall(CostMode(n > 0 ? n : 10000, steps, repeat, Split(flg ? schemes : "cd,pefrl,omf32"), csv));
  else if (m == "error") PetscCall(ErrorMode(n > 0 ? n : 100, Split(flg ? schemes : "cd,pv,omf30,fr,pefrl,chin,omf32"), nh, csv));
  else SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "-mode cost|error, got %s", mode);
  PetscCall(PetscFinalize());
  return 0;
}
