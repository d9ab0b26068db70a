// A combined scene (rigid bodies + deformable mesh) in one TS: the state's layout,
// the split RHS, the drift and the wiring of rigid-deformable contact (the contact
// engine, src/contact/rigid_mesh.hpp); see include/fdem/scene.h and doc/scene.md.
#include "../model/deformable_impl.hpp"
#include "../model/rigid_impl.hpp"
#include "../contact/rigid_mesh.hpp"
#include <fdem/scene.h>
#include <fdem/ts.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace {
PetscClassId  FDEM_SCENE_CLASSID = 0;
PetscLogEvent EV_RHS = 0;
} // namespace

struct _n_FDEMScene {
  MPI_Comm       comm;
  PetscMPIInt    rank = 0, size = 1;
  FDEMRigid      rb  = nullptr;
  FDEMDeformable dfm = nullptr;
  PetscInt       nr = 0, nd = 0, nr_global = 0;
  Vec            vr_state = nullptr, vr_q = nullptr, vr_a = nullptr; // sequential views of the rigid pieces
  TS             ts = nullptr; // the TS of FDEMSceneSetUpTS (not referenced; split RHS get sub-TS without a solution)
  // rigid-deformable contact: on with a positive penalty, rigid bodies and a mesh
  PetscReal                                        penalty = -1;
  bool                                             contact = false, hooked = false;
  std::unique_ptr<fdem::contact::RigidMeshContact> c;
  // during a force evaluation: rigid positions [x | R] and rigid state [x | R | v | H] (velocities)
  const PetscScalar *cur_rq = nullptr, *cur_ru = nullptr;
  bool               evaluating = false;
};

namespace {

// Offsets in the combined state.
inline PetscInt OffRigid(FDEMScene s) { return 3 * s->nd; }
inline PetscInt OffDefV(FDEMScene s) { return 3 * s->nd + 18 * s->nr; }

// The scene's term in the mesh's force chain: rigid-deformable contact while the scene evaluates.
PetscErrorCode SceneContactForce(FDEMDeformable, PetscReal t, Vec xloc, Vec vloc, Vec floc, void *ctx) {
  FDEMScene          s = (FDEMScene)ctx;
  const PetscScalar *xl, *vl = nullptr;
  PetscScalar       *fl;
  PetscFunctionBegin;
  if (!s->evaluating || !s->contact) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(xloc, &xl));
  if (vloc) PetscCall(VecGetArrayRead(vloc, &vl));
  PetscCall(VecGetArray(floc, &fl));
  PetscCall(s->c->Evaluate(t, xl, vl, fl, s->cur_rq, s->cur_ru));
  PetscCall(VecRestoreArray(floc, &fl));
  if (vloc) PetscCall(VecRestoreArrayRead(vloc, &vl));
  PetscCall(VecRestoreArrayRead(xloc, &xl));
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- the split RHS and the drift
// Rigid pieces on views: positions q (= [x | R]), rigid state u (= [x | R | v | H]), accelerations a (= [F/m | M]).
PetscErrorCode RigidMomentum(FDEMScene s, TS ts, PetscReal t, const PetscScalar *q, const PetscScalar *u, PetscScalar *a) {
  FDEMRigid rb = s->rb;
  PetscFunctionBegin;
  PetscCall(VecPlaceArray(s->vr_q, q));
  PetscCall(VecPlaceArray(s->vr_a, a));
  PetscCall(VecPlaceArray(s->vr_state, u));
  rb->U = s->vr_state; // rigid-rigid contact reads the velocities there
  PetscCall(fdem::model::RigidRHSMomentum(ts, t, s->vr_q, s->vr_a, rb));
  PetscCall(VecResetArray(s->vr_state));
  PetscCall(VecResetArray(s->vr_a));
  PetscCall(VecResetArray(s->vr_q));
  PetscReal extra = 0; // power of the reaction to contact on moved bodies
  if (s->contact) { // rigid-deformable contact, computed with the mesh's forces
    const fdem::model::RigidLayout L(s->nr);
    const PetscScalar             *FM = s->c->RigidForces().data();
    for (PetscInt b = 0; b < s->nr; ++b) {
      if ((PetscInt)rb->load.size() == 3 * s->nr)
        for (int k = 0; k < 3; ++k) rb->load[3 * b + k] += PetscRealPart(L.F(FM, b)[k]);
      if (rb->fixed[b]) {
        for (int k = 0; k < 3; ++k) extra -= PetscRealPart(L.F(FM, b)[k] * L.v(u, b)[k]);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        L.F(a, b)[k] += L.F(FM, b)[k] / rb->mass[b];
        L.M(a, b)[k] += L.M(FM, b)[k];
      }
    }
  }
  fdem::model::RigidSampleWork(rb, t, extra);
  PetscFunctionReturn(0);
}

// Forces at positions Q = [mesh x | rigid x, R], velocities from the TS's solution.
PetscErrorCode RHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *ctx) {
  FDEMScene          s = (FDEMScene)ctx;
  const PetscScalar *q, *u;
  PetscScalar       *a;
  Vec                U;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_RHS, 0, 0, 0, 0));
  PetscCall(TSGetSolution(s->ts, &U));
  PetscCall(VecGetArrayRead(Q, &q));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(A, &a));
  s->cur_rq     = q + 3 * s->nd;
  s->cur_ru     = u + OffRigid(s);
  s->evaluating = true;
  if (s->dfm) PetscCall(fdem::model::DeformableAcceleration(s->dfm, t, q, u + OffDefV(s), a + 6 * s->nr));
  if (s->rb) PetscCall(RigidMomentum(s, ts, t, q + 3 * s->nd, u + OffRigid(s), a));
  s->evaluating = false;
  PetscCall(VecRestoreArray(A, &a));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(Q, &q));
  PetscCall(PetscLogEventEnd(EV_RHS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Velocities of the positions P = [rigid v, H | mesh v] -> dQ = [mesh v | rigid v, [omega]x R] (R from the solution).
PetscErrorCode RHSPosition(TS ts, PetscReal, Vec P, Vec dQ, void *ctx) {
  FDEMScene          s = (FDEMScene)ctx;
  const PetscScalar *p, *u;
  PetscScalar       *dq;
  Vec                U;
  const PetscInt     nr = s->nr, nd = s->nd;
  PetscFunctionBegin;
  PetscCall(TSGetSolution(s->ts, &U));
  PetscCall(VecGetArrayRead(P, &p));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(dQ, &dq));
  for (PetscInt i = 0; i < 3 * nd; ++i) dq[i] = p[6 * nr + i];
  if (nr) fdem::model::RigidPositionRate(s->rb, p, &u[OffRigid(s) + 3 * nr], dq + 3 * nd);
  PetscCall(VecRestoreArray(dQ, &dq));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(P, &p));
  PetscFunctionReturn(0);
}

