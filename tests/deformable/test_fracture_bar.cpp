// Fracturable deformable bodies (doc/fracture.md), artificial compliance: a
// free-free bar set ringing in its first axial mode (v = v0 cos(pi X / L),
// far below the joints' strength) is softer when split into joints. The
// half-period t of its end's displacement gives an effective modulus
// E_eff = rho (L / t)^2. Asserted:
//  1. the whole bar rings at rod theory's frequency within 2% (the mesh);
//  2. split bars are softer, less so as the joint penalty p grows, and the
//     joints act in series with the elements: E_whole / E_eff = 1 + alpha E/p
//     with the same alpha (within 15%) at p = 10 E and 100 E, alpha between 1
//     and 6 (a joint has a stiffness p/h per area, h the element size, and a
//     load path crosses a few joint layers per element length: the faces
//     between cells and the diagonal faces inside them);
//  3. no joint is damaged (max damage exactly 0);
//  4. the largest stable step of cd, found by bisection, is 0.7 to 2 times
//     2 / omega_j, the joints' frequency estimate of the library's check;
//  5. FixNodes by the input mesh's ids fixes every copy of those nodes;
//  6. one rank holding the whole bar and all ranks of the run agree on the
//     half-period and the end's path to 1e-9 relative (joints straddle ranks).
#include "common.hpp"

#include <cstdio>

namespace {
constexpr double L = 1.0, E = 1.0e9, rho = 2000, nu = 0.25, v0 = 0.05;

struct Probe {
  FDEMDeformable      d;
  Vec                 X = nullptr; // reference positions (owned)
  std::vector<double> u;           // mean x-displacement of the end X = 0, per step
  std::vector<double> t;
};

// The bar (1 x 0.1 x 0.1 m, 20 x 2 x 2 cubes of 6 tetrahedra), set up; split into joints
// with penalty p_over_E E when p_over_E > 0 (strengths far above the tests' loads).
PetscErrorCode MakeBar(MPI_Comm comm, double p_over_E, FDEMDeformable *bar) {
  FDEMDeformable d;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", E, nu, rho, 0, FDEM_MATERIAL_MUNJIZA_CST));
  if (p_over_E > 0) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1.0e6, 3.0e6, 30, 100, 2000, p_over_E * E));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {L, 0.1, 0.1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, 20, 2, 2));
  PetscCall(FDEMDeformableSetUp(d));
  *bar = d;
  PetscFunctionReturn(0);
}

PetscErrorCode EndDisplacement(TS, PetscInt, PetscReal time, Vec U, void *ctx) {
  Probe             *p = (Probe *)ctx;
  const PetscScalar *u, *X;
  PetscInt           n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(p->X, &n));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(p->X, &X));
  double s[2] = {0, 0}, g[2];
  for (PetscInt k = 0; k < n / 3; ++k)
    if (X[3 * k] < 1e-9) {
      s[0] += u[3 * k] - X[3 * k];
      s[1] += 1;
    }
  PetscCall(VecRestoreArrayRead(p->X, &X));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCallMPI(MPI_Allreduce(s, g, 2, MPI_DOUBLE, MPI_SUM, PetscObjectComm((PetscObject)U)));
  p->u.push_back(g[0] / g[1]);
  p->t.push_back(time);
  PetscFunctionReturn(0);
}

PetscErrorCode Ring(PetscInt, const PetscReal X[3], PetscReal v[3], void *) {
  v[0] = v0 * std::cos(M_PI * X[0] / L);
  v[1] = v[2] = 0;
  return 0;
}

