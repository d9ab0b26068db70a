/* A combined scene: rigid bodies (FDEMRigid) and deformable tetrahedral
   meshes (FDEMDeformable) stepped by ONE TS of any fdem splitting type, with
   rigid-deformable contact (Munjiza's potential contact force between the
   rigid bodies' skin tetrahedra and the mesh's surface tetrahedra).
   See doc/scene.md.

   State per rank (one Vec, no copies on the hot path: the rigid and
   deformable pieces work on views of it):
       [ deformable x (3 nd) | rigid x (3 nr), R (9 nr) | rigid v (3 nr), H (3 nr) | deformable v (3 nd) ]
        \________________ "position" ______________/   \_______________ "momentum" _______________/
   nd = owned mesh nodes, nr = local rigid bodies. Both splits are contiguous
   and the rigid block [x | R | v | H] is exactly the rigid model's own state,
   so its RHS, drift and contact run on it unchanged. The drift moves the mesh
   nodes additively (x += s v) and turns the rigid bodies by torque-free
   motion (-fdem_rigid_rotation); the kick adds s F/m to every velocity and
   the impulse s M to every H.

   Life cycle
     FDEMSceneCreate(comm, &sc);
     FDEMSceneSetRigid(sc, rb);          optional; rb set up with its bodies (and FDEMContact, if any)
     FDEMSceneSetDeformable(sc, dfm);    optional; after FDEMDeformableSetUp
     FDEMSceneSetFromOptions(sc);        -fdem_contact_penalty etc.
     FDEMSceneSetUpTS(sc, ts, &U);
     TSSolve(ts, U);
     FDEMSceneRestoreState(sc, U);       copies U back into the swarm and the mesh's x, v
     VecDestroy(&U); FDEMSceneDestroy(&sc);
   rb and dfm are borrowed: destroy them after the scene. */
#ifndef FDEM_SCENE_H
#define FDEM_SCENE_H

#include <fdem/contact.h>
#include <fdem/deformable.h>
#include <fdem/rigid.h>

#if defined(__cplusplus)
extern "C" {
#endif

typedef struct _n_FDEMScene *FDEMScene;

typedef FDEMContactStats FDEMSceneContactStats; /* see include/fdem/contact.h */

PETSC_EXTERN PetscErrorCode FDEMSceneCreate(MPI_Comm comm, FDEMScene *sc);
PETSC_EXTERN PetscErrorCode FDEMSceneDestroy(FDEMScene *sc);
PETSC_EXTERN PetscErrorCode FDEMSceneSetRigid(FDEMScene sc, FDEMRigid rb);
PETSC_EXTERN PetscErrorCode FDEMSceneSetDeformable(FDEMScene sc, FDEMDeformable dfm);

/* Rigid-deformable contact: the contact engine (doc/contact_engine.md) with
   the mesh adapter (cells with a vertex on the boundary) and the rigid
   adapter, pairs only across the two kinds; a term of the mesh's force
   chain. Off until a positive penalty is given (a scene without contact does
   no search). penalty (Pa) as for FDEMContact; damping (Pa s/m) and friction
   (Coulomb mu) as fdem::kernels::ContactDampingFriction; buffer: search
   buffer (length), re-search when something moved more than half of it
   (< 0: automatic, as -fdem_contact_buffer). Options: -fdem_contact_* as
   FDEMContact (command-line options win).

   Parallel: the engine's halo (mesh cells and skin tetrahedra near another
   rank's region are ghosts there); a pair (mesh cell, rigid skin
   tetrahedron) is computed once, by the rank owning the cell.

   Checks: at the first evaluation after FDEMSceneSetUpTS, an overlap energy
   above that of 10% of the smaller tetrahedron of a pair is a collective
   error naming the deformable body, the rigid body id and both elements; at
   the first force evaluation of the TS, FDEMSceneCheckTimeStep. */
PETSC_EXTERN PetscErrorCode FDEMSceneSetContact(FDEMScene sc, PetscReal penalty, PetscReal damping, PetscReal friction, PetscReal buffer);
/* The tangential viscosity (Pa s/m) regularising stick, as FDEMContactSetDissipation. */
PETSC_EXTERN PetscErrorCode FDEMSceneSetContactTangentialViscosity(FDEMScene sc, PetscReal tangential_viscosity);
PETSC_EXTERN PetscErrorCode FDEMSceneSetFromOptions(FDEMScene sc);

/* Sets the splits, RHS functions, drift and solution of ts; creates *U from
   the rigid swarm and the mesh's stored x, v. The TS must not outlive sc. */
PETSC_EXTERN PetscErrorCode FDEMSceneSetUpTS(FDEMScene sc, TS ts, Vec *U);
/* Copies U into the rigid swarm and the mesh's stored x, v (U is kept). */
PETSC_EXTERN PetscErrorCode FDEMSceneRestoreState(FDEMScene sc, Vec U);
/* Local sizes: rigid bodies nr and owned mesh nodes nd (either may be NULL). */
PETSC_EXTERN PetscErrorCode FDEMSceneGetLocalSizes(FDEMScene sc, PetscInt *nr, PetscInt *nd);

/* Collective diagnostics at U (copies U into the models first):
   P, L: total linear momentum and angular momentum about the origin (rigid
   m v and x x m v + H, mesh sum m v and x x m v); E[0] rigid kinetic, E[1]
   mesh kinetic, E[2] strain energy (FDEMDeformableGetEnergy), E[3] contact
   overlap energy at U (any may be NULL). */
PETSC_EXTERN PetscErrorCode FDEMSceneGetInvariants(FDEMScene sc, Vec U, PetscReal t, PetscReal P[3], PetscReal L[3], PetscReal E[4]);
PETSC_EXTERN PetscErrorCode FDEMSceneGetContactStats(FDEMScene sc, FDEMSceneContactStats *stats);
/* Collective: the rigid-deformable contact frequency omega_c against the stability limit
   K_crit of the fdem TS type `scheme` (FDEMSchemeInfoFind); *ratio (may be NULL) =
   omega_c dt / K_crit, and a WARNING is printed when it exceeds 0.5. omega_c is the larger of
   the rigid side (as FDEMContactCheckTimeStep) and the mesh side (as
   FDEMDeformableContactCheckTimeStep), at the stored positions. Needs FDEMSceneSetUpTS with
   contact on. FDEMSceneSetUpTS arranges for it to run once by itself, at the first force
   evaluation of the TS (its type and time step are final then; the ratio is kept in
   FDEMSceneContactStats.dt_ratio). */
PETSC_EXTERN PetscErrorCode FDEMSceneCheckTimeStep(FDEMScene sc, const char *scheme, PetscReal dt, PetscReal *ratio);

#if defined(__cplusplus)
}
#endif
#endif
