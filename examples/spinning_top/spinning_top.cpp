// The book's spinning axisymmetric element (Munjiza 2004, Fig 5.6-5.9;
// doc/book.md B): principal moments I = diag(1, 1, 2) -- the printed (5.94) has I and J
// swapped, see doc/book.md B -- and body-frame angular velocity
// omega0 = (0, 1, 100), no torque. Euler's equations give, in the body frame,
//   omega_x = -sin 100 t,  omega_y = cos 100 t,  omega_z = 100.
// Runs one rigid body with -ts_type (default cd) and -fdem_rigid_rotation
// (default munjiza, the book's update), step -ts_dt (default 0.0005) to
// -ts_max_time (default 0.25), writes t, omega_body and the exact solution to
// DIR/spinning_top_<rotation>_h<dt>.csv (-fdem_output DIR, default
// out/spinning_top; a row every -fdem_output_every steps), prints the max error
// max_t max(|omega_x + sin 100t|, |omega_y - cos 100t|) over all steps and
// checks it against -fdem_expect_max_error (when given). doc/examples.md lists the options.
// run.sh runs the book's three steps and plots them (plot.py).
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/rotation.hpp>

#include "../common/options.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {
struct Rec {
  PetscReal             I[3];
  std::vector<PetscInt> step;
  std::vector<double>   t, w[3];
};

PetscErrorCode Record(TS, PetscInt step, PetscReal t, Vec U, void *ctx) {
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
  const Vec3 wb = fdem::kernels::transpose(R) * fdem::kernels::SpaceOmega(R, Vec3(r->I[0], r->I[1], r->I[2]), H);
  r->step.push_back(step);
  r->t.push_back(t);
  for (int k = 0; k < 3; ++k) r->w[k].push_back(wb[k]);
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode RunExample(int *status) {
  PetscFunctionBeginUser;
  namespace ex = fdem::examples;
  PetscReal  dt, T, expect = -1;
  PetscBool  has_expect;
  ex::Output out{"out/spinning_top", 1};
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Spinning top (book Fig 5.6); time steps: -ts_dt (0.0005), -ts_max_time (0.25), -ts_type (cd)", "");
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (CSV rows)");
  PetscCall(PetscOptionsReal("-fdem_expect_max_error", "fail if the max error exceeds this", "", expect, &expect, &has_expect));
  PetscOptionsEnd();
  if (has_expect) PetscCall(ex::CheckPositive("-fdem_expect_max_error", expect));
  PetscCall(ex::SetUpOutput(out));

  FDEMRigid rb;
  TS        ts;
  Vec       U;
  Rec       rec;
  const PetscReal I[3] = {1, 1, 2}, w0[3] = {0, 1, 100}, x[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) rec.I[k] = I[k];
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetRotationType(rb, FDEM_ROTATION_MUNJIZA)); // the book's update by default
  PetscCall(FDEMRigidSetFromOptions(rb));
  FDEMRotationType rot;
  PetscCall(FDEMRigidGetRotationType(rb, &rot));
  // R = identity at t = 0, so the space-frame omega0 is the body-frame one
  PetscCall(FDEMRigidAddBody(rb, "top", 1.0, I, x, nullptr, nullptr, w0, nullptr));
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(ex::SetTimeDefaults(ts, TSFDEMCD, 0.0005, 0.25));
  PetscCall(FDEMRigidSetUpTS(rb, ts, &U));
  PetscCall(TSMonitorSet(ts, Record, &rec, nullptr));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(ex::GetTimeSettings(ts, &dt, &T, nullptr));
  PetscCall(TSSolve(ts, U));
  PetscCall(TSGetTime(ts, &T));
  PetscCall(FDEMRigidRestoreState(rb, U));
  PetscCall(VecDestroy(&U));

  // the error on the rank that holds the body, then everywhere
  double err = 0;
  FILE  *fp  = nullptr;
  char csv[PETSC_MAX_PATH_LEN];
  PetscCall(PetscSNPrintf(csv, sizeof(csv), "%s/spinning_top_%s_h%g.csv", out.dir, FDEMRotationTypes[rot], (double)dt));
  if (out.on() && !rec.t.empty()) {
    fp = std::fopen(csv, "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", csv);
    std::fprintf(fp, "t,omega_x,omega_y,omega_z,exact_x,exact_y,exact_z\n");
  }
  for (size_t i = 0; i < rec.t.size(); ++i) {
    const double t = rec.t[i], ex = -std::sin(100 * t), ey = std::cos(100 * t);
    err = std::fmax(err, std::fmax(std::fabs(rec.w[0][i] - ex), std::fabs(rec.w[1][i] - ey)));
    if (fp && rec.step[i] % out.every == 0) std::fprintf(fp, "%.10g,%.17g,%.17g,%.17g,%.17g,%.17g,100\n", t, rec.w[0][i], rec.w[1][i], rec.w[2][i], ex, ey);
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
  const Vec3 wz = fdem::kernels::transpose(Mat3{{{{st.R[0], st.R[1], st.R[2]}, {st.R[3], st.R[4], st.R[5]}, {st.R[6], st.R[7], st.R[8]}}}}) * Vec3(st.omega_space[0], st.omega_space[1], st.omega_space[2]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "spinning top: -ts_type %s, rotation %s, h = %g, %" PetscInt_FMT " steps to t = %g: max |omega_body - exact| = %.4e (omega_z(T) - 100 = %.2e)\n", type, FDEMRotationTypes[rot], (double)dt,
                        steps, (double)T, gerr, wz[2] - 100));
  if (out.on()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "wrote %s\n", csv));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMRigidDestroy(&rb));
  int fail = 0;
  if (has_expect) {
    fail = !(gerr <= expect);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s: max error %.4e %s %.4e\n", fail ? "FAIL" : "ok", gerr, fail ? ">" : "<=", (double)expect));
  }
  *status = fail;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