// Does the split bar (p = p_over_E E) stay bounded for `steps` steps of dt? Also returns
// the joints' frequency estimate.
PetscErrorCode Bounded(double p_over_E, double dt, int steps, bool *ok, PetscReal *omega) {
  FDEMDeformable d;
  TS             ts;
  Vec            U, X;
  PetscFunctionBeginUser;
  PetscCall(MakeBar(PETSC_COMM_WORLD, p_over_E, &d));
  PetscCall(FDEMDeformableGetJointFrequency(d, omega));
  if (*omega == 0) *omega = 2 / 1e-5; // no joints: dt in units of 1e-5 s
  PetscCall(FDEMDeformableSetVelocityField(d, Ring, nullptr));
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxSteps(ts, steps));
  PetscCall(TSSetMaxTime(ts, 1e9));
  PetscCall(TSSetErrorIfStepFails(ts, PETSC_FALSE));
  // an unstable run ends in an error (an inverted element, on every rank): unbounded
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode failed = TSSolve(ts, U);
  PetscCall(PetscPopErrorHandler());
  // bounded: every node within 100 times the swing's amplitude (v0 L / (pi c)) of its place
  PetscCall(FDEMDeformableGetReferencePositions(d, &X));
  PetscInt           n;
  const PetscScalar *u, *x0;
  PetscCall(VecGetLocalSize(X, &n));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(X, &x0));
  double worst = 0, g;
  for (PetscInt i = 0; i < n; ++i) worst = std::isfinite(u[i]) ? std::fmax(worst, std::fabs(u[i] - x0[i])) : INFINITY;
  PetscCall(VecRestoreArrayRead(X, &x0));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCallMPI(MPI_Allreduce(&worst, &g, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  *ok = !failed && g < 100 * v0 * L / (M_PI * std::sqrt(E / rho));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

// FDEMDeformableFixNodes takes input ids: on a split bar, the 9 input nodes of the end
// X = 0 stand for all their copies (one per tetrahedron around each), counted here from
// the kernel's mesh; on the whole bar they are 9 nodes.
PetscErrorCode FixByInputId(double p_over_E, PetscInt *nfixed, PetscInt *expected) {
  FDEMDeformable d;
  PetscMPIInt    rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(MakeBar(PETSC_COMM_WORLD, p_over_E, &d));
  const fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh({0, 0, 0}, {L, 0.1, 0.1}, 20, 2, 2);
  std::vector<PetscInt>        ids;
  std::vector<char>            end(M.nodes.size(), 0);
  for (std::size_t i = 0; i < M.nodes.size(); ++i)
    if (M.nodes[i].x < 1e-12) {
      ids.push_back((PetscInt)i);
      end[i] = 1;
    }
  *expected = 0;
  if (p_over_E > 0)
    for (const auto &t : M.tets)
      for (int n : t) *expected += end[n];
  else *expected = (PetscInt)ids.size();
  PetscCall(FDEMDeformableFixNodes(d, rank == 0 ? (PetscInt)ids.size() : 0, ids.data(), nfixed));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

// Half-period of the end's displacement (first crossing from + to -), the
// end's path, and the joints' largest damage; p_over_E = 0: not split.
PetscErrorCode Run(MPI_Comm comm, double p_over_E, double *half, std::vector<double> *path, PetscReal *damage, PetscInt *joints) {
  FDEMDeformable d;
  TS             ts;
  Vec            U;
  Probe          p;
  PetscFunctionBeginUser;
  PetscCall(MakeBar(comm, p_over_E, &d));
  PetscCall(FDEMDeformableSetVelocityField(d, Ring, nullptr));
  p.d = d;
  PetscCall(FDEMDeformableGetReferencePositions(d, &p.X));
  PetscCall(TSCreate(comm, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, 1.0e-6)); // below the joints' limit at p = 100 E
  PetscCall(TSSetMaxTime(ts, 2.4 * L / std::sqrt(E / rho)));
  PetscCall(TSSetMaxSteps(ts, 1000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSMonitorSet(ts, EndDisplacement, &p, nullptr));
  PetscCall(TSSolve(ts, U));
  *half = -1;
  for (std::size_t i = 1; i < p.u.size() && *half < 0; ++i)
    if (p.u[i - 1] > 0 && p.u[i] <= 0) *half = p.t[i - 1] + (p.t[i] - p.t[i - 1]) * p.u[i - 1] / (p.u[i - 1] - p.u[i]);
  if (path) *path = p.u;
  *damage = 0;
  *joints = 0;
  if (p_over_E > 0) PetscCall(FDEMDeformableGetJointStats(d, joints, nullptr, damage));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const double c = std::sqrt(E / rho);
  double       tw, t10, t100;
  PetscReal    D;
  PetscInt     nj;
  PetscCall(Run(PETSC_COMM_WORLD, 0, &tw, nullptr, &D, &nj));
  CHECK(tw > 0, "the whole bar's end never swung back");
  const double Ew = rho * (L / tw) * (L / tw);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "whole bar: half-period %.6e s (rod theory %.6e), E_eff/E = %.4f\n", tw, L / c, Ew / E));
  CHECK(std::fabs(Ew / E - 1) < 0.02, "the whole bar's modulus is off rod theory by more than 2%");
  std::vector<double> path;
  double              t1;
  PetscCall(Run(PETSC_COMM_WORLD, 1, &t1, nullptr, &D, &nj));
  CHECK(D == 0, "a joint was damaged at a strain far below the strength");
  const double r1 = rho * (L / t1) * (L / t1) / Ew;
  PetscCall(Run(PETSC_COMM_WORLD, 10, &t10, &path, &D, &nj));
  CHECK(D == 0, "a joint was damaged at a strain far below the strength");
  const double r10 = rho * (L / t10) * (L / t10) / Ew;
  PetscCall(Run(PETSC_COMM_WORLD, 100, &t100, nullptr, &D, &nj));
  CHECK(D == 0, "a joint was damaged at a strain far below the strength");
  const double r100 = rho * (L / t100) * (L / t100) / Ew;
  // joints in series with the elements: E / E_eff = 1 + alpha E / p
  const double a10 = (1 / r10 - 1) * 10, a100 = (1 / r100 - 1) * 100;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "split bar (%" PetscInt_FMT " joints): E_eff/E_whole = %.4f at p = 10 E, %.4f at p = 100 E; alpha = (E_whole/E_eff - 1) p/E = %.3f and %.3f\n", nj, r10, r100, a10, a100));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "split bar at p = E: E_eff/E_whole = %.4f, alpha = %.3f\n", r1, 1 / r1 - 1));
  CHECK(r1 < r10 && r10 < r100 && r100 < 1, "split bars must be softer than the whole bar, less so for a stiffer joint");
  CHECK(std::fabs(a10 / a100 - 1) < 0.15, "the added compliance does not scale as E/p (alpha %.3f at p = 10 E, %.3f at 100 E)", a10, a100);
  CHECK(a10 > 1 && a10 < 6, "alpha = %.3f: not the 1 to 6 joint layers per element length a load path crosses", a10);
  for (double pe : {0.0, 10.0}) {
    PetscInt nf, ne;
    PetscCall(FixByInputId(pe, &nf, &ne));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s bar: the 9 input nodes of the end fix %" PetscInt_FMT " nodes (expected %" PetscInt_FMT ")\n", pe > 0 ? "split" : "whole", nf, ne));
    CHECK(nf == ne && ne >= 9, "fixing by input id: %" PetscInt_FMT " nodes fixed, expected %" PetscInt_FMT, nf, ne);
  }
  // the stable step of cd (K_crit = 2) against the joints' estimate omega_j: bisection of the
  // largest dt that stays bounded for 400 steps, as a multiple of 2 / omega_j
  for (double pe : {0.0, 1.0, 10.0, 100.0}) { // 0: the whole bar
    PetscReal w;
    bool      ok;
    PetscCall(Bounded(pe, 1e-12, 1, &ok, &w));
    double lo = 0.25, hi = 4; // in units of 2 / omega_j
    PetscCall(Bounded(pe, lo * 2 / w, 400, &ok, &w));
    CHECK(ok, "p = %g E: unstable at a quarter of the estimated limit", pe);
    PetscCall(Bounded(pe, hi * 2 / w, 400, &ok, &w));
    if (pe > 0) CHECK(!ok, "p = %g E: stable at 4 times the estimated limit", pe);
    for (int it = 0; it < 7; ++it) {
      const double mid = std::sqrt(lo * hi);
      PetscCall(Bounded(pe, mid * 2 / w, 400, &ok, &w));
      (ok ? lo : hi) = mid;
    }
    if (pe == 0) {
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "whole bar: measured stable step %.4g s\n", lo * 2 / w));
      continue;
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "p = %g E: omega_j = %.4g /s, estimated stable step 2/omega_j = %.4g s, measured %.4g s (x %.3f)\n", pe, (double)w, 2 / w, lo * 2 / w, lo));
    if (pe >= 10) // at p = E the elements' own limit is the lower one
      CHECK(lo > 0.7 && lo < 2.0, "p = %g E: the measured stable step is %.3f times the estimate (expected 0.7 to 2: the estimate is a Gershgorin bound)", pe, lo);
  }
  if (size > 1) {
    double              ts1;
    std::vector<double> path1;
    PetscMPIInt         rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    int ok = 1;
    if (rank == 0) {
      PetscCall(Run(PETSC_COMM_SELF, 10, &ts1, &path1, &D, &nj));
      double worst = 0, scale = 0;
      for (std::size_t i = 0; i < path.size() && i < path1.size(); ++i) {
        worst = std::fmax(worst, std::fabs(path[i] - path1[i]));
        scale = std::fmax(scale, std::fabs(path1[i]));
      }
      std::printf("one rank against %d: half-period %.3e relative, end path %.3e relative\n", size, std::fabs(ts1 - t10) / t10, worst / scale);
      ok = path.size() == path1.size() && std::fabs(ts1 - t10) <= 1e-9 * t10 && worst <= 1e-9 * scale;
    }
    PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, PETSC_COMM_WORLD));
    CHECK(ok, "one rank and all ranks disagree on the split bar");
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
