// What every fdem TS type shares; see fdemts.hpp.
#include "fdemts.hpp"

#include <petscblaslapack.h>

#include <cstdio>
#include <vector>
#include <string>

const char *const FDEMGradientTypes[] = {"jvp", "fd", "shifted", "FDEMGradientType", "FDEM_GRADIENT_", nullptr};

namespace fdem::ts {

namespace {
std::vector<FDEMSchemeInfo> &InfoTable() {
  static std::vector<FDEMSchemeInfo> table;
  return table;
}

struct DriftLink {
  FDEMDriftFn fn;
  void       *ctx;
};
struct IdentityLink {
  PetscBool on;
};
struct NonFiniteLink {
  FDEMNonFiniteFn fn;
  void           *ctx;
};
struct JvpLink {
  FDEMJacobianProductFn fn;
  void                 *ctx;
};
PetscErrorCode FreeLink(void *ptr) {
  PetscFunctionBegin;
  PetscCall(PetscFree(ptr));
  PetscFunctionReturn(0);
}
template <class Link>
PetscErrorCode ComposeLink(TS ts, const char *key, const Link &value, bool clear) {
  PetscContainer container;
  Link          *link;
  PetscFunctionBegin;
  if (clear) {
    PetscCall(PetscObjectCompose((PetscObject)ts, key, nullptr));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscNew(&link));
  *link = value;
  PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)ts), &container));
  PetscCall(PetscContainerSetPointer(container, link));
  PetscCall(PetscContainerSetUserDestroy(container, FreeLink));
  PetscCall(PetscObjectCompose((PetscObject)ts, key, (PetscObject)container));
  PetscCall(PetscContainerDestroy(&container));
  PetscFunctionReturn(0);
}
template <class Link>
PetscErrorCode QueryLink(TS ts, const char *key, Link **link) {
  PetscObject obj;
  PetscFunctionBegin;
  *link = nullptr;
  PetscCall(PetscObjectQuery((PetscObject)ts, key, &obj));
  if (obj) PetscCall(PetscContainerGetPointer((PetscContainer)obj, (void **)link));
  PetscFunctionReturn(0);
}

PetscErrorCode GetSchemeInfo_Common(TS ts, FDEMSchemeInfo *info) {
  PetscFunctionBegin;
  *info = static_cast<Common *>(ts->data)->info;
  PetscFunctionReturn(0);
}
PetscErrorCode GetForceEvaluations_Common(TS ts, PetscInt *n) {
  PetscFunctionBegin;
  *n = static_cast<Common *>(ts->data)->nforce;
  PetscFunctionReturn(0);
}
PetscErrorCode SetGradientType_Common(TS ts, FDEMGradientType type) {
  Common *c = static_cast<Common *>(ts->data);
  PetscFunctionBegin;
  PetscCheck(c->uses_gradient, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_WRONG, "TS type %s has no force-gradient or tangent terms", c->info.name);
  PetscCheck(type >= FDEM_GRADIENT_JVP && type <= FDEM_GRADIENT_SHIFTED && c->gradient_allowed[type], PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE,
             "TS type %s: gradient type %s is not available (the shifted-force form exists only for the force-gradient splitting schemes chin and omf32)", c->info.name,
             type >= 0 && type <= 2 ? FDEMGradientTypes[type] : "unknown");
  c->gradient = type;
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode RegisterSchemeInfo(const FDEMSchemeInfo &info) {
  PetscFunctionBegin;
  for (auto &i : InfoTable())
    if (std::string(i.name) == info.name) {
      i = info;
      PetscFunctionReturn(0);
    }
  InfoTable().push_back(info);
  PetscFunctionReturn(0);
}

PetscErrorCode SchemeInfoLookup(const char *name, FDEMSchemeInfo *info, PetscBool *found) {
  PetscFunctionBegin;
  *found = PETSC_FALSE;
  for (auto &i : InfoTable())
    if (name && std::string(i.name) == name) {
      *info  = i;
      *found = PETSC_TRUE;
    }
  PetscFunctionReturn(0);
}

PetscErrorCode CommonCompose(TS ts, PetscBool on) {
  PetscFunctionBegin;
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "FDEMTSGetSchemeInfo_C", on ? GetSchemeInfo_Common : nullptr));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "FDEMTSGetForceEvaluations_C", on ? GetForceEvaluations_Common : nullptr));
  PetscCall(PetscObjectComposeFunction((PetscObject)ts, "FDEMTSSetGradientType_C", on ? SetGradientType_Common : nullptr));
  PetscFunctionReturn(0);
}

