// Internal: checks of the contact parameters shared by FDEMContact,
// FDEMDeformableContact and FDEMScene; `who` starts the error message.
#pragma once
#include <fdem/kernels/contact.hpp>
#include <petscsys.h>

#include <cmath>

namespace fdem::contact {
inline PetscErrorCode CheckPenalty(MPI_Comm comm, const char *who, PetscReal penalty) {
  PetscFunctionBegin;
  PetscCheck(std::isfinite(penalty) && penalty > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the penalty must be positive and finite, got %g", who, (double)penalty);
  PetscFunctionReturn(0);
}

inline PetscErrorCode CheckBuffer(MPI_Comm comm, const char *who, PetscReal buffer) {
  PetscFunctionBegin;
  PetscCheck(buffer >= 0 && std::isfinite(buffer), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the search buffer must be >= 0, got %g", who, (double)buffer);
  PetscFunctionReturn(0);
}

// Validates and stores normal damping, Coulomb friction and tangential viscosity.
inline PetscErrorCode SetDissipation(MPI_Comm comm, const char *who, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity, fdem::kernels::ContactDissipation &d) {
  PetscFunctionBegin;
  PetscCheck(damping >= 0 && std::isfinite(damping), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the damping must be >= 0, got %g", who, (double)damping);
  PetscCheck(friction >= 0 && std::isfinite(friction), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the friction coefficient must be >= 0, got %g", who, (double)friction);
  PetscCheck(tangential_viscosity >= 0 && std::isfinite(tangential_viscosity), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the tangential viscosity must be >= 0, got %g", who, (double)tangential_viscosity);
  d.normal_damping       = damping;
  d.friction             = friction;
  d.tangential_viscosity = tangential_viscosity;
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
