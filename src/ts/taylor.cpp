// The Taylor-type schemes T-1/12, T-1/6 and D-1/12 (Munjiza 5.102-5.107).
//
// The book writes them for one degree of freedom with the scalar tangent
// b~ = (1/m) df/dx. For many degrees of freedom b~ becomes the operator
// J = M^-1 (df/dx) and a division by (1 - c b~ h^2) becomes the solve
// (I - c h^2 J) y = r. J is applied through directional derivatives of the
// momentum RHS (a user Jacobian-vector product, or central finite differences:
// -ts_<type>_gradient jvp|fd) and the solve is a fixed-point iteration
// y <- r + c h^2 J y, which converges while c (omega h)^2 < 1, i.e. beyond each
// scheme's stability limit; it is iterated to -ts_<type>_tangent_rtol (or
// -ts_<type>_tangent_max_it iterations) so the scheme is the book's exactly.
//
// The problem may be in momentum form: with v = F_q(p) (linear in p) the
// formulas are applied to M v = p and M a = f, so no mass matrix is needed.
//
// T-1/12 and D-1/12 need f (and D-1/12 x) at t - h. They start themselves by
// one backward step of the 4th-order PEFRL splitting with
// -ts_<type>_startup_substeps substeps, at the first step and whenever the
// solution was changed from outside or the step size changed.
#include "fdemts.hpp"

#include <fdem/kernels/schemes.hpp>

#include <cmath>

