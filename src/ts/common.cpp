// What every fdem TS type shares; see fdemts.hpp.
#include "fdemts.hpp"

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
  {
    Vec q, p;
    PetscCall(VecGetSubVector(ts->vec_sol, c->is_q, &q));
    PetscCall(VecGetSubVector(ts->vec_sol, c->is_p, &p));
    PetscCall(VecDuplicate(q, &c->q_work));
    PetscCall(VecDuplicate(q, &c->q_work2));
    PetscCall(VecDuplicate(p, &c->p_work));
    PetscCall(VecDuplicate(p, &c->p_work2));
    PetscCall(VecRestoreSubVector(ts->vec_sol, c->is_q, &q));
    PetscCall(VecRestoreSubVector(ts->vec_sol, c->is_p, &p));
    PetscCall(VecDuplicate(ts->vec_sol, &c->U_work));
  }
  PetscCall(TSGetAdapt(ts, &adapt));
  PetscCall(TSAdaptCandidatesClear(adapt));
  PetscCall(PetscObjectTypeCompare((PetscObject)adapt, TSADAPTNONE, &none));
  if (!((PetscObject)adapt)->type_name) PetscCall(TSAdaptSetType(adapt, TSADAPTNONE));
  else PetscCheck(none, comm, PETSC_ERR_SUP, "-ts_type %s takes fixed steps: use -ts_adapt_type none", c->info.name);
  c->nforce          = 0;
  c->steps_unchecked = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode CommonReset(Common *c) {
  PetscFunctionBegin;
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
    FDEMGradientType g = c->gradient;
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_gradient", c->info.name));
    PetscCall(PetscOptionsEnum(opt, "How the force-gradient / tangent terms are formed", "FDEMTSSetGradientType", FDEMGradientTypes, (PetscEnum)g, (PetscEnum *)&g, &flg));
    if (flg) PetscCall(SetGradientType_Common(ts, g));
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
  if (c->info.kcrit_book > 0) PetscCall(PetscViewerASCIIPrintf(viewer, "  stability limit K_crit = (omega h)_crit = %.4f (book Table 5.2: %.4f)\n", (double)c->info.kcrit, (double)c->info.kcrit_book));
  else PetscCall(PetscViewerASCIIPrintf(viewer, "  stability limit K_crit = (omega h)_crit = %.4f\n", (double)c->info.kcrit));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  momentum RHS evaluations so far: %" PetscInt_FMT "; Inf/NaN check every %" PetscInt_FMT " steps\n", c->nforce, c->check_interval));
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
  PetscCall(TSComputeRHSFunction(c->subts_q, t, p, dq));
  PetscFunctionReturn(0);
}

PetscErrorCode DriftDefault(TS ts, Common *c, PetscReal t, PetscReal s, Vec q, Vec p) {
  PetscFunctionBegin;
  PetscCall(Velocity(ts, c, t, p, c->q_work));
  PetscCall(VecAXPY(q, s, c->q_work));
  PetscFunctionReturn(0);
}

// Drift of the whole state vector U (user drift or default), fetching subvectors as needed.
static PetscErrorCode DriftState(TS ts, Common *c, PetscReal t, PetscReal s, Vec U) {
  PetscFunctionBegin;
  if (c->drift) PetscCall(c->drift(ts, t, s, U, c->drift_ctx));
  else {
    Split S(U, c);
    PetscCall(S.Get());
    PetscCall(DriftDefault(ts, c, t, s, S.q, S.p));
    PetscCall(S.Restore());
  }
  PetscFunctionReturn(0);
}

// Force at U_work = drift_s(U with momenta := a).
static PetscErrorCode ForceAtDriftedCopy(TS ts, Common *c, PetscReal t, Vec U, Vec a, PetscReal s, Vec f) {
  Vec q;
  PetscFunctionBegin;
  PetscCall(VecCopy(U, c->U_work));
  PetscCall(VecISCopy(c->U_work, c->is_p, SCATTER_FORWARD, a));
  PetscCall(c->drift(ts, t, s, c->U_work, c->drift_ctx));
  PetscCall(VecGetSubVector(c->U_work, c->is_q, &q));
  PetscCall(Force(ts, c, t, q, f));
  PetscCall(VecRestoreSubVector(c->U_work, c->is_q, &q));
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
    Vec qU;
    PetscCall(VecGetSubVector(U, c->is_q, &qU)); // q itself is not fetched here: U is whole
    PetscCall(VecNorm(qU, NORM_INFINITY, &nq));
    PetscCall(VecRestoreSubVector(U, c->is_q, &qU));
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

PetscErrorCode FinishStep(TS ts, Common *c, PetscBool *ok) {
  PetscReal next_h = ts->time_step;
  PetscBool accept = PETSC_TRUE;
  PetscBool last   = (PetscBool)(ts->ptime + ts->time_step >= ts->max_time - 1e-12 * PetscAbsReal(ts->max_time) || ts->steps + 1 >= ts->max_steps);

  PetscFunctionBegin;
  *ok = PETSC_TRUE;
  if (++c->steps_unchecked >= c->check_interval || last) {
    PetscReal nrm;
    c->steps_unchecked = 0;
    PetscCall(VecNorm(ts->vec_sol, NORM_INFINITY, &nrm));
    if (PetscIsInfOrNanReal(nrm)) {
      *ok = PETSC_FALSE;
      char msg[1024];
      PetscCall(PetscSNPrintf(msg, sizeof(msg),
                              "fdem -ts_type %s: the solution became Inf or NaN in step %" PetscInt_FMT " (t = %g, h = %g). The scheme is stable only for omega*h < K_crit = %.4f, omega being the highest natural "
                              "frequency of the problem: reduce the time step (-ts_dt)",
                              c->info.name, ts->steps + 1, (double)(ts->ptime + ts->time_step), (double)ts->time_step, (double)c->info.kcrit));
      PetscCheck(!ts->errorifstepfailed, PetscObjectComm((PetscObject)ts), PETSC_ERR_NOT_CONVERGED, "%s", msg);
      PetscCall(PetscPrintf(PetscObjectComm((PetscObject)ts), "%s\n", msg));
      ts->reason = TS_DIVERGED_STEP_REJECTED;
      PetscFunctionReturn(0);
    }
  }
  PetscCall(TSAdaptChoose(ts->adapt, ts, ts->time_step, nullptr, &next_h, &accept));
  ts->ptime += ts->time_step;
  ts->time_step = next_h;
  PetscFunctionReturn(0);
}

} // namespace fdem::ts

using namespace fdem::ts;

PetscErrorCode FDEMTSSetDrift(TS ts, FDEMDriftFn drift, void *ctx) {
  PetscFunctionBegin;
  PetscValidHeaderSpecific(ts, TS_CLASSID, 1);
  PetscCall(ComposeLink(ts, "FDEMTSDrift", DriftLink{drift, ctx}, drift == nullptr));
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
