/* Contact between deformable bodies (FDEMDeformable): Munjiza's potential
   contact force (book 2.6, doc/book.md C) between the surface tetrahedra (those
   with a boundary face) of different bodies, candidate pairs from a
   linear-cost cell search over their bounding spheres with a buffer (book
   3.10-3.11), optional damping and Coulomb friction; the nodal forces go into
   the FE force vector as a term of the mesh's force chain (FDEMDeformableAddForce).
   It is the contact engine (doc/contact_engine.md) with the mesh adapter.
   See doc/contact_deformable.md.

     FDEMDeformableSetUp(dfm);
     FDEMDeformableContactCreate(dfm, &c);      adds a term to dfm's force chain
     FDEMDeformableContactSetFromOptions(c);    -fdem_contact_penalty is required
     FDEMDeformableSetUpTS(dfm, ts, &U); TSSolve(ts, U);
     FDEMDeformableContactDestroy(&c);          before FDEMDeformableDestroy

   Options (-fdem_contact_*, as FDEMContact: one set for every pair of body kinds):
     penalty <Pa>                  the penalty (a modulus: a face pushed a depth d into a tetrahedron of
                                   height H over that face feels a pressure ~ penalty d / H); required
     damping <Pa s/m>              normal contact damping per unit approach speed
     friction <mu>                 Coulomb friction coefficient
     tangential_viscosity <Pa s/m> regularises sticking below the Coulomb limit
     buffer <length>               search buffer; pairs are re-searched only when some surface node has
                                   moved more than half of it (default: a quarter of the mean diameter
                                   of the surface tetrahedra)
     self <bool>                   contact between surface tetrahedra of the same body that share no
                                   node (default false). Bodies of a fracturable material always have it:
                                   their broken joints' faces and fragments touch (doc/fracture.md)

   Parallel: at each search every rank's region (8 boxes from a k-d split of
   the bounding spheres of its own surface tetrahedra, with half the buffer)
   is shared (MPI_Allgather of 56 numbers per rank) and a surface tetrahedron whose
   sphere meets another rank's region is sent there as a ghost; a PetscSF
   (rebuilt at each search) then carries positions and velocities to the
   ghosts at every evaluation and sums the forces on ghosts back into their
   owners' nodes. A pair is computed once, by the rank owning the tetrahedron
   with the smaller global element id (which holds the other as its own or as
   a ghost).

   Time step: at the first evaluation inside a TS of FDEMDeformableSetUpTS
   the contact frequency is estimated (FDEMDeformableContactCheckTimeStep)
   and a warning printed when omega_c dt exceeds half the scheme's K_crit. */
#ifndef FDEM_DEFORMABLE_CONTACT_H
#define FDEM_DEFORMABLE_CONTACT_H

#include <fdem/contact.h>
#include <fdem/deformable.h>

#if defined(__cplusplus)
extern "C" {
#endif

typedef struct _n_FDEMDeformableContact *FDEMDeformableContact;

typedef FDEMContactStats FDEMDeformableContactStats; /* see include/fdem/contact.h */

/* Collective; after FDEMDeformableSetUp. Finds the surface tetrahedra and
   adds the contact force to dfm's force chain (after the terms already there;
   Destroy removes it). */
PETSC_EXTERN PetscErrorCode FDEMDeformableContactCreate(FDEMDeformable dfm, FDEMDeformableContact *c);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactDestroy(FDEMDeformableContact *c);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactSetFromOptions(FDEMDeformableContact c);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactSetPenalty(FDEMDeformableContact c, PetscReal penalty);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactSetDissipation(FDEMDeformableContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactSetBuffer(FDEMDeformableContact c, PetscReal buffer);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactSetSelfContact(FDEMDeformableContact c, PetscBool self);
PETSC_EXTERN PetscErrorCode FDEMDeformableContactGetStats(FDEMDeformableContact c, FDEMDeformableContactStats *stats);
/* Collective: total contact force (potential + dissipative) on body `body` at the last evaluation (all ranks). */
PETSC_EXTERN PetscErrorCode FDEMDeformableContactGetBodyForce(FDEMDeformableContact c, PetscInt body, PetscReal F[3]);
/* Collective: the contact engine's time-step check; the mesh side is omega_c = max
   sqrt(4 k / m) over the free boundary nodes (k = sum of penalty A / (3 H) over the node's
   boundary faces of area A and height H, m its lumped mass), at the stored positions;
   *ratio (may be NULL) = omega_c dt / K_crit of the fdem TS type `scheme`. Prints a warning
   when the ratio exceeds 0.5. */
PETSC_EXTERN PetscErrorCode FDEMDeformableContactCheckTimeStep(FDEMDeformableContact c, const char *scheme, PetscReal dt, PetscReal *ratio);
/* Collective: contact energy at the state U (NULL: stored state); evaluates the mesh's force
   hooks there (the contact), not its internal or joint forces. */
PETSC_EXTERN PetscErrorCode FDEMDeformableContactComputeEnergy(FDEMDeformableContact c, Vec U, PetscReal *energy);

#if defined(__cplusplus)
}
#endif
#endif
