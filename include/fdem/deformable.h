/* Deformable discrete elements: 4-node tetrahedral meshes in a distributed
   DMPlex, constant-strain tetrahedra (Munjiza 2004, section 4.8; kernels in
   fdem/kernels/cst.hpp), stepped by any fdem TS type. See doc/deformable.md.

   Life cycle
     FDEMDeformableCreate(comm, &dfm);
     FDEMDeformableAddMaterial(dfm, "steel", E, nu, rho, mu_visc, FDEM_MATERIAL_MUNJIZA_CST);
     FDEMDeformableSetMeshBeam(dfm, L, W, H, n);        (or Box, Cylinder, FromGmsh, SetMesh)
     FDEMDeformableSetBodyMaterial(dfm, "beam", "steel"); (optional, see below)
     FDEMDeformableSetFromOptions(dfm);
     FDEMDeformableSetUp(dfm);            METIS partition on rank 0, DMPlex, distribution
     FDEMDeformableFixNodesInBox(...); FDEMDeformableSetVelocityField(...);
     FDEMDeformableSetUpTS(dfm, ts, &U);  splits as for -ts_type basicsymplectic
     TSSolve(ts, U);

   Meshes are given on rank 0 (the arguments of the mesh setters are read on
   rank 0 only; other ranks may pass empty arrays). Node and element ids are
   the 0-based positions in that input ("global ids"); they survive the
   distribution and name nodes and elements in every message and query.

   Materials: a body takes the material named by FDEMDeformableSetBodyMaterial,
   else the material with the body's name, else the only material if the table
   has exactly one. A body without a material is an error naming the body and
   the missing material.

   State for a TS, per rank: U = [ x (3 n) | v (3 n) ] over the n nodes the
   rank owns (in the order of the DM's global vector), "position" split = x,
   "momentum" split = v; dx/dt = v, dv/dt = (f_int(x, v) + f_ext) / m + g with
   f_int assembled from every local cell through DMLocalToGlobal(ADD_VALUES)
   and m the lumped mass; fixed nodes get dv/dt = 0. The viscous part of f_int
   reads v from the TS's current solution. */
#ifndef FDEM_DEFORMABLE_H
#define FDEM_DEFORMABLE_H

#include <petscdmplex.h>
#include <petscts.h>

