// Contact between rigid bodies and a deformable mesh (rigid_mesh.hpp).
#include "rigid_mesh.hpp"
#include "../model/deformable_object.hpp"

namespace fdem::contact {
PetscErrorCode RigidMeshContact::SetUp(FDEMRigid rb, FDEMDeformable d, TS ts) {
  MeshAdapter *m;
  PetscFunctionBegin;
  PetscCall(RegisterEvents());
  const bool first = !mesh_;
  // Again for the same mesh (a new TS after the rigid bodies migrated): its adapter is kept, as
  // the mesh's cells do not move between ranks; it lists what a new one would (its selection
  // follows the joints at every evaluation), and the engine lists and searches afresh below.
  // (The same answer on every rank.) The rigid adapter too: it lists the bodies of this rank
  // afresh at every listing and keeps its skins' surface faces.
  if (first || mesh_->Mesh() != d) {
    PetscCall(MeshAdapter::Create(d, MeshAdapter::Cells::BoundaryVertex, MeshAdapter::Pairs::OtherKindsOnly, rb->nspheres > 0 ? MeshAdapter::Spheres::Weighted : MeshAdapter::Spheres::None, &m));
    m->RequireVelocities(false); // diagnostics evaluate without velocities: taken as zero
    PetscInt nc = m->NumCells();
    PetscCallMPI(MPI_Allreduce(&nc, &cells_, 1, MPIU_INT, MPI_SUM, engine.Comm()));
    mesh_.reset(m);
  } else m = mesh_.get();
  if (first || rigid_->Model() != rb) { // (for the same model: it lists the local bodies afresh, as the rigid contact's does)
    rigid_ = std::make_unique<RigidAdapter>(rb);
    rigid_->RecordWork(true, true); // the partition counts the bodies' pairs with the mesh too
  }
  { // each mesh body's granular material: the rigid model's material of the same name (the driver adds every material)
    std::vector<std::int32_t> gm(d->body_names.size(), -1);
    for (size_t b = 0; b < gm.size() && b < d->material_of_body.size(); ++b) {
      const std::string &name = d->materials[d->material_of_body[b]].name;
      for (size_t k = 0; k < rb->gmat_names.size(); ++k)
        if (rb->gmat_names[k] == name) gm[b] = (std::int32_t)k;
    }
    m->SetGranularMaterials(gm);
  }
  PetscCall(SetGranularTable(rb, engine, 1));
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

PetscErrorCode RigidMeshContact::Evaluate(PetscReal t, const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl, const PetscScalar *rq, const PetscScalar *ru) {
  PetscFunctionBegin;
  fm_.assign(fdem::model::RigidLayout::force_size * (size_t)rigid_->NumBodies(), 0.0);
  engine.SetTime(t);
  mesh_->Bind(xl, vl, fl);
  rigid_->Bind(rq, ru, fm_.data());
  PetscCall(engine.Evaluate());
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
