/* Rigid discrete elements: one DMSwarm point per body (Munjiza ch. 5.2).

   Each body carries: centre of mass x, orientation R (3x3, row-major; its
   columns are the principal axes in space components, so a_space = R a_body),
   velocity v, space-frame angular momentum H, mass, principal moments
   I = (I1, I2, I3), an id, a bounding radius and a contact-skin index.

   In a TS the state of the local bodies is one Vec laid out per rank as
     [ x (3n) | R (9n) | v (3n) | H (3n) ]
   with the "position" split = x and R, the "momentum" split = v and H. The
   momentum RHS returns (F/m, M); the drift of length s moves x += s v and
   turns R by torque-free motion with H fixed (-fdem_rigid_rotation), the kick
   of length s adds s F/m to v and the impulse s M to H (eqs 5.74-5.76). */
#ifndef FDEM_RIGID_H
#define FDEM_RIGID_H

#include <petscdmswarm.h>
#include <petscts.h>

#if defined(__cplusplus)
extern "C" {
#endif

typedef struct _n_FDEMRigid *FDEMRigid;

typedef enum { FDEM_ROTATION_MUNJIZA = 0, FDEM_ROTATION_NOSQUISH = 1, FDEM_ROTATION_EXACT = 2 } FDEMRotationType;
PETSC_EXTERN const char *const FDEMRotationTypes[];

/* Force and torque on one body (space frame), added to F and M. */
typedef PetscErrorCode (*FDEMRigidForceFn)(PetscInt id, PetscReal t, const PetscReal x[3], const PetscReal R[9], const PetscReal v[3], const PetscReal H[3], PetscReal F[3], PetscReal M[3], void *ctx);

PETSC_EXTERN PetscErrorCode FDEMRigidCreate(MPI_Comm comm, FDEMRigid *rb);
PETSC_EXTERN PetscErrorCode FDEMRigidDestroy(FDEMRigid *rb);
/* -fdem_rigid_rotation munjiza|nosquish|exact, -fdem_rigid_gravity gx,gy,gz */
PETSC_EXTERN PetscErrorCode FDEMRigidSetFromOptions(FDEMRigid rb);
PETSC_EXTERN PetscErrorCode FDEMRigidSetRotationType(FDEMRigid rb, FDEMRotationType type);
PETSC_EXTERN PetscErrorCode FDEMRigidGetRotationType(FDEMRigid rb, FDEMRotationType *type);
PETSC_EXTERN PetscErrorCode FDEMRigidSetGravity(FDEMRigid rb, const PetscReal g[3]);
/* Force terms chain: gravity, contact (src/contact) and every function added here are
   summed, in that order; none replaces another. SetForceFunction is AddForce under its
   old name. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddForce(FDEMRigid rb, FDEMRigidForceFn fn, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMRigidSetForceFunction(FDEMRigid rb, FDEMRigidForceFn fn, void *ctx);
/* The box split into slabs along its longest axis, one per rank, that decides which rank holds a body
   until the first migration (then a recursive bisection of the bodies, FDEMRigidMigrate). */
PETSC_EXTERN PetscErrorCode FDEMRigidSetDomain(FDEMRigid rb, const PetscReal lo[3], const PetscReal hi[3]);
/* Periodic boundaries along the axes k with periodic[k] (after FDEMRigidSetDomain, before adding
   bodies): the domain's box is the periodic cell, of period hi[k] - lo[k]. A body near one side
   touches the bodies near the other (their images, doc/contact_engine.md); FDEMRigidMigrate puts
   the centres back into [lo, hi) and counts the periods each crossed in its swarm field "image"
   (3 PetscInt: its unwrapped centre is x + image (hi - lo)). Every body must be smaller than half
   the period, and move less than a quarter period between two migrations. */
PETSC_EXTERN PetscErrorCode FDEMRigidSetPeriodic(FDEMRigid rb, const PetscBool periodic[3]);
/* The periodic axes and the domain's box (any argument may be NULL). */
PETSC_EXTERN PetscErrorCode FDEMRigidGetPeriodic(FDEMRigid rb, PetscBool periodic[3], PetscReal lo[3], PetscReal hi[3]);

/* Adds a body given by its principal data. Call on every rank with the same
   arguments: the rank whose slab holds x keeps it. omega is the space-frame
   angular velocity. *id (may be NULL) gets the body's id. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddBody(FDEMRigid rb, const char *name, PetscReal mass, const PetscReal inertia[3], const PetscReal x[3], const PetscReal R[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id);
/* Adds a body from a closed tetrahedral mesh (its own frame) and a density:
   mass, centre of mass and principal axes from the geometry. The body is
   placed so that its mesh frame is turned by Q (row-major; NULL = identity)
   and its centre of mass sits at x. The mesh is kept as the body's contact skin. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddBodyFromMesh(FDEMRigid rb, const char *name, PetscInt nnodes, const PetscReal nodes[], PetscInt ntets, const PetscInt tets[], PetscReal density, const PetscReal x[3], const PetscReal Q[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id);

/* Spheres and granular contact (doc/spheres.md). A granular material gives the force law
   of a sphere's contacts; a contact mixes the materials of its two sides. Values < 0 (and
   law_set false) are not given: the mix takes them from the other side. */
typedef enum { FDEM_GRANULAR_HERTZ = 0, FDEM_GRANULAR_HOOKE = 1 } FDEMGranularLaw;
typedef struct {
  FDEMGranularLaw law;
  PetscBool       law_set;
  PetscReal       young, poisson;               /* Pa, - (Hertz) */
  PetscReal       kn, kt, gamma_n, gamma_t;     /* N/m, N/m, 1/s, 1/s (Hooke) */
  PetscReal       restitution, friction, rolling_friction;
} FDEMGranularMaterial;
/* Every value "not given". */
PETSC_EXTERN PetscErrorCode FDEMGranularMaterialInitialize(FDEMGranularMaterial *m);
/* Adds a granular material (same arguments on every rank); *index for the calls below. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddGranularMaterial(FDEMRigid rb, const char *name, const FDEMGranularMaterial *m, PetscInt *index);
/* A sphere of the given radius and density (solid: I = 2/5 m r^2) and granular material; call
   on every rank with the same arguments, as FDEMRigidAddBody. omega: space-frame. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddSphere(FDEMRigid rb, const char *name, PetscReal radius, PetscReal density, PetscInt material, const PetscReal x[3], const PetscReal v[3], const PetscReal omega[3], PetscInt *id);
/* A clump: a rigid body whose contact shape is n spheres, balls[4k .. 4k+3] = the centre (x, y,
   z) and radius of sphere k in the clump's own frame (they may overlap). Mass, centre of mass and
   principal axes are those of the union of the spheres at the given density (computed once per
   shape; doc/spheres.md, "Clumps"). Placed as FDEMRigidAddBodyFromMesh: its own frame turned by
   Q (row-major; NULL = identity), its centre of mass at x. Its spheres meet spheres, other
   clumps and surfaces with the granular material's law; two spheres of one clump never meet.
   Call on every rank with the same arguments. */
PETSC_EXTERN PetscErrorCode FDEMRigidAddClump(FDEMRigid rb, const char *name, PetscInt n, const PetscReal balls[], PetscReal density, PetscInt material, const PetscReal x[3], const PetscReal Q[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id);
/* The granular material of body id (a polyhedron that spheres touch). Every rank. */
PETSC_EXTERN PetscErrorCode FDEMRigidSetBodyMaterial(FDEMRigid rb, PetscInt id, PetscInt material);

/* Fixes body id in place (walls, floors): forces never move it. Collective. */
PETSC_EXTERN PetscErrorCode FDEMRigidFixBody(FDEMRigid rb, PetscInt id);
/* Moves body id at the constant velocity v for ever (a platen): forces never change its
   motion, it translates without turning. Contact treats it as a fixed body (no pair with
   another fixed or moved body). The work of the reactions that hold it, the integral of
   R . v over the force evaluations (R = -(the force on the body, gravity and contact
   included); trapezoidal rule in time), is given by GetExternalWork (collective);
   SetExternalWork restores it on restart. Collective. */
PETSC_EXTERN PetscErrorCode FDEMRigidMoveBody(FDEMRigid rb, PetscInt id, const PetscReal v[3]);
PETSC_EXTERN PetscErrorCode FDEMRigidGetExternalWork(FDEMRigid rb, PetscReal *W);
/* The force on body id at the last force evaluation: gravity, contact (rigid and, in a scene,
   with the mesh) and the force functions; for a fixed or moved body (a platen) it is the load
   the others put on it, the reaction that holds it being its negative. Collective. */
PETSC_EXTERN PetscErrorCode FDEMRigidGetBodyForce(FDEMRigid rb, PetscInt id, PetscReal F[3]);
PETSC_EXTERN PetscErrorCode FDEMRigidSetExternalWork(FDEMRigid rb, PetscReal W);
PETSC_EXTERN PetscErrorCode FDEMRigidGetDM(FDEMRigid rb, DM *swarm);
PETSC_EXTERN PetscErrorCode FDEMRigidGetNumBodies(FDEMRigid rb, PetscInt *nlocal, PetscInt *nglobal);

/* Sets the splits, RHS functions and drift on ts, creates the state vector
   *U from the swarm (copy) and sets it as the TS solution. */
PETSC_EXTERN PetscErrorCode FDEMRigidSetUpTS(FDEMRigid rb, TS ts, Vec *U);
/* Copies U back into the swarm; U stays the caller's (as FDEMDeformableRestoreState and
   FDEMSceneRestoreState: every ...RestoreState keeps the Vec). */
PETSC_EXTERN PetscErrorCode FDEMRigidRestoreState(FDEMRigid rb, Vec U);
/* Partitions the moving bodies by a recursive coordinate bisection of their centres weighted by
   their contact primitives and pairs (doc/rigid.md, "Parallel") and sends every body to its
   part's rank (DMSwarmMigrate). Collective. */
PETSC_EXTERN PetscErrorCode FDEMRigidMigrate(FDEMRigid rb);
/* Whether a migration is due: some body has moved farther than its radius since the last
   FDEMRigidMigrate, or a centre has left a periodic cell. Decided from the positions alone, so
   that every number of ranks decides alike; a caller that migrates only then keeps its TS running
   in between (the driver does, at the end of each output segment). Collective. */
PETSC_EXTERN PetscErrorCode FDEMRigidMigrationNeeded(FDEMRigid rb, PetscBool *needed);
/* With -fdem_rigid_partition_timed: the costs the last partition weighed the bodies by, CPU
   seconds over the segment before it summed over the ranks, per contact primitive and per
   contact pair a body took part in (0 before the first measurement; either may be NULL). */
PETSC_EXTERN PetscErrorCode FDEMRigidGetPartitionCosts(FDEMRigid rb, PetscReal *per_primitive, PetscReal *per_pair);
/* Solves from t0 to tfinal with steps dt (default type cd), migrating every
   `migrate_every` steps (a new TS per segment). dt, tfinal and the type are
   defaults: -ts_dt, -ts_max_time, -ts_max_steps and -ts_type win.
   The splitting types that turn R with the drift (cd, pv, omf30, omf32, chin,
   fr, pefrl) step rigid bodies; basicsymplectic stops with an error. */
PETSC_EXTERN PetscErrorCode FDEMRigidSolve(FDEMRigid rb, PetscReal t0, PetscReal tfinal, PetscReal dt, PetscInt migrate_every, PetscErrorCode (*monitor)(FDEMRigid, PetscInt, PetscReal, void *), void *mctx);
/* Where the last FDEMRigidSolve stopped: its final time and step number (either may be NULL). */
PETSC_EXTERN PetscErrorCode FDEMRigidGetTime(FDEMRigid rb, PetscReal *t, PetscInt *steps);

/* One body: H and omega_space are space-frame vectors (the body-frame angular
   velocity is R^T omega_space); inertia holds the principal moments. */
typedef struct {
  PetscInt  id;
  PetscReal mass, inertia[3], x[3], R[9], v[3], H[3], omega_space[3], radius;
  PetscMPIInt rank;
} FDEMRigidBodyState;
/* Collective: the state of body id, wherever it lives. */
PETSC_EXTERN PetscErrorCode FDEMRigidGetBodyState(FDEMRigid rb, PetscInt id, FDEMRigidBodyState *st);
/* Collective: every body's state, gathered on rank root in the order of the ids (*n the number
   of bodies; free *states with PetscFree); the other ranks get *n = 0 and NULL. One gather, so
   linear in the bodies, where a loop over FDEMRigidGetBodyState costs a search and a broadcast
   per body. */
PETSC_EXTERN PetscErrorCode FDEMRigidGetBodyStates(FDEMRigid rb, PetscMPIInt root, PetscInt *n, FDEMRigidBodyState **states);
/* Collective: total linear and angular momentum (about the origin) and kinetic energy. */
PETSC_EXTERN PetscErrorCode FDEMRigidGetInvariants(FDEMRigid rb, PetscReal P[3], PetscReal L[3], PetscReal *E);

/* HDF5 + XDMF output of the bodies' contact skins (surface triangles moved
   with the bodies): file base.h5 and base.xmf, one grid per call. */
PETSC_EXTERN PetscErrorCode FDEMRigidWriteHDF5(FDEMRigid rb, const char *base, PetscInt step, PetscReal t);

#if defined(__cplusplus)
}
#endif
#endif