// Drift of length s: mesh x += s v (additive), rigid bodies by the rigid model's drift.
PetscErrorCode Drift(TS ts, PetscReal t, PetscReal h, Vec U, void *ctx) {
  FDEMScene    s = (FDEMScene)ctx;
  PetscScalar *u;
  PetscFunctionBegin;
  PetscCall(VecGetArray(U, &u));
  const PetscScalar *v = u + OffDefV(s);
  for (PetscInt i = 0; i < 3 * s->nd; ++i) u[i] += h * v[i];
  if (s->rb) {
    PetscCall(VecPlaceArray(s->vr_state, u + OffRigid(s)));
    PetscCall(fdem::model::RigidDrift(ts, t, h, s->vr_state, s->rb));
    PetscCall(VecResetArray(s->vr_state));
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode Unhook(FDEMScene s) {
  PetscFunctionBegin;
  if (s->hooked) PetscCall(FDEMDeformableRemoveForce(s->dfm, SceneContactForce, s));
  s->hooked = false;
  PetscFunctionReturn(0);
}

} // namespace

// ---------------------------------------------------------------- public API
PetscErrorCode FDEMSceneCreate(MPI_Comm comm, FDEMScene *out) {
  PetscFunctionBegin;
  if (!FDEM_SCENE_CLASSID) {
    PetscCall(PetscClassIdRegister("FDEM Scene", &FDEM_SCENE_CLASSID));
    PetscCall(PetscLogEventRegister("FDEMSceneRHS", FDEM_SCENE_CLASSID, &EV_RHS));
  }
  FDEMScene s = new (std::nothrow) _n_FDEMScene();
  PetscCheck(s, comm, PETSC_ERR_MEM, "Out of memory");
  s->comm = comm;
  s->c    = std::make_unique<fdem::contact::RigidMeshContact>(comm);
  PetscCallMPI(MPI_Comm_rank(comm, &s->rank));
  PetscCallMPI(MPI_Comm_size(comm, &s->size));
  *out = s;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneDestroy(FDEMScene *sp) {
  PetscFunctionBegin;
  if (!*sp) PetscFunctionReturn(0);
  FDEMScene s = *sp;
  PetscCall(Unhook(s));
  if (s->rb && s->rb->U == s->vr_state) s->rb->U = nullptr;
  PetscCall(VecDestroy(&s->vr_state));
  PetscCall(VecDestroy(&s->vr_q));
  PetscCall(VecDestroy(&s->vr_a));
  delete s;
  *sp = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetRigid(FDEMScene s, FDEMRigid rb) {
  PetscFunctionBegin;
  s->rb = rb;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetDeformable(FDEMScene s, FDEMDeformable dfm) {
  PetscFunctionBegin;
  PetscCall(Unhook(s));
  s->dfm = dfm;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetContact(FDEMScene s, PetscReal penalty, PetscReal damping, PetscReal friction, PetscReal buffer) {
  const auto &d = s->c->engine.GetParams().diss;
  PetscFunctionBegin;
  PetscCheck(std::isfinite(penalty) && penalty >= 0, s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the contact penalty must be >= 0 (0: no contact), got %g", (double)penalty);
  PetscCall(s->c->engine.SetDissipation(damping, friction, d.tangential_viscosity));
  PetscCheck(std::isfinite(buffer), s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the search buffer must be finite");
  if (buffer < 0) s->c->engine.SetAutomaticBuffer();
  else PetscCall(s->c->engine.SetBuffer(buffer));
  if (penalty > 0) PetscCall(s->c->engine.SetPenalty(penalty));
  s->penalty = penalty > 0 ? penalty : -1;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetContactTangentialViscosity(FDEMScene s, PetscReal tangential_viscosity) {
  const auto &d = s->c->engine.GetParams().diss;
  PetscFunctionBegin;
  PetscCall(s->c->engine.SetDissipation(d.normal_damping, d.friction, tangential_viscosity));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetFromOptions(FDEMScene s) {
  PetscFunctionBegin;
  PetscCall(s->c->engine.SetFromOptions());
  const PetscReal pen = s->c->engine.GetParams().penalty;
  if (pen > 0) s->penalty = pen;
  PetscFunctionReturn(0);
}

namespace {
// FDEMTSSetNonFiniteReport for the scene's state: its first entry that is Inf or NaN, on the
// lowest rank holding one, named (a deformable body's node by its id, a rigid body by its id,
// and which of their quantities).
PetscErrorCode SceneNonFinite(TS, Vec U, char where[], size_t len, void *ctx) {
  const FDEMScene    s = (FDEMScene)ctx;
  const PetscScalar *u;
  PetscInt           n, first = -1;
  PetscMPIInt        rank, size, mine, who;
  std::string        text;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(s->comm, &rank));
  PetscCallMPI(MPI_Comm_size(s->comm, &size));
  PetscCall(VecGetLocalSize(U, &n));
  PetscCall(VecGetArrayRead(U, &u));
  for (PetscInt i = 0; i < n && first < 0; ++i)
    if (!std::isfinite(PetscRealPart(u[i]))) first = i;
  PetscCall(VecRestoreArrayRead(U, &u));
  mine = first >= 0 ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &who, 1, MPI_INT, MPI_MIN, s->comm));
  where[0] = 0;
  if (who == size) PetscFunctionReturn(0);
  if (rank == who) {
    if (first < OffRigid(s) || first >= OffDefV(s)) { // a deformable node (3 entries each)
      const bool      vel = first >= OffDefV(s);
      const PetscInt  k   = (vel ? first - OffDefV(s) : first) / 3;
      const PetscInt *ids;
      PetscInt        nn, nc, nl, body = -1;
      const char     *name = nullptr;
      PetscCall(FDEMDeformableGetNodeIds(s->dfm, &nn, &ids));
      // its body: that of a local cell holding it
      PetscCall(FDEMDeformableGetLocalCells(s->dfm, &nc, &nl, nullptr, nullptr, nullptr, nullptr));
      std::vector<PetscInt> conn(4 * (size_t)nc), cbody(nc), ngid(nl);
      PetscCall(FDEMDeformableGetLocalCells(s->dfm, &nc, &nl, conn.data(), cbody.data(), nullptr, ngid.data()));
      for (PetscInt e = 0; e < nc && body < 0; ++e)
        for (int a = 0; a < 4; ++a)
          if (ngid[conn[4 * e + a]] == ids[k]) body = cbody[e];
      if (body >= 0) PetscCall(FDEMDeformableGetBodyName(s->dfm, body, nullptr, &name));
      text = "node " + std::to_string((long long)ids[k]) + (name ? std::string(" of deformable body '") + name + "'" : std::string(" of the mesh")) + " (its " + (vel ? "velocity" : "position") + ")";
    } else { // a rigid body: x, R, v, H blocks of 3, 9, 3, 3 per body
      const PetscInt r = first - OffRigid(s), nr = s->nr;
      PetscInt       b;
      const char    *what;
      if (r < 3 * nr) b = r / 3, what = "position";
      else if (r < 12 * nr) b = (r - 3 * nr) / 9, what = "orientation";
      else if (r < 15 * nr) b = (r - 12 * nr) / 3, what = "velocity";
      else b = (r - 15 * nr) / 3, what = "angular momentum";
      text = "rigid body " + std::to_string((long long)s->rb->ids[b]) + " (its " + what + ")";
    }
  }
  int tl = (int)text.size();
  PetscCallMPI(MPI_Bcast(&tl, 1, MPI_INT, who, s->comm));
  text.resize(tl);
  PetscCallMPI(MPI_Bcast(text.data(), tl, MPI_CHAR, who, s->comm));
  PetscCall(PetscStrncpy(where, text.c_str(), len));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode FDEMSceneSetUpTS(FDEMScene s, TS ts, Vec *U) {
  PetscInt     start, nr = 0, nd = 0;
  PetscScalar *u;
  IS           isq, isp;
  PetscFunctionBegin;
  PetscCheck(s->rb || s->dfm, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneSetUpTS: the scene is empty; give it rigid bodies (FDEMSceneSetRigid) and/or a mesh (FDEMSceneSetDeformable)");
  if (s->rb && s->dfm) {
    PetscBool per[3];
    PetscCall(FDEMRigidGetPeriodic(s->rb, per, nullptr, nullptr));
    PetscCheck(!per[0] && !per[1] && !per[2], s->comm, PETSC_ERR_SUP, "FDEMSceneSetUpTS: periodic boundaries hold rigid bodies and spheres only; a scene with a deformable mesh cannot be periodic");
  }
  if (s->rb) PetscCall(FDEMRigidGetNumBodies(s->rb, &nr, &s->nr_global));
  if (s->dfm) PetscCall(FDEMDeformableGetSizes(s->dfm, nullptr, nullptr, &nd, nullptr));
  s->nr = nr;
  s->nd = nd;
  PetscCall(VecCreateMPI(s->comm, 18 * nr + 6 * nd, PETSC_DETERMINE, U));
  PetscCall(PetscObjectSetName((PetscObject)*U, "scene state"));
  PetscCall(VecGetOwnershipRange(*U, &start, nullptr));
  PetscCall(VecGetArray(*U, &u));
  if (s->dfm) {
    Vec                x, v;
    const PetscScalar *xa, *va;
    PetscCall(FDEMDeformableGetPositions(s->dfm, &x));
    PetscCall(FDEMDeformableGetVelocities(s->dfm, &v));
    PetscCall(VecGetArrayRead(x, &xa));
    PetscCall(VecGetArrayRead(v, &va));
    for (PetscInt i = 0; i < 3 * nd; ++i) {
      u[i]              = xa[i];
      u[OffDefV(s) + i] = va[i];
    }
    PetscCall(VecRestoreArrayRead(v, &va));
    PetscCall(VecRestoreArrayRead(x, &xa));
  }
  if (s->rb) {
    s->rb->n = nr;
    PetscCall(fdem::model::RigidLoadState(s->rb, u + OffRigid(s)));
    PetscCall(VecDestroy(&s->vr_state));
    PetscCall(VecDestroy(&s->vr_q));
    PetscCall(VecDestroy(&s->vr_a));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 18 * nr, nullptr, &s->vr_state));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 12 * nr, nullptr, &s->vr_q));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 6 * nr, nullptr, &s->vr_a));
  }
  PetscCall(VecRestoreArray(*U, &u));
  PetscCall(ISCreateStride(s->comm, 3 * nd + 12 * nr, start, 1, &isq));
  PetscCall(ISCreateStride(s->comm, 6 * nr + 3 * nd, start + 3 * nd + 12 * nr, 1, &isp));
  PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, s));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, s));
  // rotations are not additive: a scene with rigid bodies brings its own drift
  if (s->rb && s->nr_global > 0) PetscCall(FDEMTSSetDrift(ts, Drift, s));
  PetscCall(FDEMTSSetNonFiniteReport(ts, SceneNonFinite, s));
  PetscCall(TSSetSolution(ts, *U));
  s->ts = ts;
  if (s->rb) {
    s->rb->U = s->vr_state;
    PetscCall(fdem::model::RigidForcesSetUp(s->rb)); // the local bodies may have changed: rigid-rigid contact starts over
  }
  // rigid-deformable contact: only when asked for and there is something to touch
  // (spheres touch meshes through their granular law, without a penalty)
  s->contact = (s->penalty > 0 || (s->rb && s->rb->nspheres > 0)) && s->rb && s->dfm && s->nr_global > 0;
  PetscCall(Unhook(s));
  if (s->contact) {
    PetscCall(s->c->SetUp(s->rb, s->dfm, ts));
    PetscCall(FDEMDeformableAddForce(s->dfm, SceneContactForce, s));
    s->hooked = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetLocalSizes(FDEMScene s, PetscInt *nr, PetscInt *nd) {
  PetscFunctionBegin;
  if (nr) *nr = s->nr;
  if (nd) *nd = s->nd;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneRestoreState(FDEMScene s, Vec U) {
  const PetscScalar *u;
  PetscInt           n;
  PetscFunctionBegin;
  PetscCall(VecGetLocalSize(U, &n));
  PetscCheck(n == 18 * s->nr + 6 * s->nd, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "FDEMScene: the state has %" PetscInt_FMT " local entries, expected %" PetscInt_FMT " (a vector from FDEMSceneSetUpTS)", n, 18 * s->nr + 6 * s->nd);
  PetscCall(VecGetArrayRead(U, &u));
  if (s->dfm) {
    Vec          x, v;
    PetscScalar *xa, *va;
    PetscCall(FDEMDeformableGetPositions(s->dfm, &x));
    PetscCall(FDEMDeformableGetVelocities(s->dfm, &v));
    PetscCall(VecGetArray(x, &xa));
    PetscCall(VecGetArray(v, &va));
    for (PetscInt i = 0; i < 3 * s->nd; ++i) {
      xa[i] = u[i];
      va[i] = u[OffDefV(s) + i];
    }
    PetscCall(VecRestoreArray(v, &va));
    PetscCall(VecRestoreArray(x, &xa));
  }
  if (s->rb && s->nr > 0) PetscCall(fdem::model::RigidStoreState(s->rb, u + OffRigid(s)));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetInvariants(FDEMScene s, Vec U, PetscReal t, PetscReal P[3], PetscReal L[3], PetscReal E[4]) {
  PetscReal Pt[3] = {0, 0, 0}, Lt[3] = {0, 0, 0}, Et[4] = {0, 0, 0, 0};
  PetscFunctionBegin;
  PetscCall(FDEMSceneRestoreState(s, U));
  if (s->rb) PetscCall(FDEMRigidGetInvariants(s->rb, Pt, Lt, &Et[0]));
  if (s->dfm) {
    PetscReal m, com[3], Pd[3], Ld[3], grav;
    PetscCall(FDEMDeformableGetMomentum(s->dfm, nullptr, &m, com, Pd, Ld));
    PetscCall(FDEMDeformableGetEnergy(s->dfm, nullptr, &Et[1], &Et[2], &grav));
    for (int k = 0; k < 3; ++k) {
      Pt[k] += Pd[k];
      Lt[k] += Ld[k];
    }
  }
  if (s->contact) {
    // the contact energy at U: one evaluation of the mesh's contact hook with the rigid
    // positions of U (the internal and joint forces are not needed)
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(U, &u));
    s->cur_rq     = u + OffRigid(s);
    s->cur_ru     = u + OffRigid(s);
    s->evaluating = true;
    PetscCall(fdem::model::DeformableEvaluateHooks(s->dfm, t));
    s->evaluating = false;
    PetscCall(VecRestoreArrayRead(U, &u));
    Et[3] = s->c->engine.GetStats().energy;
  }
  for (int k = 0; k < 3; ++k) {
    if (P) P[k] = Pt[k];
    if (L) L[k] = Lt[k];
  }
  if (E)
    for (int k = 0; k < 4; ++k) E[k] = Et[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetContactStats(FDEMScene s, FDEMSceneContactStats *st) {
  PetscFunctionBegin;
  *st = s->c->engine.GetStats();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneCheckTimeStep(FDEMScene s, const char *scheme, PetscReal dt, PetscReal *ratio) {
  PetscFunctionBegin;
  PetscCheck(s->penalty > 0, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneCheckTimeStep: rigid-deformable contact is off; give a positive penalty (FDEMSceneSetContact or -fdem_contact_penalty)");
  PetscCheck(s->contact, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneCheckTimeStep: no rigid-deformable contact set up; call FDEMSceneSetUpTS first, with rigid bodies and a mesh in the scene");
  PetscCall(s->c->engine.CheckTimeStep(scheme, dt, ratio));
  PetscFunctionReturn(0);
}
