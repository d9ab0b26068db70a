// Rigid discrete elements in a DMSwarm; see include/fdem/rigid.h.
#include "../util/guard.hpp"
#include "../util/options.hpp"
#include "rigid_impl.hpp"
#include <fdem/ts.h>
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/rotation.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include <time.h>

// CPU seconds of this process (the partition's measured costs).
static double CpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;
using fdem::model::RigidFields;
using Skin = fdem::model::Skin;

const char *const FDEMRotationTypes[] = {"munjiza", "nosquish", "exact", "FDEMRotationType", "FDEM_ROTATION_", nullptr};

namespace {

Mat3 FromRowMajor(const PetscReal *a) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = a[3 * r + c];
  return M;
}
void ToRowMajor(const Mat3 &M, PetscReal *a) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[3 * r + c] = M.m[r][c];
}

fdem::kernels::FreeRotation Kind(FDEMRotationType t) {
  switch (t) {
  case FDEM_ROTATION_MUNJIZA:
    return fdem::kernels::FreeRotation::Munjiza;
  case FDEM_ROTATION_NOSQUISH:
    return fdem::kernels::FreeRotation::NoSquish;
  default:
    return fdem::kernels::FreeRotation::Exact;
  }
}

PetscMPIInt OwnerRank(FDEMRigid rb, const PetscReal x[3]) {
  if (rb->axis < 0 || rb->size == 1) return 0;
  const int a = rb->axis;
  if (!rb->rcb.empty()) {
    int i = 0;
    while (rb->rcb[i].axis >= 0) i = x[rb->rcb[i].axis] < rb->rcb[i].cut ? rb->rcb[i].left : rb->rcb[i].right;
    return (PetscMPIInt)rb->rcb[i].rank;
  }
  const double f = (x[a] - rb->lo[a]) / (rb->hi[a] - rb->lo[a]);
  long         r = (long)std::floor(f * rb->size);
  return (PetscMPIInt)std::min<long>(std::max<long>(r, 0), rb->size - 1);
}

// RHS of the "position" split, dx/dt = v, dR/dt = [omega]x R, called only by
// TS types that move the positions by adding h times it (basicsymplectic).
// That update does not keep R a rotation, so it stops with an error; fdem's
// splitting schemes never call it (they turn R with the drift below).
PetscErrorCode RHSPosition(TS, PetscReal, Vec, Vec, void *ctx) {
  FDEMRigid rb = (FDEMRigid)ctx;
  PetscFunctionBegin;
  SETERRQ(rb->comm, PETSC_ERR_SUP,
          "Rigid bodies: this -ts_type updates the positions additively (q += h dq/dt, as basicsymplectic does), which does not keep the orientations R rotation matrices; rigid orientations need an fdem splitting type that turns R with the free-rotation drift: -ts_type cd, pv, omf30, omf32, chin, fr or pefrl");
}

// RHS of the "momentum" split: (F/m, M) from gravity and the user's force function.
PetscErrorCode RHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *ctx) {
  FDEMRigid          rb = (FDEMRigid)ctx;
  const PetscScalar *q;
  PetscScalar       *a;
  const PetscInt     n = rb->n;
  PetscFunctionBegin;
  PetscCall(VecGetArrayRead(Q, &q));
  PetscCall(VecGetArray(A, &a));
  const fdem::model::RigidLayout L(n);
  const PetscScalar             *u = nullptr; // velocities of the moved bodies, for the power of their reactions
  rb->power                      = 0;
  if (rb->moved && rb->U) PetscCall(VecGetArrayRead(rb->U, &u));
  rb->FM.assign(6 * n, 0.0);
  const double cpu0 = rb->weight_timed ? CpuSeconds() : 0;
  for (const auto &term : rb->forces)
    if (term.model) PetscCall(term.model(rb, t, q, rb->FM.data(), term.ctx));
  if (rb->weight_timed) rb->cpu_terms += CpuSeconds() - cpu0;
  bool body_terms = false; // a user's per-body force function
  for (const auto &term : rb->forces) body_terms = body_terms || term.body;
  const bool       keep_load = (PetscInt)rb->load.size() == 3 * n;
  const PetscReal *FM = rb->FM.data(), *mass = rb->mass.data();
  const PetscInt  *fixed = rb->fixed.data();
  for (PetscInt b = 0; b < n; ++b) {
    PetscReal F[3], M[3];
    for (int k = 0; k < 3; ++k) {
      F[k] = mass[b] * rb->g[k] + PetscRealPart(L.F(FM, b)[k]);
      M[k] = PetscRealPart(L.M(FM, b)[k]);
    }
    if (body_terms)
      for (const auto &term : rb->forces)
        if (term.body) PetscCall(term.body(rb->ids[b], t, L.x(q, b), L.R(q, b), nullptr, nullptr, F, M, term.ctx));
    if (keep_load)
      for (int k = 0; k < 3; ++k) rb->load[3 * b + k] = F[k];
    if (fixed[b]) {
      for (int k = 0; k < 3; ++k) L.F(a, b)[k] = L.M(a, b)[k] = 0.0;
      if (u)
        for (int k = 0; k < 3; ++k) rb->power -= F[k] * PetscRealPart(L.v(u, b)[k]); // reaction R = -F
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      L.F(a, b)[k] = F[k] / mass[b];
      L.M(a, b)[k] = M[k];
    }
  }
  if (u) PetscCall(VecRestoreArrayRead(rb->U, &u));
  PetscCall(VecRestoreArray(A, &a));
  PetscCall(VecRestoreArrayRead(Q, &q));
  PetscFunctionReturn(0);
}

// The TS's momentum RHS of a rigid-only TS: RHSMomentum, then the work of the moved bodies.
PetscErrorCode RHSMomentumWithWork(TS ts, PetscReal t, Vec Q, Vec A, void *ctx) {
  PetscFunctionBegin;
  PetscCall(RHSMomentum(ts, t, Q, A, ctx));
  fdem::model::RigidSampleWork((FDEMRigid)ctx, t, 0);
  PetscFunctionReturn(0);
}

// Drift of length s: x += s v, R <- torque-free rotation with H fixed.
PetscErrorCode Drift(TS ts, PetscReal, PetscReal s, Vec U, void *ctx) {
  FDEMRigid      rb = (FDEMRigid)ctx;
  PetscScalar   *u;
  const PetscInt n = rb->n;
  PetscFunctionBegin;
  PetscCall(VecGetArray(U, &u));
  const auto kind = Kind(rb->rotation);
  PetscCall(fdem::Guard(rb->comm, [&]() -> PetscErrorCode {
    for (PetscInt b = 0; b < n; ++b) {
      PetscScalar *x = &u[3 * b], *R = &u[3 * n + 9 * b], *v = &u[12 * n + 3 * b], *H = &u[15 * n + 3 * b];
      if (rb->fixed[b]) { // a moved body translates at its held velocity (0 for a fixed one)
        if (rb->moved)
          for (int k = 0; k < 3; ++k) x[k] += s * v[k];
        continue;
      }
      for (int k = 0; k < 3; ++k) x[k] += s * v[k];
      if (rb->sphere[b] && !rb->sphere_orientation) continue; // a sphere's contacts do not see its orientation (omega = H / I all the same)
      const Vec3 I(rb->inertia[3 * b], rb->inertia[3 * b + 1], rb->inertia[3 * b + 2]);
      try {
        ToRowMajor(fdem::kernels::FreeRotate(kind, FromRowMajor(R), I, Vec3(H[0], H[1], H[2]), s), R);
      } catch (const fdem::kernels::InputError &e) {
        throw fdem::kernels::InputError("rigid body " + std::to_string(b < (PetscInt)rb->ids.size() ? rb->ids[b] : -1) + ": " + e.what());
      }
    }
    return 0;
  }));
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

} // namespace

