// Deformable bodies, assembly: internal forces of the local cells (the CST
// kernel) plus the external-force hook, assembled over ranks with
// DMLocalToGlobal(ADD_VALUES); a = f/m + g; the "position"/"momentum" split
// right-hand sides of FDEMDeformableSetUpTS; the global/local exchanges the rest of the model
// uses (copies on one rank). See doc/deformable.md.
#include "deformable_impl.hpp"
#include "deformable_object.hpp"

#include <fdem/ts.h>

#include <cstdint>

using namespace fdem::model::deformable;

// (declared in deformable_impl.hpp; AssembleForces below goes further on one rank and places
// the arrays instead of copying them)
PetscErrorCode fdem::model::DeformableGlobalToLocal(FDEMDeformable d, Vec g, Vec l) {
  PetscFunctionBegin;
  if (d->local_is_owned) PetscCall(VecCopy(g, l));
  else PetscCall(DMGlobalToLocal(d->dm, g, INSERT_VALUES, l));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableLocalToGlobal(FDEMDeformable d, Vec l, InsertMode mode, Vec g) {
  PetscFunctionBegin;
  PetscCheck(mode == INSERT_VALUES || mode == ADD_VALUES, d->comm, PETSC_ERR_SUP, "DeformableLocalToGlobal: INSERT_VALUES or ADD_VALUES only");
  if (!d->local_is_owned) PetscCall(DMLocalToGlobal(d->dm, l, mode, g));
  else if (mode == INSERT_VALUES) PetscCall(VecCopy(l, g));
  else PetscCall(VecAXPY(g, 1.0, l));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::AssembleForces(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *fo) {
  PetscScalar *xl, *vl = nullptr, *fl;
  PetscFunctionBegin;
  // One rank with local = owned nodes (d->local_is_owned): xloc, vloc and floc
  // are placed on xo, vo and fo (read in place, forces summed straight into
  // fo: the same sums as the scatter/ADD path, which copies x and adds f
  // into zeros). Otherwise: scatter to the local vectors and assemble back.
  const bool inplace = d->local_is_owned;
  // resets the placed arrays on every way out, an error of a hook included
  struct Placed {
    Vec  v[3] = {nullptr, nullptr, nullptr};
    ~Placed() {
      for (Vec w : v)
        if (w) (void)VecResetArray(w);
    }
  } placed;
  if (inplace) {
    PetscCall(VecPlaceArray(d->xloc, xo));
    placed.v[0] = d->xloc;
    if (vo) {
      PetscCall(VecPlaceArray(d->vloc, vo));
      placed.v[1] = d->vloc;
    }
    PetscCall(VecPlaceArray(d->floc, fo));
    placed.v[2] = d->floc;
  } else {
    PetscCall(VecPlaceArray(d->gwork, xo));
    PetscCall(DMGlobalToLocalBegin(d->dm, d->gwork, INSERT_VALUES, d->xloc));
    PetscCall(DMGlobalToLocalEnd(d->dm, d->gwork, INSERT_VALUES, d->xloc));
    PetscCall(VecResetArray(d->gwork));
    if (vo) {
      PetscCall(VecPlaceArray(d->gwork, vo));
      PetscCall(DMGlobalToLocalBegin(d->dm, d->gwork, INSERT_VALUES, d->vloc));
      PetscCall(DMGlobalToLocalEnd(d->dm, d->gwork, INSERT_VALUES, d->vloc));
      PetscCall(VecResetArray(d->gwork));
    }
  }
  const bool use_v = vo && d->viscous;
  PetscCall(VecSet(d->floc, 0));
  PetscCall(VecGetArray(d->xloc, &xl));
  if (use_v) PetscCall(VecGetArray(d->vloc, &vl));
  PetscCall(VecGetArray(d->floc, &fl));
  const std::int64_t bad = fdem::kernels::ComputeInternalForces(d->ed, xl, vl, fl);
  // collective inversion check: the smallest global id of an inverted element
  PetscInt   gid = bad >= 0 ? d->cell_gid[bad] : PETSC_MAX_INT, gmin;
  PetscCallMPI(MPI_Allreduce(&gid, &gmin, 1, MPIU_INT, MPI_MIN, d->comm));
  if (gmin != PETSC_MAX_INT) {
    PetscReal info[2] = {0, 0}, ginfo[2];
    if (gid == gmin) {
      info[0] = d->ed.body[bad];
      info[1] = ElementJ(d->ed.elems[bad], xl);
    }
    PetscCallMPI(MPI_Allreduce(info, ginfo, 2, MPIU_REAL, MPIU_SUM, d->comm));
    PetscCall(VecRestoreArray(d->floc, &fl));
    if (use_v) PetscCall(VecRestoreArray(d->vloc, &vl));
    PetscCall(VecRestoreArray(d->xloc, &xl));
    const int b = (int)ginfo[0];
    PetscCheck(std::isfinite(ginfo[1]), d->comm, PETSC_ERR_NOT_CONVERGED, "FDEMDeformable: element %" PetscInt_FMT " of body '%s' has corners that are Inf or NaN at t = %g (the state became non-finite: a time step beyond the stable limit, or a load, position or velocity too large)", gmin, d->body_names[b].c_str(), (double)t);
    SETERRQ(d->comm, PETSC_ERR_NOT_CONVERGED, "FDEMDeformable: element %" PetscInt_FMT " of body '%s' inverted (det F = %g <= 0) at t = %g; reduce the time step or check the loading", gmin, d->body_names[b].c_str(),
            (double)ginfo[1], (double)t);
  }
  PetscCall(AddJointForces(d, t, xl, fl));
  PetscCall(VecRestoreArray(d->floc, &fl));
  if (use_v) PetscCall(VecRestoreArray(d->vloc, &vl));
  PetscCall(VecRestoreArray(d->xloc, &xl));
  for (const auto &e : d->ext) PetscCall(e.first(d, t, d->xloc, vo ? d->vloc : nullptr, d->floc, e.second));
  if (d->equilibrate_pending) PetscCall(EquilibrateNewJoints(d)); // joints inserted under load: balanced with every force on the copies
  if (inplace) PetscFunctionReturn(0); // the sums are in fo already
  PetscCall(VecPlaceArray(d->gwork, fo));
  PetscCall(VecSet(d->gwork, 0));
  PetscCall(DMLocalToGlobalBegin(d->dm, d->floc, ADD_VALUES, d->gwork));
  PetscCall(DMLocalToGlobalEnd(d->dm, d->floc, ADD_VALUES, d->gwork));
  PetscCall(VecResetArray(d->gwork));
  PetscFunctionReturn(0);
}

// The one place of "a = f/m + g, zero at fixed nodes": the deformable TS
// right-hand side below and the combined scene (src/scene) both call it.
PetscErrorCode fdem::model::DeformableAcceleration(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *a) {
  const PetscScalar *mi;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableAcceleration"));
  PetscCall(AssembleForces(d, t, xo, vo, a));
  PetscCall(VecGetArrayRead(d->minv, &mi));
  PetscReal power = 0; // of the reactions R = -(f + m g) that hold the moved nodes
  for (PetscInt k = 0; k < d->nown; ++k) {
    if (d->fixed[k]) {
      if (d->moved)
        for (int c = 0; c < 3; ++c) power -= (PetscRealPart(a[3 * k + c]) + d->g[c] / PetscRealPart(mi[3 * k + c])) * d->vfix[3 * k + c];
      a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = 0;
      continue;
    }
    for (int c = 0; c < 3; ++c) a[3 * k + c] = a[3 * k + c] * mi[3 * k + c] + d->g[c];
  }
  PetscCall(VecRestoreArrayRead(d->minv, &mi));
  if (d->moved) d->meter.Sample(t, power);
  PetscFunctionReturn(0);
}

namespace {

// dx/dt = v
PetscErrorCode RHSPosition(TS, PetscReal, Vec V, Vec dX, void *) {
  PetscFunctionBegin;
  PetscCall(VecCopy(V, dX));
  PetscFunctionReturn(0);
}

// dv/dt = (f_int + f_ext)/m + g, 0 at fixed nodes; the viscous term and the
// external-force hook read v from the TS's current solution.
PetscErrorCode RHSMomentum(TS, PetscReal t, Vec Xq, Vec A, void *ctx) {
  FDEMDeformable     d = (FDEMDeformable)ctx;
  const PetscScalar *xq, *u = nullptr;
  PetscScalar       *a;
  Vec                U = nullptr;
  PetscFunctionBegin;
  const bool need_v = d->viscous || !d->ext.empty();
  if (need_v && d->ts) {
    PetscCall(TSGetSolution(d->ts, &U));
    PetscCall(VecGetArrayRead(U, &u));
  }
  PetscCall(VecGetArrayRead(Xq, &xq));
  PetscCall(VecGetArray(A, &a));
  PetscCall(fdem::model::DeformableAcceleration(d, t, xq, u ? u + 3 * d->nown : nullptr, a));
  PetscCall(VecRestoreArray(A, &a));
  PetscCall(VecRestoreArrayRead(Xq, &xq));
  if (u) PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FDEMDeformableComputeForces(FDEMDeformable d, PetscReal t, Vec U, Vec F) {
  StateView    sv;
  PetscScalar *f;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableComputeForces"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArray(F, &f));
  PetscCall(AssembleForces(d, t, sv.xa, sv.va, f));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(sv.Restore());
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableEvaluateHooks(FDEMDeformable d, PetscReal t, Vec U) {
  StateView sv;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableEvaluateHooks"));
  PetscCall(sv.Get(d, U));
  PetscCall(LocalPositions(d, sv.xa, sv.va));
  PetscCall(sv.Restore());
  PetscCall(VecSet(d->floc, 0));
  for (const auto &e : d->ext) PetscCall(e.first(d, t, d->xloc, d->vloc, d->floc, e.second));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetUpTS(FDEMDeformable d, TS ts, Vec *U) {
  PetscInt     start;
  PetscScalar *u;
  const PetscScalar *xa, *va;
  IS           isq, isp;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableSetUpTS"));
  const PetscInt n = 3 * d->nown;
  PetscCall(VecCreateMPI(d->comm, 2 * n, PETSC_DETERMINE, U));
  PetscCall(PetscObjectSetName((PetscObject)*U, "deformable state"));
  PetscCall(VecGetOwnershipRange(*U, &start, nullptr));
  PetscCall(VecGetArray(*U, &u));
  PetscCall(VecGetArrayRead(d->x, &xa));
  PetscCall(VecGetArrayRead(d->v, &va));
  for (PetscInt i = 0; i < n; ++i) {
    u[i]     = xa[i];
    u[n + i] = d->fixed[i / 3] ? d->vfix[i] : va[i];
  }
  PetscCall(VecRestoreArrayRead(d->v, &va));
  PetscCall(VecRestoreArrayRead(d->x, &xa));
  PetscCall(VecRestoreArray(*U, &u));
  PetscCall(ISCreateStride(d->comm, n, start, 1, &isq));
  PetscCall(ISCreateStride(d->comm, n, start + n, 1, &isp));
  PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, d));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, d));
  PetscCall(FDEMTSSetPositionRHSIdentity(ts, PETSC_TRUE)); // RHSPosition: dX = V
  PetscCall(TSSetSolution(ts, *U));
  d->ts = ts;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableRestoreState(FDEMDeformable d, Vec U) {
  const PetscScalar *u;
  PetscScalar       *xa, *va;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableRestoreState"));
  const PetscInt n = 3 * d->nown;
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(d->x, &xa));
  PetscCall(VecGetArray(d->v, &va));
  for (PetscInt i = 0; i < n; ++i) {
    xa[i] = u[i];
    va[i] = u[n + i];
  }
  PetscCall(VecRestoreArray(d->v, &va));
  PetscCall(VecRestoreArray(d->x, &xa));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

