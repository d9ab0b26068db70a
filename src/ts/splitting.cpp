// The splitting schemes: one kick/drift stepping engine driven by coefficient
// tables (doc/architecture.md, "The splitting contract").
//   kick(c h):  p += c h F_p(q)            [+ xi h^3 G, G = 2 (da/dx) a, for force-gradient kicks]
//   drift(c h): q += c h F_q(p)            (or the problem's own drift)
// A scheme that starts and ends with a kick reuses the last force of a step as
// the first of the next (first-same-as-last) while the solution is untouched.
#include "fdemts.hpp"

#include <fdem/kernels/schemes.hpp>

#include <cmath>
#include <string>
#include <deque>
#include <vector>

namespace fdem::ts {
namespace {

struct Op {
  char      kind; // 'K' or 'D'
  PetscReal c;    // fraction of h
  PetscReal xi;   // force-gradient coefficient (kicks)
};
struct Scheme {
  FDEMSchemeInfo  info;
  std::string     name, description;
  std::vector<Op> ops;
  bool            fsal = false;
  size_t          last_kick = 0, last_drift = 0; // the ops that write the step's final p and q
};
std::deque<Scheme> &Schemes() {
  static std::deque<Scheme> list; // a deque: registered schemes never move
  return list;
}

struct TS_Splitting : Common {
  const Scheme    *scheme = nullptr;
  Vec              a = nullptr, a_next = nullptr, G = nullptr;
  PetscBool        use_fsal = PETSC_TRUE;
  PetscBool        cache_valid = PETSC_FALSE;
  PetscObjectState cache_state = 0;
  PetscReal        cache_time = 0;
};

TS_Splitting *Data(TS ts) { return static_cast<TS_Splitting *>(static_cast<Common *>(ts->data)); }

PetscErrorCode TSStep_Splitting(TS ts) {
  TS_Splitting    *S = Data(ts);
  const Scheme    &sch = *S->scheme;
  const PetscReal  h = ts->time_step, t0 = ts->ptime;
  PetscReal        t = t0;
  const size_t     nops = sch.ops.size();
  PetscObjectState state;
  PetscBool        ok;
  Split            X(ts->vec_sol, S);

  PetscFunctionBegin;
  PetscCall(BeginStep(ts, S));
  PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &state));
  const PetscBool reuse = (PetscBool)(S->use_fsal && sch.fsal && S->cache_valid && state == S->cache_state && t0 == S->cache_time);
  PetscCall(X.Get());
  for (size_t i = 0; i < nops; ++i) {
    const Op &op = sch.ops[i];
    if (op.kind == 'D') {
      if (S->drift) {
        PetscCall(X.Restore());
        PetscCall(S->drift(ts, t, op.c * h, ts->vec_sol, S->drift_ctx));
        PetscCall(X.Get());
      } else PetscCall(DriftDefault(ts, S, t, op.c * h, X.q, X.p, (PetscBool)(i == sch.last_drift)));
      t += op.c * h;
      continue;
    }
    PetscCall(TSPreStage(ts, t));
    if (!(i == 0 && reuse)) PetscCall(Force(ts, S, t, X.q, S->a));
    if (op.xi == 0 && i == sch.last_kick) {
      PetscCall(AXPYScan(S, X.p, op.c * h, S->a));
      S->scanned_p = S->check_step;
    } else if (op.xi == 0) PetscCall(VecAXPY(X.p, op.c * h, S->a));
    else if (S->gradient == FDEM_GRADIENT_SHIFTED) {
      // c h a(x + (2 xi h^2 / c) a(x)) equals c h a + xi h^3 G to the scheme's order
      PetscCall(ShiftedForce(ts, S, t, ts->vec_sol, X.q, S->a, 2 * op.xi * h * h / op.c, S->G));
      PetscCall(VecAXPY(X.p, op.c * h, S->G));
    } else {
      if (S->drift) PetscCall(X.Restore()); // the drifted copy needs the whole state
      PetscCall(ForceGradient(ts, S, t, ts->vec_sol, X.q, S->a, S->G));
      if (S->drift) PetscCall(X.Get());
      PetscCall(VecAXPBYPCZ(X.p, op.c * h, op.xi * h * h * h, 1.0, S->a, S->G));
    }
    Vec Ustage = ts->vec_sol;
    PetscCall(TSPostStage(ts, t, (PetscInt)i, &Ustage));
  }
  PetscCall(X.Restore());
  PetscCall(FinishStep(ts, S, &ok));
  if (ok && sch.fsal) {
    // the last kick's force was evaluated at the final positions
    PetscCall(PetscObjectStateGet((PetscObject)ts->vec_sol, &S->cache_state));
    S->cache_time  = ts->ptime;
    S->cache_valid = PETSC_TRUE;
  } else S->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetUp_Splitting(TS ts) {
  TS_Splitting *S = Data(ts);
  PetscFunctionBegin;
  PetscCall(CommonSetUp(ts, S, PETSC_FALSE));
  PetscCall(VecDuplicate(S->p_work, &S->a));
  PetscCall(VecDuplicate(S->p_work, &S->G));
  S->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSReset_Splitting(TS ts) {
  TS_Splitting *S = Data(ts);
  PetscFunctionBegin;
  PetscCall(CommonReset(S));
  PetscCall(VecDestroy(&S->a));
  PetscCall(VecDestroy(&S->G));
  S->cache_valid = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode TSDestroy_Splitting(TS ts) {
  PetscFunctionBegin;
  PetscCall(TSReset_Splitting(ts));
  PetscCall(CommonCompose(ts, PETSC_FALSE));
  delete Data(ts);
  ts->data = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode TSSetFromOptions_Splitting(TS ts, PetscOptionItems *PetscOptionsObject) {
  TS_Splitting *S = Data(ts);
  char          opt[256];
  PetscFunctionBegin;
  PetscCall(CommonSetFromOptions(ts, S, PetscOptionsObject));
  if (S->scheme->fsal) {
    PetscOptionsHeadBegin(PetscOptionsObject, "fdem splitting scheme options");
    PetscCall(PetscSNPrintf(opt, sizeof(opt), "-ts_%s_fsal", S->info.name));
    PetscCall(PetscOptionsBool(opt, "Reuse the last force of a step as the first of the next while the solution is untouched", "", S->use_fsal, &S->use_fsal, nullptr));
    PetscOptionsHeadEnd();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode TSView_Splitting(TS ts, PetscViewer viewer) {
  TS_Splitting *S = Data(ts);
  PetscBool     iascii;
  PetscFunctionBegin;
  PetscCall(CommonView(ts, S, viewer));
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &iascii));
  if (iascii) {
    std::string seq;
    for (auto &op : S->scheme->ops) {
      char buf[64];
      PetscCall(PetscSNPrintf(buf, sizeof(buf), "%s%c(%.6g%s)", seq.empty() ? "" : " ", op.kind, (double)op.c, op.xi != 0 ? "+grad" : ""));
      seq += buf;
    }
    PetscCall(PetscViewerASCIIPrintf(viewer, "  kick/drift sequence: %s; first-same-as-last: %s\n", seq.c_str(), S->scheme->fsal && S->use_fsal ? "yes" : "no"));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode TSCreate_Splitting(TS ts) {
  const char   *name = ((PetscObject)ts)->type_name;
  const Scheme *found = nullptr;
  PetscFunctionBegin;
  for (auto &s : Schemes())
    if (name && s.name == name) found = &s;
  PetscCheck(found, PetscObjectComm((PetscObject)ts), PETSC_ERR_ARG_UNKNOWN_TYPE, "No fdem splitting scheme named %s", name ? name : "(null)");
  TS_Splitting *S = new (std::nothrow) TS_Splitting();
  PetscCheck(S, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  S->scheme        = found;
  S->info          = found->info;
  S->uses_gradient = (PetscBool)(found->info.gradients > 0);
  S->gradient_allowed[FDEM_GRADIENT_SHIFTED] = S->uses_gradient;
  S->gradient      = S->uses_gradient ? FDEM_GRADIENT_SHIFTED : FDEM_GRADIENT_FD;
  ts->data         = static_cast<Common *>(S);
  ts->ops->step           = TSStep_Splitting;
  ts->ops->setup          = TSSetUp_Splitting;
  ts->ops->reset          = TSReset_Splitting;
  ts->ops->destroy        = TSDestroy_Splitting;
  ts->ops->setfromoptions = TSSetFromOptions_Splitting;
  ts->ops->view           = TSView_Splitting;
  ts->default_adapt_type  = TSADAPTNONE;
  PetscCall(CommonCompose(ts, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode Add(const char *name, const char *desc, PetscInt order, const char *ops, std::vector<PetscReal> coef, std::vector<PetscReal> grad, PetscReal kcrit, PetscReal kbook) {
  Scheme  s;
  size_t  n = std::string(ops).size();
  PetscInt kicks = 0, grads = 0;
  PetscReal sum[2] = {0, 0};
  PetscFunctionBegin;
  PetscCheck(coef.size() >= n, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "Splitting scheme %s: %zu ops but %zu coefficients", name, n, coef.size());
  s.name = name;
  s.description = desc;
  for (size_t i = 0; i < n; ++i) {
    const char k = ops[i];
    PetscCheck(k == 'K' || k == 'D', PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Splitting scheme %s: op %zu is '%c'; use K (kick) or D (drift)", name, i, k);
    const PetscReal xi = (k == 'K' && i < grad.size()) ? grad[i] : 0;
    s.ops.push_back({k, coef[i], xi});
    sum[k == 'K'] += coef[i];
    if (k == 'K') kicks++;
    (k == 'K' ? s.last_kick : s.last_drift) = i;
    if (xi != 0) grads++;
  }
  PetscCheck(std::fabs(sum[0] - 1) < 1e-12 && std::fabs(sum[1] - 1) < 1e-12, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "Splitting scheme %s: drift coefficients sum to %g and kick coefficients to %g; both must sum to 1", name, (double)sum[0], (double)sum[1]);
  s.fsal = n > 1 && s.ops.front().kind == 'K' && s.ops.back().kind == 'K' && s.ops.back().xi == 0;
  s.info.order = order;
  s.info.stages = kicks;
  s.info.evals = kicks - (s.fsal ? 1 : 0);
  s.info.gradients = grads;
  s.info.kcrit = kcrit;
  s.info.kcrit_book = kbook;
  for (auto &x : Schemes())
    PetscCheck(x.name != name, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "A splitting scheme named %s is already registered", name);
  Schemes().push_back(s);
  // the strings live in the list now (a deque: its elements never move)
  Scheme &stored = Schemes().back();
  stored.info.name = stored.name.c_str();
  stored.info.description = stored.description.c_str();
  PetscCall(RegisterSchemeInfo(stored.info));
  PetscCall(TSRegister(name, TSCreate_Splitting));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RegisterSplittingTypes() {
  PetscFunctionBegin;
  for (const auto &tab : fdem::kernels::BuiltinSplittingTables())
    PetscCall(Add(tab.name, tab.description, tab.order, tab.ops.c_str(), tab.coef, tab.grad, tab.kcrit, tab.kcrit_book));
  PetscFunctionReturn(0);
}

} // namespace fdem::ts

PetscErrorCode FDEMTSRegisterSplitting(const char *name, const char *description, PetscInt order, const char *ops, const PetscReal coef[], const PetscReal grad[], PetscReal kcrit, PetscReal kcrit_book) {
  PetscFunctionBegin;
  PetscValidCharPointer(name, 1);
  PetscValidCharPointer(ops, 4);
  const size_t           n = std::string(ops).size();
  std::vector<PetscReal> c(coef, coef + n), g;
  if (grad) g.assign(grad, grad + n);
  PetscCall(fdem::ts::Add(name, description ? description : name, order, ops, c, g, kcrit, kcrit_book));
  PetscFunctionReturn(0);
}

namespace fdem::ts {
PetscErrorCode ClearSplittingRegistry() {
  PetscFunctionBegin;
  Schemes().clear();
  PetscFunctionReturn(0);
}
} // namespace fdem::ts
