// Internal: the rigid-body container shared by src/model/rigid*.cpp.
#pragma once
#include "work_meter.hpp"
#include <fdem/rigid.h>
#include <fdem/kernels/granular.hpp>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/vec3.hpp>

#include <array>
#include <map>
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
  // a clump (FDEMRigidAddClump): its spheres, centre and radius in the body frame; nodes and
  // faces then draw each sphere as an octahedron for output, and there are no tetrahedra
  std::vector<std::array<double, 4>> balls;
  // the contact primitives the skin lends: its tetrahedra, or its spheres
  size_t Primitives() const { return tets.size() + balls.size(); }
};
// The octahedron of unit radius (nodes and outward faces) that draws a sphere in the output.
const Skin &UnitOctahedron();
// The named layout of n rigid bodies' state and of the arrays of the split RHS:
//   state     U = [x (3n) | R (9n) | v (3n) | H (3n)]   centre, orientation (row-major,
//                                                        body to space), velocity, space-frame
//                                                        angular momentum
//   positions Q = [x | R] (the first 12n entries of U)
//   forces    A = [F (3n) | M (3n)]                     (or F/m and M in the momentum RHS)
// RigidLayout(n).x(u, b) is the address of body b's x in u, and so on.
struct RigidLayout {
  PetscInt n;
  explicit RigidLayout(PetscInt nbodies) : n(nbodies) {}
  static constexpr PetscInt state_size = 18, position_size = 12, force_size = 6; // per body
  template <class T> T *x(T *u, PetscInt b) const { return u + 3 * b; }
  template <class T> T *R(T *u, PetscInt b) const { return u + 3 * n + 9 * b; }
  template <class T> T *v(T *u, PetscInt b) const { return u + 12 * n + 3 * b; }
  template <class T> T *H(T *u, PetscInt b) const { return u + 15 * n + 3 * b; }
  template <class T> T *F(T *a, PetscInt b) const { return a + 3 * b; }
  template <class T> T *M(T *a, PetscInt b) const { return a + 3 * n + 3 * b; }
};
inline Vec3 ToVec3(const PetscScalar *p) { return Vec3(PetscRealPart(p[0]), PetscRealPart(p[1]), PetscRealPart(p[2])); }
inline Mat3 ToMat3(const PetscScalar *p) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = PetscRealPart(p[3 * r + c]);
  return M;
}

// The skin index of a sphere body (a body without contact skin has -1).
constexpr PetscInt kSphereSkin = -2;
// Bytes per body of the swarm field "history": the tangential springs of a sphere's granular
// contacts (the contact engine's slots, src/contact/engine.hpp), carried when it migrates.
constexpr size_t kHistoryBytes = 12 * 32;

struct OutputRecord {
  PetscInt  step;
  PetscReal t;
  PetscInt  nvert, ntri;
};

