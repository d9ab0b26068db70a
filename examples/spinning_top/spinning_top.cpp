// The book's spinning axisymmetric element (Munjiza 2004, Fig 5.6-5.9; SPEC.md
// B.6): principal moments I = diag(1, 1, 2) -- the printed (5.94) has I and J
// swapped, see SPEC B.6 -- and body-frame angular velocity
// omega0 = (0, 1, 100), no torque. Euler's equations give, in the body frame,
//   omega_x = -sin 100 t,  omega_y = cos 100 t,  omega_z = 100.
// Runs one rigid body with -ts_type (default cd) and -fdem_rigid_rotation
// (default munjiza, the book's update), step -dt (default 0.0005) to -T
// (default 0.25), writes t, omega_body and the exact solution to -csv, prints
// the max error max_t max(|omega_x + sin 100t|, |omega_y - cos 100t|) and
// checks it against -expect_max_error (when given).
// run.sh runs the book's three steps and plots them (plot.py).
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/rotation.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {
struct Rec {
  PetscReal            I[3];
  std::vector<double> t, w[3];
};

PetscErrorCode Record(TS, PetscInt, PetscReal t, Vec U, void *ctx) {
  Rec               *r = (Rec *)ctx;
  const PetscScalar *u;
  PetscInt           n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(U, &n));
  if (n == 0) PetscFunctionReturn(0); // the body lives on another rank
  n /= 18;                           // state layout [x 3n | R 9n | v 3n | H 3n]
  PetscCall(VecGetArrayRead(U, &u));
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.m[i][j] = u[3 * n + 3 * i + j];
  const Vec3 H(u[15 * n], u[15 * n + 1], u[15 * n + 2]);
  const Vec3 wb = fdem::kernels::transpose(R) * fdem::kernels::BodyOmega(R, Vec3(r->I[0], r->I[1], r->I[2]), H);
  r->t.push_back(t);
  for (int k = 0; k < 3; ++k) r->w[k].push_back(wb[k]);
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscReal dt = 0.0005, T = 0.25, expect = -1;
  char      csv[PETSC_MAX_PATH_LEN] = "";
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Spinning top (book Fig 5.6)", "");
  PetscCall(PetscOptionsReal("-dt", "time step h", "", dt, &dt, nullptr));
  PetscCall(PetscOptionsReal("-T", "final time", "", T, &T, nullptr));
  PetscCall(PetscOptionsString("-csv", "write t, omega_body, exact to this file", "", csv, csv, sizeof(csv), nullptr));
  PetscCall(PetscOptionsReal("-expect_max_error", "fail if the max error exceeds this", "", expect, &expect, nullptr));
  PetscOptionsEnd();

  FDEMRigid rb;
  TS        ts;
  Vec       U;
  Rec       rec;
  const PetscReal I[3] = {1, 1, 2}, w0[3] = {0, 1, 100}, x[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) rec.I[k] = I[k];
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  FDEMRotationType rot = FDEM_ROTATION_MUNJIZA; // the book's update by default
  PetscCall(PetscOptionsGetEnum(nullptr, nullptr, "-fdem_rigid_rotation", FDEMRotationTypes, (PetscEnum *)&rot, nullptr));
  PetscCall(FDEMRigidSetRotationType(rb, rot));
  PetscCall(FDEMRigidSetFromOptions(rb));
  // R = identity at t = 0, so the space-frame omega0 is the body-frame one
  PetscCall(FDEMRigidAddBody(rb, "top", 1.0, I, x, nullptr, nullptr, w0, nullptr));
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMRigidSetUpTS(rb, ts, &U));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxTime(ts, T));
  PetscCall(TSSetMaxSteps(ts, 100000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSMonitorSet(ts, Record, &rec, nullptr));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMRigidRestoreState(rb, U));
  PetscCall(VecDestroy(&U));

  // the error on the rank that holds the body, then everywhere
  double err = 0;
  FILE  *fp  = nullptr;
  if (csv[0] && !rec.t.empty()) {
    fp = std::fopen(csv, "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", csv);
    std::fprintf(fp, "t,omega_x,omega_y,omega_z,exact_x,exact_y,exact_z\n");
  }
  for (size_t i = 0; i < rec.t.size(); ++i) {
    const double t = rec.t[i], ex = -std::sin(100 * t), ey = std::cos(100 * t);
    err = std::fmax(err, std::fmax(std::fabs(rec.w[0][i] - ex), std::fabs(rec.w[1][i] - ey)));
    if (fp) std::fprintf(fp, "%.10g,%.17g,%.17g,%.17g,%.17g,%.17g,100\n", t, rec.w[0][i], rec.w[1][i], rec.w[2][i], ex, ey);
  }
  if (fp) std::fclose(fp);
  double gerr;
  PetscCallMPI(MPI_Allreduce(&err, &gerr, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  TSType    type;
  PetscInt  steps;
  FDEMRigidBodyState st;
  PetscCall(TSGetType(ts, &type));
  PetscCall(TSGetStepNumber(ts, &steps));
  PetscCall(FDEMRigidGetBodyState(rb, 0, &st));
  const Vec3 wz = fdem::kernels::transpose(Mat3{{{{st.R[0], st.R[1], st.R[2]}, {st.R[3], st.R[4], st.R[5]}, {st.R[6], st.R[7], st.R[8]}}}}) * Vec3(st.omega[0], st.omega[1], st.omega[2]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "spinning top: -ts_type %s, rotation %s, h = %g, %" PetscInt_FMT " steps to t = %g: max |omega_body - exact| = %.4e (omega_z(T) - 100 = %.2e)\n", type, FDEMRotationTypes[rot], (double)dt,
                        steps, (double)T, gerr, wz[2] - 100));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMRigidDestroy(&rb));
  int fail = 0;
  if (expect > 0) {
    fail = !(gerr <= expect);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: max error %.4e %s %.4e\n", fail ? "FAIL" : "ok", gerr, fail ? ">" : "<=", (double)expect));
  }
  PetscCall(PetscFinalize());
  return fail;
}
