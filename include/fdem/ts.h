/* fdem time integration schemes as PETSc TS types.

   Every scheme takes the problem exactly as TSBASICSYMPLECTIC does:
     TSRHSSplitSetIS(ts, "position", is_q);  TSRHSSplitSetIS(ts, "momentum", is_p);
     TSRHSSplitSetRHSFunction(ts, "position", NULL, dq/dt = F_q(t, p), ctx);
     TSRHSSplitSetRHSFunction(ts, "momentum", NULL, dp/dt = F_p(t, q), ctx);
   and is selected with -ts_type NAME (after FDEMInitializePackage() or
   -dll_append libfdem.so). */
#ifndef FDEM_TS_H
#define FDEM_TS_H

#include <petscts.h>

#if defined(__cplusplus)
extern "C" {
#endif

/* Splitting schemes: one kick/drift engine driven by coefficient tables. */
#define TSFDEMCD    "cd"    /* central difference (Munjiza eqs 5.12-5.13), velocity reported at t */
#define TSFDEMPV    "pv"    /* position Verlet / leap-frog (5.101) */
#define TSFDEMCHIN  "chin"  /* Chin's 4th-order force-gradient scheme (5.111) */
#define TSFDEMOMF30 "omf30" /* Omelyan-Mryglod-Folk 2nd order, 2 forces (5.112) */
#define TSFDEMOMF32 "omf32" /* Omelyan-Mryglod-Folk 4th order force-gradient (5.113) */
#define TSFDEMFR    "fr"    /* Forest & Ruth 4th order (5.114-5.115) */
#define TSFDEMPEFRL "pefrl" /* Omelyan-Mryglod-Folk position-extended Forest-Ruth-like, 4th order */
/* Taylor-type schemes (5.102-5.107). */
#define TSFDEMT112 "t112"
#define TSFDEMT16  "t16"
#define TSFDEMD112 "d112"
/* Gear predictor-correctors (5.108-5.110, Table 5.1). */
#define TSFDEMPC3 "pc3"
#define TSFDEMPC4 "pc4"
#define TSFDEMPC5 "pc5"

/* How the force-gradient terms (chin, omf32) and the tangent terms b~ (t112,
   t16, d112) are formed:
     FDEM_GRADIENT_JVP     - a Jacobian-vector product of the momentum RHS set by FDEMTSSetForceJacobianProduct()
     FDEM_GRADIENT_FD      - a central finite-difference directional derivative of the momentum RHS
     FDEM_GRADIENT_SHIFTED - the shifted-force form (chin/omf32 only): one extra RHS per gradient kick */
typedef enum { FDEM_GRADIENT_DEFAULT = -1, FDEM_GRADIENT_JVP = 0, FDEM_GRADIENT_FD = 1, FDEM_GRADIENT_SHIFTED = 2 } FDEMGradientType;
PETSC_EXTERN const char *const FDEMGradientTypes[];

/* A drift of length s moves the positions with the momenta held fixed; by
   default position += s F_q(momentum). A problem whose positions are not
   additive (rigid-body orientations) sets its own: it receives the whole
   state U and updates its position entries in place. */
typedef PetscErrorCode (*FDEMDriftFn)(TS ts, PetscReal t, PetscReal s, Vec U, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMTSSetDrift(TS ts, FDEMDriftFn drift, void *ctx);
/* Names what became Inf or NaN: when a step's check finds a non-finite entry, the
   scheme calls it (collectively) with the bad state U and prints its text (`where`, at
   most len bytes with the terminating zero; empty: nothing to add) after its own message,
   before it returns the last checked state. A problem whose state holds bodies names the
   body, node and quantity. */
typedef PetscErrorCode (*FDEMNonFiniteFn)(TS ts, Vec U, char where[], size_t len, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMTSSetNonFiniteReport(TS ts, FDEMNonFiniteFn fn, void *ctx);
/* Declares that the "position" split's right-hand side is the momentum itself
   (F_q(p) = p, dq/dt = p entry by entry, the two splits laid out alike): the
   default drift is then position += s momentum in one pass, without calling
   the position RHS or copying its result (the same answer to the bit). Read
   at TSSetUp. */
PETSC_EXTERN PetscErrorCode FDEMTSSetPositionRHSIdentity(TS ts, PetscBool flg);

/* JW = (dF_p/dq)(t, q) W : the derivative of the momentum RHS along a
   position-space direction W (q, W position-sized; JW momentum-sized). */
typedef PetscErrorCode (*FDEMJacobianProductFn)(TS ts, PetscReal t, Vec q, Vec W, Vec JW, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMTSSetForceJacobianProduct(TS ts, FDEMJacobianProductFn jvp, void *ctx);

PETSC_EXTERN PetscErrorCode FDEMTSSetGradientType(TS ts, FDEMGradientType type);

/* Facts about the scheme of a TS of one of the fdem types. */
typedef struct {
  const char *name;
  const char *description;
  PetscInt    order;        /* design order of the global error */
  PetscInt    stages;       /* force stages per step (kicks, or 1 for PC/Taylor) */
  PetscReal   evals;        /* force (momentum RHS) evaluations per step in steady state, gradients excluded */
  PetscInt    gradients;    /* force-gradient / tangent terms per step */
  PetscReal   kcrit;        /* exact stability limit (omega h)_crit on the undamped oscillator */
  PetscReal   kcrit_book;   /* the book's Table 5.2 value (0 when not in the book) */
} FDEMSchemeInfo;
PETSC_EXTERN PetscErrorCode FDEMTSGetSchemeInfo(TS ts, FDEMSchemeInfo *info);
PETSC_EXTERN PetscErrorCode FDEMSchemeInfoFind(const char *name, PetscBool *found, FDEMSchemeInfo *info);
/* Counters since TSSetUp: momentum-RHS evaluations (all, including gradients and start-up). */
PETSC_EXTERN PetscErrorCode FDEMTSGetForceEvaluations(TS ts, PetscInt *nforce);

/* Add a splitting scheme: ops is a string of 'K' (kick) and 'D' (drift), coef
   the coefficient of each op (fractions of h), grad the force-gradient
   coefficient xi of each kick (v += c h a + xi h^3 G, G = 2 (da/dx) a; 0 for a
   plain kick). Registers a TS type of that name. */
PETSC_EXTERN PetscErrorCode FDEMTSRegisterSplitting(const char *name, const char *description, PetscInt order, const char *ops, const PetscReal coef[], const PetscReal grad[], PetscReal kcrit, PetscReal kcrit_book);

#if defined(__cplusplus)
}
#endif

#endif
