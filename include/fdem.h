/* fdem: the combined finite-discrete element method (Munjiza 2004) on PETSc.
   The public, C-callable API. */
#ifndef FDEM_H
#define FDEM_H

#include <petscts.h>
#include <fdem/ts.h>
#include <fdem/rigid.h>
#include <fdem/contact.h>
#include <fdem/deformable.h>
#include <fdem/deformable_contact.h>
#include <fdem/scene.h>

#if defined(__cplusplus)
extern "C" {
#endif

PETSC_EXTERN PetscErrorCode FDEMInitializePackage(void);
PETSC_EXTERN PetscErrorCode FDEMFinalizePackage(void);

#if defined(__cplusplus)
}
#endif

#endif