namespace {
std::string InterpolateMessage(const Common *c) {
  return std::string("-ts_type ") + c->info.name +
         ": -ts_exact_final_time interpolate (which PETSc also takes for unspecified) is not available; the fdem types end exactly at the final time with -ts_exact_final_time matchstep (the last step is shortened to land on it)";
}

// The step size must be a positive finite number.
PetscErrorCode CheckStep(TS ts, Common *c) {
  const PetscReal h = ts->time_step;
  PetscFunctionBegin;
  PetscCheck(h > 0 && !PetscIsInfOrNanReal(h), PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE,
             "-ts_type %s: the time step (-ts_dt, TSSetTimeStep) is %g at t = %g; it must be positive and finite", c->info.name, (double)h, (double)ts->ptime);
  PetscFunctionReturn(0);
}

// Sub-vector shells (see SubViews) when both splits are one contiguous block
// of the state on every rank and the state is a plain seq/mpi Vec.
PetscErrorCode CreateShells(TS ts, Common *c) {
  Vec         U = ts->vec_sol;
  MPI_Comm    comm;
  PetscMPIInt size;
  PetscInt    lo, hi, sq = -1, sp = -1, nq, np, Nq, Np, bq, bp;
  PetscBool   cq = PETSC_FALSE, cp = PETSC_FALSE, plain;
  PetscFunctionBegin;
  PetscCall(PetscObjectGetComm((PetscObject)U, &comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)U, &plain, VECSEQ, VECMPI, ""));
  PetscCall(VecGetOwnershipRange(U, &lo, &hi));
  PetscCall(ISContiguousLocal(c->is_q, lo, hi, &sq, &cq));
  PetscCall(ISContiguousLocal(c->is_p, lo, hi, &sp, &cp));
  PetscCall(ISGetLocalSize(c->is_q, &nq));
  PetscCall(ISGetLocalSize(c->is_p, &np));
  PetscCall(ISGetSize(c->is_q, &Nq));
  PetscCall(ISGetSize(c->is_p, &Np));
  PetscCall(ISGetBlockSize(c->is_q, &bq));
  PetscCall(ISGetBlockSize(c->is_p, &bp));
  {
    PetscInt nU;
    PetscCall(VecGetSize(U, &nU));
    c->covers_all = (PetscBool)(Nq + Np == nU);
  }
  PetscBool mine = (PetscBool)(plain && cq && cp), all;
  PetscCall(MPIU_Allreduce(&mine, &all, 1, MPIU_BOOL, MPI_LAND, comm));
  c->off_q = c->off_p = c->n_local = -1;
  if (!all) PetscFunctionReturn(0);
  if (nq % bq) bq = 1;
  if (np % bp) bp = 1;
  for (auto &v : c->views) {
    if (size == 1) {
      PetscCall(VecCreateSeqWithArray(comm, bq, nq, nullptr, &v.q));
      PetscCall(VecCreateSeqWithArray(comm, bp, np, nullptr, &v.p));
    } else {
      PetscCall(VecCreateMPIWithArray(comm, bq, nq, Nq, nullptr, &v.q));
      PetscCall(VecCreateMPIWithArray(comm, bp, np, Np, nullptr, &v.p));
    }
    v.in_use = false;
  }
  c->off_q = sq;
  c->off_p = sp;
  PetscCall(VecGetLocalSize(U, &c->n_local));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode Split::Get() {
  PetscFunctionBegin;
  PetscCheck(!q && !p, PETSC_COMM_SELF, PETSC_ERR_PLIB, "Split::Get called twice");
  v_ = nullptr;
  if (c_->off_q >= 0) {
    PetscInt  n;
    PetscBool plain;
    PetscCall(VecGetLocalSize(U_, &n));
    PetscCall(PetscObjectTypeCompareAny((PetscObject)U_, &plain, VECSEQ, VECMPI, ""));
    if (n == c_->n_local && plain)
      for (auto &v : c_->views)
        if (!v.in_use && v.q) {
          v_ = &v;
          break;
        }
  }
  if (v_) {
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(U_, &u));
    PetscCall(VecPlaceArray(v_->q, u + c_->off_q));
    PetscCall(VecPlaceArray(v_->p, u + c_->off_p));
    PetscCall(VecRestoreArrayRead(U_, &u));
    PetscCall(PetscObjectStateGet((PetscObject)v_->q, &v_->sq));
    PetscCall(PetscObjectStateGet((PetscObject)v_->p, &v_->sp));
    v_->in_use = true;
    q          = v_->q;
    p          = v_->p;
  } else {
    PetscCall(VecGetSubVector(U_, c_->is_q, &q));
    PetscCall(VecGetSubVector(U_, c_->is_p, &p));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode Split::Restore() {
  PetscFunctionBegin;
  if (v_) {
    PetscObjectState sq, sp;
    PetscCall(PetscObjectStateGet((PetscObject)v_->q, &sq));
    PetscCall(PetscObjectStateGet((PetscObject)v_->p, &sp));
    PetscCall(VecResetArray(v_->q));
    PetscCall(VecResetArray(v_->p));
    v_->in_use = false;
    // a write through a shell is a write to the state
    if (sq != v_->sq || sp != v_->sp) PetscCall(PetscObjectStateIncrease((PetscObject)U_));
    v_ = nullptr;
  } else {
    if (q) PetscCall(VecRestoreSubVector(U_, c_->is_q, &q));
    if (p) PetscCall(VecRestoreSubVector(U_, c_->is_p, &p));
  }
  q = p = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode CommonSetUp(TS ts, Common *c, PetscBool need_default_drift) {
  MPI_Comm    comm = PetscObjectComm((PetscObject)ts);
  const char *names[2] = {"position", "momentum"};
  IS          is[2];
  TS          sub[2];
  DriftLink  *drift;
  JvpLink    *jvp;
  TSAdapt     adapt;
  PetscBool   none;

  PetscFunctionBegin;
  for (int k = 0; k < 2; ++k) {
    PetscCall(TSRHSSplitGetIS(ts, names[k], &is[k]));
    PetscCheck(is[k], comm, PETSC_ERR_ARG_WRONGSTATE,
               "-ts_type %s: the \"%s\" split is missing; give it with TSRHSSplitSetIS(ts, \"%s\", is) as for -ts_type basicsymplectic (both \"position\" and \"momentum\" are needed)",
               c->info.name, names[k], names[k]);
    PetscCall(TSRHSSplitGetSubTS(ts, names[k], &sub[k]));
    TSRHSFunction fn = nullptr;
    if (sub[k]) PetscCall(TSGetRHSFunction(sub[k], nullptr, &fn, nullptr));
    PetscCheck(sub[k] && fn, comm, PETSC_ERR_ARG_WRONGSTATE, "-ts_type %s: the \"%s\" split has no RHS function; set it with TSRHSSplitSetRHSFunction(ts, \"%s\", NULL, fn, ctx)", c->info.name,
               names[k], names[k]);
  }
  c->is_q = is[0];
  c->is_p = is[1];
  c->subts_q = sub[0];
  c->subts_p = sub[1];
  {
    IS       both;
    PetscInt n, nq, np, nU;
    PetscCall(ISIntersect(c->is_q, c->is_p, &both));
    PetscCall(ISGetSize(both, &n));
    PetscCall(ISDestroy(&both));
    PetscCheck(n == 0, comm, PETSC_ERR_ARG_INCOMP, "-ts_type %s: the \"position\" and \"momentum\" splits overlap in %" PetscInt_FMT " entries; each entry of the solution belongs to one split",
               c->info.name, n);
    PetscCall(ISGetSize(c->is_q, &nq));
    PetscCall(ISGetSize(c->is_p, &np));
    PetscCall(VecGetSize(ts->vec_sol, &nU));
    PetscCheck(nq + np <= nU, comm, PETSC_ERR_ARG_SIZ, "-ts_type %s: the splits hold %" PetscInt_FMT " + %" PetscInt_FMT " entries but the solution has only %" PetscInt_FMT, c->info.name, nq, np, nU);
    PetscCall(QueryLink(ts, "FDEMTSDrift", &drift));
    c->drift     = drift ? drift->fn : nullptr;
    c->drift_ctx = drift ? drift->ctx : nullptr;
    {
      IdentityLink *idl;
      PetscCall(QueryLink(ts, "FDEMTSPositionRHSIdentity", &idl));
      c->velocity_identity = (PetscBool)(idl && idl->on && !c->drift);
    }
    PetscCall(QueryLink(ts, "FDEMTSJacobianProduct", &jvp));
    c->jvp     = jvp ? jvp->fn : nullptr;
    c->jvp_ctx = jvp ? jvp->ctx : nullptr;
    if (need_default_drift) PetscCheck(!c->drift, comm, PETSC_ERR_SUP, "-ts_type %s works on additive positions only; this problem sets its own drift (FDEMTSSetDrift, e.g. rigid-body rotations): use a splitting scheme (cd, pv, omf30, chin, fr, pefrl, omf32)", c->info.name);
    if (!c->drift) {
      PetscInt nql, npl;
      PetscCall(ISGetLocalSize(c->is_q, &nql));
      PetscCall(ISGetLocalSize(c->is_p, &npl));
      PetscCheck(nq == np, comm, PETSC_ERR_ARG_SIZ,
                 "-ts_type %s: split sizes do not match: \"position\" has %" PetscInt_FMT " entries, \"momentum\" %" PetscInt_FMT "; the additive drift position += h F_q(momentum) needs equal sizes (a problem with non-additive positions sets FDEMTSSetDrift)",
                 c->info.name, nq, np);
      PetscCheck(nql == npl, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "-ts_type %s: on this rank the \"position\" split has %" PetscInt_FMT " local entries and \"momentum\" %" PetscInt_FMT "; lay them out alike", c->info.name, nql, npl);
    }
  }
  if (c->uses_gradient && c->gradient == FDEM_GRADIENT_JVP) {
    PetscCheck(c->jvp, comm, PETSC_ERR_ARG_WRONGSTATE, "-ts_%s_gradient jvp needs a Jacobian-vector product: call FDEMTSSetForceJacobianProduct(), or use -ts_%s_gradient fd", c->info.name, c->info.name);
    PetscCheck(!c->drift, comm, PETSC_ERR_SUP, "-ts_%s_gradient jvp is for additive positions only; with a custom drift use fd or shifted", c->info.name);
  }
  PetscCall(CreateShells(ts, c));
  {
    Split X(ts->vec_sol, c);
    PetscCall(X.Get());
    PetscCall(VecDuplicate(X.q, &c->q_work));
    PetscCall(VecDuplicate(X.q, &c->q_work2));
    PetscCall(VecDuplicate(X.p, &c->p_work));
    PetscCall(VecDuplicate(X.p, &c->p_work2));
    PetscCall(X.Restore());
    PetscCall(VecDuplicate(ts->vec_sol, &c->U_work));
  }
  PetscCall(CheckStep(ts, c));
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptCandidatesClear(adapt));
  PetscCall(PetscObjectTypeCompare((PetscObject)adapt, TSADAPTNONE, &none));
  if (!((PetscObject)adapt)->type_name) PetscCall(TSAdaptSetType(adapt, TSADAPTNONE));
  else PetscCheck(none, comm, PETSC_ERR_SUP, "-ts_type %s takes fixed steps: use -ts_adapt_type none", c->info.name);
  c->nforce          = 0;
  c->steps_unchecked = 0;
  c->good_of         = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode CommonReset(Common *c) {
  PetscFunctionBegin;
  for (auto &v : c->views) {
    PetscCall(VecDestroy(&v.q));
    PetscCall(VecDestroy(&v.p));
    v.in_use = false;
  }
  c->off_q = c->off_p = c->n_local = -1;
  PetscCall(VecDestroy(&c->U_good));
  c->good_of = 0;
  PetscCall(VecDestroy(&c->q_work));
  PetscCall(VecDestroy(&c->q_work2));
  PetscCall(VecDestroy(&c->p_work));
  PetscCall(VecDestroy(&c->p_work2));
  PetscCall(VecDestroy(&c->U_work));
  PetscFunctionReturn(0);
}

PetscErrorCode CommonSetFromOptions(TS ts, Common *c, PetscOptionItems *PetscOptionsObject) {
  char      opt[256];
  PetscBool flg;
  PetscFunctionBegin;
  PetscOptionsHeadBegin(PetscOptionsObject, "fdem scheme options");
  if (c->uses_gradient) {
    // offer only the forms this type has (jvp, fd and, for chin/omf32, shifted: the enum's order)
    PetscInt nform = c->gradient_allowed[FDEM_GRADIENT_SHIFTED] ? 3 : 2, g = c->gradient;
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_gradient", c->info.name));
    PetscCall(PetscOptionsEList(opt, "How the force-gradient / tangent terms are formed", "FDEMTSSetGradientType", FDEMGradientTypes, nform, FDEMGradientTypes[c->gradient], &g, &flg));
    if (flg) PetscCall(SetGradientType_Common(ts, (FDEMGradientType)g));
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_fd_delta", c->info.name));
    PetscCall(PetscOptionsReal(opt, "Relative step of the finite-difference directional derivative", "", c->fd_delta, &c->fd_delta, nullptr));
    PetscCheck(c->fd_delta > 0, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE, "%s must be positive", opt);
  }
  PetscCall(PetscOptionsInt("-ts_fdem_check_interval", "Steps between checks of the solution for Inf/NaN (the last step is always checked)", "", c->check_interval, &c->check_interval, nullptr));
  PetscCheck(c->check_interval >= 1, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE, "-ts_fdem_check_interval must be >= 1");
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode CommonView(TS ts, Common *c, PetscViewer viewer) {
  PetscBool iascii;
  PetscFunctionBegin;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (!iascii) PetscFunctionReturn(0);
  PetscCall(PetscViewerASCIIPrintf(viewer, "  fdem scheme %s: %s\n", c->info.name, c->info.description));
  char grad[160] = ", no gradient terms";
  if (c->uses_gradient) PetscCall(PetscSNPrintf(grad, sizeof(grad), " + %" PetscInt_FMT " gradient terms per step, formed by: %s", c->info.gradients, FDEMGradientTypes[c->gradient]));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  order %" PetscInt_FMT ", %" PetscInt_FMT " force stages, %" PetscInt_FMT " force evaluations per step%s\n", c->info.order, c->info.stages, (PetscInt)c->info.evals, grad));
  char kc[64];
  if (c->info.kcrit_book > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "  stability limit K_crit = (omega h)_crit = %s (book Table 5.2: %.4f)\n", KcritText(c, kc, sizeof(kc)), (double)c->info.kcrit_book));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "  stability limit K_crit = (omega h)_crit = %s\n", KcritText(c, kc, sizeof(kc))));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  momentum RHS evaluations so far: %" PetscInt_FMT "; Inf/NaN check every %" PetscInt_FMT " steps%s\n", c->nforce, c->check_interval,
                                   ts->errorifstepfailed ? "" : " (a failed check returns the last checked state)"));
  PetscFunctionReturn(0);
}

