// Option readers shared by the models' SetFromOptions, for options whose value PETSc takes
// without a range check.
#pragma once
#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace fdem {

// A 3-vector option inside PetscOptionsBegin/End (e.g. -fdem_rigid_gravity, whose three
// numbers `form` names as gx,gy,gz): exactly three finite numbers, else an error naming the
// option; v is changed only when the option is given. (PETSc reads as many numbers as there is
// room for and says nothing of the rest, so one more place tells that a fourth was given.)
inline PetscErrorCode OptionsVector3(PetscOptionItems *PetscOptionsObject, MPI_Comm comm, const char *opt, const char *form, const char *text, const char *man, PetscReal v[3]) {
  PetscReal g[4] = {v[0], v[1], v[2], 0};
  PetscInt  n    = 4;
  PetscBool flg;
  PetscFunctionBegin;
  PetscCall(PetscOptionsRealArray(opt, text, man, g, &n, &flg));
  PetscCheck(!flg || n == 3, comm, PETSC_ERR_ARG_SIZ, "%s takes three numbers %s; got %s", opt, form, n > 3 ? "more" : std::to_string(n).c_str());
  PetscCheck(!flg || (std::isfinite(g[0]) && std::isfinite(g[1]) && std::isfinite(g[2])), comm, PETSC_ERR_ARG_OUTOFRANGE, "%s %g,%g,%g: give finite numbers", opt, (double)g[0], (double)g[1], (double)g[2]);
  if (flg) std::copy(g, g + 3, v);
  PetscFunctionReturn(0);
}

} // namespace fdem
