// FDEMDeformableContact: contact between deformable bodies, the contact engine
// (engine.hpp) with the mesh adapter over the surface tetrahedra, attached to the
// mesh's force chain. See include/fdem/deformable_contact.h and doc/contact_engine.md.
#include "engine.hpp"
#include "mesh_adapter.hpp"
#include "../model/deformable_impl.hpp"
#include <fdem/deformable_contact.h>

#include <memory>
#include <new>

struct _n_FDEMDeformableContact {
  FDEMDeformable                             d;
  std::unique_ptr<fdem::contact::MeshAdapter> mesh;
  fdem::contact::Engine                      engine;
  _n_FDEMDeformableContact(FDEMDeformable dfm, MPI_Comm comm) : d(dfm), engine(comm, "Deformable contact") {}
};

namespace {
// The mesh's force term: local positions, velocities (may be null) and forces.
PetscErrorCode ContactForce(FDEMDeformable, PetscReal, Vec xloc, Vec vloc, Vec floc, void *ctx) {
  FDEMDeformableContact c = (FDEMDeformableContact)ctx;
  const PetscScalar    *xl, *vl = nullptr;
  PetscScalar          *fl;
  TS                    ts;
  PetscFunctionBegin;
  PetscCall(fdem::model::DeformableGetTS(c->d, &ts));
  c->engine.SetTS(ts); // the time step is checked at the first evaluation of each TS
  PetscCall(VecGetArrayRead(xloc, &xl));
  if (vloc) PetscCall(VecGetArrayRead(vloc, &vl));
  PetscCall(VecGetArray(floc, &fl));
  c->mesh->Bind(xl, vl, fl);
  PetscCall(c->engine.Evaluate());
  PetscCall(VecRestoreArray(floc, &fl));
  if (vloc) PetscCall(VecRestoreArrayRead(vloc, &vl));
  PetscCall(VecRestoreArrayRead(xloc, &xl));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode FDEMDeformableContactCreate(FDEMDeformable dfm, FDEMDeformableContact *out) {
  DM                          dm;
  MPI_Comm                    comm;
  fdem::contact::MeshAdapter *m;
  PetscFunctionBegin;
  PetscCall(fdem::contact::RegisterEvents());
  PetscCall(fdem::contact::MeshAdapter::Create(dfm, fdem::contact::MeshAdapter::Cells::BoundaryFace, fdem::contact::MeshAdapter::Pairs::WithItself, fdem::contact::MeshAdapter::Spheres::None, &m)); // also checks set-up
  PetscCall(FDEMDeformableGetDM(dfm, &dm));
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  FDEMDeformableContact c = new (std::nothrow) _n_FDEMDeformableContact(dfm, comm);
  PetscCheck(c, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  c->mesh.reset(m);
  const int k = c->engine.AddAdapter(m);
  c->engine.AllowPair(k, k);
  PetscCall(FDEMDeformableAddForce(dfm, ContactForce, c));
  *out = c;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactDestroy(FDEMDeformableContact *c) {
  PetscFunctionBegin;
  if (!*c) PetscFunctionReturn(0);
  PetscCall(FDEMDeformableRemoveForce((*c)->d, ContactForce, *c));
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetPenalty(FDEMDeformableContact c, PetscReal penalty) { return c->engine.SetPenalty(penalty); }

PetscErrorCode FDEMDeformableContactSetDissipation(FDEMDeformableContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity) { return c->engine.SetDissipation(damping, friction, tangential_viscosity); }

PetscErrorCode FDEMDeformableContactSetBuffer(FDEMDeformableContact c, PetscReal buffer) { return c->engine.SetBuffer(buffer); }

PetscErrorCode FDEMDeformableContactSetSelfContact(FDEMDeformableContact c, PetscBool self) { return c->engine.SetSelfContact(self); }

PetscErrorCode FDEMDeformableContactSetFromOptions(FDEMDeformableContact c) { return c->engine.SetFromOptions(); }

PetscErrorCode FDEMDeformableContactGetStats(FDEMDeformableContact c, FDEMDeformableContactStats *s) {
  PetscFunctionBegin;
  *s = c->engine.GetStats();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactGetBodyForce(FDEMDeformableContact c, PetscInt body, PetscReal F[3]) {
  PetscFunctionBegin;
  PetscCheck(body >= 0 && body < c->mesh->NumBodies(), c->engine.Comm(), PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: no body %" PetscInt_FMT " (the mesh has %" PetscInt_FMT ")", body, c->mesh->NumBodies());
  PetscCallMPI(MPI_Allreduce(&c->mesh->BodyForce()[3 * body], F, 3, MPIU_REAL, MPI_SUM, c->engine.Comm()));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactCheckTimeStep(FDEMDeformableContact c, const char *scheme, PetscReal dt, PetscReal *ratio) { return c->engine.CheckTimeStep(scheme, dt, ratio); }

PetscErrorCode FDEMDeformableContactComputeEnergy(FDEMDeformableContact c, Vec U, PetscReal *energy) {
  PetscFunctionBegin;
  PetscCall(fdem::model::DeformableEvaluateHooks(c->d, 0, U)); // the contact alone: no internal or joint forces
  *energy = c->engine.GetStats().energy;
  PetscFunctionReturn(0);
}
