// Rigid bodies in parallel: 40 irregular convex polyhedra (hulls of random
// points, fixed seed) in a box split into slabs (FDEMRigidSetDomain; each
// migration moves the slab boundaries to balance the bodies), with
// velocities that carry them across the slab boundaries, gravity and an
// orientation-dependent torque, solved with FDEMRigidSolve(migrate_every = 5)
// on PETSC_COMM_WORLD. The same scene is solved on PETSC_COMM_SELF in the same
// process; every body's final x, R, v, H (by id) must agree to 1e-12
// relative, and on more than one rank bodies must really have changed rank.
// TS options (-ts_type, -fdem_rigid_rotation) apply to both runs.
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/rotation.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

#include "../common/check.hpp"

// torque of a constant space force F0 = (0, 0, -4 m) applied at the body point c (body frame), c depending on the id
static PetscErrorCode Torque(PetscInt id, PetscReal, const PetscReal *, const PetscReal R[9], const PetscReal *, const PetscReal *, PetscReal F[3], PetscReal M[3], void *) {
  PetscFunctionBeginUser;
  const Vec3 c(0.05 + 0.01 * (id % 5), -0.04, 0.03 + 0.005 * (id % 3)), F0(0.5, 0, -4.0);
  Vec3       rc;
  for (int r = 0; r < 3; ++r) rc[r] = R[3 * r] * c[0] + R[3 * r + 1] * c[1] + R[3 * r + 2] * c[2];
  const Vec3 m = fdem::kernels::cross(rc, F0);
  for (int k = 0; k < 3; ++k) {
    M[k] += m[k];
    F[k] += F0[k];
  }
  PetscFunctionReturn(0);
}

static const PetscInt  NB = 40;
static const PetscReal LX = 8.0;

static PetscReal X0(PetscInt b) { return 0.5 + 7.0 * (b + 0.5) / NB; }
static std::vector<PetscInt> g_tets(NB); // each body's tetrahedra: its weight in the partition

static PetscErrorCode BuildScene(MPI_Comm comm, FDEMRigid *out) {
  FDEMRigid rb;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(comm, &rb));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {LX, 2, 2};
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  const PetscReal g[3] = {0, 0, -9.81};
  PetscCall(FDEMRigidSetGravity(rb, g));
  PetscCall(FDEMRigidSetForceFunction(rb, Torque, nullptr));
  PetscCall(FDEMRigidSetFromOptions(rb));
  std::mt19937_64                        rng(20240611ULL);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (PetscInt b = 0; b < NB; ++b) {
    std::vector<Vec3> pts, X;
    std::vector<std::array<int, 4>> T;
    const int npts = 8 + (int)(b % 7);
    for (int i = 0; i < npts; ++i) pts.push_back(Vec3(0.3 * U(rng), 0.2 * U(rng), 0.15 * U(rng)));
    fdem::kernels::MakeConvexPolyhedronTets(pts, X, T);
    g_tets[b] = (PetscInt)T.size();
    std::vector<PetscReal> nodes;
    std::vector<PetscInt>  tets;
    for (const Vec3 &p : X) nodes.insert(nodes.end(), {p.x, p.y, p.z});
    for (const auto &t : T) tets.insert(tets.end(), {t[0], t[1], t[2], t[3]});
    // spread over [0.5, 7.5] along x with speeds of 1.5-3.5 towards the middle and beyond:
    // in T = 1 most bodies cross x = 4 (2 ranks) and stay in the box
    const PetscReal x[3] = {X0(b), 1.0 + 0.5 * U(rng), 1.0 + 0.5 * U(rng)};
    const PetscReal v[3] = {(x[0] < LX / 2 ? 1 : -1) * (1.5 + 2.0 * (0.5 + 0.5 * U(rng))), 0.5 * U(rng), 3.0 + U(rng)};
    const PetscReal w[3] = {4 * U(rng), 4 * U(rng), 4 * U(rng)};
    const Mat3      Q    = fdem::kernels::RotationMatrix(Vec3(2 * U(rng), 2 * U(rng), 2 * U(rng)));
    PetscReal       Qr[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) Qr[3 * r + c] = Q.m[r][c];
    PetscCall(FDEMRigidAddBodyFromMesh(rb, "hull", (PetscInt)X.size(), nodes.data(), (PetscInt)T.size(), tets.data(), 800.0, x, Qr, v, w, nullptr));
  }
  *out = rb;
  PetscFunctionReturn(0);
}

