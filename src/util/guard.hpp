// The one error path from C++ to PETSc (doc/architecture.md, "Errors"): no C++
// exception crosses a PETSc frame, and an error found on one rank stops every
// rank instead of leaving the others waiting in the next collective call.
//
// Guard is collective on comm: every rank calls it and runs f (f may do no
// work on some ranks, e.g. input read on rank 0 only). A C++ exception thrown
// on any rank (a kernel's InputError naming the file, body or element, or any
// other std::exception) becomes, on every rank, the PETSc error `code` with
// the message prefix + what() of the lowest failing rank. A PETSc error
// returned by f is returned on its rank, and the other ranks fail with a
// message naming that rank. Cost when nothing fails: one MPI_Allreduce of an int.
#pragma once
#include <petscsys.h>

#include <exception>
#include <string>

namespace fdem {
template <class F>
PetscErrorCode Guard(MPI_Comm comm, F &&f, PetscErrorCode code = PETSC_ERR_USER_INPUT, const char *prefix = "") {
  std::string    msg;
  PetscErrorCode ierr = 0;
  PetscMPIInt    rank, bad, first;
  int            len;
  PetscFunctionBegin;
  try {
    ierr = f();
  } catch (const std::exception &e) {
    msg = e.what();
    if (msg.empty()) msg = "unknown C++ exception";
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (ierr) msg = "PETSc error " + std::to_string((int)ierr) + " on rank " + std::to_string(rank) + " (see its message)";
  bad = msg.empty() ? PETSC_MPI_INT_MAX : rank;
  PetscCallMPI(MPI_Allreduce(&bad, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == PETSC_MPI_INT_MAX) PetscFunctionReturn(0);
  len = rank == first ? (int)msg.size() : 0;
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, comm));
  msg.resize((size_t)len);
  PetscCallMPI(MPI_Bcast(&msg[0], len, MPI_CHAR, first, comm));
  PetscCall(ierr);
  SETERRQ(comm, code, "%s%s", prefix, msg.c_str());
}
} // namespace fdem
