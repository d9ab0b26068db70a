// The builder: the only file of the driver that calls the fdem library
// (FDEMRigid, FDEMContact, FDEMDeformable, FDEMDeformableContact, FDEMScene),
// so a change of the library's API is a local edit here. It turns a checked
// Scene and its meshes into models and one TS, and answers the run loop's
// questions (energies, momenta, output, migration).
#pragma once
#include "scene.hpp"

#include <fdem/kernels/tetmesh.hpp>
#include <petscts.h>

#include <string>
#include <vector>

struct _n_FDEMRigid;
struct _n_FDEMContact;
struct _n_FDEMDeformable;
struct _n_FDEMDeformableContact;
struct _n_FDEMScene;

namespace fdem::driver {

// One row of out/balance.csv (see doc/scenes.md).
struct Balance {
  double t = 0, kinetic = 0, strain = 0, contact = 0, gravity = 0, fracture = 0, external_work = 0, dissipated = 0, total = 0, P[3] = {0, 0, 0}, L[3] = {0, 0, 0};
};

// What limits the time step.
struct StableStep {
  double      dt = 0, kcrit = 0, omega_elements = 0, omega_contact = 0, omega_joints = 0;
  std::string limit; // "elements of body B", "contact", ...
};

struct Sim {
  MPI_Comm                      comm = MPI_COMM_NULL;
  const Scene                  *scene = nullptr;
  std::vector<kernels::TetMesh> meshes; // per scene body, in its shape's frame
  _n_FDEMRigid                 *rb    = nullptr;
  _n_FDEMContact               *rc    = nullptr; // rigid-rigid contact
  _n_FDEMDeformable            *dfm   = nullptr;
  _n_FDEMDeformableContact     *dc    = nullptr; // deformable-deformable contact
  _n_FDEMScene                 *sc    = nullptr;
  TS                            ts    = nullptr;
  Vec                           U     = nullptr;
  std::vector<int>              rigid_bodies, deformable_bodies; // scene body indices per model
  PetscInt                      nrigid = 0, ntets = 0, nnodes = 0, ndofs = 0, nfixed_nodes = 0, nmoved_nodes = 0, njoints = 0; // nnodes: after any split
  double                        E0    = 0; // total energy at the start (for `dissipated`)
  bool                          have_E0 = false;
  bool                          inserting = false; // some deformable body gets joints during the run
};

// Builds the models of the scene (only those it uses). Collective.
// fracture_cells: tetrahedra of bodies with joints inserted during the run that are split
// already (FDEMDeformableAddFractureCells; from a checkpoint or an insertion). previous: the
// model of the same scene this one replaces (an insertion), whose set-up products it may reuse.
// sim.rb (and sim.rc) set beforehand: that rigid bodies' model (and contact) is kept, not built.
PetscErrorCode SimBuild(MPI_Comm comm, const Scene &scene, std::vector<kernels::TetMesh> meshes, Sim &sim, const std::vector<PetscInt> &fracture_cells = {}, _n_FDEMDeformable *previous = nullptr);
// Creates sim.ts (type `scheme`) and sim.U from the models' stored state. Time and step as given.
PetscErrorCode SimSetUpTS(Sim &sim, const char *scheme, PetscReal t, PetscInt step);
// Copies sim.U back into the models, destroys the TS and U.
PetscErrorCode SimEndTS(Sim &sim);
// Copies sim.U into the models (keeps the TS).
PetscErrorCode SimRestore(Sim &sim);
// Sends rigid bodies to the ranks of a new partition (between TSs, after SimEndTS).
PetscErrorCode SimMigrate(Sim &sim);
PetscBool      SimNeedsMigration(const Sim &sim);
PetscErrorCode SimMigrationDue(Sim &sim, PetscBool *due); // at a segment's end, after SimBalance or SimRestore
// Stable time step of the scene for `scheme` after SimSetUpTS (safety * K_crit / omega_max).
PetscErrorCode SimStableStep(Sim &sim, const char *scheme, PetscReal safety, StableStep &st);
// Energy and momentum balance at the TS state (collective; b.t must be set).
PetscErrorCode SimBalance(Sim &sim, Balance &b);
// Appends step `step` at time t to the HDF5 + XDMF files in dir (rigid.h5/xmf, mesh.h5/xmf).
PetscErrorCode SimWriteOutput(Sim &sim, const std::string &dir, PetscInt step, PetscReal t);
// Checkpoint of the models' stored state (call after SimRestore/SimEndTS): one HDF5 file through
// PETSc's viewer, with the mesh's x, v by node id, the rigid bodies' x, R, v, H by body id and
// meta = [t, step, E0, dt, external work]. Written by the caller to a temporary name and renamed.
PetscErrorCode SimWriteCheckpoint(Sim &sim, const char *file, PetscReal t, PetscInt step, PetscReal dt);
// Loads a checkpoint into the models (any rank count) and migrates the rigid bodies; gives t, step and dt.
PetscErrorCode SimReadCheckpoint(Sim &sim, const char *file, PetscReal *t, PetscInt *step, PetscReal *dt);
// The tetrahedra split by insertion when a checkpoint was written (none for a run without).
PetscErrorCode SimReadFractureCells(MPI_Comm comm, const char *file, std::vector<PetscInt> &cells);
// Joints inserted during the run (doc/fracture.md): the whole tetrahedra whose stress nears
// the strength, with their neighbours (the same list on every rank; after SimRestore).
PetscErrorCode SimFindCellsToSplit(Sim &sim, std::vector<PetscInt> &cells);
// Builds the scene again with `cells` split too and carries the state over from the old
// model, as a checkpoint it wrote would (no file); sim is then the new one, with its output
// continuing the old one's files. Call after SimEndTS; then SimSetUpTS. Collective.
PetscErrorCode SimInsertJoints(Sim &sim, const std::vector<PetscInt> &cells);
PetscErrorCode SimDestroy(Sim &sim);
// Names of rigid body `id` (the library's numbering) in the scene.
std::string RigidBodyName(const Sim &sim, PetscInt id);

// Element frequency 2 c_p / h_min of a mesh of a material (c_p: P-wave speed, h_min: smallest altitude).
double ElementFrequency(const kernels::TetMesh &m, const Material &mat);

} // namespace fdem::driver
