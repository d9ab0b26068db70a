// Internal: contact between rigid bodies and a deformable mesh (used by FDEMScene): the
// contact engine with the mesh adapter (cells with a vertex on the boundary) and the
// rigid adapter, pairs only across the two kinds.
#pragma once
#include "engine.hpp"
#include "mesh_adapter.hpp"
#include "rigid_adapter.hpp"

#include <memory>

namespace fdem::contact {
class RigidMeshContact {
public:
  explicit RigidMeshContact(MPI_Comm comm) : engine(comm, "Scene contact") {}
  Engine engine; // parameters, statistics, time-step check
  // Collective: the mesh cells taking part and the local rigid bodies (after migration);
  // the next evaluation lists, searches and checks the initial overlap again. ts: its first
  // evaluation checks the time step.
  PetscErrorCode SetUp(FDEMRigid rb, FDEMDeformable d, TS ts);
  // Collective: forces at mesh positions xl (local; velocities vl may be null) and rigid
  // positions rq = [x | R], state ru = [x | R | v | H]: nodal forces added to fl; the local
  // bodies' [F | M] in RigidForces().
  PetscErrorCode Evaluate(PetscReal t, const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl, const PetscScalar *rq, const PetscScalar *ru);
  const std::vector<PetscScalar> &RigidForces() const { return fm_; }
  PetscInt                        NumMeshCells() const { return cells_; }

private:
  std::unique_ptr<MeshAdapter>  mesh_;
  std::unique_ptr<RigidAdapter> rigid_;
  std::vector<PetscScalar>      fm_;
  PetscInt                      cells_ = 0;
};
} // namespace fdem::contact