// One term of a rigid model's force chain. A model term (contact) adds the forces and
// torques of all local bodies at once, FM += [F | M] (RigidLayout) at positions q = [x | R],
// and may be told when the local bodies change (setup, at FDEMRigidSetUpTS); a body term
// is a user's FDEMRigidForceFn, called per body after the model terms and gravity.
struct RigidForceTerm {
  PetscErrorCode (*model)(FDEMRigid, PetscReal t, const PetscScalar *q, PetscScalar *FM, void *ctx) = nullptr;
  PetscErrorCode (*setup)(FDEMRigid, void *ctx)                                                      = nullptr;
  PetscErrorCode (*store)(FDEMRigid, void *ctx)                                                      = nullptr; // the state goes back to the swarm: write what the term keeps of it (contact springs)
  FDEMRigidForceFn body                                                                              = nullptr;
  void            *ctx                                                                               = nullptr;
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
  PetscReal         lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  int               axis = -1; // slab axis; -1: rank 0 holds everything
  PetscBool         periodic[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}; // periodic along axis k with period hi - lo (FDEMRigidSetPeriodic)
  // the partition (FDEMRigidMigrate): a recursive coordinate bisection of the moving bodies'
  // centres, weighted by their contact primitives; node 0 is the root, a leaf names its rank.
  // Empty (before the first migration, or fewer moving bodies than ranks): equal slabs of
  // [lo, hi] along `axis`.
  struct RcbNode {
    int       axis = -1, left = -1, right = -1; // axis < 0: a leaf
    PetscReal cut  = 0;                         // x[axis] < cut: left
    int       rank = 0;
  };
  std::vector<RcbNode> rcb;
  PetscInt          next_id = 0;
  std::vector<Skin> skins; // replicated: every rank adds every body
  // granular materials and each body's (by id; -1: none), replicated
  std::vector<fdem::kernels::GranularMaterial> gmats;
  std::vector<std::string>                     gmat_names;
  std::vector<PetscInt>                        gmat;
  std::vector<fdem::kernels::GranularPair>     gtable; // every pair mixed (the contact engine's), made for gtable_n materials
  size_t                                       gtable_n = 0;
  PetscInt                                     nspheres = 0; // sphere bodies and clumps added (every rank): bodies with granular contact
  std::map<std::vector<double>, fdem::kernels::MassProperties> clump_props; // a clump's shape (its spheres over its first radius) at unit size and density (FDEMRigidAddClump)
  // while a TS runs
  PetscInt               n = 0; // local bodies
  std::vector<PetscReal> mass, inertia;
  std::vector<PetscInt>  ids;
  // output
  std::vector<OutputRecord> outputs;
  // fixed bodies (walls, floors): never moved by forces
  std::vector<PetscInt> fixed;      // per local body while a TS runs (1 = fixed or moved)
  std::vector<char>     sphere;     // per local body while a TS runs: a sphere
  std::vector<PetscReal> load;      // per local body: the force on it at the last evaluation (3 each; FDEMRigidGetBodyForce)
  PetscBool             sphere_orientation = PETSC_FALSE; // turn the spheres' R too (-fdem_rigid_sphere_orientation)
  PetscBool             weight_pairs = PETSC_TRUE; // partition weights: contact pairs measured at the last search (-fdem_rigid_partition_pairs)
  std::vector<PetscReal> mesh_work;                 // per local body: its pairs in the rigid-mesh contact of a combined scene at its last search (until the next migration)
  PetscBool             weight_timed = PETSC_FALSE; // partition weights in measured CPU seconds (-fdem_rigid_partition_timed)
  double                cpu_mark = -1, cpu_terms = 0; // CPU seconds (this rank): at the last partition; in the model force terms since
  PetscReal             cost_primitive = 0, cost_pair = 0; // the last measured costs (s per primitive-step, per pair-step summed over the segment; 0: none)
  // moved bodies (FDEMRigidMoveBody): fixed bodies with a held velocity; the power of their
  // reactions at the last force evaluation (this rank) and its time integral
  PetscReal              power = 0;
  bool                   moved = false;
  fdem::model::WorkMeter meter;
  Vec                   U = nullptr; // the TS state while a TS runs (borrowed)
  // the force chain: every term adds, none replaces (gravity comes first, from g)
  std::vector<fdem::model::RigidForceTerm> forces;
  std::vector<PetscScalar>                 FM;
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
// The rb->n local bodies between the swarm and a state u = [x | R | v | H] (RigidLayout):
// Load writes u and sets rb's mass, inertia, ids and fixed; Store writes the swarm.
PetscErrorCode RigidLoadState(FDEMRigid rb, PetscScalar *u);
PetscErrorCode RigidStoreState(FDEMRigid rb, const PetscScalar *u);
// Tells the force chain's terms that the local bodies changed (at a TS set-up).
PetscErrorCode RigidForcesSetUp(FDEMRigid rb);
} // namespace fdem::model

// The rigid model's split RHS and drift, for a combined state assembled
// elsewhere (src/scene): Q = [x (3n) | R (9n)], A = [F/m (3n) | M (3n)], U =
// [x | R | v | H] of rb->n bodies; rb->n, mass, inertia, ids and fixed must be
// set (as FDEMRigidSetUpTS does) and rb->U must hold the velocities for contact.
namespace fdem::model {
PetscErrorCode RigidRHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *rb);
PetscErrorCode RigidDrift(TS ts, PetscReal t, PetscReal s, Vec U, void *rb);
// After RigidRHSMomentum (which sets rb->power from gravity and the force chain): adds the
// power extra of forces added since on the moved bodies (contact) and samples the work meter.
void RigidSampleWork(FDEMRigid rb, PetscReal t, PetscReal extra);
} // namespace fdem::model
