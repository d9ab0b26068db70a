// Contact between rigid bodies and a deformable mesh (rigid_mesh.hpp).
#include "rigid_mesh.hpp"

namespace fdem::contact {
PetscErrorCode RigidMeshContact::SetUp(FDEMRigid rb, FDEMDeformable d, TS ts) {
  MeshAdapter *m;
  PetscFunctionBegin;
  PetscCall(RegisterEvents());
  PetscCall(MeshAdapter::Create(d, MeshAdapter::Cells::BoundaryVertex, &m));
  m->RequireVelocities(false); // diagnostics evaluate without velocities: taken as zero
  PetscInt nc = m->NumCells();
  PetscCallMPI(MPI_Allreduce(&nc, &cells_, 1, MPIU_INT, MPI_SUM, engine.Comm()));
  const bool first = !mesh_;
  mesh_.reset(m);
  rigid_ = std::make_unique<RigidAdapter>(rb);
  if (first) {
    engine.AddAdapter(mesh_.get()); // kind 0: a pair is computed by the rank owning its mesh cell
    engine.AddAdapter(rigid_.get());
    engine.AllowPair(0, 1);
  } else {
    engine.ReplaceAdapter(0, mesh_.get());
    engine.ReplaceAdapter(1, rigid_.get());
  }
  engine.Reset();
  engine.RecheckInitialOverlap();
  engine.SetTS(ts);
  PetscFunctionReturn(0);
}

PetscErrorCode RigidMeshContact::Evaluate(const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl, const PetscScalar *rq, const PetscScalar *ru) {
  PetscFunctionBegin;
  fm_.assign(fdem::model::RigidLayout::force_size * (size_t)rigid_->NumBodies(), 0.0);
  mesh_->Bind(xl, vl, fl);
  rigid_->Bind(rq, ru, fm_.data());
  PetscCall(engine.Evaluate());
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
