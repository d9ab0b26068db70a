// Package registration: FDEMInitializePackage() for programs that link fdem,
// PetscDLLibraryRegister_fdem() for -dll_append libfdem.so.
#include <fdem.h>
#include "ts/fdemts.hpp"

static PetscBool FDEMPackageInitialized = PETSC_FALSE;

/*@C
  FDEMFinalizePackage - Forgets fdem's registrations; called by PetscFinalize().

  Level: developer
@*/
PetscErrorCode FDEMFinalizePackage(void) {
  PetscFunctionBegin;
  PetscCall(fdem::ts::ClearSplittingRegistry());
  PetscCall(fdem::ts::ClearSchemeInfo());
  FDEMPackageInitialized = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/*@C
  FDEMInitializePackage - Registers fdem's TS types (cd, pv, t112, t16, d112,
  pc3, pc4, pc5, chin, omf30, omf32, fr, pefrl) so -ts_type can select them.
  Idempotent; call after PetscInitialize().

  Level: beginner
@*/
PetscErrorCode FDEMInitializePackage(void) {
  PetscFunctionBegin;
  if (FDEMPackageInitialized) PetscFunctionReturn(0);
  FDEMPackageInitialized = PETSC_TRUE;
  PetscCall(TSInitializePackage());
  PetscCall(fdem::ts::RegisterSplittingTypes());
  PetscCall(fdem::ts::RegisterGearTypes());
  PetscCall(fdem::ts::RegisterTaylorTypes());
  PetscCall(PetscRegisterFinalize(FDEMFinalizePackage));
  PetscFunctionReturn(0);
}

/* Called by -dll_append /path/libfdem.so in any PETSc program. */
PETSC_EXTERN PetscErrorCode PetscDLLibraryRegister_fdem(void) {
  PetscFunctionBegin;
  PetscCall(FDEMInitializePackage());
  PetscFunctionReturn(0);
}
