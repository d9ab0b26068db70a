// FDEMContact: contact between rigid bodies, the contact engine (engine.hpp) with
// the rigid adapter, attached to the rigid model's force chain.
#include "engine.hpp"
#include "rigid_adapter.hpp"
#include <fdem/contact.h>

#include <algorithm>
#include <new>

struct _n_FDEMContact {
  FDEMRigid                     rb;
  fdem::contact::RigidAdapter   rigid;
  fdem::contact::Engine         engine;
  explicit _n_FDEMContact(FDEMRigid r) : rb(r), rigid(r), engine(r->comm, "Contact") {
    rigid.RecordWork(true);
    const int k = engine.AddAdapter(&rigid);
    engine.AllowPair(k, k);
  }
};

namespace {
// The model term of the force chain: q = local positions [x | R], FM += [F | M]; the
// velocities come from the TS state rb->U.
PetscErrorCode ContactForces(FDEMRigid rb, PetscReal t, const PetscScalar *q, PetscScalar *FM, void *ctx) {
  FDEMContact        c = (FDEMContact)ctx;
  const PetscScalar *u = nullptr;
  PetscFunctionBegin;
  c->engine.SetTime(t);
  if (rb->U) PetscCall(VecGetArrayRead(rb->U, &u));
  c->rigid.Bind(q, u, FM);
  PetscCall(c->engine.Evaluate());
  if (rb->U) PetscCall(VecRestoreArrayRead(rb->U, &u));
  PetscFunctionReturn(0);
}

// At FDEMRigidSetUpTS: the local bodies changed (migration): start over.
PetscErrorCode ContactSetUp(FDEMRigid rb, void *ctx) {
  PetscBool per[3];
  PetscReal lo[3], hi[3], period[3];
  PetscFunctionBegin;
  PetscCall(FDEMRigidGetPeriodic(rb, per, lo, hi));
  for (int k = 0; k < 3; ++k) period[k] = per[k] ? hi[k] - lo[k] : 0;
  ((FDEMContact)ctx)->engine.SetPeriodic(lo, period);
  PetscCall(fdem::contact::SetGranularTable(rb, ((FDEMContact)ctx)->engine, 0));
  ((FDEMContact)ctx)->engine.Reset();
  PetscFunctionReturn(0);
}

// The state goes back to the swarm (the end of a TS segment, before a migration or a checkpoint):
// the sphere-sphere springs the engine keeps with its pairs go to their slots.
PetscErrorCode ContactStore(FDEMRigid, void *ctx) { return ((FDEMContact)ctx)->engine.FlushSprings(); }
} // namespace

PetscErrorCode FDEMContactCreate(FDEMRigid rb, FDEMContact *out) {
  fdem::model::RigidForceTerm term;
  PetscFunctionBegin;
  PetscCall(fdem::contact::RegisterEvents());
  for (const auto &t : rb->forces) PetscCheck(t.model != ContactForces, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMContactCreate: these rigid bodies already have contact attached");
  FDEMContact c = new (std::nothrow) _n_FDEMContact(rb);
  PetscCheck(c, rb->comm, PETSC_ERR_MEM, "Out of memory");
  term.model = ContactForces;
  term.setup = ContactSetUp;
  term.store = ContactStore;
  term.ctx   = c;
  rb->forces.push_back(term);
  *out = c;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactDestroy(FDEMContact *c) {
  PetscFunctionBegin;
  if (!*c) PetscFunctionReturn(0);
  auto &f = (*c)->rb->forces;
  f.erase(std::remove_if(f.begin(), f.end(), [&](const fdem::model::RigidForceTerm &t) { return t.ctx == *c && t.model == ContactForces; }), f.end());
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactSetPenalty(FDEMContact c, PetscReal penalty) { return c->engine.SetPenalty(penalty); }

PetscErrorCode FDEMContactSetDissipation(FDEMContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity) { return c->engine.SetDissipation(damping, friction, tangential_viscosity); }

PetscErrorCode FDEMContactSetBuffer(FDEMContact c, PetscReal buffer) { return c->engine.SetBuffer(buffer); }

PetscErrorCode FDEMContactSetFromOptions(FDEMContact c) { return c->engine.SetFromOptions(); }

PetscErrorCode FDEMContactGetStats(FDEMContact c, FDEMContactStats *s) {
  PetscFunctionBegin;
  *s = c->engine.GetStats();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactComputeEnergy(FDEMContact c, PetscReal *energy) {
  FDEMRigid rb = c->rb;
  PetscInt  n;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCheck(n == rb->n, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "FDEMContactComputeEnergy: the rigid bodies have no TS set up for their %" PetscInt_FMT " local bodies (call it after FDEMRigidSetUpTS or FDEMSceneSetUpTS)", n);
  std::vector<PetscScalar> u(18 * (size_t)n), fm(6 * (size_t)n, 0.0); // the state [x | R | v | H] from the swarm; forces discarded
  PetscCall(fdem::model::RigidLoadState(rb, u.data()));
  c->rigid.Bind(u.data(), u.data(), fm.data());
  PetscCall(c->engine.EvaluateStill());
  c->rigid.Bind(nullptr, nullptr, nullptr);
  *energy = c->engine.GetStats().energy;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactCheckTimeStep(FDEMContact c, const char *scheme, PetscReal dt, PetscReal *ratio) { return c->engine.CheckTimeStep(scheme, dt, ratio); }
