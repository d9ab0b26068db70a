/* Contact between rigid discrete elements: Munjiza's potential contact force
   between the tetrahedra of the bodies' contact skins (book 2.6), found by a
   linear-cost cell search (book 3.8-3.11), in parallel with ghost copies of
   the skin tetrahedra of other ranks within the search distance (PetscSF).
   FDEMContact is the contact engine of doc/contact_engine.md with the rigid
   adapter; FDEMDeformableContact and FDEMScene's rigid-deformable contact are
   the same engine with other adapters, and share its options and statistics.

   Options (-fdem_contact_*, the same for every pair of body kinds):
     penalty <Pa>                 the penalty (a modulus: a face pushed a depth d into a tetrahedron
                                  of height H over that face feels a pressure ~ penalty d / H); required
     damping <Pa s/m>             normal contact damping per unit approach speed (book 2.6.4)
     friction <mu>                Coulomb friction coefficient
     tangential_viscosity <Pa s/m> regularises sticking below the Coulomb limit
     buffer <length>              search buffer; pairs are re-searched only when some body has moved
                                  more than half of it (default, or < 0: the mean of a tenth of each
                                  rigid body's radius and a quarter of each mesh contact cell's diameter)
     self <bool>                  self-contact within a deformable body (FDEMDeformableContact)
   Command-line options win over the values set in code. */
#ifndef FDEM_CONTACT_H
#define FDEM_CONTACT_H

#include <fdem/rigid.h>

#if defined(__cplusplus)
extern "C" {
#endif

typedef struct _n_FDEMContact *FDEMContact;

/* The statistics of every contact object (FDEMContact, FDEMDeformableContact,
   FDEMScene): one meaning each, and every count and sum is over all ranks. */
typedef struct {
  PetscInt  searches;        /* cell searches (re-searches) so far */
  PetscInt  evaluations;     /* contact force evaluations */
  PetscInt  primitives;      /* contact tetrahedra lent by the bodies (rigid skins, mesh cells) */
  PetscInt  ghosts;          /* ghost copies of contact tetrahedra held by other ranks (last search) */
  PetscInt  candidate_pairs; /* tetrahedron pairs from the last search */
  PetscInt  active_pairs;    /* overlapping pairs at the last evaluation */
  PetscReal energy;          /* overlap energy at the last evaluation */
  PetscReal buffer;          /* search buffer in use (0 before the first evaluation with an automatic buffer) */
  PetscReal dt_ratio;        /* omega_c dt / K_crit of the automatic time-step check (0: not done) */
  PetscReal onset;           /* the overlap energy that listings caused by fracture added at their state, summed (doc/fracture.md, "The handover to contact") */
  PetscInt  kept;            /* listings caused by fracture that kept the last search (the same contact tetrahedra, only their records changed; doc/contact_engine.md) */
  PetscInt  in_place;        /* of those, the listings made in place (only the changed records written; doc/contact_engine.md) */
  PetscInt  in_place_few;    /* of those, the listings that asked again only the candidates of the records that changed (doc/contact_engine.md) */
} FDEMContactStats;

/* Attaches contact to the rigid bodies rb (before FDEMRigidSetUpTS / FDEMRigidSolve): a
   term of rb's force chain, added to gravity and the functions of FDEMRigidAddForce. */
PETSC_EXTERN PetscErrorCode FDEMContactCreate(FDEMRigid rb, FDEMContact *c);
PETSC_EXTERN PetscErrorCode FDEMContactDestroy(FDEMContact *c);
PETSC_EXTERN PetscErrorCode FDEMContactSetFromOptions(FDEMContact c);
PETSC_EXTERN PetscErrorCode FDEMContactSetPenalty(FDEMContact c, PetscReal penalty);
PETSC_EXTERN PetscErrorCode FDEMContactSetDissipation(FDEMContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity);
PETSC_EXTERN PetscErrorCode FDEMContactSetBuffer(FDEMContact c, PetscReal buffer);
PETSC_EXTERN PetscErrorCode FDEMContactGetStats(FDEMContact c, FDEMContactStats *stats);
/* The contact energy of the rigid bodies' state in their swarm: one evaluation over zero time
   (no tangential spring advances, the clock of the next evaluation is kept; the forces are
   discarded; the statistics count it). For a state no step has evaluated yet, e.g. bodies that
   touch at the start. After FDEMRigidSetUpTS or FDEMSceneSetUpTS. Collective. */
PETSC_EXTERN PetscErrorCode FDEMContactComputeEnergy(FDEMContact c, PetscReal *energy);
/* The contact engine's time-step check (doc/contact_engine.md): the contact frequency
   omega_c ~ sqrt(penalty A / (L m)) of the lightest body (A = (2 r)^2 its cross-section, L its
   skin tetrahedra's size) against K_crit of the fdem TS type `scheme`; *ratio (may be NULL) =
   omega_c dt / K_crit, and a warning above 0.5. Collective. */
PETSC_EXTERN PetscErrorCode FDEMContactCheckTimeStep(FDEMContact c, const char *scheme, PetscReal dt, PetscReal *ratio);

#if defined(__cplusplus)
}
#endif
#endif