void fdem::model::RigidPositionRate(FDEMRigid rb, const PetscScalar *p, const PetscScalar *R9, PetscScalar *dq) {
  const PetscInt n = rb->n;
  for (PetscInt b = 0; b < n; ++b) {
    for (int k = 0; k < 3; ++k) dq[3 * b + k] = p[3 * b + k];
    const Mat3 R = FromRowMajor(&R9[9 * b]);
    const Vec3 I(rb->inertia[3 * b], rb->inertia[3 * b + 1], rb->inertia[3 * b + 2]);
    const Vec3 w = fdem::kernels::SpaceOmega(R, I, Vec3(p[3 * n + 3 * b], p[3 * n + 3 * b + 1], p[3 * n + 3 * b + 2]));
    for (int c = 0; c < 3; ++c) {
      const Vec3 d = fdem::kernels::cross(w, R.col(c));
      for (int r = 0; r < 3; ++r) dq[3 * n + 9 * b + 3 * r + c] = d[r];
    }
  }
}

const fdem::model::Skin &fdem::model::UnitOctahedron() {
  static const fdem::model::Skin oct = [] {
    fdem::model::Skin s;
    s.name  = "octahedron";
    s.nodes = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
    // outward normals: (b - a) x (c - a) points away from the centre
    s.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    return s;
  }();
  return oct;
}

PetscErrorCode fdem::model::RigidGetFields(DM sw, RigidFields &f) {
  PetscFunctionBegin;
  PetscCall(DMSwarmGetField(sw, "x", nullptr, nullptr, (void **)&f.x));
  PetscCall(DMSwarmGetField(sw, "R", nullptr, nullptr, (void **)&f.R));
  PetscCall(DMSwarmGetField(sw, "v", nullptr, nullptr, (void **)&f.v));
  PetscCall(DMSwarmGetField(sw, "H", nullptr, nullptr, (void **)&f.H));
  PetscCall(DMSwarmGetField(sw, "mass", nullptr, nullptr, (void **)&f.mass));
  PetscCall(DMSwarmGetField(sw, "inertia", nullptr, nullptr, (void **)&f.I));
  PetscCall(DMSwarmGetField(sw, "radius", nullptr, nullptr, (void **)&f.radius));
  PetscCall(DMSwarmGetField(sw, "id", nullptr, nullptr, (void **)&f.id));
  PetscCall(DMSwarmGetField(sw, "skin", nullptr, nullptr, (void **)&f.skin));
  PetscCall(DMSwarmGetField(sw, "fixed", nullptr, nullptr, (void **)&f.fixed));
  PetscFunctionReturn(0);
}
PetscErrorCode fdem::model::RigidRestoreFields(DM sw, RigidFields &f) {
  PetscFunctionBegin;
  PetscCall(DMSwarmRestoreField(sw, "x", nullptr, nullptr, (void **)&f.x));
  PetscCall(DMSwarmRestoreField(sw, "R", nullptr, nullptr, (void **)&f.R));
  PetscCall(DMSwarmRestoreField(sw, "v", nullptr, nullptr, (void **)&f.v));
  PetscCall(DMSwarmRestoreField(sw, "H", nullptr, nullptr, (void **)&f.H));
  PetscCall(DMSwarmRestoreField(sw, "mass", nullptr, nullptr, (void **)&f.mass));
  PetscCall(DMSwarmRestoreField(sw, "inertia", nullptr, nullptr, (void **)&f.I));
  PetscCall(DMSwarmRestoreField(sw, "radius", nullptr, nullptr, (void **)&f.radius));
  PetscCall(DMSwarmRestoreField(sw, "id", nullptr, nullptr, (void **)&f.id));
  PetscCall(DMSwarmRestoreField(sw, "skin", nullptr, nullptr, (void **)&f.skin));
  PetscCall(DMSwarmRestoreField(sw, "fixed", nullptr, nullptr, (void **)&f.fixed));
  PetscFunctionReturn(0);
}

