// Deformable-body throughput through the PETSc path (FDEMDeformable):
//  - set-up: METIS partition on rank 0, DMPlex creation and distribution;
//  - internal forces alone: G2L scatter of x, the CST kernel over the local
//    cells, L2G ADD assembly (FDEMDeformableComputeForces);
//  - a whole explicit step: -ts_type cd (one force evaluation per step + drift/kick).
// Prints tetrahedra per second per core, and for the whole step the bytes it
// must move per tetrahedron (counted below from the code), the bandwidth that
// achieves and its fraction of a STREAM triad measured in the same process,
// on every rank at once (so that 2 ranks share the memory system as the step
// does). Options: -n 55 (box cells per side, 6 n^3 tetrahedra: 998 250 for 55)
// -repeats 5 (force evaluations, and runs of -steps steps; the best taken) -steps 20 -model munjiza_cst -visc 0 -stream_mb 64 -stream_repeats 10
// -shuffle (the box numbered in a random order, as an unordered mesh file would be)
#include <fdem.h>
#include <fdem/deformable.h>
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/tetmesh.hpp>
#include <algorithm>
#include <numeric>
#include <random>

#include <cmath>
#include <ctime>
#include <vector>

// CPU seconds of this process (all threads).
static double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static PetscErrorCode Perturb(PetscInt id, const PetscReal X[3], PetscReal x[3], void *) {
  for (int k = 0; k < 3; ++k) x[k] = X[k] * (1 + 1e-3 * k) + 1e-4 * std::sin(0.37 * id + k);
  return 0;
}
static PetscErrorCode Shake(PetscInt id, const PetscReal[3], PetscReal v[3], void *) {
  for (int k = 0; k < 3; ++k) v[k] = 1e-3 * std::cos(0.73 * id + k);
  return 0;
}

// STREAM triad a[i] = b[i] + s c[i] on arrays of `mb` MB each (much larger
// than the caches), the best of `repeats` passes, run on every rank at once
// (a barrier before each pass). Returns this rank's bytes/s, counted as
// STREAM does: 24 bytes per index (two reads and one write).
static PetscErrorCode StreamTriad(PetscInt mb, PetscInt repeats, double *bw, double *bw_cpu) {
  const size_t        len = (size_t)mb * 1024 * 1024 / sizeof(double);
  std::vector<double> a(len, 0.0), b(len, 1.0), c(len, 2.0);
  const double        s = 3.0;
  double              best = 1e300, best_cpu = 1e300, sink = 0;
  PetscLogDouble      t0, t1;
  PetscFunctionBegin;
  for (PetscInt r = 0; r < repeats + 1; ++r) {
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t0));
    const double c0 = CpuSeconds();
    double *__restrict pa = a.data();
    const double *__restrict pb = b.data(), *__restrict pc = c.data();
    for (size_t i = 0; i < len; ++i) pa[i] = pb[i] + s * pc[i];
    const double c1 = CpuSeconds();
    PetscCall(PetscTime(&t1));
    sink += pa[(size_t)r % len];
    if (r > 0) best = std::fmin(best, t1 - t0), best_cpu = std::fmin(best_cpu, c1 - c0); // the first pass warms the pages
  }
  PetscCheck(sink == 7.0 * (repeats + 1), PETSC_COMM_SELF, PETSC_ERR_PLIB, "STREAM triad: wrong result");
  *bw     = 24.0 * (double)len / best;
  *bw_cpu = 24.0 * (double)len / best_cpu; // per CPU second: what a loaded machine's time slices give
  PetscFunctionReturn(0);
}

