// Internal: no C++ exception crosses a PETSc frame. Guard runs f and turns an
// exception (a kernel's InputError naming the body/element, or any other)
// into a PETSc error on comm.
#pragma once
#include <petscsys.h>
#include <exception>

namespace fdem {
template <class F>
PetscErrorCode Guard(MPI_Comm comm, F &&f) {
  try {
    return f();
  } catch (const std::exception &e) {
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s", e.what());
  }
}
} // namespace fdem
