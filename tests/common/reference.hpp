// The local reference positions of a deformable model, for tests that look inside it
// (src/model/deformable_object.hpp): 3 numbers per local node, owned and ghost, in the
// model's local numbering (the numbering of its elements' and joints' node indices).
#pragma once
#include "../../src/model/deformable_object.hpp"

#include <fdem/deformable.h>

#include <vector>

static PetscErrorCode LocalReference(FDEMDeformable d, std::vector<PetscScalar> &xl) {
  Vec                X, Xl;
  const PetscScalar *x;
  PetscInt           n;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetReferencePositions(d, &X));
  PetscCall(DMGetLocalVector(d->dm, &Xl));
  PetscCall(DMGlobalToLocal(d->dm, X, INSERT_VALUES, Xl));
  PetscCall(VecGetLocalSize(Xl, &n));
  PetscCall(VecGetArrayRead(Xl, &x));
  xl.assign(x, x + n);
  PetscCall(VecRestoreArrayRead(Xl, &x));
  PetscCall(DMRestoreLocalVector(d->dm, &Xl));
  PetscFunctionReturn(0);
}