namespace fdem::ts {
namespace {

enum class Kind { T112, T16, D112 };

struct TS_Taylor : Common {
  Kind             kind = Kind::T16;
  Vec              f = nullptr, f_old = nullptr, f_new = nullptr, x_old = nullptr;
  Vec              pa = nullptr, pb = nullptr, pz = nullptr, pr = nullptr, qa = nullptr, qb = nullptr, qz = nullptr, qr = nullptr;
  PetscInt         startup_substeps = 32, tangent_max_it = 1000, tangent_its = 0, starts = 0, resumes = 0;
  char             failure[512] = "";
  PetscReal        tangent_rtol = 1e-13;
  PetscBool        started = PETSC_FALSE;
  PetscObjectState state = 0;
  PetscReal        t_hist = 0, h_hist = 0;
};
TS_Taylor *Data(TS ts) { return static_cast<TS_Taylor *>(static_cast<Common *>(ts->data)); }
// What a restart would rebuild: f at t, and f and x at t - h.
std::vector<Vec *> History(TS_Taylor *T) { return {&T->f, &T->f_old, &T->x_old}; }

// y = (I - c h^2 J)^-1 r at positions x, J = M^-1 df/dx (q space) or (df/dx) M^-1 (p space).
PetscErrorCode TangentSolve(TS ts, TS_Taylor *T, PetscReal t, Vec x, PetscReal ch2, Vec r, Vec y, bool pspace, PetscBool *ok) {
  Vec       Jy = pspace ? T->pa : T->qa, z = pspace ? T->pz : T->qz;
  PetscReal prev = PETSC_MAX_REAL, first = PETSC_MAX_REAL;
  PetscFunctionBegin;
  *ok = PETSC_TRUE;
  PetscCall(VecCopy(r, y));
  for (PetscInt it = 1;; ++it) {
    if (pspace) {
      PetscCall(Velocity(ts, T, t, y, T->qb));
      PetscCall(ForceDirectional(ts, T, t, x, T->qb, Jy));
    } else {
      PetscCall(ForceDirectional(ts, T, t, x, y, T->pb));
      PetscCall(Velocity(ts, T, t, T->pb, Jy));
    }
    PetscCall(VecWAXPY(z, ch2, Jy, r));
    PetscReal diff, nz;
    PetscCall(VecAXPY(y, -1.0, z)); // y - z
    PetscCall(VecNorm(y, NORM_INFINITY, &diff));
    PetscCall(VecNorm(z, NORM_INFINITY, &nz));
    PetscCall(VecCopy(z, y));
    T->tangent_its++;
    if (diff <= T->tangent_rtol * nz || it >= T->tangent_max_it) break;
    if (it > 1 && diff >= prev && diff <= 1e-7 * nz) break; // at the floor set by round-off and finite differences
    if (it == 1) first = diff;
    if (!(diff <= 1e3 * first)) { // diverging (or Inf/NaN): the step fails (StepFailed, once the state is released)
      char kc[64];
      PetscCall(PetscSNPrintf(T->failure, sizeof(T->failure), "-ts_type %s: the tangent solve (I - c h^2 J) y = r diverges at t = %g: h = %g is beyond the scheme's stability limit omega*h < K_crit = %s; reduce -ts_dt",
                              T->info.name, (double)t, (double)ts->time_step, KcritText(T, kc, sizeof(kc))));
      *ok = PETSC_FALSE;
      PetscFunctionReturn(0);
    }
    prev = diff;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode TaylorStart(TS ts, TS_Taylor *T, PetscReal h) {
  const PetscReal t0 = ts->ptime;
  Split           X(ts->vec_sol, T);
  PetscFunctionBegin;
  PetscCall(X.Get());
  PetscCall(Force(ts, T, t0, X.q, T->f));
  PetscCall(X.Restore());
  if (T->kind != Kind::T16) {
    Split W(T->U_work, T);
    PetscCall(VecCopy(ts->vec_sol, T->U_work));
    PetscCall(AdvanceAccurate(ts, T, t0, -h, T->startup_substeps, T->U_work));
    PetscCall(W.Get());
    PetscCall(Force(ts, T, t0 - h, W.q, T->f_old));
    PetscCall(VecCopy(W.q, T->x_old));
    PetscCall(W.Restore());
  }
  T->started = PETSC_TRUE;
  T->h_hist  = h;
  T->starts++;
  PetscFunctionReturn(0);
}

PetscErrorCode TSStep_Taylor(TS ts) {
  TS_Taylor       *T = Data(ts);
  const PetscReal  h = ts->time_step, t0 = ts->ptime;
  PetscObjectState state;
  PetscBool        ok;
  Split            X(ts->vec_sol, T);

  PetscFunctionBegin;
  PetscCall(BeginStep(ts, T));
  PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &state));
  {
    PetscReal t_kept, h_kept;
    PetscBool resume;
    PetscCall(ResumeHistory(ts, T, &t_kept, &h_kept, &resume));
    if (resume && t_kept == t0 && h_kept == h) { // the history kept across TSReset belongs to this state
      T->started = PETSC_TRUE;
      T->state   = state;
      T->t_hist  = t_kept;
      T->h_hist  = h_kept;
      T->resumes++;
    }
  }
  if (!T->started || state != T->state || t0 != T->t_hist || h != T->h_hist) PetscCall(TaylorStart(ts, T, h));
  PetscCall(TSPreStage(ts, t0 + h));
  PetscCall(X.Get());
  if (T->kind == Kind::T16) {
    // x+ = x + F_q(h p + h^2/2 f + h^3/6 (df/dx) v)                                 (5.104)
    // p+ = (I - h^2/6 J+)^-1 [p + h f + h^2/3 (df/dx) v]                              (5.105)
    PetscCall(Velocity(ts, T, t0, X.p, T->qz));
    PetscCall(ForceDirectional(ts, T, t0, X.q, T->qz, T->pz)); // pz = (df/dx) v
    PetscCall(VecCopy(X.p, T->pb));
    PetscCall(VecAXPBYPCZ(T->pb, h * h / 2, h * h * h / 6, h, T->f, T->pz)); // h p + h^2/2 f + h^3/6 Jv
    PetscCall(Velocity(ts, T, t0, T->pb, T->qa));
    PetscCall(VecAXPY(X.q, 1.0, T->qa));
    PetscCall(VecAXPBYPCZ(X.p, h, h * h / 3, 1.0, T->f, T->pz)); // r = p + h f + h^2/3 Jv (in X.p)
    PetscCall(Force(ts, T, t0 + h, X.q, T->f_new));
    PetscCall(VecCopy(X.p, T->pr));
    PetscCall(TangentSolve(ts, T, t0 + h, X.q, h * h / 6, T->pr, X.p, true, &ok));
  } else {
    // r = F_q(h p + h^2/12 (7 f - f_old))              (T-1/12, 5.102)
    // r = x - x_old + F_q(h p + h^2/2 f)              (D-1/12, 5.106; the book's "t^2" read as h^2)
    PetscCall(VecCopy(X.p, T->pb));
    if (T->kind == Kind::T112) PetscCall(VecAXPBYPCZ(T->pb, 7 * h * h / 12, -h * h / 12, h, T->f, T->f_old));
    else PetscCall(VecAXPBY(T->pb, h * h / 2, h, T->f));
    PetscCall(Velocity(ts, T, t0, T->pb, T->qr));
    if (T->kind == Kind::D112) {
      PetscCall(VecAXPY(T->qr, 1.0, X.q));
      PetscCall(VecAXPY(T->qr, -1.0, T->x_old));
    }
    PetscCall(TangentSolve(ts, T, t0, X.q, h * h / 12, T->qr, T->qb, false, &ok)); // qb = y
    if (T->kind == Kind::D112) {
      PetscCall(VecAXPY(T->qb, 1.0, T->x_old)); // x+ = x_old + y
      PetscCall(VecCopy(X.q, T->x_old));
      PetscCall(VecCopy(T->qb, X.q));
    } else PetscCall(VecAXPY(X.q, 1.0, T->qb));
    PetscCall(Force(ts, T, t0 + h, X.q, T->f_new));
    // p+ = p + h/12 (8 f + 5 f+ - f_old)               (5.103, 5.107)
    PetscCall(VecAXPBYPCZ(X.p, 8 * h / 12, 5 * h / 12, 1.0, T->f, T->f_new));
    PetscCall(VecAXPY(X.p, -h / 12, T->f_old));
    PetscCall(VecCopy(T->f, T->f_old));
  }
  PetscCall(VecCopy(T->f_new, T->f));
  PetscCall(X.Restore());
  if (!ok) {
    T->started = PETSC_FALSE;
    PetscCall(StepFailed(ts, T, T->failure));
    PetscFunctionReturn(0);
  }
  Vec Ustage = ts->vec_sol;
  PetscCall(TSPostStage(ts, t0 + h, 0, &Ustage));
  PetscCall(FinishStep(ts, T, &ok));
  if (ok) {
    PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &T->state));
    T->t_hist = ts->ptime;
  } else T->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetUp_Taylor(TS ts) {
  TS_Taylor *T = Data(ts);
  PetscFunctionBegin;
  PetscCall(CommonSetUp(ts, T, PETSC_TRUE));
  for (Vec *v : {&T->f, &T->f_old, &T->f_new, &T->pa, &T->pb, &T->pz, &T->pr}) PetscCall(VecDuplicate(T->p_work, v));
  for (Vec *v : {&T->x_old, &T->qa, &T->qb, &T->qz, &T->qr}) PetscCall(VecDuplicate(T->q_work, v));
  PetscCall(AdoptHistory(ts, T, History(T)));
  T->started     = PETSC_FALSE;
  T->tangent_its = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode TSReset_Taylor(TS ts) {
  TS_Taylor       *T = Data(ts);
  PetscObjectState state = 0;
  PetscFunctionBegin;
  if (ts->vec_sol) PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &state));
  // keep the history for a set-up with the same splits (PETSc's re-set-up pattern)
  if (T->started && ts->vec_sol && state == T->state && ts->ptime == T->t_hist) PetscCall(KeepHistory(ts, T, History(T), T->t_hist, T->h_hist));
  PetscCall(CommonReset(T));
  for (Vec *v : {&T->f, &T->f_old, &T->f_new, &T->pa, &T->pb, &T->pz, &T->pr, &T->x_old, &T->qa, &T->qb, &T->qz, &T->qr}) PetscCall(VecDestroy(v));
  T->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSDestroy_Taylor(TS ts) {
  TS_Taylor *T = Data(ts);
  PetscFunctionBegin;
  PetscCall(TSReset_Taylor(ts));
  PetscCall(DropHistory(T));
  PetscCall(CommonCompose(ts, PETSC_FALSE));
  delete Data(ts);
  ts->data = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetFromOptions_Taylor(TS ts, PetscOptionItems *PetscOptionsObject) {
  TS_Taylor *T = Data(ts);
  char       opt[256];
  PetscFunctionBegin;
  PetscCall(CommonSetFromOptions(ts, T, PetscOptionsObject));
  PetscOptionsHeadBegin(PetscOptionsObject, "fdem Taylor-type scheme options");
  PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_tangent_rtol", T->info.name));
  PetscCall(PetscOptionsReal(opt, "Relative tolerance of the fixed-point solve (I - c h^2 J) y = r", "", T->tangent_rtol, &T->tangent_rtol, nullptr));
  PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_tangent_max_it", T->info.name));
  PetscCall(PetscOptionsInt(opt, "Iteration limit of that solve (1 gives the explicit truncation y = r + c h^2 J r)", "", T->tangent_max_it, &T->tangent_max_it, nullptr));
  PetscCheck(T->tangent_max_it >= 1, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE, "%s must be >= 1", opt);
  if (T->kind != Kind::T16) {
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_startup_substeps", T->info.name));
    PetscCall(PetscOptionsInt(opt, "PEFRL substeps of the backward start-up step", "", T->startup_substeps, &T->startup_substeps, nullptr));
    PetscCheck(T->startup_substeps >= 1, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE, "%s must be >= 1", opt);
  }
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode TSView_Taylor(TS ts, PetscViewer viewer) {
  TS_Taylor *T = Data(ts);
  PetscBool  iascii;
  PetscFunctionBegin;
  PetscCall(CommonView(ts, T, viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (iascii)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  tangent solve: fixed point to rtol %g (at most %" PetscInt_FMT " its; %" PetscInt_FMT " its so far); starts %" PetscInt_FMT
                                     "; history kept across %" PetscInt_FMT " TSReset/TSSetUp with the same splits and state\n",
                                     (double)T->tangent_rtol, T->tangent_max_it, T->tangent_its, T->starts, T->resumes));
  PetscFunctionReturn(0);
}

template <Kind K>
PetscErrorCode TSCreate_Taylor(TS ts) {
  PetscFunctionBegin;
  TS_Taylor *T = new (std::nothrow) TS_Taylor();
  PetscCheck(T, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  T->kind = K;
  const char *name = K == Kind::T112 ? TSFDEMT112 : (K == Kind::T16 ? TSFDEMT16 : TSFDEMD112);
  PetscBool   found;
  PetscCall(SchemeInfoLookup(name, &T->info, &found));
  T->uses_gradient = PETSC_TRUE;
  T->gradient      = FDEM_GRADIENT_FD;
  T->gradient_allowed[FDEM_GRADIENT_SHIFTED] = PETSC_FALSE;
  ts->data                = static_cast<Common *>(T);
  ts->ops->step           = TSStep_Taylor;
  ts->ops->setup          = TSSetUp_Taylor;
  ts->ops->reset          = TSReset_Taylor;
  ts->ops->destroy        = TSDestroy_Taylor;
  ts->ops->setfromoptions = TSSetFromOptions_Taylor;
  ts->ops->view           = TSView_Taylor;
  ts->default_adapt_type  = TSADAPTNONE;
  PetscCall(CommonCompose(ts, PETSC_TRUE));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RegisterTaylorTypes() {
  PetscFunctionBegin;
  using fdem::kernels::SchemeKcrit;
  FDEMSchemeInfo t112{TSFDEMT112, "Taylor-type T-1/12 (5.102-5.103)", 3, 1, 1, 1, SchemeKcrit(TSFDEMT112), 2.450};
  FDEMSchemeInfo t16{TSFDEMT16, "Taylor-type T-1/6 (5.104-5.105)", 3, 1, 1, 2, SchemeKcrit(TSFDEMT16), 2.280};
  FDEMSchemeInfo d112{TSFDEMD112, "Taylor-type D-1/12 (5.106-5.107)", 3, 1, 1, 1, SchemeKcrit(TSFDEMD112), 2.450};
  PetscCall(RegisterSchemeInfo(t112));
  PetscCall(RegisterSchemeInfo(t16));
  PetscCall(RegisterSchemeInfo(d112));
  PetscCall(TSRegister(TSFDEMT112, TSCreate_Taylor<Kind::T112>));
  PetscCall(TSRegister(TSFDEMT16, TSCreate_Taylor<Kind::T16>));
  PetscCall(TSRegister(TSFDEMD112, TSCreate_Taylor<Kind::D112>));
  PetscFunctionReturn(0);
}

} // namespace fdem::ts
