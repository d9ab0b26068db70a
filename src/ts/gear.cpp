// Gear predictor-corrector schemes PC-3, PC-4, PC-5 (Munjiza 5.108-5.110,
// Table 5.1) for second-order equations, in Nordsieck form.
//
// The history lives inside the TS as scaled derivatives. For a problem in
// momentum form (dq/dt = F_q(p) linear in p, dp/dt = F_p(q)) the entries of
// order k >= 1 are kept in momentum space, y_k = M h^k x^(k)/k!, so that no
// mass matrix is needed: y_1 = h p, y_2 = h^2 f/2, y_3 = h^3 f'/6, ...; the
// position entry is the solution's position split itself.
//
// Start-up: at the first step (and whenever the solution was changed from
// outside, or the step changed beyond a rescaling), the forces at t0-2h,
// t0-h, t0+h, t0+2h are computed by the 4th-order PEFRL splitting with
// -ts_pcN_startup_substeps substeps per h, and f', f'', f''' at t0 come from
// 5-point central differences: enough for the scaled derivatives to be exact
// to O(h^7). A change of h alone rescales the history (y_k *= (h_new/h)^k).
#include "fdemts.hpp"

#include <fdem/kernels/schemes.hpp>

#include <array>
#include <cmath>

namespace fdem::ts {
namespace {

struct TS_Gear : Common {
  PetscInt                 nq = 3; // highest derivative carried
  std::array<PetscReal, 6> alpha{};
  std::array<Vec, 6>       y{};    // y[1..nq] in momentum space
  Vec                      f = nullptr, delta = nullptr, sum = nullptr;
  PetscInt                 startup_substeps = 32;
  PetscBool                started = PETSC_FALSE;
  PetscObjectState         state = 0;
  PetscReal                t_hist = 0, h_hist = 0;
  PetscInt                 starts = 0, resumes = 0;
};
TS_Gear *Data(TS ts) { return static_cast<TS_Gear *>(static_cast<Common *>(ts->data)); }
// The Nordsieck vector in momentum space: what a restart would rebuild.
std::vector<Vec *> History(TS_Gear *G) {
  std::vector<Vec *> v;
  for (PetscInt k = 1; k <= G->nq; ++k) v.push_back(&G->y[k]);
  return v;
}

PetscErrorCode GearStart(TS ts, TS_Gear *G, PetscReal h) {
  const PetscReal t0 = ts->ptime;
  Vec             fj[5];
  Split           X(ts->vec_sol, G);
  PetscFunctionBegin;
  for (auto &v : fj) PetscCall(VecDuplicate(G->f, &v));
  PetscCall(X.Get());
  PetscCall(Force(ts, G, t0, X.q, fj[2]));
  PetscCall(VecCopy(X.p, G->y[1]));
  PetscCall(X.Restore());
  PetscCall(VecScale(G->y[1], h));
  for (int j = -2; j <= 2; ++j) {
    if (!j) continue;
    Split W(G->U_work, G);
    PetscCall(VecCopy(ts->vec_sol, G->U_work));
    PetscCall(AdvanceAccurate(ts, G, t0, j * h, G->startup_substeps * PetscAbsInt(j), G->U_work));
    PetscCall(W.Get());
    PetscCall(Force(ts, G, t0 + j * h, W.q, fj[j + 2]));
    PetscCall(W.Restore());
  }
  // y_2 = h^2/2 f ; y_3 = h^3/6 f' ; y_4 = h^4/24 f'' ; y_5 = h^5/120 f'''
  PetscCall(VecAXPBY(G->y[2], h * h / 2, 0.0, fj[2]));
  {
    PetscScalar a3[4] = {1, -8, 8, -1}; // f' = (f-2 - 8 f-1 + 8 f1 - f2)/(12 h)
    Vec         v4[4] = {fj[0], fj[1], fj[3], fj[4]};
    PetscCall(VecSet(G->y[3], 0));
    PetscCall(VecMAXPY(G->y[3], 4, a3, v4));
    PetscCall(VecScale(G->y[3], h * h * h / 6 / (12 * h)));
  }
  if (G->nq >= 4) {
    PetscScalar a4[5] = {-1, 16, -30, 16, -1}; // f'' = (...)/(12 h^2)
    PetscCall(VecSet(G->y[4], 0));
    PetscCall(VecMAXPY(G->y[4], 5, a4, fj));
    PetscCall(VecScale(G->y[4], h * h / 24 / 12));
  }
  if (G->nq >= 5) {
    PetscScalar a5[4] = {-1, 2, -2, 1}; // f''' = (-f-2 + 2 f-1 - 2 f1 + f2)/(2 h^3)
    Vec         v4[4] = {fj[0], fj[1], fj[3], fj[4]};
    PetscCall(VecSet(G->y[5], 0));
    PetscCall(VecMAXPY(G->y[5], 4, a5, v4));
    PetscCall(VecScale(G->y[5], h * h / 120 / 2));
  }
  for (auto &v : fj) PetscCall(VecDestroy(&v));
  G->started = PETSC_TRUE;
  G->h_hist  = h;
  G->starts++;
  PetscFunctionReturn(0);
}

PetscErrorCode TSStep_Gear(TS ts) {
  TS_Gear         *G = Data(ts);
  const PetscReal  h = ts->time_step, t0 = ts->ptime;
  const PetscInt   nq = G->nq;
  PetscObjectState state;
  PetscBool        ok;
  Split            X(ts->vec_sol, G);

  PetscFunctionBegin;
  PetscCall(BeginStep(ts, G));
  PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &state));
  {
    PetscReal t_kept, h_kept;
    PetscBool resume;
    PetscCall(ResumeHistory(ts, G, &t_kept, &h_kept, &resume));
    if (resume && t_kept == t0) { // the history kept across TSReset belongs to this state
      G->started = PETSC_TRUE;
      G->state   = state;
      G->t_hist  = t_kept;
      G->h_hist  = h_kept;
      G->resumes++;
    }
  }
  if (!G->started || state != G->state || t0 != G->t_hist) PetscCall(GearStart(ts, G, h));
  else if (h != G->h_hist) {
    PetscReal r = h / G->h_hist, s = 1;
    for (PetscInt k = 1; k <= nq; ++k) {
      s *= r;
      PetscCall(VecScale(G->y[k], s));
    }
    G->h_hist = h;
  }
  PetscCall(TSPreStage(ts, t0 + h));
  PetscCall(X.Get());
  // (a) prediction: x += F_q(y_1 + ... + y_nq); y_k = sum_{j>=k} C(j,k) y_j
  PetscCall(VecCopy(G->y[1], G->sum));
  for (PetscInt k = 2; k <= nq; ++k) PetscCall(VecAXPY(G->sum, 1.0, G->y[k]));
  PetscCall(Velocity(ts, G, t0, G->sum, G->q_work));
  PetscCall(VecAXPY(X.q, 1.0, G->q_work));
  for (PetscInt i = 0; i < nq; ++i)
    for (PetscInt j = nq; j > i; --j)
      if (j - 1 >= 1) PetscCall(VecAXPY(G->y[j - 1], 1.0, G->y[j]));
  // (b) evaluation: delta = h^2/2 f(x_pred) - y_2,pred   (5.109, times M h^2/2)
  PetscCall(Force(ts, G, t0 + h, X.q, G->f));
  PetscCall(VecAXPBY(G->delta, h * h / 2, 0.0, G->f));
  PetscCall(VecAXPY(G->delta, -1.0, G->y[2]));
  // (c) correction (5.110)
  PetscCall(Velocity(ts, G, t0 + h, G->delta, G->q_work));
  PetscCall(VecAXPY(X.q, G->alpha[0], G->q_work));
  for (PetscInt k = 1; k <= nq; ++k) PetscCall(VecAXPY(G->y[k], G->alpha[k], G->delta));
  PetscCall(VecAXPBY(X.p, 1.0 / h, 0.0, G->y[1]));
  PetscCall(X.Restore());
  Vec Ustage = ts->vec_sol;
  PetscCall(TSPostStage(ts, t0 + h, 0, &Ustage));
  PetscCall(FinishStep(ts, G, &ok));
  if (ok) {
    PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &G->state));
    G->t_hist = ts->ptime;
  } else G->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetUp_Gear(TS ts) {
  TS_Gear *G = Data(ts);
  PetscFunctionBegin;
  PetscCall(CommonSetUp(ts, G, PETSC_TRUE));
  for (PetscInt k = 1; k <= G->nq; ++k) PetscCall(VecDuplicate(G->p_work, &G->y[k]));
  PetscCall(VecDuplicate(G->p_work, &G->f));
  PetscCall(VecDuplicate(G->p_work, &G->delta));
  PetscCall(VecDuplicate(G->p_work, &G->sum));
  PetscCall(AdoptHistory(ts, G, History(G)));
  G->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSReset_Gear(TS ts) {
  TS_Gear         *G = Data(ts);
  PetscObjectState state = 0;
  PetscFunctionBegin;
  if (ts->vec_sol) PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &state));
  // keep the history for a set-up with the same splits (PETSc's re-set-up pattern)
  if (G->started && ts->vec_sol && state == G->state && ts->ptime == G->t_hist) PetscCall(KeepHistory(ts, G, History(G), G->t_hist, G->h_hist));
  PetscCall(CommonReset(G));
  for (auto &v : G->y) PetscCall(VecDestroy(&v));
  PetscCall(VecDestroy(&G->f));
  PetscCall(VecDestroy(&G->delta));
  PetscCall(VecDestroy(&G->sum));
  G->started = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSDestroy_Gear(TS ts) {
  TS_Gear *G = Data(ts);
  PetscFunctionBegin;
  PetscCall(TSReset_Gear(ts));
  PetscCall(DropHistory(G));
  PetscCall(CommonCompose(ts, PETSC_FALSE));
  delete Data(ts);
  ts->data = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetFromOptions_Gear(TS ts, PetscOptionItems *PetscOptionsObject) {
  TS_Gear *G = Data(ts);
  char     opt[256];
  PetscFunctionBegin;
  PetscCall(CommonSetFromOptions(ts, G, PetscOptionsObject));
  PetscOptionsHeadBegin(PetscOptionsObject, "fdem Gear predictor-corrector options");
  PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_startup_substeps", G->info.name));
  PetscCall(PetscOptionsInt(opt, "PEFRL substeps per step used to build the starting derivatives", "", G->startup_substeps, &G->startup_substeps, nullptr));
  PetscCheck(G->startup_substeps >= 1, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_OUTOFRANGE, "%s must be >= 1", opt);
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode TSView_Gear(TS ts, PetscViewer viewer) {
  TS_Gear  *G = Data(ts);
  PetscBool iascii;
  PetscFunctionBegin;
  PetscCall(CommonView(ts, G, viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (iascii) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "  Gear corrector (Table 5.1):"));
    for (PetscInt k = 0; k <= G->nq; ++k) PetscCall(PetscViewerASCIIPrintf(viewer, " a%" PetscInt_FMT "=%.6g", k, (double)G->alpha[k]));
    PetscCall(PetscViewerASCIIPrintf(viewer, "\n  start-up: PEFRL with %" PetscInt_FMT " substeps per step (%" PetscInt_FMT " starts so far; history kept across %" PetscInt_FMT " TSReset/TSSetUp with the same splits and state)\n",
                                     G->startup_substeps, G->starts, G->resumes));
  }
  PetscFunctionReturn(0);
}

template <int NQ>
PetscErrorCode TSCreate_Gear(TS ts) {
  PetscFunctionBegin;
  TS_Gear *G = new (std::nothrow) TS_Gear();
  PetscCheck(G, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  G->nq = NQ;
  if (NQ == 3) G->alpha = {1.0 / 6, 5.0 / 6, 1, 1.0 / 3, 0, 0};
  if (NQ == 4) G->alpha = {19.0 / 120, 3.0 / 4, 1, 1.0 / 2, 1.0 / 12, 0};
  if (NQ == 5) G->alpha = {3.0 / 16, 251.0 / 360, 1, 11.0 / 18, 1.0 / 6, 1.0 / 60};
  const char *name = NQ == 3 ? TSFDEMPC3 : (NQ == 4 ? TSFDEMPC4 : TSFDEMPC5);
  PetscBool   found;
  PetscCall(SchemeInfoLookup(name, &G->info, &found));
  ts->data                = static_cast<Common *>(G);
  ts->ops->step           = TSStep_Gear;
  ts->ops->setup          = TSSetUp_Gear;
  ts->ops->reset          = TSReset_Gear;
  ts->ops->destroy        = TSDestroy_Gear;
  ts->ops->setfromoptions = TSSetFromOptions_Gear;
  ts->ops->view           = TSView_Gear;
  ts->default_adapt_type  = TSADAPTNONE;
  PetscCall(CommonCompose(ts, PETSC_TRUE));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RegisterGearTypes() {
  PetscFunctionBegin;
  // order: the global order measured on a nonlinear problem (tests/ts/test_order); kcrit: the exact
  // spectral-radius limit (kernels/schemes.cpp). PC-4 grows at every h > 0 (rho - 1 < 1e-12 below
  // omega h = 0.017, 5e-7 at the book's 0.155), so its exact limit is 0.
  using fdem::kernels::SchemeKcrit;
  FDEMSchemeInfo pc3{TSFDEMPC3, "Gear predictor-corrector PC-3 (5.108-5.110, Table 5.1)", 3, 1, 1, 0, SchemeKcrit(TSFDEMPC3), 1.417};
  FDEMSchemeInfo pc4{TSFDEMPC4, "Gear predictor-corrector PC-4 (5.108-5.110, Table 5.1)", 4, 1, 1, 0, SchemeKcrit(TSFDEMPC4), 0.155};
  FDEMSchemeInfo pc5{TSFDEMPC5, "Gear predictor-corrector PC-5 (5.108-5.110, Table 5.1)", 5, 1, 1, 0, SchemeKcrit(TSFDEMPC5), 0.3204};
  PetscCall(RegisterSchemeInfo(pc3));
  PetscCall(RegisterSchemeInfo(pc4));
  PetscCall(RegisterSchemeInfo(pc5));
  PetscCall(TSRegister(TSFDEMPC3, TSCreate_Gear<3>));
  PetscCall(TSRegister(TSFDEMPC4, TSCreate_Gear<4>));
  PetscCall(TSRegister(TSFDEMPC5, TSCreate_Gear<5>));
  PetscFunctionReturn(0);
}

} // namespace fdem::ts