PetscErrorCode Force(TS, Common *c, PetscReal t, Vec q, Vec f) {
  PetscFunctionBegin;
  PetscCall(TSComputeRHSFunction(c->subts_p, t, q, f));
  c->nforce++;
  PetscFunctionReturn(0);
}

PetscErrorCode Velocity(TS, Common *c, PetscReal t, Vec p, Vec dq) {
  PetscFunctionBegin;
  if (c->velocity_identity) PetscCall(VecCopy(p, dq));
  else PetscCall(TSComputeRHSFunction(c->subts_q, t, p, dq));
  PetscFunctionReturn(0);
}

PetscErrorCode DriftDefault(TS ts, Common *c, PetscReal t, PetscReal s, Vec q, Vec p, PetscBool last) {
  PetscFunctionBegin;
  // with F_q(p) = p the copy into q_work is skipped: the same AXPY reads p
  Vec dq = p;
  if (!c->velocity_identity) {
    PetscCall(Velocity(ts, c, t, p, c->q_work));
    dq = c->q_work;
  }
  if (last) {
    PetscCall(AXPYScan(c, q, s, dq));
    c->scanned_q = c->check_step;
  } else PetscCall(VecAXPY(q, s, dq));
  PetscFunctionReturn(0);
}

// Drift of the whole state vector U (user drift or default), fetching subvectors as needed.
static PetscErrorCode DriftState(TS ts, Common *c, PetscReal t, PetscReal s, Vec U) {
  PetscFunctionBegin;
  if (c->drift) PetscCall(c->drift(ts, t, s, U, c->drift_ctx));
  else {
    Split S(U, c);
    PetscCall(S.Get());
    PetscCall(DriftDefault(ts, c, t, s, S.q, S.p, PETSC_FALSE));
    PetscCall(S.Restore());
  }
  PetscFunctionReturn(0);
}

