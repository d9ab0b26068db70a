// Shared by the fracture benches: a joint state loaded into a fracturable model the way a
// checkpoint's is (FDEMDeformableLoadJointState): every third joint broken, every joint, or
// none, as `every` says (a joint j is broken when every > 0 and j % every == 0; its three
// points get damage 1 and shear damage 1), the dissipated energies 0; written to `file` (a scratch file in the
// working directory), read back and removed.
#pragma once
#include <fdem/deformable.h>
#include <petscviewerhdf5.h>

#include <cstdio>

static inline PetscErrorCode LoadJointDamage(FDEMDeformable d, PetscInt joints, PetscInt every, const char *file) {
  Vec         D, W, E;
  PetscViewer v;
  PetscInt    lo, hi;
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, 3 * joints, &D));
  PetscCall(PetscObjectSetName((PetscObject)D, "joint_damage"));
  PetscCall(VecGetOwnershipRange(D, &lo, &hi));
  for (PetscInt i = lo; i < hi; ++i) PetscCall(VecSetValue(D, i, every > 0 && (i / 3) % every == 0 ? 1.0 : 0.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(D));
  PetscCall(VecAssemblyEnd(D));
  PetscCall(VecDuplicate(D, &W));
  PetscCall(VecCopy(D, W));
  PetscCall(PetscObjectSetName((PetscObject)W, "joint_shear_damage"));
  PetscCall(VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, joints, &E));
  PetscCall(PetscObjectSetName((PetscObject)E, "joint_dissipated"));
  PetscCall(VecSet(E, 0.0));
  PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, file, FILE_MODE_WRITE, &v));
  PetscCall(VecView(D, v));
  PetscCall(VecView(W, v));
  PetscCall(VecView(E, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, file, FILE_MODE_READ, &v));
  PetscCall(FDEMDeformableLoadJointState(d, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD)); // every rank has closed it
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (rank == 0) std::remove(file);
  PetscCall(VecDestroy(&D));
  PetscCall(VecDestroy(&W));
  PetscCall(VecDestroy(&E));
  PetscFunctionReturn(0);
}
