// Shared by the PETSc test programs: CHECK counts a failure and prints why;
// ExpectError runs f with errors returned (not aborted) and checks that it
// fails with a message containing `needle`.
#pragma once
#include <petscsys.h>
#include <cstring>

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
static PetscErrorCode ExpectError(const char *what, const char *needle, F &&f) {
  char *msg = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  PetscErrorCode ierr = f();
  PetscCall(PetscPopErrorHandler());
  if (ierr) PetscCall(PetscErrorMessage(ierr, nullptr, &msg));
  CHECK(ierr && msg && std::strstr(msg, needle), "%s: expected an error mentioning \"%s\", got %s", what, needle, ierr ? msg : "no error");
  if (ierr) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: %s -> %s\n", what, msg));
  PetscFunctionReturn(0);
}
