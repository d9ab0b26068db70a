// A rigid cube (tilted, spinning) strikes a free deformable block in one TS:
//  - total linear momentum (rigid m v + mesh sum m v) conserved to 1e-12 relative;
//  - the cube bounces back and separates; with no damping the energy after
//    separation (kinetic + strain) returns to the initial energy within a
//    tolerance, and the error shrinks with the time step (-dts list);
//  - on more than one rank, the run equals the same run on one rank (rank 0,
//    PETSC_COMM_SELF) to 1e-10 relative, node by node (by global id).
#include <fdem.h>
#include <fdem/scene.h>
#include <fdem/kernels/massprops.hpp>
#include "../common/check.hpp"
#include "common.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace {
struct Result {
  PetscReal              P0[3], P1[3], E0, E1, Emax_contact, vz_end;
  PetscInt               searches, max_active;
  FDEMRigidBodyState     cube;
  std::vector<PetscReal> nodes; // on rank 0 of comm: (x, v) by global id
};

PetscErrorCode Impact(MPI_Comm comm, const char *type, PetscReal dt, PetscReal tend, Result &res) {
  FDEMRigid      rb;
  FDEMDeformable d;
  FDEMScene      sc;
  TS             ts;
  Vec            U;
  PetscFunctionBeginUser;
  // the block: free, neo-Hookean (an exact strain energy), undamped
  const PetscReal blo[3] = {0, 0, 0}, bhi[3] = {1, 1, 0.5};
  PetscCall(FDEMDeformableCreate(comm, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rubber", 5e7, 0.3, 1000, 0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshBox(d, blo, bhi, 4, 4, 2));
  PetscCall(FDEMDeformableSetUp(d));
  // the cube: 0.2 wide, tilted, spinning slowly, off-centre, 1 m/s down; lives on the last rank
  std::vector<fdem::kernels::Vec3>  cn;
  std::vector<std::array<int, 4>>   ct;
  fdem::kernels::MakeBoxTets(fdem::kernels::Vec3(-0.1, -0.1, -0.1), fdem::kernels::Vec3(0.1, 0.1, 0.1), 1, 1, 1, cn, ct);
  std::vector<PetscReal> nodes;
  std::vector<PetscInt>  tets;
  for (const auto &p : cn) nodes.insert(nodes.end(), {p.x, p.y, p.z});
  for (const auto &t : ct) tets.insert(tets.end(), t.begin(), t.end());
  const PetscReal a = 0.03, ca = std::cos(a), sa = std::sin(a);
  const PetscReal Q[9] = {ca, 0, sa, 0, 1, 0, -sa, 0, ca};
  const PetscReal x[3] = {0.45, 0.55, 0.5 + 0.1 * (ca + sa) + 0.005}, v[3] = {0.05, 0, -1}, w[3] = {0.5, 0.3, 0};
  const PetscReal dlo[3] = {0, 0, 0}, dhi[3] = {0.8, 0.7, 0.7};
  PetscCall(FDEMRigidCreate(comm, &rb));
  PetscCall(FDEMRigidSetDomain(rb, dlo, dhi));
  PetscCall(FDEMRigidAddBodyFromMesh(rb, "cube", (PetscInt)cn.size(), nodes.data(), (PetscInt)ct.size(), tets.data(), 500, x, Q, v, w, nullptr));
  PetscCall(FDEMSceneCreate(comm, &sc));
  PetscCall(FDEMSceneSetRigid(sc, rb));
  PetscCall(FDEMSceneSetDeformable(sc, d));
  PetscCall(FDEMSceneSetContact(sc, 5e8, 0, 0, -1));
  PetscCall(FDEMSceneSetFromOptions(sc));
  PetscCall(TSCreate(comm, &ts));
  PetscCall(TSSetType(ts, type));
  PetscCall(FDEMSceneSetUpTS(sc, ts, &U));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscReal E[4], L[3];
  PetscCall(FDEMSceneGetInvariants(sc, U, 0, res.P0, L, E));
  res.E0           = E[0] + E[1] + E[2] + E[3];
  res.Emax_contact = 0;
  res.max_active   = 0;
  const PetscInt nsteps = (PetscInt)std::lround(tend / dt), chunk = std::max<PetscInt>(1, nsteps / 40);
  for (PetscInt s = 0; s < nsteps; s += chunk) {
    PetscCall(TSSetMaxSteps(ts, std::min(nsteps, s + chunk)));
    PetscCall(TSSetMaxTime(ts, 1e9));
    PetscCall(TSSolve(ts, U));
    FDEMSceneContactStats st;
    PetscCall(FDEMSceneGetContactStats(sc, &st));
    res.max_active = std::max(res.max_active, st.active_pairs);
    res.Emax_contact = std::max(res.Emax_contact, st.energy);
  }
  PetscReal t;
  PetscCall(TSGetTime(ts, &t));
  PetscCall(FDEMSceneGetInvariants(sc, U, t, res.P1, L, E));
  res.E1 = E[0] + E[1] + E[2] + E[3];
  CHECK(E[3] == 0, "the cube and the block still touch at the end (contact energy %g)", (double)E[3]);
  FDEMSceneContactStats st;
  PetscCall(FDEMSceneGetContactStats(sc, &st));
  res.searches = st.searches;
  PetscCall(FDEMRigidGetBodyState(rb, 0, &res.cube));
  res.vz_end = res.cube.v[2];
  PetscCall(GatherNodes(comm, d, res.nodes));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscReal   dts[8] = {1e-4, 5e-5, 2.5e-5};
  PetscInt    ndt = 8;
  PetscBool   flg;
  char        type[64] = "cd";
  PetscReal   tend = 0.015;
  PetscMPIInt size, rank;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(PetscOptionsGetRealArray(nullptr, nullptr, "-dts", dts, &ndt, &flg));
  if (!flg) ndt = 3;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-type", type, sizeof(type), nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-tend", &tend, nullptr));
  std::vector<PetscReal> err;
  for (PetscInt i = 0; i < ndt; ++i) {
    Result r;
    PetscCall(Impact(PETSC_COMM_WORLD, type, dts[i], tend, r));
    const PetscReal P0 = std::sqrt(r.P0[0] * r.P0[0] + r.P0[1] * r.P0[1] + r.P0[2] * r.P0[2]);
    PetscReal       dP = 0;
    for (int k = 0; k < 3; ++k) dP = PetscMax(dP, PetscAbsReal(r.P1[k] - r.P0[k]));
    const PetscReal dE = PetscAbsReal(r.E1 - r.E0) / r.E0;
    err.push_back(dE);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s dt %.1e: momentum drift %.2e (relative), energy after separation %.4e vs %.4e (rel err %.3e), peak contact energy %.3e (%.1f%% of E0), active pairs max %" PetscInt_FMT ", searches %" PetscInt_FMT ", cube vz %.3f -> %.4f\n",
                          type, (double)dts[i], (double)(dP / P0), (double)r.E1, (double)r.E0, (double)dE, (double)r.Emax_contact, (double)(100 * r.Emax_contact / r.E0), r.max_active, r.searches, -1.0, (double)r.vz_end));
    CHECK(dP / P0 < 1e-12, "dt %g: linear momentum drifts by %g relative", (double)dts[i], (double)(dP / P0));
    CHECK(r.max_active > 0 && r.Emax_contact > 1e-3 * r.E0, "dt %g: no contact happened", (double)dts[i]);
    CHECK(r.vz_end > 0.2, "dt %g: the cube did not bounce back (vz = %g)", (double)dts[i], (double)r.vz_end);
    CHECK(dE < 0.02, "dt %g: energy after separation off by %g relative", (double)dts[i], (double)dE);
    if (i > 0) CHECK(err[i] < err[i - 1], "energy error does not shrink with dt: %g (dt %g) vs %g (dt %g)", (double)err[i], (double)dts[i], (double)err[i - 1], (double)dts[i - 1]);
    if (size > 1 && i == 0) {
      // the same on one rank
      Result s;
      if (rank == 0) PetscCall(Impact(PETSC_COMM_SELF, type, dts[i], tend, s));
      PetscReal diff[2] = {0, 0};
      if (rank == 0) {
        PetscReal scale = 0;
        for (size_t k = 0; k < s.nodes.size(); ++k) {
          diff[0] = PetscMax(diff[0], PetscAbsReal(s.nodes[k] - r.nodes[k]));
          scale   = PetscMax(scale, PetscAbsReal(s.nodes[k]));
        }
        diff[0] /= scale;
        PetscReal cs = 0;
        for (int k = 0; k < 3; ++k) {
          diff[1] = PetscMax(diff[1], PetscMax(PetscAbsReal(s.cube.x[k] - r.cube.x[k]), PetscAbsReal(s.cube.v[k] - r.cube.v[k])));
          diff[1] = PetscMax(diff[1], PetscAbsReal(s.cube.H[k] - r.cube.H[k]));
          cs      = PetscMax(cs, PetscMax(PetscAbsReal(s.cube.x[k]), PetscAbsReal(s.cube.v[k])));
        }
        diff[1] /= cs;
      }
      PetscCallMPI(MPI_Bcast(diff, 2, MPIU_REAL, 0, PETSC_COMM_WORLD));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d ranks vs 1 rank: mesh nodes differ by %.3e, cube by %.3e (relative); the cube lived on rank %d\n", size, (double)diff[0], (double)diff[1], r.cube.rank));
      CHECK(diff[0] < 1e-10 && diff[1] < 1e-10, "%d ranks differ from 1 rank: nodes %g, cube %g", size, (double)diff[0], (double)diff[1]);
      CHECK(r.cube.rank == size - 1 || size > 2, "the cube should live on the last rank (it is on %d)", r.cube.rank);
    }
  }
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failure(s)\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
