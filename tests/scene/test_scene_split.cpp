// A combined scene without contact -- a spinning rigid body and a vibrating,
// viscous deformable bar in ONE TS -- gives the trajectories of the rigid body
// and of the bar stepped separately in their own TS (to 1e-12), for every
// splitting scheme given by -schemes (default cd,pefrl). The bar is viscous so
// that its internal force reads velocities: they must come from the combined
// state.
#include <fdem.h>
#include <fdem/scene.h>
#include "../common/check.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace {
const PetscReal dt = 1e-4;
const PetscInt  nsteps = 500;

PetscErrorCode BendVelocity(PetscInt, const PetscReal X[3], PetscReal v[3], void *) {
  v[0] = 0;
  v[1] = 0.3 * X[0] * X[0];
  v[2] = 0.5 * X[0];
  return 0;
}

PetscErrorCode MakeRigid(FDEMRigid *rb) {
  const PetscReal I[3] = {1.0, 2.0, 2.7}, x[3] = {3, 0, 0}, v[3] = {0.1, -0.2, 0.3}, w[3] = {3, 1, -2}, g[3] = {0, 0, -9.81};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, rb));
  PetscCall(FDEMRigidSetGravity(*rb, g));
  PetscCall(FDEMRigidSetFromOptions(*rb));
  PetscCall(FDEMRigidAddBody(*rb, "spinner", 2.0, I, x, nullptr, v, w, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode MakeBar(FDEMDeformable *d) {
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1e-9, 1, 1};
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, d));
  PetscCall(FDEMDeformableAddMaterial(*d, "rubber", 1e6, 0.3, 1000, 50, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshBeam(*d, 1.0, 0.1, 0.1, 2));
  PetscCall(FDEMDeformableSetFromOptions(*d));
  PetscCall(FDEMDeformableSetUp(*d));
  PetscCall(FDEMDeformableFixNodesInBox(*d, lo, hi, nullptr));
  PetscCall(FDEMDeformableSetVelocityField(*d, BendVelocity, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode Run(TS ts, Vec U, const char *type) {
  PetscFunctionBeginUser;
  PetscCall(TSSetType(ts, type));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxSteps(ts, nsteps));
  PetscCall(TSSetMaxTime(ts, 1e9));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSolve(ts, U));
  PetscFunctionReturn(0);
}

PetscReal MaxDiff(Vec a, Vec b) {
  PetscInt           n;
  const PetscScalar *x, *y;
  PetscReal          m = 0, g = 0, s = 0, gs;
  VecGetLocalSize(a, &n);
  VecGetArrayRead(a, &x);
  VecGetArrayRead(b, &y);
  for (PetscInt i = 0; i < n; ++i) {
    m = PetscMax(m, PetscAbsScalar(x[i] - y[i]));
    s = PetscMax(s, PetscAbsScalar(x[i]));
  }
  VecRestoreArrayRead(a, &x);
  VecRestoreArrayRead(b, &y);
  MPIU_Allreduce(&m, &g, 1, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD);
  MPIU_Allreduce(&s, &gs, 1, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD);
  return g / PetscMax(gs, 1e-300);
}
} // namespace