static PetscErrorCode CountSegments(FDEMRigid, PetscInt, PetscReal, void *ctx) {
  PetscFunctionBeginUser;
  (*(PetscInt *)ctx)++;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscReal   T = 1.0, dt = 0.01;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-T", &T, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-dt", &dt, nullptr));

  FDEMRigid par, ser;
  PetscCall(BuildScene(PETSC_COMM_WORLD, &par));
  PetscCall(BuildScene(PETSC_COMM_SELF, &ser));
  PetscInt nloc, nglob;
  PetscCall(FDEMRigidGetNumBodies(par, &nloc, &nglob));
  CHECK(nglob == NB, "the parallel scene has %" PetscInt_FMT " bodies, expected %" PetscInt_FMT, nglob, NB);
  std::vector<PetscMPIInt> rank0(NB), rank1(NB);
  for (PetscInt id = 0; id < NB; ++id) {
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(par, id, &st));
    rank0[id] = st.rank;
  }
  PetscInt segments = 0;
  PetscCall(FDEMRigidSolve(par, 0.0, T, dt, 5, CountSegments, &segments));
  PetscCall(FDEMRigidSolve(ser, 0.0, T, dt, 5, nullptr, nullptr));
  PetscCall(FDEMRigidGetNumBodies(par, &nloc, &nglob));
  CHECK(nglob == NB, "after the run the parallel scene has %" PetscInt_FMT " bodies, expected %" PetscInt_FMT, nglob, NB);

  double                worst = 0;
  PetscInt              moved = 0, crossed = 0;
  std::vector<double>   lo(size, INFINITY), hi(size, -INFINITY);
  std::vector<PetscInt> count(size, 0), weight(size, 0);
  for (PetscInt id = 0; id < NB; ++id) {
    FDEMRigidBodyState a, b;
    PetscCall(FDEMRigidGetBodyState(par, id, &a));
    PetscCall(FDEMRigidGetBodyState(ser, id, &b));
    rank1[id] = a.rank;
    if (rank1[id] != rank0[id]) moved++;
    // relative to the size of each quantity: |x| (box ~ 8), |R| = 1, |v|, |H|
    double nx = 0, nv = 0, nH = 0, dx = 0, dR = 0, dv = 0, dH = 0;
    for (int k = 0; k < 3; ++k) {
      nx = std::fmax(nx, std::fabs(b.x[k]));
      nv = std::fmax(nv, std::fabs(b.v[k]));
      nH = std::fmax(nH, std::fabs(b.H[k]));
      dx = std::fmax(dx, std::fabs(a.x[k] - b.x[k]));
      dv = std::fmax(dv, std::fabs(a.v[k] - b.v[k]));
      dH = std::fmax(dH, std::fabs(a.H[k] - b.H[k]));
    }
    for (int k = 0; k < 9; ++k) dR = std::fmax(dR, std::fabs(a.R[k] - b.R[k]));
    const double rel = std::fmax(std::fmax(dx / nx, dR), std::fmax(dv / nv, dH / nH));
    worst = std::fmax(worst, rel);
    CHECK(rel <= 1e-12, "body %" PetscInt_FMT ": parallel and serial differ by %.3e (x %.2e, R %.2e, v %.2e, H %.2e)", id, rel, dx / nx, dR, dv / nv, dH / nH);
    // slabs along x: the ranks' ranges of x, and their numbers of bodies
    lo[a.rank] = std::fmin(lo[a.rank], a.x[0]);
    hi[a.rank] = std::fmax(hi[a.rank], a.x[0]);
    count[a.rank]++;
    weight[a.rank] += g_tets[id];
    // it crossed the middle of the box (the slab boundary on 2 ranks) in the serial run
    CHECK(b.x[0] > 0 && b.x[0] < LX, "body %" PetscInt_FMT " left the box: x = %g", id, b.x[0]);
    if ((b.x[0] < LX / 2) != (X0(id) < LX / 2)) crossed++;
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d ranks, %" PetscInt_FMT " bodies, T = %g, dt = %g, %" PetscInt_FMT " segments of 5 steps: max relative difference parallel vs serial %.3e (bound 1e-12)\n", size, NB, (double)T, (double)dt,
                        segments - 1, worst));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "bodies that crossed the middle of the box: %" PetscInt_FMT "; bodies that changed rank: %" PetscInt_FMT "\n", crossed, moved));
  // the last migration bisected along x (the longest spread, at every level here: the box is
  // 8 x 2 x 2): each rank's bodies lie below the next rank's
  for (int r = 0; r + 1 < size; ++r) CHECK(hi[r] < lo[r + 1], "the bodies of rank %d reach x = %g, beyond the first of rank %d at x = %g", r, hi[r], r + 1, lo[r + 1]);
  // the partition balances the bodies' weights (their tetrahedra): each rank within one body's
  // weight of its share per level of the bisection
  PetscInt wtot = 0, wmax = 0, levels = 0;
  for (PetscInt id = 0; id < NB; ++id) wtot += g_tets[id], wmax = std::max(wmax, g_tets[id]);
  while ((1 << levels) < size) ++levels;
  for (int r = 0; r < size; ++r)
    CHECK(std::fabs((double)weight[r] - (double)wtot / size) <= (double)(levels * wmax), "rank %d holds %" PetscInt_FMT " of %" PetscInt_FMT " bodies, %" PetscInt_FMT " of %" PetscInt_FMT " tetrahedra: the partition is not balanced", r, count[r], NB, weight[r], wtot);
  CHECK(crossed >= NB / 4, "only %" PetscInt_FMT " bodies crossed the middle of the box: the scene does not exercise migration", crossed);
  if (size > 1) CHECK(moved >= NB / 4, "only %" PetscInt_FMT " bodies changed rank on %d ranks", moved, size);
  else CHECK(moved == 0, "%" PetscInt_FMT " bodies changed rank on one rank", moved);

  // every body's state gathered at once on the last rank (FDEMRigidGetBodyStates) is the state
  // FDEMRigidGetBodyState gives body by body, to the bit, in the order of the ids
  {
    PetscInt            n;
    FDEMRigidBodyState *all;
    PetscMPIInt         rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    PetscCall(FDEMRigidGetBodyStates(par, size - 1, &n, &all));
    PetscInt wrong = !(n == (rank == size - 1 ? NB : 0) && (n == 0) == (all == nullptr)), differ = 0;
    for (PetscInt id = 0; id < NB; ++id) {
      FDEMRigidBodyState a;
      PetscCall(FDEMRigidGetBodyState(par, id, &a));
      if (id >= n) continue;
      const FDEMRigidBodyState &b = all[id];
      bool same = a.id == b.id && a.rank == b.rank && a.mass == b.mass && a.radius == b.radius;
      for (int k = 0; k < 3; ++k) same = same && a.inertia[k] == b.inertia[k] && a.x[k] == b.x[k] && a.v[k] == b.v[k] && a.H[k] == b.H[k] && a.omega_space[k] == b.omega_space[k];
      for (int k = 0; k < 9; ++k) same = same && a.R[k] == b.R[k];
      differ += !same;
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &wrong, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &differ, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    CHECK(wrong == 0, "FDEMRigidGetBodyStates gave the wrong number of bodies on %" PetscInt_FMT " rank(s) (all %" PetscInt_FMT " on the root, none elsewhere)", wrong, NB);
    CHECK(differ == 0, "%" PetscInt_FMT " bodies differ between FDEMRigidGetBodyStates and FDEMRigidGetBodyState", differ);
    PetscCall(PetscFree(all));
  }

  PetscCall(FDEMRigidDestroy(&par));
  PetscCall(FDEMRigidDestroy(&ser));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