namespace {
PetscErrorCode AddLocal(FDEMRigid rb, PetscInt skin, PetscReal mass, const Vec3 &I, const PetscReal x[3], const Mat3 &R, const PetscReal v[3], const PetscReal omega[3], PetscReal radius, PetscInt *id) {
  const PetscInt myid = rb->next_id++;
  PetscFunctionBegin;
  if (id) *id = myid;
  if (OwnerRank(rb, x) != rb->rank) PetscFunctionReturn(0);
  PetscInt n;
  RigidFields f;
  PetscCall(DMSwarmAddPoint(rb->sw));
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  const PetscInt b = n - 1;
  const Vec3     H = fdem::kernels::AngularMomentum(R, I, Vec3(omega[0], omega[1], omega[2]));
  for (int k = 0; k < 3; ++k) {
    f.x[3 * b + k] = x[k];
    f.v[3 * b + k] = v[k];
    f.H[3 * b + k] = H[k];
    f.I[3 * b + k] = I[k];
  }
  ToRowMajor(R, &f.R[9 * b]);
  f.mass[b]   = mass;
  f.radius[b] = radius;
  f.id[b]     = myid;
  f.skin[b]   = skin;
  f.fixed[b]  = 0;
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  char *hist;
  PetscCall(DMSwarmGetField(rb->sw, "history", nullptr, nullptr, (void **)&hist));
  std::memset(hist + fdem::model::kHistoryBytes * (size_t)b, 0, fdem::model::kHistoryBytes);
  PetscCall(DMSwarmRestoreField(rb->sw, "history", nullptr, nullptr, (void **)&hist));
  PetscInt *image;
  PetscCall(DMSwarmGetField(rb->sw, "image", nullptr, nullptr, (void **)&image));
  for (int k = 0; k < 3; ++k) image[3 * b + k] = 0;
  PetscCall(DMSwarmRestoreField(rb->sw, "image", nullptr, nullptr, (void **)&image));
  PetscReal *x0;
  PetscCall(DMSwarmGetField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  for (int k = 0; k < 3; ++k) x0[3 * b + k] = x[k];
  PetscCall(DMSwarmRestoreField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  PetscReal *work;
  PetscCall(DMSwarmGetField(rb->sw, "work", nullptr, nullptr, (void **)&work));
  work[b] = 0;
  PetscCall(DMSwarmRestoreField(rb->sw, "work", nullptr, nullptr, (void **)&work));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FDEMRigidCreate(MPI_Comm comm, FDEMRigid *out) {
  PetscFunctionBegin;
  FDEMRigid rb = new (std::nothrow) _n_FDEMRigid();
  PetscCheck(rb, comm, PETSC_ERR_MEM, "Out of memory");
  rb->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &rb->rank));
  PetscCallMPI(MPI_Comm_size(comm, &rb->size));
  PetscCall(DMCreate(comm, &rb->sw));
  PetscCall(PetscObjectSetName((PetscObject)rb->sw, "rigid bodies"));
  PetscCall(DMSetType(rb->sw, DMSWARM));
  PetscCall(DMSetDimension(rb->sw, 3));
  PetscCall(DMSwarmSetType(rb->sw, DMSWARM_BASIC));
  PetscCall(DMSwarmInitializeFieldRegister(rb->sw));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "x", 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "R", 9, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "v", 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "H", 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "mass", 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "inertia", 3, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "radius", 1, PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "id", 1, PETSC_INT));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "skin", 1, PETSC_INT));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "fixed", 1, PETSC_INT));
  PetscCall(DMSwarmRegisterUserStructField(rb->sw, "history", fdem::model::kHistoryBytes));
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "image", 3, PETSC_INT)); // periods crossed (FDEMRigidSetPeriodic)
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "work", 1, PETSC_REAL));  // contact pairs at the last search (the partition's weight; 0: not measured)
  PetscCall(DMSwarmRegisterPetscDatatypeField(rb->sw, "x_migrated", 3, PETSC_REAL)); // the centre at the last migration (FDEMRigidMigrationNeeded; not in checkpoints: a restart migrates)
  PetscCall(DMSwarmFinalizeFieldRegister(rb->sw));
  PetscCall(DMSwarmSetLocalSizes(rb->sw, 0, 16));
  *out = rb;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidDestroy(FDEMRigid *rb) {
  PetscFunctionBegin;
  if (!*rb) PetscFunctionReturn(0);
  PetscCall(DMDestroy(&(*rb)->sw));
  delete *rb;
  *rb = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetRotationType(FDEMRigid rb, FDEMRotationType type) {
  PetscFunctionBegin;
  rb->rotation = type;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetRotationType(FDEMRigid rb, FDEMRotationType *type) {
  PetscFunctionBegin;
  *type = rb->rotation;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetGravity(FDEMRigid rb, const PetscReal g[3]) {
  PetscFunctionBegin;
  for (int k = 0; k < 3; ++k) rb->g[k] = g[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddForce(FDEMRigid rb, FDEMRigidForceFn fn, void *ctx) {
  fdem::model::RigidForceTerm term;
  PetscFunctionBegin;
  PetscCheck(fn, rb->comm, PETSC_ERR_ARG_NULL, "FDEMRigidAddForce: the force function is NULL");
  term.body = fn;
  term.ctx  = ctx;
  rb->forces.push_back(term);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetForceFunction(FDEMRigid rb, FDEMRigidForceFn fn, void *ctx) { return FDEMRigidAddForce(rb, fn, ctx); }

PetscErrorCode FDEMRigidSetFromOptions(FDEMRigid rb) {
  PetscFunctionBegin;
  PetscOptionsBegin(rb->comm, nullptr, "fdem rigid bodies", "FDEMRigid");
  PetscCall(PetscOptionsEnum("-fdem_rigid_rotation", "Free rotation of the drift: munjiza (book 5.2.10, order 2), nosquish (symplectic, order 2), exact (Jacobi elliptic)", "FDEMRigidSetRotationType",
                             FDEMRotationTypes, (PetscEnum)rb->rotation, (PetscEnum *)&rb->rotation, nullptr));
  PetscCall(PetscOptionsBool("-fdem_rigid_partition_pairs", "Weigh each body in the partition by the contact pairs it took part in at the last search (false: by its contact primitives only)", "FDEMRigidMigrate", rb->weight_pairs, &rb->weight_pairs, nullptr));
  PetscCall(PetscOptionsBool("-fdem_rigid_partition_timed", "Weigh each body in the partition by measured CPU time: its primitives times the time per primitive and its pairs times the time per pair, both measured over the last segment on every rank (not reproducible to the bit from run to run)", "FDEMRigidMigrate", rb->weight_timed, &rb->weight_timed, nullptr));
  PetscCall(PetscOptionsBool("-fdem_rigid_sphere_orientation", "Turn the spheres' orientation R with their spin (for output; their contacts do not need it)", "FDEMRigidAddSphere", rb->sphere_orientation, &rb->sphere_orientation, nullptr));
  PetscCall(fdem::OptionsVector3(PetscOptionsObject, rb->comm, "-fdem_rigid_gravity", "gx,gy,gz", "Gravity acceleration gx,gy,gz", "FDEMRigidSetGravity", rb->g));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetDomain(FDEMRigid rb, const PetscReal lo[3], const PetscReal hi[3]) {
  PetscInt n;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetSize(rb->sw, &n));
  PetscCheck(n == 0, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMRigidSetDomain: set the domain before adding bodies");
  int a = 0;
  for (int k = 0; k < 3; ++k) {
    PetscCheck(hi[k] > lo[k], rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSetDomain: the box is empty along axis %d (lo %g, hi %g)", k, (double)lo[k], (double)hi[k]);
    rb->lo[k] = lo[k];
    rb->hi[k] = hi[k];
    if (hi[k] - lo[k] > hi[a] - lo[a]) a = k;
  }
  rb->axis = a;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddBody(FDEMRigid rb, const char *name, PetscReal mass, const PetscReal I[3], const PetscReal x[3], const PetscReal R[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id) {
  const char *nm = name ? name : "(unnamed)";
  PetscFunctionBegin;
  PetscCheck(std::isfinite(mass) && mass > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Rigid body %s (id %" PetscInt_FMT "): mass %g must be positive", nm, rb->next_id, (double)mass);
  const double Imax = std::max({I[0], I[1], I[2]});
  for (int k = 0; k < 3; ++k)
    PetscCheck(std::isfinite(I[k]) && I[k] > 1e-12 * Imax && I[k] > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Rigid body %s (id %" PetscInt_FMT "): principal moment I%d = %g is not positive (degenerate inertia)", nm,
               rb->next_id, k + 1, (double)I[k]);
  PetscCheck(I[0] + I[1] >= I[2] * (1 - 1e-12) && I[1] + I[2] >= I[0] * (1 - 1e-12) && I[0] + I[2] >= I[1] * (1 - 1e-12), rb->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "Rigid body %s (id %" PetscInt_FMT "): principal moments (%g, %g, %g) violate the triangle inequality; no mass distribution has them", nm, rb->next_id, (double)I[0], (double)I[1], (double)I[2]);
  const Mat3 Rm = R ? FromRowMajor(R) : Mat3::identity();
  PetscCheck(fdem::kernels::OrthonormalityError(Rm) < 1e-10 && fdem::kernels::det(Rm) > 0, rb->comm, PETSC_ERR_ARG_WRONG, "Rigid body %s (id %" PetscInt_FMT "): the orientation is not a rotation matrix", nm, rb->next_id);
  const PetscReal zero[3] = {0, 0, 0};
  const PetscReal r       = std::sqrt(2.5 * Imax / mass); // a sphere's radius for the largest moment
  PetscCall(AddLocal(rb, -1, mass, Vec3(I[0], I[1], I[2]), x, Rm, v ? v : zero, omega ? omega : zero, r, id));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMGranularMaterialInitialize(FDEMGranularMaterial *m) {
  PetscFunctionBegin;
  m->law     = FDEM_GRANULAR_HERTZ;
  m->law_set = PETSC_FALSE;
  m->young = m->poisson = m->kn = m->kt = m->gamma_n = m->gamma_t = -1;
  m->restitution = m->friction = m->rolling_friction = -1;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddGranularMaterial(FDEMRigid rb, const char *name, const FDEMGranularMaterial *m, PetscInt *index) {
  fdem::kernels::GranularMaterial g;
  const char                     *nm = name ? name : "(unnamed)";
  PetscFunctionBegin;
  auto given = [](PetscReal v) { return std::isfinite(v) && v >= 0; };
  PetscCheck(!(m->restitution >= 0) || (m->restitution > 0 && m->restitution <= 1), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Granular material %s: restitution %g is not in (0, 1]", nm, (double)m->restitution);
  for (PetscReal v : {m->young, m->poisson, m->kn, m->kt, m->gamma_n, m->gamma_t, m->restitution, m->friction, m->rolling_friction})
    PetscCheck(!std::isnan(v) && !std::isinf(v), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Granular material %s: a value is not finite", nm);
  g.law_set         = m->law_set;
  g.law             = m->law == FDEM_GRANULAR_HOOKE ? fdem::kernels::GranularLaw::Hooke : fdem::kernels::GranularLaw::Hertz;
  g.young           = given(m->young) ? m->young : 0;
  g.poisson         = m->poisson > -1 && m->poisson < 0.5 && m->young >= 0 ? m->poisson : 0;
  g.kn              = given(m->kn) ? m->kn : 0;
  g.kt              = given(m->kt) ? m->kt : 0;
  g.gamma_n         = given(m->gamma_n) ? m->gamma_n : 0;
  g.gamma_t         = given(m->gamma_t) ? m->gamma_t : 0;
  g.has_restitution = given(m->restitution);
  g.restitution     = g.has_restitution ? m->restitution : 0;
  g.has_friction    = given(m->friction);
  g.friction        = g.has_friction ? m->friction : 0;
  g.has_rolling     = given(m->rolling_friction);
  g.rolling_friction = g.has_rolling ? m->rolling_friction : 0;
  rb->gmats.push_back(g);
  rb->gmat_names.push_back(nm);
  if (index) *index = (PetscInt)rb->gmats.size() - 1;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetBodyMaterial(FDEMRigid rb, PetscInt id, PetscInt material) {
  PetscFunctionBegin;
  PetscCheck(id >= 0 && id < rb->next_id, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSetBodyMaterial: no body %" PetscInt_FMT, id);
  PetscCheck(material >= -1 && material < (PetscInt)rb->gmats.size(), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSetBodyMaterial: body %" PetscInt_FMT ": no granular material %" PetscInt_FMT " (%zu added)", id, material, rb->gmats.size());
  if ((PetscInt)rb->gmat.size() < rb->next_id) rb->gmat.resize(rb->next_id, -1);
  rb->gmat[id] = material;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddSphere(FDEMRigid rb, const char *name, PetscReal radius, PetscReal density, PetscInt material, const PetscReal x[3], const PetscReal v[3], const PetscReal omega[3], PetscInt *id) {
  const char     *nm = name ? name : "(unnamed)";
  const PetscReal zero[3] = {0, 0, 0};
  PetscInt        myid;
  PetscFunctionBegin;
  PetscCheck(std::isfinite(radius) && radius > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Sphere %s (id %" PetscInt_FMT "): radius %g must be positive", nm, rb->next_id, (double)radius);
  PetscCheck(std::isfinite(density) && density > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Sphere %s (id %" PetscInt_FMT "): density %g must be positive", nm, rb->next_id, (double)density);
  PetscCheck(material >= 0 && material < (PetscInt)rb->gmats.size(), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Sphere %s (id %" PetscInt_FMT "): no granular material %" PetscInt_FMT " (%zu added)", nm, rb->next_id, material, rb->gmats.size());
  for (int k = 0; k < 3; ++k) PetscCheck(std::isfinite(x[k]), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Sphere %s (id %" PetscInt_FMT "): the position is not finite", nm, rb->next_id);
  const PetscReal m = 4.0 / 3.0 * PETSC_PI * radius * radius * radius * density, I = 0.4 * m * radius * radius;
  PetscCheck(std::isfinite(m) && std::isfinite(I) && I > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "Sphere %s (id %" PetscInt_FMT "): radius %g and density %g give the mass %g and moment of inertia %g, out of the range of numbers", nm, rb->next_id, (double)radius,
             (double)density, (double)m, (double)I);
  PetscCall(AddLocal(rb, fdem::model::kSphereSkin, m, Vec3(I, I, I), x, Mat3::identity(), v ? v : zero, omega ? omega : zero, radius, &myid));
  PetscCall(FDEMRigidSetBodyMaterial(rb, myid, material));
  rb->nspheres++;
  if (id) *id = myid;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddBodyFromMesh(FDEMRigid rb, const char *name, PetscInt nnodes, const PetscReal nodes[], PetscInt ntets, const PetscInt tets[], PetscReal density, const PetscReal x[3], const PetscReal Q[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id) {
  char nm[256];
  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(nm, sizeof(nm), "%s (id %" PetscInt_FMT ")", name ? name : "(unnamed)", rb->next_id));
  PetscCall(fdem::Guard(rb->comm, [&]() -> PetscErrorCode {
    std::vector<Vec3>               X(nnodes);
    std::vector<std::array<int, 4>> T(ntets);
    for (PetscInt i = 0; i < nnodes; ++i) X[i] = Vec3(nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]);
    for (PetscInt e = 0; e < ntets; ++e)
      for (int k = 0; k < 4; ++k) T[e][k] = (int)tets[4 * e + k];
    const auto mp = fdem::kernels::ComputeMassProperties(X, T, density, nm);
    // body frame = principal axes about the centre of mass
    Skin       s;
    s.name = nm;
    s.tets = T;
    double rmax = 0;
    for (const Vec3 &p : X) {
      const Vec3 b = transpose(mp.principal_axes) * (p - mp.com);
      s.nodes.push_back(b);
      rmax = std::max(rmax, fdem::kernels::norm(b));
    }
    s.faces = fdem::kernels::BoundaryFaces(T);
    rb->skins.push_back(std::move(s));
    const Mat3      Qm = Q ? FromRowMajor(Q) : Mat3::identity();
    const Mat3      R  = Qm * mp.principal_axes;
    const PetscReal zero[3] = {0, 0, 0};
    const Vec3      I = mp.principal_moments;
    return AddLocal(rb, (PetscInt)rb->skins.size() - 1, mp.mass, I, x, R, v ? v : zero, omega ? omega : zero, rmax, id);
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidAddClump(FDEMRigid rb, const char *name, PetscInt n, const PetscReal balls[], PetscReal density, PetscInt material, const PetscReal x[3], const PetscReal Q[9], const PetscReal v[3], const PetscReal omega[3], PetscInt *id) {
  char           nm[256];
  const PetscReal zero[3] = {0, 0, 0};
  PetscInt        myid;
  PetscFunctionBegin;
  PetscCall(PetscSNPrintf(nm, sizeof(nm), "Clump %s (id %" PetscInt_FMT ")", name ? name : "(unnamed)", rb->next_id));
  PetscCheck(n > 0 && balls, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: give at least one sphere", nm);
  PetscCheck(material >= 0 && material < (PetscInt)rb->gmats.size(), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: no granular material %" PetscInt_FMT " (%zu added)", nm, material, rb->gmats.size());
  for (int k = 0; k < 3; ++k) PetscCheck(std::isfinite(x[k]), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: the position is not finite", nm);
  PetscCall(fdem::Guard(rb->comm, [&]() -> PetscErrorCode {
    // clumps of one shape at any size and density share one integration: that of the shape
    // scaled by its first radius at unit density (mass ~ rho s^3, inertia ~ rho s^5)
    const double        sc = balls[3];
    PetscCheck(std::isfinite(sc) && sc > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: sphere 0: radius %g must be positive", nm, (double)sc);
    PetscCheck(std::isfinite(density) && density > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: density %g must be positive", nm, (double)density);
    std::vector<double> key(balls, balls + 4 * n);
    for (double &k : key) k /= sc;
    auto it = rb->clump_props.find(key);
    if (it == rb->clump_props.end()) {
      std::vector<fdem::kernels::Ball> B((size_t)n);
      for (PetscInt k = 0; k < n; ++k) B[k] = {Vec3(key[4 * k], key[4 * k + 1], key[4 * k + 2]), key[4 * k + 3]};
      it = rb->clump_props.emplace(key, fdem::kernels::BallUnionMassProperties(B, 1.0, nm)).first;
    }
    fdem::kernels::MassProperties mp = it->second;
    mp.mass *= density * sc * sc * sc;
    mp.volume *= sc * sc * sc;
    mp.com = sc * mp.com;
    mp.principal_moments = (density * sc * sc * sc * sc * sc) * mp.principal_moments;
    // body frame = principal axes about the centre of mass; each sphere drawn as an octahedron
    Skin   s;
    double rmax = 0;
    s.name      = nm;
    for (PetscInt k = 0; k < n; ++k) {
      const Vec3   p = transpose(mp.principal_axes) * (Vec3(balls[4 * k], balls[4 * k + 1], balls[4 * k + 2]) - mp.com);
      const double r = balls[4 * k + 3];
      s.balls.push_back({p.x, p.y, p.z, r});
      rmax             = std::max(rmax, fdem::kernels::norm(p) + r);
      const int   base = (int)s.nodes.size();
      const Skin &oct  = fdem::model::UnitOctahedron();
      for (const Vec3 &e : oct.nodes) s.nodes.push_back(p + r * e);
      for (const auto &f : oct.faces) s.faces.push_back({base + f[0], base + f[1], base + f[2]});
    }
    rb->skins.push_back(std::move(s));
    const Mat3 R = (Q ? FromRowMajor(Q) : Mat3::identity()) * mp.principal_axes;
    return AddLocal(rb, (PetscInt)rb->skins.size() - 1, mp.mass, mp.principal_moments, x, R, v ? v : zero, omega ? omega : zero, rmax, &myid);
  }));
  PetscCall(FDEMRigidSetBodyMaterial(rb, myid, material));
  rb->nspheres++;
  if (id) *id = myid;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetBodyForce(FDEMRigid rb, PetscInt id, PetscReal F[3]) {
  PetscReal mine[3] = {0, 0, 0};
  PetscFunctionBegin;
  PetscCheck(id >= 0 && id < rb->next_id, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidGetBodyForce: no body %" PetscInt_FMT, id);
  for (size_t b = 0; b < rb->ids.size() && 3 * b + 2 < rb->load.size(); ++b)
    if (rb->ids[b] == id)
      for (int k = 0; k < 3; ++k) mine[k] = rb->load[3 * b + k];
  PetscCallMPI(MPI_Allreduce(mine, F, 3, MPIU_REAL, MPI_SUM, rb->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetDM(FDEMRigid rb, DM *sw) {
  PetscFunctionBegin;
  *sw = rb->sw;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetNumBodies(FDEMRigid rb, PetscInt *nlocal, PetscInt *nglobal) {
  PetscFunctionBegin;
  if (nlocal) PetscCall(DMSwarmGetLocalSize(rb->sw, nlocal));
  if (nglobal) PetscCall(DMSwarmGetSize(rb->sw, nglobal));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetUpTS(FDEMRigid rb, TS ts, Vec *U) {
  PetscInt     n, start;
  PetscScalar *u;
  IS           isq, isp;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  rb->n = n;
  PetscCall(VecCreateMPI(rb->comm, 18 * n, PETSC_DETERMINE, U));
  PetscCall(PetscObjectSetName((PetscObject)*U, "rigid body state"));
  PetscCall(VecGetOwnershipRange(*U, &start, nullptr));
  PetscCall(VecGetArray(*U, &u));
  PetscCall(fdem::model::RigidLoadState(rb, u));
  PetscCall(VecRestoreArray(*U, &u));
  PetscCall(ISCreateStride(rb->comm, 12 * n, start, 1, &isq));
  PetscCall(ISCreateStride(rb->comm, 6 * n, start + 12 * n, 1, &isp));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, rb));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentumWithWork, rb));
  PetscCall(FDEMTSSetDrift(ts, Drift, rb));
  PetscCall(TSSetSolution(ts, *U));
  rb->U = *U;
  PetscCall(fdem::model::RigidForcesSetUp(rb));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::RigidForcesSetUp(FDEMRigid rb) {
  PetscFunctionBegin;
  for (const auto &term : rb->forces)
    if (term.setup) PetscCall(term.setup(rb, term.ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::RigidLoadState(FDEMRigid rb, PetscScalar *u) {
  RigidFields    f;
  const PetscInt n = rb->n;
  const RigidLayout L(n);
  PetscFunctionBegin;
  PetscCall(RigidGetFields(rb->sw, f));
  rb->mass.assign(f.mass, f.mass + n);
  rb->inertia.assign(f.I, f.I + 3 * n);
  rb->ids.assign(f.id, f.id + n);
  rb->fixed.assign(f.fixed, f.fixed + n);
  rb->sphere.assign(n, 0);
  rb->load.assign(3 * n, 0.0);
  for (PetscInt b = 0; b < n; ++b) rb->sphere[b] = f.skin[b] == kSphereSkin;
  for (PetscInt b = 0; b < n; ++b) {
    for (int k = 0; k < 3; ++k) {
      L.x(u, b)[k] = f.x[3 * b + k];
      L.v(u, b)[k] = f.v[3 * b + k];
      L.H(u, b)[k] = f.H[3 * b + k];
    }
    for (int k = 0; k < 9; ++k) L.R(u, b)[k] = f.R[9 * b + k];
  }
  PetscCall(RigidRestoreFields(rb->sw, f));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::RigidStoreState(FDEMRigid rb, const PetscScalar *u) {
  RigidFields       f;
  const RigidLayout L(rb->n);
  PetscFunctionBegin;
  PetscCall(RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < rb->n; ++b) {
    for (int k = 0; k < 3; ++k) {
      f.x[3 * b + k] = PetscRealPart(L.x(u, b)[k]);
      f.v[3 * b + k] = PetscRealPart(L.v(u, b)[k]);
      f.H[3 * b + k] = PetscRealPart(L.H(u, b)[k]);
    }
    for (int k = 0; k < 9; ++k) f.R[9 * b + k] = PetscRealPart(L.R(u, b)[k]);
  }
  PetscCall(RigidRestoreFields(rb->sw, f));
  for (const auto &term : rb->forces)
    if (term.store) PetscCall(term.store(rb, term.ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidRestoreState(FDEMRigid rb, Vec U) {
  const PetscScalar *u;
  PetscFunctionBegin;
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(fdem::model::RigidStoreState(rb, u));
  PetscCall(VecRestoreArrayRead(U, &u));
  if (rb->U == U) rb->U = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidFixBody(FDEMRigid rb, PetscInt id) {
  PetscInt    n;
  RigidFields f;
  PetscFunctionBegin;
  PetscCheck(id >= 0 && id < rb->next_id, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidFixBody: no body with id %" PetscInt_FMT, id);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < n; ++b)
    if (f.id[b] == id) {
      f.fixed[b] = 1;
      for (int k = 0; k < 3; ++k) f.v[3 * b + k] = f.H[3 * b + k] = 0;
    }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidMoveBody(FDEMRigid rb, PetscInt id, const PetscReal v[3]) {
  PetscInt    n;
  RigidFields f;
  PetscFunctionBegin;
  PetscCheck(id >= 0 && id < rb->next_id, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidMoveBody: no body with id %" PetscInt_FMT, id);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < n; ++b)
    if (f.id[b] == id) {
      f.fixed[b] = 1;
      for (int k = 0; k < 3; ++k) f.v[3 * b + k] = v[k], f.H[3 * b + k] = 0;
    }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  rb->moved = true;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetExternalWork(FDEMRigid rb, PetscReal *W) {
  PetscFunctionBegin;
  PetscCall(MPIU_Allreduce(&rb->meter.work, W, 1, MPIU_REAL, MPIU_SUM, rb->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetExternalWork(FDEMRigid rb, PetscReal W) {
  PetscFunctionBegin;
  rb->meter.Reset(rb->rank == 0 ? W : 0);
  PetscFunctionReturn(0);
}

// The partition's measured costs: the CPU time of the model force terms (t_terms: contact)
// per pair and of the rest (t_rest: the TS's passes, the RHS) per contact primitive, both
// summed over the ranks and over one segment; 0 where nothing was measured (no time, no
// primitives; no pairs for the per-pair cost).
static void PartitionCosts(PetscReal t_rest, PetscReal t_terms, PetscReal primitives, PetscReal pairs, PetscReal *per_primitive, PetscReal *per_pair) {
  const bool ok = std::isfinite(t_rest) && std::isfinite(t_terms) && t_rest > 0 && t_terms >= 0 && primitives > 0;
  *per_primitive = ok ? t_rest / primitives : 0;
  *per_pair      = ok && pairs > 0 ? t_terms / pairs : 0;
}

PetscErrorCode FDEMRigidGetPartitionCosts(FDEMRigid rb, PetscReal *per_primitive, PetscReal *per_pair) {
  PetscFunctionBegin;
  if (per_primitive) *per_primitive = rb->cost_primitive;
  if (per_pair) *per_pair = rb->cost_pair;
  PetscFunctionReturn(0);
}

void fdem::model::RigidSampleWork(FDEMRigid rb, PetscReal t, PetscReal extra) {
  if (rb->moved) rb->meter.Sample(t, rb->power + extra);
}

// The partition: a recursive coordinate bisection of the moving bodies' centres, each weighted
// by its contact work: its contact primitives (a sphere 1, a polyhedron its skin tetrahedra)
// plus the candidate pairs its primitives took part in at the last search on its rank (the
// swarm field "work", set by the rigid bodies' contact, and mesh_work, set by a combined
// scene's rigid-mesh contact; -fdem_rigid_partition_pairs false: the primitives only), each
// counted as 1 or, with -fdem_rigid_partition_timed, in measured CPU seconds. A group of
// ranks [r0, r1) splits its bodies along the axis of their largest spread (between the 10% and
// 90% quantiles, so a few bodies thrown far do not choose it) at the weighted quantile
// (r1 - r0) / 2 / (r1 - r0), the cut half-way between the two bodies on either side. Fixed bodies (walls, floors) are left out: their pairs are computed
// by the moving body's owner. Every rank computes the same tree from the same gathered centres.
// Fewer moving bodies than ranks: equal slabs of the domain.
static PetscErrorCode BalanceRcb(FDEMRigid rb) {
  PetscInt         n, *fx, *sk;
  const PetscReal *x, *work;
  std::vector<PetscReal> mine;
  PetscFunctionBegin;
  if (rb->axis < 0) PetscFunctionReturn(0);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(rb->sw, "fixed", nullptr, nullptr, (void **)&fx));
  PetscCall(DMSwarmGetField(rb->sw, "skin", nullptr, nullptr, (void **)&sk));
  PetscCall(DMSwarmGetField(rb->sw, "work", nullptr, nullptr, (void **)&work));
  // the weight of a body is a primitives + b pairs; counts (a = b = 1), or measured: the CPU
  // time since the last partition, summed over the ranks, split into the model force terms'
  // (contact: per pair) and the rest (the TS's passes, per primitive)
  PetscReal a = 1, bw = rb->weight_pairs ? 1 : 0;
  std::vector<PetscReal> mesh(rb->mesh_work); // the pairs with a mesh, if measured since the last migration
  mesh.resize((size_t)n, 0);
  if (rb->weight_timed) {
    const double now = CpuSeconds();
    if (rb->cpu_mark >= 0) {
      PetscReal loc[4] = {(PetscReal)rb->cpu_terms, (PetscReal)(now - rb->cpu_mark - rb->cpu_terms), 0, 0}, sum[4];
      for (PetscInt b = 0; b < n; ++b)
        if (!fx[b]) loc[2] += sk[b] >= 0 ? (PetscReal)rb->skins[sk[b]].Primitives() : 1.0, loc[3] += work[b] + mesh[b];
      PetscCallMPI(MPI_Allreduce(loc, sum, 4, MPIU_REAL, MPI_SUM, rb->comm));
      PartitionCosts(sum[1], sum[0], sum[2], sum[3], &rb->cost_primitive, &rb->cost_pair);
      if (rb->cost_primitive > 0) a = rb->cost_primitive, bw = rb->weight_pairs ? rb->cost_pair : 0;
      PetscCall(PetscInfo(nullptr, "partition: %g s per primitive, %g s per pair (CPU, since the last partition)\n", (double)rb->cost_primitive, (double)rb->cost_pair));
    }
    rb->cpu_mark  = now;
    rb->cpu_terms = 0;
  }
  for (PetscInt b = 0; b < n; ++b)
    if (!fx[b]) {
      mine.insert(mine.end(), x + 3 * b, x + 3 * b + 3);
      mine.push_back(a * (sk[b] >= 0 ? (PetscReal)rb->skins[sk[b]].Primitives() : 1.0) + bw * (work[b] + mesh[b]));
    }
  PetscCall(DMSwarmRestoreField(rb->sw, "work", nullptr, nullptr, (void **)&work));
  PetscCall(DMSwarmRestoreField(rb->sw, "skin", nullptr, nullptr, (void **)&sk));
  PetscCall(DMSwarmRestoreField(rb->sw, "fixed", nullptr, nullptr, (void **)&fx));
  PetscCall(DMSwarmRestoreField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscMPIInt              cnt = (PetscMPIInt)mine.size();
  std::vector<PetscMPIInt> cnts(rb->size), displs(rb->size + 1, 0);
  PetscCallMPI(MPI_Allgather(&cnt, 1, MPI_INT, cnts.data(), 1, MPI_INT, rb->comm));
  for (int r = 0; r < rb->size; ++r) displs[r + 1] = displs[r] + cnts[r];
  std::vector<PetscReal> all(displs[rb->size]);
  PetscCallMPI(MPI_Allgatherv(mine.data(), cnt, MPIU_REAL, all.data(), cnts.data(), displs.data(), MPIU_REAL, rb->comm));
  const size_t m = all.size() / 4;
  rb->rcb.clear();
  if (m < (size_t)rb->size) PetscFunctionReturn(0);
  std::vector<size_t> idx(m);
  for (size_t i = 0; i < m; ++i) idx[i] = i;
  auto at = [&](size_t i, int k) { return all[4 * i + k]; };
  // node for ranks [r0, r1) over the bodies idx[b, e); returns its index
  std::function<int(size_t, size_t, int, int)> split = [&](size_t b, size_t e, int r0, int r1) -> int {
    const int node = (int)rb->rcb.size();
    rb->rcb.emplace_back();
    if (r1 - r0 == 1 || e - b < 2) {
      rb->rcb[node].rank = r0;
      return node;
    }
    int       ax = 0;
    PetscReal spread[3];
    for (int k = 0; k < 3; ++k) {
      std::vector<PetscReal> c(e - b);
      for (size_t i = b; i < e; ++i) c[i - b] = at(idx[i], k);
      std::sort(c.begin(), c.end());
      spread[k] = c[(9 * (c.size() - 1)) / 10] - c[(c.size() - 1) / 10];
      if (spread[k] > spread[ax]) ax = k;
    }
    std::sort(idx.begin() + b, idx.begin() + e, [&](size_t u, size_t v) { return at(u, ax) < at(v, ax) || (at(u, ax) == at(v, ax) && u < v); });
    const int rm    = r0 + (r1 - r0) / 2;
    PetscReal total = 0, acc = 0;
    for (size_t i = b; i < e; ++i) total += at(idx[i], 3);
    const PetscReal goal = total * (PetscReal)(rm - r0) / (PetscReal)(r1 - r0);
    size_t          c    = b + 1; // bodies [b, c) go left; at least one on each side
    for (size_t i = b; i < e - 1; ++i) {
      acc += at(idx[i], 3);
      c = i + 1;
      if (acc >= goal) break;
    }
    const PetscReal cut = 0.5 * (at(idx[c - 1], ax) + at(idx[c], ax));
    const int       l = split(b, c, r0, rm), r = split(c, e, rm, r1);
    rb->rcb[node].axis  = ax;
    rb->rcb[node].cut   = cut;
    rb->rcb[node].left  = l;
    rb->rcb[node].right = r;
    return node;
  };
  split(0, m, 0, rb->size);
  PetscFunctionReturn(0);
}

// The local bodies in the order of their ids (after DMSwarmMigrate appended the arrivals): the
// order of every local sum then depends on the partition alone, not on the bodies' history, so
// a run restarted from a checkpoint repeats the straight run to the bit on any number of ranks.
static PetscErrorCode SortLocalById(FDEMRigid rb) {
  PetscInt  n, *id;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "id", nullptr, nullptr, (void **)&id));
  std::vector<PetscInt> perm(n);
  for (PetscInt b = 0; b < n; ++b) perm[b] = b;
  const bool sorted = std::is_sorted(id, id + n);
  if (!sorted) std::sort(perm.begin(), perm.end(), [&](PetscInt u, PetscInt v) { return id[u] < id[v]; });
  PetscCall(DMSwarmRestoreField(rb->sw, "id", nullptr, nullptr, (void **)&id));
  if (sorted) PetscFunctionReturn(0);
  // every field, its bytes per body from its block size and type (the spring slots are raw bytes)
  const char *const names[] = {"x", "R", "v", "H", "mass", "inertia", "radius", "id", "skin", "fixed", "history", "image", "work", "x_migrated", DMSwarmField_pid, DMSwarmField_rank};
  std::vector<char> tmp;
  for (const char *name : names) {
    char         *data;
    PetscInt      bs;
    PetscDataType type;
    size_t        sz;
    PetscCall(DMSwarmGetField(rb->sw, name, &bs, &type, (void **)&data));
    if (!std::strcmp(name, "history")) sz = fdem::model::kHistoryBytes;
    else {
      PetscCall(PetscDataTypeGetSize(type, &sz));
      sz *= (size_t)bs;
    }
    tmp.assign(data, data + sz * (size_t)n);
    for (PetscInt b = 0; b < n; ++b) std::memcpy(data + sz * (size_t)b, tmp.data() + sz * (size_t)perm[b], sz);
    PetscCall(DMSwarmRestoreField(rb->sw, name, &bs, &type, (void **)&data));
  }
  PetscFunctionReturn(0);
}

// Periodic axes: every body's centre back into [lo, hi), the periods it crossed counted in its
// field "image" (its unwrapped centre is x + image (hi - lo)).
static PetscErrorCode WrapPeriodic(FDEMRigid rb) {
  PetscInt   n, *image;
  PetscReal *x;
  PetscFunctionBegin;
  if (!rb->periodic[0] && !rb->periodic[1] && !rb->periodic[2]) PetscFunctionReturn(0);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(rb->sw, "image", nullptr, nullptr, (void **)&image));
  for (PetscInt b = 0; b < n; ++b)
    for (int k = 0; k < 3; ++k) {
      if (!rb->periodic[k]) continue;
      const PetscReal L = rb->hi[k] - rb->lo[k], m = std::floor((x[3 * b + k] - rb->lo[k]) / L);
      if (m == 0 || !std::isfinite(m)) continue;
      x[3 * b + k] -= m * L;
      if (x[3 * b + k] >= rb->hi[k]) x[3 * b + k] -= L, image[3 * b + k] += 1; // round-off
      if (x[3 * b + k] < rb->lo[k]) x[3 * b + k] += L, image[3 * b + k] -= 1;
      image[3 * b + k] += (PetscInt)m;
    }
  PetscCall(DMSwarmRestoreField(rb->sw, "image", nullptr, nullptr, (void **)&image));
  PetscCall(DMSwarmRestoreField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSetPeriodic(FDEMRigid rb, const PetscBool periodic[3]) {
  PetscInt n;
  PetscFunctionBegin;
  PetscCheck(rb->axis >= 0, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMRigidSetPeriodic: set the domain first (FDEMRigidSetDomain): its box is the periodic cell");
  PetscCall(DMSwarmGetSize(rb->sw, &n));
  PetscCheck(n == 0, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMRigidSetPeriodic: make the boundaries periodic before adding bodies");
  for (int k = 0; k < 3; ++k) rb->periodic[k] = periodic[k] ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetPeriodic(FDEMRigid rb, PetscBool periodic[3], PetscReal lo[3], PetscReal hi[3]) {
  PetscFunctionBegin;
  for (int k = 0; k < 3; ++k) {
    if (periodic) periodic[k] = rb->periodic[k];
    if (lo) lo[k] = rb->lo[k];
    if (hi) hi[k] = rb->hi[k];
  }
  PetscFunctionReturn(0);
}

// A migration is due when some body has moved farther than its own radius since the last one, or
// a centre has left the periodic cell: decided from the bodies' positions alone, so that every
// number of ranks decides alike (a migration ends the caller's TS, and a new TS starts with a
// fresh force evaluation: 1 and 2 ranks agree only if both do it at the same steps).
PetscErrorCode FDEMRigidMigrationNeeded(FDEMRigid rb, PetscBool *needed) {
  PetscInt         n;
  const PetscReal *x, *x0, *r;
  PetscBool        mine = PETSC_FALSE;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  PetscCall(DMSwarmGetField(rb->sw, "radius", nullptr, nullptr, (void **)&r));
  for (PetscInt b = 0; b < n && !mine; ++b) {
    PetscReal d2 = 0;
    for (int k = 0; k < 3; ++k) {
      d2 += (x[3 * b + k] - x0[3 * b + k]) * (x[3 * b + k] - x0[3 * b + k]);
      if (rb->periodic[k] && !(x[3 * b + k] >= rb->lo[k] && x[3 * b + k] < rb->hi[k])) mine = PETSC_TRUE;
    }
    if (!(d2 <= r[b] * r[b])) mine = PETSC_TRUE;
  }
  PetscCall(DMSwarmRestoreField(rb->sw, "radius", nullptr, nullptr, (void **)&r));
  PetscCall(DMSwarmRestoreField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  PetscCall(DMSwarmRestoreField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCallMPI(MPI_Allreduce(&mine, needed, 1, MPIU_BOOL, MPI_LOR, rb->comm));
  PetscFunctionReturn(0);
}

// The centres at this migration, from which FDEMRigidMigrationNeeded measures the bodies' motion.
static PetscErrorCode MarkMigrated(FDEMRigid rb) {
  PetscInt   n;
  PetscReal *x, *x0;
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  std::copy(x, x + 3 * n, x0);
  PetscCall(DMSwarmRestoreField(rb->sw, "x_migrated", nullptr, nullptr, (void **)&x0));
  PetscCall(DMSwarmRestoreField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidMigrate(FDEMRigid rb) {
  PetscInt  n, *rk;
  PetscReal *x;
  PetscFunctionBegin;
  PetscCall(WrapPeriodic(rb));
  if (rb->size == 1) {
    PetscCall(MarkMigrated(rb));
    PetscFunctionReturn(0);
  }
  PetscCall(BalanceRcb(rb));
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(DMSwarmGetField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmGetField(rb->sw, DMSwarmField_rank, nullptr, nullptr, (void **)&rk));
  for (PetscInt b = 0; b < n; ++b) rk[b] = OwnerRank(rb, &x[3 * b]);
  PetscCall(DMSwarmRestoreField(rb->sw, DMSwarmField_rank, nullptr, nullptr, (void **)&rk));
  PetscCall(DMSwarmRestoreField(rb->sw, "x", nullptr, nullptr, (void **)&x));
  PetscCall(DMSwarmMigrate(rb->sw, PETSC_TRUE));
  PetscCall(SortLocalById(rb));
  PetscCall(MarkMigrated(rb));
  rb->mesh_work.clear(); // indexed by the local bodies before the migration
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidSolve(FDEMRigid rb, PetscReal t0, PetscReal tfinal, PetscReal dt, PetscInt migrate_every, PetscErrorCode (*monitor)(FDEMRigid, PetscInt, PetscReal, void *), void *mctx) {
  PetscReal t    = t0;
  PetscInt  step = 0, max_steps = PETSC_MAX_INT;
  PetscFunctionBegin;
  PetscCheck(std::isfinite(dt) && dt > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSolve: the time step must be positive and finite, got %g", (double)dt);
  if (migrate_every <= 0) migrate_every = PETSC_MAX_INT / 2;
  rb->solve_time  = t;
  rb->solve_steps = 0;
  if (monitor) PetscCall(monitor(rb, step, t, mctx));
  // dt, tfinal and max_steps are defaults: -ts_dt, -ts_max_time and -ts_max_steps win (read back from each segment's TS)
  for (bool first = true; first || (t < tfinal - 1e-12 * PetscMax(1.0, PetscAbsReal(tfinal)) && step < max_steps); first = false) {
    TS                ts;
    Vec               U;
    TSConvergedReason reason;
    const PetscInt    step0 = step;
    PetscCall(TSCreate(rb->comm, &ts));
    PetscCall(TSSetType(ts, TSFDEMCD));
    PetscCall(FDEMRigidSetUpTS(rb, ts, &U));
    PetscCall(TSSetTime(ts, t));
    PetscCall(TSSetStepNumber(ts, step));
    PetscCall(TSSetTimeStep(ts, dt));
    PetscCall(TSSetMaxTime(ts, tfinal));
    PetscCall(TSSetMaxSteps(ts, max_steps));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(TSSetFromOptions(ts));
    PetscCall(TSGetTimeStep(ts, &dt));
    PetscCall(TSGetMaxTime(ts, &tfinal));
    PetscCall(TSGetMaxSteps(ts, &max_steps));
    PetscCheck(std::isfinite(dt) && dt > 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSolve: the time step (-ts_dt) must be positive and finite, got %g", (double)dt);
    PetscCheck(std::isfinite(tfinal), rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidSolve: the final time (-ts_max_time) must be finite, got %g", (double)tfinal);
    PetscCall(TSSetMaxSteps(ts, PetscMin(max_steps, step + migrate_every)));
    if (t < tfinal - 1e-12 * PetscMax(1.0, PetscAbsReal(tfinal)) && step < max_steps) PetscCall(TSSolve(ts, U));
    PetscCall(TSGetConvergedReason(ts, &reason));
    PetscCall(TSGetTime(ts, &t));
    PetscCall(TSGetStepNumber(ts, &step));
    PetscCall(FDEMRigidRestoreState(rb, U));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    PetscCheck(reason >= 0, rb->comm, PETSC_ERR_NOT_CONVERGED, "FDEMRigidSolve: the time stepping failed at t = %g (%s)", (double)t, TSConvergedReasons[reason]);
    rb->solve_time  = t;
    rb->solve_steps = step;
    if (step == step0) break; // nothing left to do (the TS's own end test)
    PetscCall(FDEMRigidMigrate(rb));
    if (monitor) PetscCall(monitor(rb, step, t, mctx));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetTime(FDEMRigid rb, PetscReal *t, PetscInt *steps) {
  PetscFunctionBegin;
  if (t) *t = rb->solve_time;
  if (steps) *steps = rb->solve_steps;
  PetscFunctionReturn(0);
}

// The state of local body b (its id from the swarm; rank is this rank).
static void LocalBodyState(const RigidFields &f, PetscInt b, PetscMPIInt rank, FDEMRigidBodyState *st) {
  *st      = FDEMRigidBodyState{};
  st->id   = f.id[b];
  st->rank = rank;
  st->mass = f.mass[b];
  for (int i = 0; i < 3; ++i) {
    st->inertia[i] = f.I[3 * b + i];
    st->x[i]       = f.x[3 * b + i];
    st->v[i]       = f.v[3 * b + i];
    st->H[i]       = f.H[3 * b + i];
  }
  for (int i = 0; i < 9; ++i) st->R[i] = f.R[9 * b + i];
  const Vec3 w = fdem::kernels::SpaceOmega(FromRowMajor(&f.R[9 * b]), Vec3(f.I[3 * b], f.I[3 * b + 1], f.I[3 * b + 2]), Vec3(f.H[3 * b], f.H[3 * b + 1], f.H[3 * b + 2]));
  for (int i = 0; i < 3; ++i) st->omega_space[i] = w[i];
  st->radius = f.radius[b];
}

PetscErrorCode FDEMRigidGetBodyState(FDEMRigid rb, PetscInt id, FDEMRigidBodyState *st) {
  PetscInt           n;
  RigidFields        f;
  PetscMPIInt        owner = -1, gowner;
  FDEMRigidBodyState mine{};
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < n; ++b)
    if (f.id[b] == id) {
      owner = rb->rank;
      LocalBodyState(f, b, rb->rank, &mine);
    }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  PetscCallMPI(MPI_Allreduce(&owner, &gowner, 1, MPI_INT, MPI_MAX, rb->comm));
  PetscCheck(gowner >= 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "No rigid body with id %" PetscInt_FMT, id);
  PetscCallMPI(MPI_Bcast(&mine, (int)sizeof(mine), MPI_BYTE, gowner, rb->comm));
  *st = mine;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetBodyStates(FDEMRigid rb, PetscMPIInt root, PetscInt *n, FDEMRigidBodyState **states) {
  PetscInt                        nl, ng;
  RigidFields                     f;
  std::vector<FDEMRigidBodyState> mine;
  PetscFunctionBegin;
  PetscCheck(root >= 0 && root < rb->size, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidGetBodyStates: root %d is not a rank of the communicator (size %d)", root, rb->size);
  *n      = 0;
  *states = nullptr;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &nl));
  PetscCall(DMSwarmGetSize(rb->sw, &ng));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  mine.resize((size_t)nl);
  for (PetscInt b = 0; b < nl; ++b) LocalBodyState(f, b, rb->rank, &mine[(size_t)b]);
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  // one MPI type for a record (its bytes), so that counts and displacements are in records
  MPI_Datatype     rec;
  int              count = (int)nl;
  std::vector<int> counts(rb->rank == root ? rb->size : 0), displs(counts.size());
  PetscCallMPI(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, rb->comm));
  std::vector<FDEMRigidBodyState> all;
  if (rb->rank == root) {
    PetscInt total = 0;
    for (size_t r = 0; r < counts.size(); ++r) displs[r] = (int)total, total += counts[r];
    all.resize((size_t)total);
  }
  PetscCallMPI(MPI_Type_contiguous((int)sizeof(FDEMRigidBodyState), MPI_BYTE, &rec));
  PetscCallMPI(MPI_Type_commit(&rec));
  PetscCallMPI(MPI_Gatherv(mine.data(), count, rec, all.data(), counts.data(), displs.data(), rec, root, rb->comm));
  PetscCallMPI(MPI_Type_free(&rec));
  if (rb->rank != root) PetscFunctionReturn(0);
  // in the order of the ids (0 .. ng - 1, each once)
  PetscCheck((PetscInt)all.size() == ng, PETSC_COMM_SELF, PETSC_ERR_PLIB, "FDEMRigidGetBodyStates: gathered %zu bodies of %" PetscInt_FMT, all.size(), ng);
  PetscCall(PetscMalloc1(ng, states));
  std::vector<char> seen((size_t)ng, 0);
  for (const auto &st : all) {
    PetscCheck(st.id >= 0 && st.id < ng && !seen[(size_t)st.id], PETSC_COMM_SELF, PETSC_ERR_PLIB, "FDEMRigidGetBodyStates: body id %" PetscInt_FMT " out of range or held twice", st.id);
    seen[(size_t)st.id] = 1;
    (*states)[st.id]    = st;
  }
  *n = ng;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMRigidGetInvariants(FDEMRigid rb, PetscReal P[3], PetscReal L[3], PetscReal *E) {
  PetscInt  n;
  RigidFields f;
  PetscReal loc[7] = {0}, glob[7];
  PetscFunctionBegin;
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < n; ++b) {
    const Vec3 x(f.x[3 * b], f.x[3 * b + 1], f.x[3 * b + 2]), v(f.v[3 * b], f.v[3 * b + 1], f.v[3 * b + 2]), H(f.H[3 * b], f.H[3 * b + 1], f.H[3 * b + 2]);
    const Vec3 p = f.mass[b] * v, l = fdem::kernels::cross(x, p) + H;
    for (int k = 0; k < 3; ++k) {
      loc[k] += p[k];
      loc[3 + k] += l[k];
    }
    loc[6] += 0.5 * f.mass[b] * dot(v, v) + fdem::kernels::RotationalKineticEnergy(FromRowMajor(&f.R[9 * b]), Vec3(f.I[3 * b], f.I[3 * b + 1], f.I[3 * b + 2]), H);
  }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  PetscCall(MPIU_Allreduce(loc, glob, 7, MPIU_REAL, MPIU_SUM, rb->comm));
  for (int k = 0; k < 3; ++k) {
    if (P) P[k] = glob[k];
    if (L) L[k] = glob[3 + k];
  }
  if (E) *E = glob[6];
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::RigidRHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *ctx) {
  PetscFunctionBegin;
  PetscCall(RHSMomentum(ts, t, Q, A, ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::RigidDrift(TS ts, PetscReal t, PetscReal s, Vec U, void *ctx) {
  PetscFunctionBegin;
  PetscCall(Drift(ts, t, s, U, ctx));
  PetscFunctionReturn(0);
}