int main(int argc, char **argv) {
  char      schemes[256] = "cd,pefrl";
  PetscBool flg;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-schemes", schemes, sizeof(schemes), &flg));
  std::string list = schemes;
  size_t      pos  = 0;
  while (pos < list.size()) {
    size_t            e    = list.find(',', pos);
    const std::string type = list.substr(pos, e == std::string::npos ? std::string::npos : e - pos);
    pos                    = e == std::string::npos ? list.size() : e + 1;
    // separately
    FDEMRigid         rb1, rb2;
    FDEMDeformable    d1, d2;
    TS                ts;
    Vec               U;
    FDEMRigidBodyState s1, s2;
    PetscCall(MakeRigid(&rb1));
    PetscCall(MakeBar(&d1));
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, type.c_str()));
    PetscCall(FDEMRigidSetUpTS(rb1, ts, &U));
    PetscCall(Run(ts, U, type.c_str()));
    PetscCall(FDEMRigidRestoreState(rb1, U));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, type.c_str()));
    PetscCall(FDEMDeformableSetUpTS(d1, ts, &U));
    PetscCall(Run(ts, U, type.c_str()));
    PetscCall(FDEMDeformableRestoreState(d1, U));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    // together
    FDEMScene sc;
    PetscCall(MakeRigid(&rb2));
    PetscCall(MakeBar(&d2));
    PetscCall(FDEMSceneCreate(PETSC_COMM_WORLD, &sc));
    PetscCall(FDEMSceneSetRigid(sc, rb2));
    PetscCall(FDEMSceneSetDeformable(sc, d2));
    PetscCall(FDEMSceneSetFromOptions(sc));
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, type.c_str()));
    PetscCall(FDEMSceneSetUpTS(sc, ts, &U));
    PetscCall(Run(ts, U, type.c_str()));
    PetscCall(FDEMSceneRestoreState(sc, U));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    // compare
    PetscCall(FDEMRigidGetBodyState(rb1, 0, &s1));
    PetscCall(FDEMRigidGetBodyState(rb2, 0, &s2));
    PetscReal er = 0, sr = 0;
    for (int k = 0; k < 3; ++k) {
      er = PetscMax(er, PetscMax(PetscAbsReal(s1.x[k] - s2.x[k]), PetscMax(PetscAbsReal(s1.v[k] - s2.v[k]), PetscAbsReal(s1.H[k] - s2.H[k]))));
      sr = PetscMax(sr, PetscMax(PetscAbsReal(s1.x[k]), PetscMax(PetscAbsReal(s1.v[k]), PetscAbsReal(s1.H[k]))));
    }
    for (int k = 0; k < 9; ++k) er = PetscMax(er, PetscAbsReal(s1.R[k] - s2.R[k]));
    er /= sr;
    Vec x1, x2, v1, v2;
    PetscCall(FDEMDeformableGetPositions(d1, &x1));
    PetscCall(FDEMDeformableGetPositions(d2, &x2));
    PetscCall(FDEMDeformableGetVelocities(d1, &v1));
    PetscCall(FDEMDeformableGetVelocities(d2, &v2));
    const PetscReal ex = MaxDiff(x1, x2), ev = MaxDiff(v1, v2);
    PetscReal       x0[3], vtip[3], vtip2[3];
    PetscCall(FDEMDeformableGetNodeState(d1, nullptr, 0, x0, vtip));
    // the bar moved: the test is not vacuous
    Vec X;
    PetscCall(FDEMDeformableGetReferencePositions(d1, &X));
    const PetscReal moved = MaxDiff(x1, X);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-6s rigid rel diff %.3e, mesh x rel diff %.3e, v rel diff %.3e (mesh moved %.3e of its size, body travelled %.3f)\n", type.c_str(), (double)er, (double)ex, (double)ev,
                          (double)moved, (double)std::hypot(s1.x[0] - 3, std::hypot(s1.x[1], s1.x[2]))));
    CHECK(er <= 1e-12, "%s: rigid body differs by %g (relative)", type.c_str(), (double)er);
    CHECK(ex <= 1e-12 && ev <= 1e-12, "%s: mesh differs by %g (x) %g (v) (relative)", type.c_str(), (double)ex, (double)ev);
    CHECK(moved > 1e-4, "%s: the bar did not move (%g)", type.c_str(), (double)moved);
    (void)vtip2;
    PetscCall(FDEMSceneDestroy(&sc));
    PetscCall(FDEMRigidDestroy(&rb1));
    PetscCall(FDEMRigidDestroy(&rb2));
    PetscCall(FDEMDeformableDestroy(&d1));
    PetscCall(FDEMDeformableDestroy(&d2));
  }
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failure(s)\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