#if defined(__cplusplus)
extern "C" {
#endif

typedef struct _n_FDEMDeformable *FDEMDeformable;

/* Constitutive models (doc/element.md): book eq 4.220, compressible
   neo-Hookean, and the (non-objective) small-strain linear tetrahedron. */
typedef enum { FDEM_MATERIAL_MUNJIZA_CST = 0, FDEM_MATERIAL_NEO_HOOKEAN = 1, FDEM_MATERIAL_SMALL_STRAIN_LINEAR = 2 } FDEMMaterialModel;
PETSC_EXTERN const char *const FDEMMaterialModels[];

/* Extra nodal forces (contact, loads): add into floc, a local vector (3 per
   local node, ghosts included) that is then summed over ranks with
   DMLocalToGlobal(ADD_VALUES): add each force on one rank only. xloc, vloc:
   current positions and velocities of the local nodes (vloc may be NULL when
   no material is viscous). */
typedef PetscErrorCode (*FDEMDeformableForceFn)(FDEMDeformable dfm, PetscReal t, Vec xloc, Vec vloc, Vec floc, void *ctx);
/* A nodal field from the reference position X of node `id` (initial velocity or position);
   `id` is the input mesh's node id (for a split fracturable body: the node it was copied from). */
typedef PetscErrorCode (*FDEMDeformableFieldFn)(PetscInt id, const PetscReal X[3], PetscReal out[3], void *ctx);

PETSC_EXTERN PetscErrorCode FDEMDeformableCreate(MPI_Comm comm, FDEMDeformable *dfm);
PETSC_EXTERN PetscErrorCode FDEMDeformableDestroy(FDEMDeformable *dfm);

/* Material table. Checked at once (E > 0, -1 < nu < 0.5, rho > 0, mu_visc >= 0). */
PETSC_EXTERN PetscErrorCode FDEMDeformableAddMaterial(FDEMDeformable dfm, const char *name, PetscReal E, PetscReal nu, PetscReal rho, PetscReal mu_visc, FDEMMaterialModel model);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetBodyMaterial(FDEMDeformable dfm, const char *body, const char *material);

/* Meshes (one per object; a later call replaces the earlier). SetMesh: nodes
   3 per node, tets 4 per tetrahedron with positive volume det[x1-x0, x2-x0,
   x3-x0] > 0, body per tetrahedron (NULL: all 0) and nbodies names (NULL:
   "body_<i>"). Generators: box [lo, hi] in nx*ny*nz Kuhn cells (body "box");
   beam [0,L]x[0,W]x[0,H] with n cells across the smallest side ("beam");
   cylinder of axis z ("cylinder"). Gmsh: physical volumes or connected
   components become bodies (fdem::kernels::ReadGmsh). */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMesh(FDEMDeformable dfm, PetscInt nnodes, const PetscReal nodes[], PetscInt ntets, const PetscInt tets[], const PetscInt body[], PetscInt nbodies, const char *const body_names[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMeshBox(FDEMDeformable dfm, const PetscReal lo[3], const PetscReal hi[3], PetscInt nx, PetscInt ny, PetscInt nz);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMeshBeam(FDEMDeformable dfm, PetscReal L, PetscReal W, PetscReal H, PetscInt n);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMeshCylinder(FDEMDeformable dfm, PetscReal radius, PetscReal height, PetscInt n_radial, PetscInt n_axial);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMeshFromGmsh(FDEMDeformable dfm, const char *path);

/* Fracture (doc/fracture.md): the bodies of `material` become fracturable. At set-up
   each of their tetrahedra gets its own four nodes (only those in the body's fracture
   zones, if it has any: FDEMDeformableAddFractureZone) and every face two of them shared
   becomes a joint held by the cohesive law: tensile strength f_t (Pa), cohesion c (Pa),
   friction angle (degrees), fracture energies G_I and G_II (J/m^2) and the joint penalty
   (Pa). The split renumbers the nodes of those bodies; FixNodes, MoveNodes and the field
   callbacks still use the input mesh's ids (an input node stands for all its copies), while node ids and
   counts that the library reports are those of the split mesh. Joints that straddle
   ranks are computed by the rank of one side. A joint is broken when all three of its
   points are; its two faces then become contact surfaces of the contact engine
   (FDEMDeformableContact and a scene's rigid-deformable contact) and the body may fall
   into fragments (FDEMDeformableGetFragments). The joints' energy: GetJointEnergy;
   their state in checkpoints: View/LoadJointState. */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetMaterialFracture(FDEMDeformable dfm, const char *material, PetscReal tensile_strength, PetscReal cohesion, PetscReal friction_angle, PetscReal GI, PetscReal GII, PetscReal joint_penalty);
/* Limits the split of a fracturable body to a zone, the box [lo, hi] in the input mesh's
   coordinates (doc/fracture.md, "Fracture zones"). A body with zones gets nodes of its own
   and joints only at the tetrahedra whose centroids lie in one of them (calls add zones:
   their union); every face such a tetrahedron shares with another of the body is a joint,
   also with a tetrahedron outside, which keeps the body's shared nodes. Elsewhere the body
   is as if not fracturable: no joints, no artificial compliance, no cost. A body without
   zones is split everywhere. At set-up, a zone on a body whose material is not fracturable,
   or that holds the centroid of none of the body's tetrahedra, is an error naming the body. */
PETSC_EXTERN PetscErrorCode FDEMDeformableAddFractureZone(FDEMDeformable dfm, const char *body, const PetscReal lo[3], const PetscReal hi[3]);
/* Joints inserted during a run (doc/fracture.md, "Joints inserted during a run"). A
   fracturable body given a stress ratio r in (0, 1] starts split only in its fracture zones
   (none: nowhere) and at the tetrahedra given with AddFractureCells (ids of the input mesh).
   FindCellsToSplit (collective, after set-up) lists, the same on every rank, its whole
   tetrahedra whose Cauchy stress at U reaches r times the strength, max(sigma_1 / f_t,
   Mohr-Coulomb's (sigma_1 - sigma_3) / 2 over c cos(phi) - (sigma_1 + sigma_3) / 2 sin(phi)),
   and those that reach (1 - a) r linked to one of them by a chain of such tetrahedra sharing
   nodes (a: -fdem_insert_ahead, default 0.25; 0: none), each with the whole tetrahedra that
   share a node with it; free *cells with PetscFree. The
   caller then builds the model again with them added (the fdem driver does it between steps):
   LoadNodeVector and LoadJointState read a checkpoint written with fewer tetrahedra split
   into the larger split, each copy of a node taking the state of the node its tetrahedron
   had and each new joint starting intact. ViewJointState saves the inserted tetrahedra
   (`fracture_cells`); ReadFractureCells reads them back from a checkpoint (free with
   PetscFree), for a restart to build the same split. ContinueOutput carries the frames
   written by one model to its successor's WriteHDF5 (the same file). ReuseSetUp, before
   SetUp, lets the successor take from its predecessor (a set-up model of the same mesh) what
   set-up derives from the input mesh alone: its faces sorted for splitting, and the joints'
   frequency and the check of every joint that insertion may make; where the mesh, the
   bodies' materials, their fracture properties, insertion or zones differ, SetUp makes them
   anew (the same answers either way). ContinueNodeVector and ContinueJointState do for the
   successor what LoadNodeVector and LoadJointState do with a checkpoint its predecessor
   wrote, straight from the predecessor (set up, of the same input mesh, insertion and
   fracture properties, with no tetrahedron split that `to` keeps whole): a node vector in
   the predecessor's natural order (its split's node numbering, as a checkpoint saves it) is
   mapped into the successor's, and the joints' state taken over, with the same values as
   through a file. */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetFractureInsertion(FDEMDeformable dfm, const char *body, PetscReal ratio);
PETSC_EXTERN PetscErrorCode FDEMDeformableAddFractureCells(FDEMDeformable dfm, PetscInt n, const PetscInt cells[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetFractureCells(FDEMDeformable dfm, PetscInt *n, const PetscInt *cells[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableFindCellsToSplit(FDEMDeformable dfm, Vec U, PetscInt *n, PetscInt *cells[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableReadFractureCells(MPI_Comm comm, PetscViewer viewer, PetscInt *n, PetscInt *cells[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableLoadNodeVector(FDEMDeformable dfm, PetscViewer viewer, Vec natural);
PETSC_EXTERN PetscErrorCode FDEMDeformableContinueOutput(FDEMDeformable to, FDEMDeformable from);
PETSC_EXTERN PetscErrorCode FDEMDeformableReuseSetUp(FDEMDeformable to, FDEMDeformable from);
PETSC_EXTERN PetscErrorCode FDEMDeformableContinueNodeVector(FDEMDeformable to, FDEMDeformable from, Vec from_natural, Vec to_natural);
PETSC_EXTERN PetscErrorCode FDEMDeformableContinueJointState(FDEMDeformable to, FDEMDeformable from);
/* After set-up: an estimate of the joints' largest frequency omega_j (1/s; 0 without joints):
   max over nodes of sqrt(2 K / m), K the joint stiffness p A / (3 h) per point summed at the
   node, m its mass. A time step with omega_j dt above half the scheme's K_crit is warned at
   the first evaluation of a TS (the limit measured in test_fracture_bar: doc/fracture.md). */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetJointFrequency(FDEMDeformable dfm, PetscReal *omega);
/* After set-up: the number of joints, of joints broken at all three points, and the
   largest damage reached (collective). */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetJointStats(FDEMDeformable dfm, PetscInt *joints, PetscInt *broken, PetscReal *max_damage);
/* The joints that broke (their third point broken: the joint is gone) since the previous
   call, or since set-up: *count gets their number and *breaks (may be NULL) an array of them,
   allocated with PetscMalloc1 (free it with PetscFree), the same on every rank, ordered by
   time and then by joint id, which is the same on any number of ranks. A break is recorded
   by the force evaluation in which it happens; joints broken in a loaded joint state
   (LoadJointState) are not reported. Collective. */
typedef struct {
  PetscInt  joint; /* its id in the split's joint order (independent of the rank count) */
  PetscInt  body;  /* the body of its tetrahedra (FDEMDeformableGetBodyName) */
  PetscReal t;     /* the time of the force evaluation in which it broke */
  PetscReal x[3];  /* the centroid of its two triangles' six nodes then */
} FDEMJointBreak;
PETSC_EXTERN PetscErrorCode FDEMDeformableGetJointBreaks(FDEMDeformable dfm, PetscInt *count, FDEMJointBreak *breaks[]);
/* The joints' energy (collective; each output may be NULL): `stored`, the recoverable
   energy of the joints at the state U (NULL: the stored positions), the free energy whose
   derivatives are the joint tractions; `dissipated`, the energy fracture has taken out of
   the scene so far: what the joints' damage dissipated (the fracture energy spent), plus
   the compression energy joints held when they broke through and were removed, less the
   contact energy their faces had when a contact object listed them (the handover to
   contact; it may lower `dissipated` a little at such a listing). The work done on the
   joints is stored + dissipated (doc/fracture.md, "Energy" and "The handover to
   contact"). Both 0 without joints. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetJointEnergy(FDEMDeformable dfm, Vec U, PetscReal *stored, PetscReal *dissipated);
/* Writes (loads) the joints' state to (from) a viewer, e.g. an HDF5 file: `joint_damage`,
   3 damages per joint in the split's joint order (1 = broken; independent of the rank
   count), and `joint_dissipated` (1 value). Loading checks the size and the range and names
   the first bad joint. Nothing is written or read without joints. Collective. */
PETSC_EXTERN PetscErrorCode FDEMDeformableViewJointState(FDEMDeformable dfm, PetscViewer viewer);
PETSC_EXTERN PetscErrorCode FDEMDeformableLoadJointState(FDEMDeformable dfm, PetscViewer viewer);
/* Fragments: the connected components of the tetrahedra of each body, two tetrahedra being
   connected when they share a node or are held by a joint that is not broken (an unsplit
   body, or a fracturable one with no crack through it, is one fragment). A fragment's id is
   the smallest element id in it, the same on any number of ranks (and kept by the piece that
   holds that element when the fragment breaks further). Collective, at the state U (NULL:
   the stored state). *count gets the number of fragments; *fragments (may be NULL) gets an
   array of them, allocated with PetscMalloc1 (free it with PetscFree; NULL when there are
   none), ordered by body and then by id.
   GetLocalFragments gives each rank its share: the fragments whose id modulo the number of
   ranks is the rank, so that every fragment is on exactly one rank and no rank holds
   anything per fragment of the whole mesh. GetFragments gives every rank all of them (it
   gathers the shares: memory per rank grows with the fragments of the whole mesh). */
typedef struct {
  PetscInt  body;  /* the body the fragment belongs to (FDEMDeformableGetBodyName) */
  PetscInt  id;    /* the smallest element id in it (FDEMDeformableGetLocalCells' ids) */
  PetscInt  cells; /* its tetrahedra */
  PetscReal mass;  /* the sum of its tetrahedra's masses rho V */
  PetscReal x[3];  /* its centre of mass */
  PetscReal v[3];  /* the velocity of its centre of mass (momentum / mass) */
} FDEMFragment;
PETSC_EXTERN PetscErrorCode FDEMDeformableGetFragments(FDEMDeformable dfm, Vec U, PetscInt *count, FDEMFragment *fragments[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetLocalFragments(FDEMDeformable dfm, Vec U, PetscInt *count, FDEMFragment *fragments[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetGravity(FDEMDeformable dfm, const PetscReal g[3]);
/* Force terms chain: each added function adds its nodal forces to floc at every force
   evaluation, in the order added (a user's load, contact, ...); none replaces another.
   RemoveForce removes the term (fn, ctx). SetExternalForce is AddForce under its old name. */
PETSC_EXTERN PetscErrorCode FDEMDeformableAddForce(FDEMDeformable dfm, FDEMDeformableForceFn fn, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMDeformableRemoveForce(FDEMDeformable dfm, FDEMDeformableForceFn fn, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetExternalForce(FDEMDeformable dfm, FDEMDeformableForceFn fn, void *ctx);
/* -fdem_deformable_gravity gx,gy,gz
   -fdem_deformable_partition metis|simple   (simple: contiguous blocks of elements, for comparison)
   -fdem_deformable_view                     (prints sizes and the partition balance) */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetFromOptions(FDEMDeformable dfm);

/* Collective. Validates the mesh and materials on rank 0 (errors name the
   element, body or material), partitions the elements with METIS
   (METIS_PartMeshDual, element weights = relative cost of the element's
   model) into one part per rank, builds the DMPlex with
   DMPlexCreateFromCellListPetsc, distributes it through PETSCPARTITIONERSHELL,
   builds each rank's element data from its cells and assembles the lumped
   masses. Positions start at the reference positions, velocities at 0. */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetUp(FDEMDeformable dfm);

PETSC_EXTERN PetscErrorCode FDEMDeformableGetDM(FDEMDeformable dfm, DM *dm);
/* Local (this rank's) and global counts of cells and nodes (owned nodes for nlocal). */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetSizes(FDEMDeformable dfm, PetscInt *cells_local, PetscInt *cells_global, PetscInt *nodes_owned, PetscInt *nodes_global);
/* Global ids of the owned nodes, in the order of the DM's global vectors (borrowed). */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetNodeIds(FDEMDeformable dfm, PetscInt *n, const PetscInt *ids[]);
/* The DM's global vectors (borrowed; 3 entries per owned node): current
   positions x, velocities v, reference positions X, lumped masses m (same in
   all three entries of a node). Changing x or v changes the initial state of
   the next FDEMDeformableSetUpTS. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetPositions(FDEMDeformable dfm, Vec *x);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetVelocities(FDEMDeformable dfm, Vec *v);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetReferencePositions(FDEMDeformable dfm, Vec *X);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetMasses(FDEMDeformable dfm, Vec *m);
/* Sets x (or v) of every node from its reference position. */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetPositionField(FDEMDeformable dfm, FDEMDeformableFieldFn fn, void *ctx);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetVelocityField(FDEMDeformable dfm, FDEMDeformableFieldFn fn, void *ctx);

/* Fixed nodes (Dirichlet: their force is zeroed and their velocity set to 0).
   By global id (any rank may list any id) or every node whose reference
   position lies in the box [lo, hi]. *nfixed (may be NULL) gets the global
   number of fixed nodes. Collective. */
PETSC_EXTERN PetscErrorCode FDEMDeformableFixNodes(FDEMDeformable dfm, PetscInt n, const PetscInt ids[], PetscInt *nfixed);
PETSC_EXTERN PetscErrorCode FDEMDeformableFixNodesInBox(FDEMDeformable dfm, const PetscReal lo[3], const PetscReal hi[3], PetscInt *nfixed);
/* Moved nodes (a prescribed-velocity boundary): the listed nodes (global ids, any rank may
   list any id) keep the velocity v for ever, their positions advance with it; like fixed
   nodes they get no acceleration. *nmoved (may be NULL): the number of ids listed that
   exist. The work the held motion does on the rest, the integral of sum R . v over the
   force evaluations (R = -(internal + external + gravity force) of the node; trapezoidal
   rule in time, exact for the impulses of the central-difference scheme), is given by
   GetExternalWork (collective); SetExternalWork restores it on restart. Collective. */
PETSC_EXTERN PetscErrorCode FDEMDeformableMoveNodes(FDEMDeformable dfm, PetscInt n, const PetscInt ids[], const PetscReal v[3], PetscInt *nmoved);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetExternalWork(FDEMDeformable dfm, PetscReal *W);
PETSC_EXTERN PetscErrorCode FDEMDeformableSetExternalWork(FDEMDeformable dfm, PetscReal W);

/* Assembled nodal forces at the state U (a TS state [x | v] from
   FDEMDeformableSetUpTS, or NULL for the stored x, v): F = f_int + f_ext
   (no gravity, no division by mass, fixed nodes included), a DM global vector. */
PETSC_EXTERN PetscErrorCode FDEMDeformableComputeForces(FDEMDeformable dfm, PetscReal t, Vec U, Vec F);
/* Cauchy stress of every local cell (xx, yy, zz, xy, yz, xz): *S is created,
   6 entries per local cell in the order of FDEMDeformableGetCellIds. */
PETSC_EXTERN PetscErrorCode FDEMDeformableComputeCellStress(FDEMDeformable dfm, Vec U, Vec *S);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetCellIds(FDEMDeformable dfm, PetscInt *n, const PetscInt *ids[]);

/* Sets the splits, the RHS functions and the solution of ts; creates *U from
   the stored x, v. The TS must not outlive dfm. */
PETSC_EXTERN PetscErrorCode FDEMDeformableSetUpTS(FDEMDeformable dfm, TS ts, Vec *U);
/* Copies a state U back into the stored x, v (U is kept). */
PETSC_EXTERN PetscErrorCode FDEMDeformableRestoreState(FDEMDeformable dfm, Vec U);

/* Collective diagnostics at U (NULL: stored state). Kinetic energy, strain
   energy (exact potential for neo_hookean and small_strain_linear; for
   munjiza_cst, which is Cauchy-elastic but not hyperelastic, the neo-Hookean
   potential with the same G and K, equal to third order in the strain) and
   gravity potential -sum m g.x. Each output may be NULL; without `strain` the
   elements are not visited (pass NULL the same way on every rank). */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetEnergy(FDEMDeformable dfm, Vec U, PetscReal *kinetic, PetscReal *strain, PetscReal *gravity);
/* Total mass, centre of mass, linear momentum and angular momentum about the origin. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetMomentum(FDEMDeformable dfm, Vec U, PetscReal *mass, PetscReal com[3], PetscReal P[3], PetscReal L[3]);
/* Position and velocity of node `id` (global id), wherever it lives. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetNodeState(FDEMDeformable dfm, Vec U, PetscInt id, PetscReal x[3], PetscReal v[3]);
/* Smallest det F over all elements and the global id of that element. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetMinJacobian(FDEMDeformable dfm, Vec U, PetscReal *Jmin, PetscInt *element);

/* HDF5 + XDMF output of the deforming mesh at U (NULL: stored state): group
   /step_NNNNNN of base.h5 with vertices (current positions), displacement,
   velocity, cells (global vertex numbers), body, rank and stress (per cell);
   base.xmf (rewritten by rank 0 at each call) is a temporal collection that
   ParaView opens. */
PETSC_EXTERN PetscErrorCode FDEMDeformableWriteHDF5(FDEMDeformable dfm, Vec U, const char *base, PetscInt step, PetscReal t);

/* ---- developer section ---------------------------------------------------
   For code built on FDEMDeformable (contact, scenes); not needed to run a
   simulation. Defined in src/model/deformable.cpp.
   GetLocalCells: this rank's cells with their 4 local node indices (the node
   numbering of the local vectors of the external-force hook; positive
   reference volume), body, global element id, and the global id of every
   local node; any array may be NULL (call first with NULL arrays for the
   sizes). GetBodyName: the name of body `body` ("?" if out of range) and the
   number of bodies. Both after FDEMDeformableSetUp. */
PETSC_EXTERN PetscErrorCode FDEMDeformableGetLocalCells(FDEMDeformable dfm, PetscInt *ncells, PetscInt *nlocal, PetscInt conn[], PetscInt body[], PetscInt cell_gid[], PetscInt node_gid[]);
PETSC_EXTERN PetscErrorCode FDEMDeformableGetBodyName(FDEMDeformable dfm, PetscInt body, PetscInt *nbodies, const char **name);

#if defined(__cplusplus)
}
#endif
#endif
