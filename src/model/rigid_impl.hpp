// Internal: the rigid-body container shared by src/model/rigid*.cpp.
#pragma once
#include <fdem/rigid.h>
#include <fdem/kernels/vec3.hpp>

#include <array>
#include <string>
#include <vector>

namespace fdem::model {
using fdem::kernels::Mat3;
using fdem::kernels::Vec3;
struct Skin {
  std::string                     name;
  std::vector<Vec3>               nodes; // principal (body) frame, centred at the centre of mass
  std::vector<std::array<int, 3>> faces; // boundary triangles
  std::vector<std::array<int, 4>> tets;
};
struct OutputRecord {
  PetscInt  step;
  PetscReal t;
  PetscInt  nvert, ntri;
};

} // namespace fdem::model

struct _n_FDEMRigid {
  using Skin = fdem::model::Skin;
  using OutputRecord = fdem::model::OutputRecord;
  MPI_Comm          comm;
  PetscMPIInt       rank = 0, size = 1;
  DM                sw = nullptr;
  FDEMRotationType  rotation = FDEM_ROTATION_EXACT;
  PetscReal         g[3] = {0, 0, 0};
  FDEMRigidForceFn  force = nullptr;
  void             *force_ctx = nullptr;
  PetscReal         lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  int               axis = -1; // slab axis; -1: rank 0 holds everything
  PetscInt          next_id = 0;
  std::vector<Skin> skins; // replicated: every rank adds every body
  // while a TS runs
  PetscInt               n = 0; // local bodies
  std::vector<PetscReal> mass, inertia;
  std::vector<PetscInt>  ids;
  // output
  std::vector<OutputRecord> outputs;
  // fixed bodies (walls, floors): never moved by forces
  std::vector<PetscInt> fixed;      // per local body while a TS runs (1 = fixed)
  Vec                   U = nullptr; // the TS state while a TS runs (borrowed)
  // contact (src/contact): adds forces and torques of the local bodies, FM = [F (3n) | M (3n)]
  PetscErrorCode (*contact_fn)(FDEMRigid, PetscReal t, const PetscScalar *q, PetscScalar *FM, void *) = nullptr;
  PetscErrorCode (*contact_setup)(FDEMRigid, void *) = nullptr; // at FDEMRigidSetUpTS
  void *contact_ctx = nullptr;
  std::vector<PetscScalar> FM;
  // where the last FDEMRigidSolve stopped (FDEMRigidGetTime)
  PetscReal solve_time  = 0;
  PetscInt  solve_steps = 0;
};

namespace fdem::model {
struct RigidFields {
  PetscReal *x, *R, *v, *H, *mass, *I, *radius;
  PetscInt  *id, *skin, *fixed;
};
PetscErrorCode RigidGetFields(DM sw, RigidFields &f);
// dq = [v | [omega]x R] of the rb->n local bodies from p = [v | H] and their orientations R9 (9 per body).
void RigidPositionRate(FDEMRigid rb, const PetscScalar *p, const PetscScalar *R9, PetscScalar *dq);
PetscErrorCode RigidRestoreFields(DM sw, RigidFields &f);
} // namespace fdem::model

// The rigid model's split RHS and drift, for a combined state assembled
// elsewhere (src/scene): Q = [x (3n) | R (9n)], A = [F/m (3n) | M (3n)], U =
// [x | R | v | H] of rb->n bodies; rb->n, mass, inertia, ids and fixed must be
// set (as FDEMRigidSetUpTS does) and rb->U must hold the velocities for contact.
namespace fdem::model {
PetscErrorCode RigidRHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *rb);
PetscErrorCode RigidDrift(TS ts, PetscReal t, PetscReal s, Vec U, void *rb);
} // namespace fdem::model
