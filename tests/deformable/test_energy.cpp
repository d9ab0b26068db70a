// Energy and parallel consistency of a free vibrating block (no fixed nodes).
//  1. Undamped (mu = 0), -ts_type cd: kinetic + strain energy stays within
//     3e-3 of its initial value over ~10 periods of the lowest mode (the
//     bounded O((w h)^2) oscillation of a symplectic scheme, no drift).
//  2. Damped (mu > 0): the energy never grows (beyond 1e-9 relative between
//     samples) and ends below a tenth of its initial value.
//  3. The same undamped run on PETSC_COMM_SELF (one rank holds the whole mesh)
//     and on PETSC_COMM_WORLD: positions of a few nodes, by global id, and the
//     energy history agree to 1e-9 relative (with 2 ranks only the summation
//     order of shared nodes differs).
#include "common.hpp"

namespace {
struct History {
  FDEMDeformable      d;
  std::vector<double> E;
};

PetscErrorCode Monitor(TS, PetscInt step, PetscReal, Vec U, void *ctx) {
  History  *h = (History *)ctx;
  PetscReal k, s;
  PetscFunctionBeginUser;
  if (step % 10) PetscFunctionReturn(0);
  PetscCall(FDEMDeformableGetEnergy(h->d, U, &k, &s, nullptr));
  h->E.push_back(k + s);
  PetscFunctionReturn(0);
}

// a smooth deformational initial velocity (stretching, bending, twisting) with
// (nearly) zero linear and angular momentum, so the damping can take it all
PetscErrorCode Kick(PetscInt, const PetscReal X[3], PetscReal v[3], void *) {
  const double a = 1e-3;
  v[0] = a * std::cos(M_PI * X[0]);
  v[1] = a * std::cos(M_PI * X[0]) * (X[2] - 0.25);
  v[2] = a * std::cos(2 * M_PI * X[0]);
  return 0;
}

PetscErrorCode Run(MPI_Comm comm, double mu, double T, History *h, std::vector<double> *probe) {
  FDEMDeformable d;
  TS             ts;
  Vec            U;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "gel", 1.0, 0.3, 1.0, mu, FDEM_MATERIAL_MUNJIZA_CST));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1.0, 0.5, 0.5};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, 6, 3, 3));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableSetVelocityField(d, Kick, nullptr));
  h->d = d;
  PetscCall(TSCreate(comm, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, 0.02));
  PetscCall(TSSetMaxTime(ts, T));
  PetscCall(TSSetMaxSteps(ts, 1000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSMonitorSet(ts, Monitor, h, nullptr));
  PetscCall(TSSolve(ts, U));
  if (probe)
    for (PetscInt id : {0, 17, 60, 83, 111}) {
      PetscReal x[3], v[3];
      PetscCall(FDEMDeformableGetNodeState(d, U, id, x, v));
      probe->insert(probe->end(), {x[0], x[1], x[2], v[0], v[1], v[2]});
    }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  const double T = 30; // the lowest (bending) mode has a period of about 3
  History      h0, h1, hs;
  std::vector<double> pw, ps;
  PetscCall(Run(PETSC_COMM_WORLD, 0.0, T, &h0, &pw));
  double drift = 0;
  for (double e : h0.E) drift = std::fmax(drift, std::fabs(e - h0.E[0]) / h0.E[0]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "undamped, t in [0, %g], %zu samples: E0 = %.6e, max |E - E0| / E0 = %.2e\n", T, h0.E.size(), h0.E[0], drift));
  CHECK(drift < 3e-3, "undamped energy drifts by %g", drift);

  PetscCall(Run(PETSC_COMM_WORLD, 0.05, T, &h1, nullptr));
  double rise = 0;
  for (size_t i = 1; i < h1.E.size(); ++i) rise = std::fmax(rise, (h1.E[i] - h1.E[i - 1]) / h1.E[0]);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "damped (mu = 0.05): E_end / E0 = %.3e, largest rise between samples %.2e E0\n", h1.E.back() / h1.E[0], rise));
  CHECK(h1.E.back() < 0.1 * h1.E[0], "damping does not dissipate: %g", h1.E.back() / h1.E[0]);
  CHECK(rise < 1e-9, "damped energy grows by %g", rise);

  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  if (size > 1) {
    PetscCall(Run(PETSC_COMM_SELF, 0.0, T, &hs, &ps));
    double de = 0, dx = 0, xs = 0;
    for (size_t i = 0; i < hs.E.size(); ++i) de = std::fmax(de, std::fabs(hs.E[i] - h0.E[i]) / h0.E[0]);
    for (size_t i = 0; i < ps.size(); ++i) {
      dx = std::fmax(dx, std::fabs(ps[i] - pw[i]));
      xs = std::fmax(xs, std::fabs(ps[i]));
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d ranks vs 1: max energy difference %.2e E0, max nodal difference %.2e (5 nodes by global id)\n", size, de, dx));
    CHECK(hs.E.size() == h0.E.size() && de < 1e-9, "energy histories differ: %g", de);
    CHECK(dx < 1e-9 * xs, "nodal values differ: %g", dx);
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "energy test passed\n"));
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