// Bytes the cd step must move per step on this rank, counted from the code
// (doc/performance.md, "The deformable step"): every array a pass reads or
// writes is counted once per pass (a read-modify-write twice), the gathers
// and scatter-adds of the element loop once per local node (they hit the
// cache when cells and nodes are ordered for locality), nothing for
// write-allocate. Per local cell: the element record. Per owned node (3
// doubles = 24 bytes a vector): the passes over global vectors, plus the
// fixed-node flag (1 byte). Per local node: the passes over local vectors.
struct StepBytes {
  int    owned_passes, local_passes;
  double cell_bytes;
  double PerStep(PetscInt ncells, PetscInt nown, PetscInt nlocal) const { return ncells * cell_bytes + nown * (24.0 * owned_passes + 1) + nlocal * 24.0 * local_passes; }
};
// The passes of one cd step (kick, drift, kick; the first kick reuses the
// last force, so one force evaluation per step). The drift reads the momentum
// directly (FDEMTSSetPositionRHSIdentity: no copy through the position RHS).
// On one rank the force evaluation works in place on the state and on the
// acceleration vector (local nodes = owned nodes); on more ranks it scatters
// the positions to the local vectors and assembles the forces back:
//                                                           1 rank      more ranks
//   kick      p += h/2 a               VecAXPY              owned 3     owned 3
//   drift     q += h p                 VecAXPY              owned 3     owned 3
//   force     x_loc <- q               DMGlobalToLocal      -           owned 1, local 1
//             f_loc = 0                VecSet               owned 1     local 1
//             element loop             x read, f +=         owned 3     local 3
//             a = 0                    VecSet               -           owned 1
//             a += f_loc               DMLocalToGlobal ADD  -           owned 2, local 1
//             a = a / m + g, 0 if fixed acceleration loop   owned 3     owned 3 (+ flag)
//   kick      p += h/2 a               AXPYScan             owned 3     owned 3
// (Before this work: 24 passes on any number of ranks, 18 over owned and 6
// over local nodes: the drift copied the momentum through the position RHS,
// 2 more passes, and one rank took the scatter/assembly path too.)
static StepBytes CdStepBytes(PetscMPIInt size) {
  const double cell = (double)sizeof(fdem::kernels::TetElement);
  if (size == 1) return {3 + 3 + 1 + 3 + 3 + 3, 0, cell};
  return {3 + 3 + 1 + 1 + 2 + 3 + 3, 1 + 1 + 3 + 1, cell};
}

