// What every example does with its options (doc/examples.md has the table of
// names): range checks that name the option and the allowed range, the
// output folder (-fdem_output DIR|none), and the time-stepping defaults that
// the command line (-ts_dt, -ts_max_time, -ts_max_steps, -ts_type) overrides.
// Options are the same on every rank, so each check fails on all ranks at once.
#pragma once
#include <petscts.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <filesystem>
#include <string>
#include <system_error>
#include <thread>

namespace fdem::examples {

// value must be finite and lie in the interval from lo to hi; lo_open / hi_open
// exclude the end (an infinite end is always open).
inline PetscErrorCode CheckReal(const char *opt, PetscReal value, PetscReal lo, bool lo_open, PetscReal hi, bool hi_open) {
  PetscFunctionBeginUser;
  const bool ok = std::isfinite(value) && (lo_open ? value > lo : value >= lo) && (hi_open ? value < hi : value <= hi);
  if (!ok) {
    char msg[256];
    std::snprintf(msg, sizeof(msg), "Option %s = %g is out of range: it must be a finite number in %s%g, %g%s", opt, (double)value, lo_open || std::isinf(lo) ? "(" : "[", (double)lo, (double)hi, hi_open || std::isinf(hi) ? ")" : "]");
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "%s", msg);
  }
  PetscFunctionReturn(0);
}
inline PetscErrorCode CheckPositive(const char *opt, PetscReal value) { return CheckReal(opt, value, 0, true, std::numeric_limits<PetscReal>::infinity(), true); }
inline PetscErrorCode CheckNonNegative(const char *opt, PetscReal value) { return CheckReal(opt, value, 0, false, std::numeric_limits<PetscReal>::infinity(), true); }

inline PetscErrorCode CheckInt(const char *opt, PetscInt value, PetscInt lo, PetscInt hi) {
  PetscFunctionBeginUser;
  PetscCheck(value >= lo && value <= hi, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "Option %s = %" PetscInt_FMT " is out of range: it must be an integer in [%" PetscInt_FMT ", %" PetscInt_FMT "]", opt, value, lo, hi);
  PetscFunctionReturn(0);
}

// -fdem_output DIR|none and -fdem_output_every K, registered inside the
// caller's PetscOptionsBegin/End block (PetscOptionsObject is the block's).
struct Output {
  char     dir[PETSC_MAX_PATH_LEN];
  PetscInt every;
  bool     on() const { return dir[0] != 0; }
  // DIR/name, or "" when output is off
  std::string path(const char *name) const { return on() ? std::string(dir) + "/" + name : std::string(); }
};
#define FDEM_EXAMPLE_OUTPUT_OPTIONS(out, what_every)                                                                                                                                            \
  do {                                                                                                                                                                                          \
    PetscCall(PetscOptionsString("-fdem_output", "folder for the results (none: write nothing)", "", (out).dir, (out).dir, sizeof((out).dir), nullptr));                                       \
    PetscCall(PetscOptionsInt("-fdem_output_every", "time steps between outputs" what_every, "", (out).every, &(out).every, nullptr));                                                           \
  } while (0)

// Checks -fdem_output_every and creates the folder (rank 0; collective error).
// "none" (or an empty name) switches output off.
inline PetscErrorCode SetUpOutput(Output &out) {
  PetscFunctionBeginUser;
  PetscCall(CheckInt("-fdem_output_every", out.every, 1, PETSC_MAX_INT));
  if (!std::strcmp(out.dir, "none")) out.dir[0] = 0;
  if (!out.on()) PetscFunctionReturn(0);
  PetscMPIInt rank;
  int         ok = 1;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (rank == 0) {
    std::error_code ec;
    std::filesystem::create_directories(out.dir, ec);
    ok = !ec && std::filesystem::is_directory(out.dir, ec);
  }
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, PETSC_COMM_WORLD));
  PetscCheck(ok, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN, "Option -fdem_output %s: cannot create this folder", out.dir);
  PetscFunctionReturn(0);
}