// Force at U_work = drift_s(U with momenta := a).
static PetscErrorCode ForceAtDriftedCopy(TS ts, Common *c, PetscReal t, Vec U, Vec a, PetscReal s, Vec f) {
  Split W(c->U_work, c);
  PetscFunctionBegin;
  PetscCall(VecCopy(U, c->U_work));
  PetscCall(W.Get());
  PetscCall(VecCopy(a, W.p));
  PetscCall(W.Restore());
  PetscCall(c->drift(ts, t, s, c->U_work, c->drift_ctx));
  PetscCall(W.Get());
  PetscCall(Force(ts, c, t, W.q, f));
  PetscCall(W.Restore());
  PetscFunctionReturn(0);
}

PetscErrorCode ShiftedForce(TS ts, Common *c, PetscReal t, Vec U, Vec q, Vec a, PetscReal s, Vec f) {
  PetscFunctionBegin;
  if (c->drift) PetscCall(ForceAtDriftedCopy(ts, c, t, U, a, s, f));
  else {
    PetscCall(Velocity(ts, c, t, a, c->q_work));
    PetscCall(VecWAXPY(c->q_work2, s, c->q_work, q));
    PetscCall(Force(ts, c, t, c->q_work2, f));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ForceDirectional(TS ts, Common *c, PetscReal t, Vec q, Vec W, Vec JW) {
  PetscReal nq, nw, eps;
  PetscFunctionBegin;
  if (c->gradient == FDEM_GRADIENT_JVP) {
    PetscCall(c->jvp(ts, t, q, W, JW, c->jvp_ctx));
    PetscFunctionReturn(0);
  }
  PetscCall(VecNorm(W, NORM_INFINITY, &nw));
  if (nw == 0) {
    PetscCall(VecSet(JW, 0));
    PetscFunctionReturn(0);
  }
  PetscCall(VecNorm(q, NORM_INFINITY, &nq));
  eps = c->fd_delta * (1 + nq) / nw;
  PetscCall(VecWAXPY(c->q_work2, eps, W, q));
  PetscCall(Force(ts, c, t, c->q_work2, JW));
  PetscCall(VecWAXPY(c->q_work2, -eps, W, q));
  PetscCall(Force(ts, c, t, c->q_work2, c->p_work2));
  PetscCall(VecAXPY(JW, -1.0, c->p_work2));
  PetscCall(VecScale(JW, 0.5 / eps));
  PetscFunctionReturn(0);
}

PetscErrorCode ForceGradient(TS ts, Common *c, PetscReal t, Vec U, Vec q, Vec a, Vec G) {
  PetscFunctionBegin;
  if (!c->drift) {
    // direction d = F_q(a) (the acceleration for a momentum-form problem)
    PetscCall(Velocity(ts, c, t, a, c->q_work));
    PetscCall(ForceDirectional(ts, c, t, q, c->q_work, G)); // uses q_work2/p_work2 only
    PetscCall(VecScale(G, 2.0));
  } else {
    PetscReal nq, na, eps;
    PetscCall(VecNorm(a, NORM_INFINITY, &na));
    if (na == 0) {
      PetscCall(VecSet(G, 0));
      PetscFunctionReturn(0);
    }
    Split X(U, c); // q itself is not fetched here: U is whole
    PetscCall(X.Get());
    PetscCall(VecNorm(X.q, NORM_INFINITY, &nq));
    PetscCall(X.Restore());
    eps = c->fd_delta * (1 + nq) / na;
    PetscCall(ForceAtDriftedCopy(ts, c, t, U, a, eps, G));
    PetscCall(ForceAtDriftedCopy(ts, c, t, U, a, -eps, c->p_work2));
    PetscCall(VecAXPY(G, -1.0, c->p_work2));
    PetscCall(VecScale(G, 1.0 / eps));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode AdvanceAccurate(TS ts, Common *c, PetscReal t, PetscReal H, PetscInt n, Vec U) {
  // PEFRL (Omelyan, Mryglod, Folk 2002), position form: D xi, K (1-2l)/2, D chi, K l, D 1-2(chi+xi), K l, D chi, K (1-2l)/2, D xi.
  const PetscReal xi = 0.1786178958448091, lam = -0.2123418310626054, chi = -0.06626458266981849;
  const PetscReal dc[5] = {xi, chi, 1 - 2 * (chi + xi), chi, xi}, kc[4] = {(1 - 2 * lam) / 2, lam, lam, (1 - 2 * lam) / 2};
  const PetscReal h = H / n;
  PetscFunctionBegin;
  for (PetscInt s = 0; s < n; ++s) {
    PetscReal tt = t + s * h;
    for (int k = 0; k < 5; ++k) {
      PetscCall(DriftState(ts, c, tt, dc[k] * h, U));
      tt += dc[k] * h;
      if (k == 4) break;
      Split S(U, c);
      PetscCall(S.Get());
      PetscCall(Force(ts, c, tt, S.q, c->p_work));
      PetscCall(VecAXPY(S.p, kc[k] * h, c->p_work));
      PetscCall(S.Restore());
    }
  }
  PetscFunctionReturn(0);
}

const char *KcritText(const Common *c, char buf[], size_t n) {
  if (c->info.kcrit > 0) std::snprintf(buf, n, "%.6f", (double)c->info.kcrit);
  else std::snprintf(buf, n, "0 (the scheme grows at every step size)");
  return buf;
}

PetscErrorCode BeginStep(TS ts, Common *c) {
  const PetscReal h = ts->time_step;
  PetscFunctionBegin;
  PetscCall(CheckStep(ts, c));
  // PETSc's default without adaptivity is interpolate, needed only when a step passes the final time
  PetscCheck(ts->exact_final_time != TS_EXACTFINALTIME_INTERPOLATE || !(ts->ptime + h > ts->max_time), PetscObjectComm((PetscObject)ts), PETSC_ERR_SUP, "%s", InterpolateMessage(c).c_str());
  const PetscBool last = (PetscBool)(ts->ptime + h >= ts->max_time - 1e-12 * PetscAbsReal(ts->max_time) || ts->steps + 1 >= ts->max_steps);
  c->check_step        = (PetscBool)(c->steps_unchecked + 1 >= c->check_interval || last);
  c->scanned_q = c->scanned_p = PETSC_FALSE;
  c->scan                     = 0;
  if (!ts->errorifstepfailed && c->good_of != ((PetscObject)ts->vec_sol)->id) {
    // the state a run starts from counts as checked
    if (!c->U_good) PetscCall(VecDuplicate(ts->vec_sol, &c->U_good));
    PetscCall(VecCopy(ts->vec_sol, c->U_good));
    c->good_of    = ((PetscObject)ts->vec_sol)->id;
    c->t_good     = ts->ptime;
    c->steps_good = ts->steps;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode AXPYScan(Common *c, Vec y, PetscReal a, Vec x) {
  PetscFunctionBegin;
  if (!c->check_step) {
    PetscCall(VecAXPY(y, a, x));
    PetscFunctionReturn(0);
  }
  PetscScalar       *py;
  const PetscScalar *px;
  PetscInt           n;
  PetscReal          scan = 0;
  PetscCall(VecGetLocalSize(y, &n));
  PetscCall(VecGetArray(y, &py));
  PetscCall(VecGetArrayRead(x, &px));
  // the same BLAS axpy as VecAXPY (bitwise the same result), in chunks that
  // are scanned while they are in cache
  const PetscInt chunk = 2048;
  for (PetscInt i0 = 0; i0 < n; i0 += chunk) {
    const PetscInt m = PetscMin(chunk, n - i0);
    PetscBLASInt   bm, one = 1;
    PetscScalar    sa = a;
    PetscCall(PetscBLASIntCast(m, &bm));
    if (a != 0) PetscCallBLAS("BLASaxpy", BLASaxpy_(&bm, &sa, px + i0, &one, py + i0, &one));
    // 0 * y is 0 for a finite entry and NaN for Inf or NaN; eight independent
    // sums so that the scan is not one chain of dependent additions
    PetscReal s8[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    PetscInt  i     = i0;
    for (; i + 8 <= i0 + m; i += 8)
      for (int k = 0; k < 8; ++k) s8[k] += 0 * PetscRealPart(py[i + k]);
    for (; i < i0 + m; ++i) s8[0] += 0 * PetscRealPart(py[i]);
    for (int k = 0; k < 8; ++k) scan += s8[k];
  }
  PetscCall(VecRestoreArrayRead(x, &px));
  PetscCall(VecRestoreArray(y, &py));
  if (a != 0) PetscCall(PetscLogFlops(2.0 * n));
  c->scan += scan;
  PetscFunctionReturn(0);
}

PetscErrorCode StepFailed(TS ts, Common *c, const char *msg) {
  char full[1400];
  PetscFunctionBegin;
  PetscCheck(!ts->errorifstepfailed, PetscObjectComm((PetscObject)ts), PETSC_ERR_NOT_CONVERGED, "%s", msg);
  ts->reject++;
  ts->reason = TS_DIVERGED_STEP_REJECTED;
  if (c->U_good && c->good_of == ((PetscObject)ts->vec_sol)->id) {
    PetscCall(VecCopy(c->U_good, ts->vec_sol));
    ts->ptime = c->t_good;
    ts->steps = c->steps_good;
    PetscCall(PetscSNPrintf(full, sizeof(full), "%s. Returning the last checked state, at t = %g (step %" PetscInt_FMT ")", msg, (double)c->t_good, c->steps_good));
  } else PetscCall(PetscSNPrintf(full, sizeof(full), "%s", msg));
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ts), "%s\n", full));
  PetscFunctionReturn(0);
}

PetscErrorCode FinishStep(TS ts, Common *c, PetscBool *ok) {
  PetscReal next_h = ts->time_step;
  PetscBool accept = PETSC_TRUE;

  PetscFunctionBegin;
  *ok = PETSC_TRUE;
  if (c->check_step) {
    PetscBool bad;
    c->steps_unchecked = 0;
    if (c->scanned_q && c->scanned_p && c->covers_all) {
      // the step's last drift and kick scanned everything they wrote
      PetscBool mine = (PetscBool)!(c->scan == 0);
      PetscCall(MPIU_Allreduce(&mine, &bad, 1, MPIU_BOOL, MPI_LOR, PetscObjectComm((PetscObject)ts)));
    } else {
      PetscReal nrm;
      PetscCall(VecNorm(ts->vec_sol, NORM_INFINITY, &nrm));
      bad = (PetscBool)PetscIsInfOrNanReal(nrm);
    }
    if (bad) {
      char           msg[1024], kc[64], where[400] = "";
      NonFiniteLink *report;
      *ok = PETSC_FALSE;
      PetscCall(QueryLink(ts, "FDEMTSNonFinite", &report));
      if (report) PetscCall(report->fn(ts, ts->vec_sol, where, sizeof(where), report->ctx)); // (collective)
      PetscCall(PetscSNPrintf(msg, sizeof(msg),
                              "fdem -ts_type %s: the solution became Inf or NaN in step %" PetscInt_FMT " (t = %g, h = %g)%s%s. The scheme is stable only for omega*h < K_crit = %s, omega being the highest natural "
                              "frequency of the problem: reduce the time step (-ts_dt)",
                              c->info.name, ts->steps + 1, (double)(ts->ptime + ts->time_step), (double)ts->time_step, where[0] ? ", first at " : "", where, KcritText(c, kc, sizeof(kc))));
      PetscCall(StepFailed(ts, c, msg));
      PetscFunctionReturn(0);
    }
  } else c->steps_unchecked++;
  PetscCall(TSAdaptChoose(ts->adapt, ts, ts->time_step, nullptr, &next_h, &accept));
  ts->ptime += ts->time_step;
  ts->time_step = next_h;
  if (c->check_step && !ts->errorifstepfailed) {
    if (!c->U_good) PetscCall(VecDuplicate(ts->vec_sol, &c->U_good));
    PetscCall(VecCopy(ts->vec_sol, c->U_good));
    c->good_of    = ((PetscObject)ts->vec_sol)->id;
    c->t_good     = ts->ptime;
    c->steps_good = ts->steps + 1;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode KeepHistory(TS ts, Common *c, const std::vector<Vec *> &vecs, PetscReal t, PetscReal h) {
  PetscFunctionBegin;
  PetscCall(DropHistory(c));
  if (!ts->vec_sol || !c->is_q || !c->is_p) PetscFunctionReturn(0);
  for (Vec *v : vecs) {
    c->kept.vecs.push_back(*v);
    *v = nullptr;
  }
  PetscCall(VecDuplicate(ts->vec_sol, &c->kept.U));
  PetscCall(VecCopy(ts->vec_sol, c->kept.U));
  PetscCall(ISDuplicate(c->is_q, &c->kept.is_q));
  PetscCall(ISCopy(c->is_q, c->kept.is_q));
  PetscCall(ISDuplicate(c->is_p, &c->kept.is_p));
  PetscCall(ISCopy(c->is_p, c->kept.is_p));
  c->kept.t       = t;
  c->kept.h       = h;
  c->kept.adopted = false;
  PetscFunctionReturn(0);
}

PetscErrorCode AdoptHistory(TS ts, Common *c, const std::vector<Vec *> &vecs) {
  PetscBool same = PETSC_FALSE;
  PetscFunctionBegin;
  if (!c->kept.U || c->kept.vecs.size() != vecs.size()) {
    PetscCall(DropHistory(c));
    PetscFunctionReturn(0);
  }
  {
    PetscInt  n[2], m[2];
    PetscBool eq[2] = {PETSC_FALSE, PETSC_FALSE};
    PetscCall(VecGetSize(ts->vec_sol, &n[0]));
    PetscCall(VecGetLocalSize(ts->vec_sol, &n[1]));
    PetscCall(VecGetSize(c->kept.U, &m[0]));
    PetscCall(VecGetLocalSize(c->kept.U, &m[1]));
    PetscBool mine = (PetscBool)(n[0] == m[0] && n[1] == m[1]);
    PetscCall(MPIU_Allreduce(&mine, &same, 1, MPIU_BOOL, MPI_LAND, PetscObjectComm((PetscObject)ts)));
    if (same) {
      PetscCall(ISEqualUnsorted(c->is_q, c->kept.is_q, &eq[0]));
      PetscCall(ISEqualUnsorted(c->is_p, c->kept.is_p, &eq[1]));
      same = (PetscBool)(eq[0] && eq[1]);
    }
  }
  if (!same) {
    PetscCall(DropHistory(c));
    PetscFunctionReturn(0);
  }
  size_t i = 0;
  for (Vec *v : vecs) {
    PetscCall(VecDestroy(v));
    *v = c->kept.vecs[i];
    c->kept.vecs[i++] = nullptr;
  }
  c->kept.vecs.clear();
  c->kept.adopted = true;
  PetscFunctionReturn(0);
}

PetscErrorCode ResumeHistory(TS ts, Common *c, PetscReal *t, PetscReal *h, PetscBool *resume) {
  PetscFunctionBegin;
  *resume = PETSC_FALSE;
  if (!c->kept.adopted) PetscFunctionReturn(0);
  PetscCall(VecEqual(ts->vec_sol, c->kept.U, resume));
  *t = c->kept.t;
  *h = c->kept.h;
  PetscCall(DropHistory(c));
  PetscFunctionReturn(0);
}

PetscErrorCode DropHistory(Common *c) {
  PetscFunctionBegin;
  for (Vec &v : c->kept.vecs) PetscCall(VecDestroy(&v));
  c->kept.vecs.clear();
  PetscCall(VecDestroy(&c->kept.U));
  PetscCall(ISDestroy(&c->kept.is_q));
  PetscCall(ISDestroy(&c->kept.is_p));
  c->kept.adopted = false;
  PetscFunctionReturn(0);
}

} // namespace fdem::ts

using namespace fdem::ts;

PetscErrorCode FDEMTSSetNonFiniteReport(TS ts, FDEMNonFiniteFn fn, void *ctx) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscCall(ComposeLink(ts, "FDEMTSNonFinite", NonFiniteLink{fn, ctx}, fn == nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSSetDrift(TS ts, FDEMDriftFn drift, void *ctx) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscCall(ComposeLink(ts, "FDEMTSDrift", DriftLink{drift, ctx}, drift == nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSSetPositionRHSIdentity(TS ts, PetscBool flg) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscCall(ComposeLink(ts, "FDEMTSPositionRHSIdentity", IdentityLink{flg}, !flg));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSSetForceJacobianProduct(TS ts, FDEMJacobianProductFn jvp, void *ctx) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscCall(ComposeLink(ts, "FDEMTSJacobianProduct", JvpLink{jvp, ctx}, jvp == nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSSetGradientType(TS ts, FDEMGradientType type) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscTryMethod(ts, "FDEMTSSetGradientType_C", (TS, FDEMGradientType), (ts, type));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSGetSchemeInfo(TS ts, FDEMSchemeInfo *info) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscUseMethod(ts, "FDEMTSGetSchemeInfo_C", (TS, FDEMSchemeInfo *), (ts, info));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMTSGetForceEvaluations(TS ts, PetscInt *n) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscUseMethod(ts, "FDEMTSGetForceEvaluations_C", (TS, PetscInt *), (ts, n));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSchemeInfoFind(const char *name, PetscBool *found, FDEMSchemeInfo *info) {
  FDEMSchemeInfo tmp;
  PetscFunctionBegin;
  PetscCall(SchemeInfoLookup(name, &tmp, found));
  if (*found && info) *info = tmp;
  PetscFunctionReturn(0);
}

namespace fdem::ts {
PetscErrorCode ClearSchemeInfo() {
  PetscFunctionBegin;
  InfoTable().clear();
  PetscFunctionReturn(0);
}
} // namespace fdem::ts
