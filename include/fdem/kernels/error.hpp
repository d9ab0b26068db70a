// Errors a user can cause (bad meshes, bad parameters) are thrown by kernels
// as InputError with a message that names the body/element/file and what is
// wrong. The PETSc layer catches them at its boundary and returns a PETSc
// error (no exception ever crosses a PETSc callback).
#pragma once
#include <stdexcept>
#include <string>

namespace fdem::kernels {
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
} // namespace fdem::kernels
