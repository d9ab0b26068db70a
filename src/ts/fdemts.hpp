// Internal: what every fdem TS type shares — access to the position/momentum
// splits, counted RHS evaluations, the drift, force-gradient terms, the
// start-up integrator, divergence checks and the end-of-step bookkeeping.
#pragma once
#include <fdem/ts.h>
#include <petsc/private/tsimpl.h>

#include <vector>

namespace fdem::ts {

// Shells that show the position and momentum parts of a state vector without
// copying and without creating a Vec per use: when each split is one
// contiguous block of the state on every rank, the shells (created once at
// set-up) are pointed at the state's storage (VecPlaceArray). Otherwise a
// Split falls back to VecGetSubVector.
struct SubViews {
  Vec              q = nullptr, p = nullptr;
  PetscObjectState sq = 0, sp = 0; // shell states when placed: a write shows as a change
  bool             in_use = false;
};

// History a multistep scheme (Gear, Taylor) keeps across TSReset, for
// PETSc's re-set-up pattern (DMSwarm migration: TSReset between segments):
// the next set-up adopts it when the splits are the same, and the first step
// resumes from it when the state is bitwise the one the history belongs to.
struct KeptHistory {
  std::vector<Vec> vecs;
  Vec              U = nullptr;           // the state at the reset
  IS               is_q = nullptr, is_p = nullptr;
  PetscReal        t = 0, h = 0;
  bool             adopted = false;       // set-up took the vectors; the first step decides
};

struct Common {
  FDEMSchemeInfo   info{};
  IS               is_q = nullptr, is_p = nullptr;
  TS               subts_q = nullptr, subts_p = nullptr;
  PetscInt         nforce = 0;
  FDEMGradientType gradient = FDEM_GRADIENT_DEFAULT;
  PetscBool        gradient_allowed[3] = {PETSC_TRUE, PETSC_TRUE, PETSC_FALSE};
  PetscBool        uses_gradient = PETSC_FALSE; // scheme has gradient/tangent terms
  PetscReal        fd_delta = 6e-6;             // relative step of finite-difference derivatives
  PetscInt         check_interval = 10;         // steps between Inf/NaN checks
  PetscInt         steps_unchecked = 0;
  FDEMDriftFn      drift = nullptr;
  PetscBool        velocity_identity = PETSC_FALSE; // F_q(p) = p (FDEMTSSetPositionRHSIdentity)
  void            *drift_ctx = nullptr;
  FDEMJacobianProductFn jvp = nullptr;
  void            *jvp_ctx = nullptr;
  PetscBool        equal_sizes = PETSC_FALSE;
  Vec              q_work = nullptr, q_work2 = nullptr, U_work = nullptr;
  Vec              p_work = nullptr, p_work2 = nullptr;
  // sub-vector shells (see SubViews): local offsets of the splits in the state
  // (-1: not one contiguous block here, or a Vec type that cannot be shared)
  SubViews         views[3];
  PetscInt         off_q = -1, off_p = -1, n_local = -1;
  PetscBool        covers_all = PETSC_FALSE; // the splits hold every entry of the state
  // Inf/NaN check of this step (set by BeginStep); kernels that write the
  // final q (p) of a checked step and scan it on the way set scanned_q (_p)
  // and accumulate a non-finite value into scan (0 while all finite)
  PetscBool        check_step = PETSC_FALSE, scanned_q = PETSC_FALSE, scanned_p = PETSC_FALSE;
  PetscReal        scan = 0;
  // the last checked state (kept only with -ts_error_if_step_fails false)
  Vec              U_good = nullptr;
  PetscObjectId    good_of = 0;
  PetscReal        t_good = 0;
  PetscInt         steps_good = 0;
  KeptHistory      kept;
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
// last: the step's last drift (in a checked step it scans the new positions).
PetscErrorCode DriftDefault(TS ts, Common *c, PetscReal t, PetscReal s, Vec q, Vec p, PetscBool last);
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
// Start of a step: the step size must be positive and finite and the final
// time reached exactly (matchstep); decides whether this step is checked for
// Inf/NaN (c->check_step) and keeps the last good state when asked to.
PetscErrorCode BeginStep(TS ts, Common *c);
// y += a x; in a checked step also scans the result for Inf/NaN (into c->scan).
PetscErrorCode AXPYScan(Common *c, Vec y, PetscReal a, Vec x);
// A step that cannot be completed (Inf/NaN, a diverging inner solve): with
// -ts_error_if_step_fails (the default) an error with msg; otherwise msg is
// printed, the last checked state is put back and the step counted as rejected.
PetscErrorCode StepFailed(TS ts, Common *c, const char *msg);
// K_crit with enough digits for the messages.
const char *KcritText(const Common *c, char buf[], size_t n);
// History across TSReset (see KeptHistory). Keep: at reset, moves the
// vectors out of the scheme (each *v becomes null). Adopt: at set-up, moves
// them back when the splits are the same. Resume: at the first step, whether
// the state is the one the history belongs to (else the scheme restarts).
PetscErrorCode KeepHistory(TS ts, Common *c, const std::vector<Vec *> &vecs, PetscReal t, PetscReal h);
PetscErrorCode AdoptHistory(TS ts, Common *c, const std::vector<Vec *> &vecs);
PetscErrorCode ResumeHistory(TS ts, Common *c, PetscReal *t, PetscReal *h, PetscBool *resume);
PetscErrorCode DropHistory(Common *c);

// The position and momentum parts of a state U (ts->vec_sol or U_work):
// shells placed on U's storage when possible (nothing created), else
// VecGetSubVector. Released by Restore() or, on an error path, by the
// destructor.
class Split {
public:
  Vec q = nullptr, p = nullptr;
  Split(Vec U, Common *c) : U_(U), c_(c) {}
  Split(const Split &)            = delete;
  Split &operator=(const Split &) = delete;
  ~Split() {
    if (q) (void)Restore();
  }
  PetscErrorCode Get();
  PetscErrorCode Restore();

private:
  Vec       U_;
  Common   *c_;
  SubViews *v_ = nullptr;
};
PetscErrorCode RegisterSplittingTypes();
PetscErrorCode RegisterGearTypes();
PetscErrorCode RegisterTaylorTypes();
PetscErrorCode ClearSplittingRegistry();
PetscErrorCode ClearSchemeInfo();

} // namespace fdem::ts
