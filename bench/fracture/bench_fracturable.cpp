// The cost of a fracturable body per step (doc/fracture.md, "Speed"): the same box of
// n^3 cubes (6 n^3 tetrahedra) stepped by -ts_type cd, whole and split into joints (a
// joint on every interior face, strengths far above the load so that nothing softens,
// and then every joint softening), at the same time step, in interleaved rounds in one
// process. Prints CPU seconds per step of each and the ratios split / whole. A fourth case
// splits the box only in a fracture zone (FDEMDeformableAddFractureZone), the slab
// |x - 1/2| <= zone / 2, intact joints: what a body costs that may crack in part of it.
// Options: -n 16 (cubes per side) -steps 50 -rounds 3 -softening 1 (0: leave out the softening case)
//          -zone 0.125 (the slab's share of the box; 0: leave out the zone case)
//          -zone_centre 0.5 (x of the slab's middle: 0.125 with -zone 0.25 puts it at an end,
//          where a partition that does not weigh the split cells loads one rank more)
#include <fdem.h>
#include <fdem/deformable.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <vector>

static double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// a small random motion, far below the strength for `intact`; an opening stretch of
// 3% (past every joint's peak: they soften) for the damaged case
static PetscReal g_stretch = 0;
static PetscErrorCode Shake(PetscInt id, const PetscReal X[3], PetscReal v[3], void *) {
  for (int k = 0; k < 3; ++k) v[k] = 1e-3 * std::cos(0.73 * id + k) + g_stretch * X[k];
  return 0;
}

static PetscReal g_zone = 0.125, g_zone_centre = 0.5;
static double    g_balance[2] = {1, 1}; // the zone case's busiest rank over the mean: owned nodes, cells

// kind 0: whole; 1: split, intact joints; 2: split, joints softening; 3: split in the zone, intact joints
static PetscErrorCode Run(PetscInt n, PetscInt steps, int kind, double dt, double *cpu_per_step, PetscInt *joints) {
  FDEMDeformable d;
  TS             ts;
  Vec            U;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.25, 2000, 0, FDEM_MATERIAL_MUNJIZA_CST));
  // intact: f_t 1 GPa, never reached; softening: f_t 1 Pa with a large G: the joints pass their peak within a
  // few steps of the stretch and soften without breaking
  if (kind == 1 || kind == 3) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e9, 3e9, 30, 1e9, 1e10, 1e10));
  if (kind == 2) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1, 3, 30, 1e3, 1e4, 1e10));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, n, n));
  if (kind == 3) {
    const PetscReal zlo[3] = {g_zone_centre - g_zone / 2, -1, -1}, zhi[3] = {g_zone_centre + g_zone / 2, 2, 2};
    PetscCall(FDEMDeformableAddFractureZone(d, "box", zlo, zhi));
  }
  g_stretch = kind == 2 ? 30.0 : 0.0; // 30 /s: a strain of 3% per ms
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableSetVelocityField(d, Shake, nullptr));
  PetscCall(FDEMDeformableGetJointStats(d, joints, nullptr, nullptr));
  if (kind == 3) { // the partition's balance: owned nodes (four per split tetrahedron) and cells, busiest rank over the mean
    PetscInt    cl, no;
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    PetscCall(FDEMDeformableGetSizes(d, &cl, nullptr, &no, nullptr));
    double mine[2] = {(double)no, (double)cl}, mx[2], sum[2];
    PetscCallMPI(MPI_Allreduce(mine, mx, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    PetscCallMPI(MPI_Allreduce(mine, sum, 2, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
    g_balance[0] = mx[0] * size / sum[0], g_balance[1] = mx[1] * size / sum[1];
  }
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxSteps(ts, steps));
  PetscCall(TSSetMaxTime(ts, 1e30));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetUp(ts));
  PetscCall(TSStep(ts)); // the first step pays for first-touch set-up
  const double c0 = CpuSeconds();
  PetscCall(TSSolve(ts, U));
  double c = CpuSeconds() - c0, cmax;
  PetscCallMPI(MPI_Allreduce(&c, &cmax, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  PetscInt done;
  PetscCall(TSGetStepNumber(ts, &done));
  *cpu_per_step = cmax / std::max<PetscInt>(1, done - 1);
  if (kind == 2) {
    PetscReal D;
    PetscCall(FDEMDeformableGetJointStats(d, nullptr, nullptr, &D));
    PetscCheck(D > 0, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "bench: the joints of the softening case did not soften");
  }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscInt n = 16, steps = 50, rounds = 3;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-n", &n, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-steps", &steps, nullptr));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-rounds", &rounds, nullptr));
  PetscBool softening = PETSC_TRUE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-softening", &softening, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-zone", &g_zone, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-zone_centre", &g_zone_centre, nullptr));
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const double dt = 1e-7; // below every case's limit (the joints' at p = 10 E), the same for all
  std::vector<double> best(4, 1e300);
  PetscInt            nj[4] = {0, 0, 0, 0};
  for (PetscInt r = 0; r < rounds; ++r)
    for (int kind = 0; kind < 4; ++kind) {
      double c;
      if ((kind == 2 && !softening) || (kind == 3 && !(g_zone > 0))) continue;
      PetscCall(Run(n, steps, kind, dt, &c, &nj[kind]));
      best[kind] = std::min(best[kind], c);
    }
  const double tets = 6.0 * n * n * n;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "box of %" PetscInt_FMT "^3 cubes, %.0f tetrahedra, %d rank(s), cd, %" PetscInt_FMT " steps, best of %" PetscInt_FMT " interleaved rounds (CPU s per step, busiest rank)\n", n, tets, size, steps, rounds));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  whole body            %.4e s/step  (%.3g tet-steps/s/core)\n", best[0], tets / (best[0] * size)));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  split, intact joints  %.4e s/step  (%" PetscInt_FMT " joints, %.2f per tetrahedron)  ratio to whole %.2f\n", best[1], nj[1], nj[1] / tets, best[1] / best[0]));
  if (softening) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  split, joints softening %.4e s/step  ratio to whole %.2f\n", best[2], best[2] / best[0]));
  if (g_zone > 0) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  split in a zone (slab of %.3g of the box at x = %.3g), intact joints  %.4e s/step  (%" PetscInt_FMT " joints)  ratio to whole %.2f\n", (double)g_zone, (double)g_zone_centre, best[3], nj[3], best[3] / best[0]));
  if (g_zone > 0 && size > 1) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "    its partition: busiest rank over the mean, owned nodes %.3f, cells %.3f\n", g_balance[0], g_balance[1]));
  PetscCall(PetscFinalize());
  return 0;
}
