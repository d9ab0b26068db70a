// The one CHECK and ExpectError of the PETSc test programs.
//  - CHECK(cond, fmt, ...) counts a failure and prints "FAIL: <message>"; the
//    test goes on, so one run reports every failing check. main ends with
//        PetscCall(ReportChecks()); PetscCall(PetscFinalize()); return failures ? 1 : 0;
//  - ExpectError(what, needles, f) runs f with PETSc errors returned (not
//    aborted) and checks that it fails with a message containing every
//    needle (one string or a list); prints "ok: what -> message" when it does.
#pragma once
#include <petscsys.h>

#include <cstring>
#include <initializer_list>

static int failures = 0;
#define CHECK(cond, ...) \
  do { \
    if (!(cond)) { \
      failures++; \
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: " __VA_ARGS__)); \
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\n")); \
    } \
  } while (0)

template <class F>
static PetscErrorCode ExpectError(const char *what, std::initializer_list<const char *> needles, F &&f) {
  char *msg = nullptr;
  bool  all = true;
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  PetscErrorCode ierr = f();
  PetscCall(PetscPopErrorHandler());
  if (ierr) PetscCall(PetscErrorMessage(ierr, nullptr, &msg));
  CHECK(ierr && msg, "%s: expected an error, got none", what);
  if (!ierr || !msg) PetscFunctionReturn(0);
  for (const char *n : needles) {
    const bool found = std::strstr(msg, n) != nullptr;
    CHECK(found, "%s: expected an error mentioning \"%s\", got: %s", what, n, msg);
    all = all && found;
  }
  if (all) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: %s -> %s\n", what, msg));
  PetscFunctionReturn(0);
}

template <class F>
static PetscErrorCode ExpectError(const char *what, const char *needle, F &&f) {
  return ExpectError(what, {needle}, f);
}

// Prints the number of failed checks, if any (call before PetscFinalize).
static inline PetscErrorCode ReportChecks() {
  PetscFunctionBeginUser;
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failure(s)\n", failures));
  PetscFunctionReturn(0);
}
