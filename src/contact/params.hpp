// Internal: checks of the contact parameters shared by FDEMContact,
// FDEMDeformableContact and FDEMScene; `who` starts the error message, and the option that
// gave a value, when one did (else nullptr), follows it: a scene's petsc: line is found by it.
#pragma once
#include <fdem/kernels/contact.hpp>
#include <petscsys.h>

#include <cmath>
#include <string>

namespace fdem::contact {
// "option: " or "".
inline std::string Given(const char *option) { return option ? std::string(option) + ": " : std::string(); }

inline PetscErrorCode CheckPenalty(MPI_Comm comm, const char *who, PetscReal penalty, const char *option = nullptr) {
  PetscFunctionBegin;
  PetscCheck(std::isfinite(penalty) && penalty > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %sthe penalty must be positive and finite, got %g", who, Given(option).c_str(), (double)penalty);
  PetscFunctionReturn(0);
}

inline PetscErrorCode CheckBuffer(MPI_Comm comm, const char *who, PetscReal buffer, const char *option = nullptr) {
  PetscFunctionBegin;
  PetscCheck(buffer >= 0 && std::isfinite(buffer), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %sthe search buffer must be >= 0 and finite, got %g", who, Given(option).c_str(), (double)buffer);
  PetscFunctionReturn(0);
}

// Validates and stores normal damping, Coulomb friction and tangential viscosity (options: the
// options that gave them, each nullptr where none did; or nullptr).
inline PetscErrorCode SetDissipation(MPI_Comm comm, const char *who, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity, fdem::kernels::ContactDissipation &d, const char *const *options = nullptr) {
  PetscFunctionBegin;
  PetscCheck(damping >= 0 && std::isfinite(damping), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %sthe damping must be >= 0 and finite, got %g", who, Given(options ? options[0] : nullptr).c_str(), (double)damping);
  PetscCheck(friction >= 0 && std::isfinite(friction), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %sthe friction coefficient must be >= 0 and finite, got %g", who, Given(options ? options[1] : nullptr).c_str(), (double)friction);
  PetscCheck(tangential_viscosity >= 0 && std::isfinite(tangential_viscosity), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %sthe tangential viscosity must be >= 0 and finite, got %g", who, Given(options ? options[2] : nullptr).c_str(), (double)tangential_viscosity);
  d.normal_damping       = damping;
  d.friction             = friction;
  d.tangential_viscosity = tangential_viscosity;
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