// The example's time-stepping defaults, set before TSSetFromOptions so that
// -ts_type, -ts_dt, -ts_max_time and -ts_max_steps on the command line win;
// then the values in force are read back and checked.
inline PetscErrorCode SetTimeDefaults(TS ts, TSType type, PetscReal dt, PetscReal tfinal) {
  PetscFunctionBeginUser;
  PetscCall(TSSetType(ts, type));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxTime(ts, tfinal));
  PetscCall(TSSetMaxSteps(ts, PETSC_MAX_INT));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscFunctionReturn(0);
}
inline PetscErrorCode GetTimeSettings(TS ts, PetscReal *dt, PetscReal *tfinal, PetscInt *max_steps) {
  PetscFunctionBeginUser;
  PetscCall(TSGetTimeStep(ts, dt));
  PetscCall(TSGetMaxTime(ts, tfinal));
  if (max_steps) PetscCall(TSGetMaxSteps(ts, max_steps));
  PetscCall(CheckPositive("-ts_dt", *dt));
  PetscCall(CheckPositive("-ts_max_time", *tfinal));
  if (max_steps) PetscCall(CheckInt("-ts_max_steps", *max_steps, 1, PETSC_MAX_INT));
  PetscFunctionReturn(0);
}

// For a program that hands the time stepping to a library call that builds
// its own TS (FDEMRigidSolve) but needs the values in force beforehand: the
// defaults, overridden by -ts_type, -ts_dt and -ts_max_time as that TS will be
// (PETSc lists these options under -help), checked.
inline PetscErrorCode PeekTimeOptions(char *type, size_t len, PetscReal *dt, PetscReal *tfinal) {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-ts_type", type, len, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-ts_dt", dt, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-ts_max_time", tfinal, nullptr));
  PetscCall(CheckPositive("-ts_dt", *dt));
  PetscCall(CheckPositive("-ts_max_time", *tfinal));
  PetscFunctionReturn(0);
}

// PETSc's default error handler lets rank 0 of the communicator print the
// error and makes every other rank sleep 10 s and exit without PetscFinalize.
// Here those ranks return the error quietly, so that all of them end through
// PetscFinalize; rank 0 of that communicator prints it as usual.
inline PetscErrorCode QuietOnOtherRanks(MPI_Comm comm, int line, const char *fun, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx) {
  static bool quiet = false; // this error is another rank's to print, up to the last traceback line
  if (p == PETSC_ERROR_INITIAL) {
    PetscMPIInt rank = 0;
    if (comm != MPI_COMM_NULL && MPI_Comm_rank(comm, &rank) != MPI_SUCCESS) rank = 0;
    quiet = rank != 0;
  }
  if (quiet) return n;
  return PetscTraceBackErrorHandler(PETSC_COMM_SELF, line, fun, file, n, p, mess, ctx);
}

// main() of an example: the work runs in run(&status) between PetscInitialize
// and PetscFinalize, so an error (collective: every rank returns it) ends every
// rank through PetscFinalize with exit status 1, instead of PETSc's MPI_Abort
// for an error that reaches main(). A rank that fails alone while the others
// go on cannot finalize with them: after 30 s of waiting it aborts the job
// (never a hang). status: the program's own result (0 = its checks passed).
inline int Main(int argc, char **argv, PetscErrorCode (*run)(int *status)) {
  int      status = 0, failed, any = 0, done = 0;
  MPI_Comm guard;
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  if (PetscPushErrorHandler(QuietOnOtherRanks, nullptr)) return 1;
  MPI_Comm_dup(PETSC_COMM_WORLD, &guard);
  failed = run(&status) != 0;
  MPI_Request req;
  MPI_Iallreduce(&failed, &any, 1, MPI_INT, MPI_MAX, guard, &req);
  for (int ms = 0; !done; ms += 10) {
    MPI_Test(&req, &done, MPI_STATUS_IGNORE);
    if (done) break;
    if (ms > 30000) MPI_Abort(MPI_COMM_WORLD, 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  MPI_Comm_free(&guard);
  if (PetscFinalize()) return 1;
  return any ? 1 : status;
}

} // namespace fdem::examples
