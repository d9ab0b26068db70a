// Internal: what every fdem TS type shares — access to the position/momentum
// splits, counted RHS evaluations, the drift, force-gradient terms, the
// start-up integrator, divergence checks and the end-of-step bookkeeping.
#pragma once
#include <fdem/ts.h>
#include <petsc/private/tsimpl.h>

namespace fdem::ts {

struct Common {
  FDEMSchemeInfo   info{};
  IS               is_q = nullptr, is_p = nullptr;
  TS               subts_q = nullptr, subts_p = nullptr;
  PetscInt         nforce = 0;
  FDEMGradientType gradient = FDEM_GRADIENT_DEFAULT;
  PetscBool        gradient_allowed[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE};
  PetscBool        uses_gradient = PETSC_FALSE; // scheme has gradient/tangent terms
  PetscReal        fd_delta = 6e-6;             // relative step of finite-difference derivatives
  PetscInt         check_interval = 10;         // steps between Inf/NaN checks (one pass over the state: ~30% of a cd step)
  PetscInt         steps_unchecked = 0;
  FDEMDriftFn      drift = nullptr;
  void            *drift_ctx = nullptr;
  FDEMJacobianProductFn jvp = nullptr;
  void            *jvp_ctx = nullptr;
  PetscBool        equal_sizes = PETSC_FALSE;
  Vec              q_work = nullptr, q_work2 = nullptr, U_work = nullptr;
  Vec              p_work = nullptr, p_work2 = nullptr;
};

// Looks up the fixed facts about a scheme by type name.
PetscErrorCode SchemeInfoLookup(const char *name, FDEMSchemeInfo *info, PetscBool *found);
PetscErrorCode RegisterSchemeInfo(const FDEMSchemeInfo &info);

PetscErrorCode CommonSetUp(TS ts, Common *c, PetscBool need_default_drift);
PetscErrorCode CommonReset(Common *c);
PetscErrorCode CommonSetFromOptions(TS ts, Common *c, PetscOptionItems *PetscOptionsObject);
PetscErrorCode CommonView(TS ts, Common *c, PetscViewer viewer);
// Registers FDEMTSGetSchemeInfo/... composed methods on ts (and removes them with on = false).
PetscErrorCode CommonCompose(TS ts, PetscBool on);

// F_p(t, q) -> f (momentum space); counted.
PetscErrorCode Force(TS ts, Common *c, PetscReal t, Vec q, Vec f);
// F_q(t, p) -> dq (position space).
PetscErrorCode Velocity(TS ts, Common *c, PetscReal t, Vec p, Vec dq);
// Drift the full state U by s (user drift or q += s F_q(p)). q, p: optional
// already-fetched subvectors of U for the default drift (else fetched here).
PetscErrorCode DriftDefault(TS ts, Common *c, PetscReal t, PetscReal s, Vec q, Vec p);
// F_p at the configuration reached from U by a drift of length s with the
// momenta replaced by a (x + s a(x) for translation). Result in f.
PetscErrorCode ShiftedForce(TS ts, Common *c, PetscReal t, Vec U, Vec q, Vec a, PetscReal s, Vec f);
// G = 2 (dF_p/dq) F_q(a) at q (the force-gradient term of chin/omf32).
PetscErrorCode ForceGradient(TS ts, Common *c, PetscReal t, Vec U, Vec q, Vec a, Vec G);
// JW = (dF_p/dq)(q) W for a position-space W (tangent terms of the Taylor schemes).
PetscErrorCode ForceDirectional(TS ts, Common *c, PetscReal t, Vec q, Vec W, Vec JW);
// Advances the full state U from t by H with n substeps of the 4th-order
// PEFRL splitting (used to start multistep and Gear schemes; H may be negative).
PetscErrorCode AdvanceAccurate(TS ts, Common *c, PetscReal t, PetscReal H, PetscInt n, Vec U);
// End of a step: Inf/NaN check, TSAdaptChoose (trims the last step under
// matchstep), advance ts->ptime. Returns PETSC_FALSE in *ok if the step failed.
PetscErrorCode FinishStep(TS ts, Common *c, PetscBool *ok);

// VecGetSubVector pairs on the solution.
struct Split {
  Vec U, q = nullptr, p = nullptr;
  IS  is_q, is_p;
  Split(Vec U_, Common *c) : U(U_), is_q(c->is_q), is_p(c->is_p) {}
  PetscErrorCode Get() {
    PetscFunctionBegin;
    PetscCall(VecGetSubVector(U, is_q, &q));
    PetscCall(VecGetSubVector(U, is_p, &p));
    PetscFunctionReturn(0);
  }
  PetscErrorCode Restore() {
    PetscFunctionBegin;
    if (q) PetscCall(VecRestoreSubVector(U, is_q, &q));
    if (p) PetscCall(VecRestoreSubVector(U, is_p, &p));
    q = p = nullptr;
    PetscFunctionReturn(0);
  }
};

PetscErrorCode RegisterSplittingTypes();
PetscErrorCode RegisterGearTypes();
PetscErrorCode RegisterTaylorTypes();
PetscErrorCode ClearSplittingRegistry();
PetscErrorCode ClearSchemeInfo();

} // namespace fdem::ts