int main(int argc, char **argv) {
  PetscInt          n = 55, repeats = 5, steps = 20, stream_mb = 64, stream_repeats = 10;
  char              state_out[PETSC_MAX_PATH_LEN] = "";
  PetscReal         visc = 0;
  PetscBool         shuffle = PETSC_FALSE;
  FDEMMaterialModel model = FDEM_MATERIAL_MUNJIZA_CST;
  PetscMPIInt       size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Deformable bench", "");
  PetscCall(PetscOptionsInt("-n", "box cells per side", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-repeats", "force evaluations timed, and runs of -steps steps (best taken)", "", repeats, &repeats, nullptr));
  PetscCall(PetscOptionsInt("-steps", "cd steps in each timed run", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsEnum("-model", "material model", "", FDEMMaterialModels, (PetscEnum)model, (PetscEnum *)&model, nullptr));
  PetscCall(PetscOptionsReal("-visc", "viscosity mu", "", visc, &visc, nullptr));
  PetscCall(PetscOptionsInt("-stream_mb", "STREAM triad: MB per array (3 arrays per rank)", "", stream_mb, &stream_mb, nullptr));
  PetscCall(PetscOptionsInt("-stream_repeats", "STREAM triad passes timed (best taken)", "", stream_repeats, &stream_repeats, nullptr));
  PetscCall(PetscOptionsBool("-shuffle", "give the box's nodes and tetrahedra in a random order (as an unordered mesh file would)", "", shuffle, &shuffle, nullptr));
  PetscCall(PetscOptionsString("-state_out", "write the final state [x | v] (PETSc binary, global node order) to this file, to compare builds", "", state_out, state_out, sizeof(state_out), nullptr));
  PetscOptionsEnd();
  PetscCheck(n >= 1 && n <= 400, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-n %d: give 1..400 cells per side", (int)n);
  PetscCheck(repeats >= 1 && repeats <= 1000, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-repeats %d: give 1..1000", (int)repeats);
  PetscCheck(steps >= 1 && steps <= 100000, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-steps %d: give 1..100000", (int)steps);
  PetscCheck(visc >= 0 && std::isfinite(visc), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-visc %g: give a finite value >= 0", (double)visc);
  PetscCheck(stream_mb >= 1 && stream_mb <= 4096, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-stream_mb %d: give 1..4096 MB per array", (int)stream_mb);
  PetscCheck(stream_repeats >= 1 && stream_repeats <= 1000, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "-stream_repeats %d: give 1..1000", (int)stream_repeats);

  FDEMDeformable d;
  PetscLogDouble t0, t1;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1.0, 0.25, 1.0, visc, model));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  if (!shuffle) PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, n, n));
  else {
    // the same box, its nodes and tetrahedra numbered in a random order (fixed seed)
    const fdem::kernels::TetMesh m = fdem::kernels::MakeBoxMesh({lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, (int)n, (int)n, (int)n);
    std::mt19937_64       rng(12345);
    std::vector<PetscInt> pn(m.nodes.size()), pt(m.tets.size()); // new number of each node; old tetrahedron of each new one
    std::iota(pn.begin(), pn.end(), 0);
    std::iota(pt.begin(), pt.end(), 0);
    std::shuffle(pn.begin(), pn.end(), rng);
    std::shuffle(pt.begin(), pt.end(), rng);
    std::vector<PetscReal> xyz(3 * m.nodes.size());
    std::vector<PetscInt>  tets(4 * m.tets.size()), body(m.tets.size(), 0);
    for (std::size_t i = 0; i < m.nodes.size(); ++i)
      for (int k = 0; k < 3; ++k) xyz[3 * pn[i] + k] = m.nodes[i][k];
    for (std::size_t e = 0; e < m.tets.size(); ++e)
      for (int a = 0; a < 4; ++a) tets[4 * e + a] = pn[m.tets[pt[e]][a]];
    const char *names[] = {"box"};
    PetscCall(FDEMDeformableSetMesh(d, (PetscInt)m.nodes.size(), xyz.data(), (PetscInt)m.tets.size(), tets.data(), body.data(), 1, names));
  }
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t0));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
  PetscCall(PetscTime(&t1));
  PetscInt cl, cg, no, ng, cmin, cmax;
  PetscCall(FDEMDeformableGetSizes(d, &cl, &cg, &no, &ng));
  PetscCall(MPIU_Allreduce(&cl, &cmin, 1, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  PetscCall(MPIU_Allreduce(&cl, &cmax, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ranks %d: %d tetrahedra, %d nodes, cells per rank %d..%d; %s%s\n", size, (int)cg, (int)ng, (int)cmin, (int)cmax, FDEMMaterialModels[model], visc > 0 ? " + viscosity" : ""));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "set-up (METIS + DMPlex create/distribute + element data + masses): %.2f s\n", t1 - t0));
  PetscInt d_nlocal; // local nodes (owned + ghosts): the local vectors' length / 3
  {
    DM  dm;
    Vec l;
    PetscCall(FDEMDeformableGetDM(d, &dm));
    PetscCall(DMGetLocalVector(dm, &l));
    PetscCall(VecGetLocalSize(l, &d_nlocal));
    PetscCall(DMRestoreLocalVector(dm, &l));
    d_nlocal /= 3;
  }
  PetscCall(FDEMDeformableSetPositionField(d, Perturb, nullptr));
  PetscCall(FDEMDeformableSetVelocityField(d, Shake, nullptr));

  Vec x, F;
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(VecDuplicate(x, &F));
  double best = 1e300, best_cpu = 1e300, best_cpu_max;
  for (PetscInt r = 0; r < repeats + 1; ++r) {
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t0));
    const double cf0 = CpuSeconds();
    PetscCall(FDEMDeformableComputeForces(d, 0.0, nullptr, F));
    const double cf1 = CpuSeconds();
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t1));
    if (r > 0) best = std::fmin(best, t1 - t0), best_cpu = std::fmin(best_cpu, cf1 - cf0);
  }
  PetscCallMPI(MPI_Allreduce(&best_cpu, &best_cpu_max, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "internal forces (scatter + kernel + ADD assembly): %.4f s per evaluation, %.3g tet/s, %.3g tet/s/core; CPU of the busiest rank %.4f s\n", best, cg / best, cg / best / size, best_cpu_max));

  TS  ts;
  Vec U;
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, 0.2 / n / 1.2));
  PetscCall(TSSetMaxSteps(ts, 1));
  PetscCall(TSSetMaxTime(ts, 1e30));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSolve(ts, U)); // warm-up (set-up, first force)
  // -repeats runs of -steps steps each; the best run's time per step (wall
  // and, separately, the CPU of the busiest rank): a loaded machine only
  // ever makes a run slower
  double per = 1e300, cpu_max = 1e300;
  for (PetscInt r = 0; r < repeats; ++r) {
    PetscCall(TSSetMaxSteps(ts, 1 + (r + 1) * steps));
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t0));
    const double c0 = CpuSeconds();
    PetscCall(TSSolve(ts, U));
    const double c1 = CpuSeconds();
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(PetscTime(&t1));
    double cpu = (c1 - c0) / steps, cpu_r;
    PetscCallMPI(MPI_Allreduce(&cpu, &cpu_r, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    per     = std::fmin(per, (t1 - t0) / steps);
    cpu_max = std::fmin(cpu_max, cpu_r);
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "whole explicit step (-ts_type cd, best of %d runs of %d steps): %.4f s per step, %.3g tet/s, %.3g tet/s/core; CPU of the busiest rank %.4f s per step (%.3g tet-steps per CPU second per core)\n", (int)repeats, (int)steps, per, cg / per, cg / per / size, cpu_max, cg / cpu_max / size));
  // bytes counted, the STREAM bound and the fraction reached
  double bw, bw_all, bwc, bwc_all, bytes, bytes_all;
  const StepBytes kStepBytes = CdStepBytes(size);
  bytes = kStepBytes.PerStep(cl, no, d_nlocal);
  PetscCallMPI(MPI_Allreduce(&bytes, &bytes_all, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(StreamTriad(stream_mb, stream_repeats, &bw, &bwc));
  PetscCallMPI(MPI_Allreduce(&bw, &bw_all, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Allreduce(&bwc, &bwc_all, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  const double bpt = bytes_all / cg, achieved = bytes_all / per, frac = achieved / bw_all, frac_cpu = bytes_all / cpu_max / bwc_all;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "bytes per tetrahedron per step (counted): %.1f (element record %d B; node vectors %d passes over owned, %d over local nodes, 24 B a node each)\n", bpt, (int)kStepBytes.cell_bytes, kStepBytes.owned_passes, kStepBytes.local_passes));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "STREAM triad (%d MB arrays, all ranks at once): %.2f GB/s in all, %.2f GB/s/core; per CPU second %.2f GB/s/core\n", (int)stream_mb, bw_all * 1e-9, bw_all * 1e-9 / size, bwc_all * 1e-9 / size));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "step: %.3g tet-steps/s/core, %.2f GB/s moved, %.1f%% of the STREAM bound (%.3g tet-steps/s/core); from the CPU times (step and STREAM): %.1f%%\n", cg / per / size, achieved * 1e-9, 100 * frac, bw_all / bpt / size, 100 * frac_cpu));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "RESULT ranks=%d tets=%d force_s=%.5f step_s=%.5f bytes_per_tet=%.1f stream_GBs=%.3f fraction=%.4f step_cpu_s=%.5f force_cpu_s=%.5f fraction_cpu=%.4f stream_cpu_GBs=%.3f\n", size, (int)cg, best, per, bpt, bw_all * 1e-9, frac, cpu_max, best_cpu_max, frac_cpu, bwc_all * 1e-9));
  if (state_out[0]) {
    PetscViewer viewer;
    PetscCall(PetscViewerBinaryOpen(PETSC_COMM_WORLD, state_out, FILE_MODE_WRITE, &viewer));
    PetscCall(VecView(U, viewer));
    PetscCall(PetscViewerDestroy(&viewer));
  }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&F));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(PetscFinalize());
  return 0;
}
