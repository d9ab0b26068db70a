/* fdem: the combined finite-discrete element method (Munjiza 2004) on PETSc.
   The public, C-callable API. */
#ifndef FDEM_H
#define FDEM_H

#include <petscts.h>
#include <fdem/ts.h>

#if defined(__cplusplus)
extern "C" {
#endif

PETSC_EXTERN PetscErrorCode FDEMInitializePackage(void);
PETSC_EXTERN PetscErrorCode FDEMFinalizePackage(void);

#if defined(__cplusplus)
}
#endif

#endif
