// Benchmark of the whole contact pipeline between rigid bodies (halo,
// broad phase, narrow phase, forces back to the owners) on many pebbles:
// N = -n_list pebbles (convex hulls of 8 random points on an ellipsoid,
// 8..12 skin tetrahedra each) on a cubic lattice at two packing densities,
//   dense:  lattice spacing 1.6 a (-dense; a = the long semi-axis: bounding
//           spheres overlap, every pebble has its lattice neighbours within
//           the search distance and some touch),
//   sparse: spacing 4 a (no neighbour within reach: only the self-pairs of
//           the cell search are rejected),
// with random velocities (-v) and spins, no gravity, -steps steps of -dt.
// The timings come from the PETSc log events FDEMContactDetect (ghost halo
// set-up + cell search, per search), FDEMContactForce (narrow phase + damping
// + force reduction, per evaluation) and FDEMContactHalo (ghost state update
// between searches). Prints per N and density: time per body for a search,
// per body-evaluation and per candidate tetrahedron pair, and the pair counts;
// -csv FILE writes the table. step/body is the wall time of the whole step
// per body (rigid motion included: -fdem_rigid_rotation exact, the default,
// costs ~18 us per body-step by itself; munjiza 0.7 us; bench/contact/run.sh uses munjiza).
// Usage: bench_contact [-n_list 100,1000,10000] [-steps 10] [-csv out.csv] [-log_view]
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/rotation.hpp>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {

struct EventTimes {
  double detect = 0, force = 0, halo = 0;
  int    ndetect = 0, nforce = 0;
};

PetscErrorCode GetEventTimes(EventTimes &e) {
  PetscLogEvent      ev;
  PetscEventPerfInfo info;
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventGetId("FDEMContactDetect", &ev));
  PetscCall(PetscLogEventGetPerfInfo(0, ev, &info));
  e.detect  = info.time;
  e.ndetect = info.count;
  PetscCall(PetscLogEventGetId("FDEMContactForce", &ev));
  PetscCall(PetscLogEventGetPerfInfo(0, ev, &info));
  e.force  = info.time;
  e.nforce = info.count;
  PetscCall(PetscLogEventGetId("FDEMContactHalo", &ev));
  PetscCall(PetscLogEventGetPerfInfo(0, ev, &info));
  e.halo = info.time;
  PetscFunctionReturn(0);
}

struct Row {
  PetscInt n;
  double   spacing;
  double   detect_per_body, force_per_body, force_per_pair, halo_per_body, step_per_body, cand_per_body, active_per_body;
};

PetscErrorCode RunOne(PetscInt n, double spacing_factor, PetscInt steps, PetscReal dt, PetscReal vmax, Row &row) {
  const double a = 0.05;
  const int    m = (int)std::ceil(std::cbrt((double)n) - 1e-9);
  const double s = spacing_factor * a;
  FDEMRigid    rb;
  FDEMContact  c;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  const PetscReal lo[3] = {-s, -s, -s}, hi[3] = {m * s * 1.01, m * s, m * s};
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMRigidSetFromOptions(rb)); // -fdem_rigid_rotation (default exact: most of step/body when sparse)
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMContactSetPenalty(c, 1e6));
  PetscCall(FDEMContactSetDissipation(c, 1e4, 0.5, 1e4));
  PetscCall(FDEMContactSetFromOptions(c));
  std::mt19937_64                        rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  std::normal_distribution<double>       N(0, 1);
  for (PetscInt p = 0; p < n; ++p) {
    std::vector<Vec3> pts;
    while (pts.size() < 8) {
      Vec3 d(N(rng), N(rng), N(rng));
      if (norm(d) < 1e-6) continue;
      d = d / norm(d);
      pts.push_back(Vec3(a * d.x, 0.8 * a * d.y, 0.6 * a * d.z));
    }
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> T;
    fdem::kernels::MakeConvexPolyhedronTets(pts, X, T);
    std::vector<PetscReal> nodes;
    std::vector<PetscInt>  tets;
    for (const Vec3 &q : X) nodes.insert(nodes.end(), {q.x, q.y, q.z});
    for (const auto &t : T) tets.insert(tets.end(), {t[0], t[1], t[2], t[3]});
    const PetscReal x[3] = {(p % m) * s, ((p / m) % m) * s, (p / (m * m)) * s};
    const Mat3      Q    = fdem::kernels::RotationMatrix(Vec3(3 * U(rng), 3 * U(rng), 3 * U(rng)));
    PetscReal       Qr[9], v[3], w[3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) Qr[3 * r + k] = Q.m[r][k];
    for (int k = 0; k < 3; ++k) {
      v[k] = vmax * U(rng);
      w[k] = 10 * vmax * U(rng);
    }
    PetscCall(FDEMRigidAddBodyFromMesh(rb, "pebble", (PetscInt)X.size(), nodes.data(), (PetscInt)T.size(), tets.data(), 2600, x, Qr, v, w, nullptr));
  }
  EventTimes e0, e1;
  PetscCall(GetEventTimes(e0));
  PetscLogDouble t0, t1;
  PetscCall(PetscTime(&t0));
  PetscCall(FDEMRigidSolve(rb, 0, steps * dt, dt, steps, nullptr, nullptr));
  PetscCall(PetscTime(&t1));
  PetscCall(GetEventTimes(e1));
  FDEMContactStats st;
  PetscCall(FDEMContactGetStats(c, &st));
  // candidate / active pairs summed over the ranks; event times: the slowest rank
  double loc[2] = {(double)st.candidate_pairs, (double)st.active_pairs}, glob[2];
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  double tl[4] = {e1.detect - e0.detect, e1.force - e0.force, e1.halo - e0.halo, t1 - t0}, tg[4];
  PetscCallMPI(MPI_Allreduce(tl, tg, 4, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
  const int nsearch = e1.ndetect - e0.ndetect, neval = e1.nforce - e0.nforce;
  row.n               = n;
  row.spacing         = spacing_factor;
  row.detect_per_body = tg[0] / std::max(1, nsearch) / n;
  row.force_per_body  = tg[1] / std::max(1, neval) / n;
  row.force_per_pair  = glob[0] > 0 ? tg[1] / std::max(1, neval) / glob[0] : 0;
  row.halo_per_body   = tg[2] / std::max(1, neval - nsearch) / n;
  row.step_per_body   = tg[3] / steps / n;
  row.cand_per_body   = glob[0] / n;
  row.active_per_body = glob[1] / n;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%7d | %-6s | %10.2f %10.2f %10.3f %9.3f %10.2f | %9.1f %8.2f | %3d %3d\n", (int)n, spacing_factor < 3.5 ? "dense" : "sparse", 1e6 * row.detect_per_body, 1e6 * row.force_per_body,
                        1e9 * row.force_per_pair, 1e6 * row.halo_per_body, 1e6 * row.step_per_body, row.cand_per_body, row.active_per_body, nsearch, neval));
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  PetscInt    nlist[16] = {100, 1000, 10000}, nn = 16, steps = 10;
  PetscReal   dt = 1e-4, vmax = 0.5, dense = 1.6;
  char        csv[PETSC_MAX_PATH_LEN] = "";
  PetscMPIInt size;
  PetscBool   set;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscLogDefaultBegin());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Contact pipeline benchmark", "");
  PetscCall(PetscOptionsIntArray("-n_list", "numbers of pebbles", "", nlist, &nn, &set));
  if (!set) nn = 3;
  PetscCall(PetscOptionsInt("-steps", "time steps per configuration", "", steps, &steps, nullptr));
  PetscCall(PetscOptionsReal("-dt", "time step", "", dt, &dt, nullptr));
  PetscCall(PetscOptionsReal("-dense", "lattice spacing of the dense packing / long semi-axis", "", dense, &dense, nullptr));
  PetscCall(PetscOptionsReal("-v", "largest initial speed component (m/s)", "", vmax, &vmax, nullptr));
  PetscCall(PetscOptionsString("-csv", "CSV output", "", csv, csv, sizeof(csv), nullptr));
  PetscOptionsEnd();
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "contact pipeline, %d rank(s), %d steps of %g s per configuration, pebbles of 8..12 tetrahedra\n", (int)size, (int)steps, (double)dt));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "      N | pack   |  detect/body  force/body  force/pair  halo/body  step/body | cand/body active/body | searches evals\n"));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "        |        |  (us/search)  (us/eval)    (ns)     (us/eval)   (us)     |   (tet pairs)         |\n"));
  std::vector<Row> rows;
  for (double sp : {dense, 4.0})
    for (PetscInt i = 0; i < nn; ++i) {
      Row r;
      PetscCall(RunOne(nlist[i], sp, steps, dt, vmax, r));
      rows.push_back(r);
    }
  if (csv[0]) {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
    if (rank == 0) {
      FILE *fp = std::fopen(csv, "w");
      PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", csv);
      std::fprintf(fp, "ranks,n,packing,detect_us_per_body_search,force_us_per_body_eval,force_ns_per_candidate_pair,halo_us_per_body_eval,step_us_per_body,candidate_pairs_per_body,active_pairs_per_body\n");
      for (const Row &r : rows)
        std::fprintf(fp, "%d,%d,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%.4f\n", (int)size, (int)r.n, r.spacing < 3.5 ? "dense" : "sparse", 1e6 * r.detect_per_body, 1e6 * r.force_per_body, 1e9 * r.force_per_pair, 1e6 * r.halo_per_body,
                     1e6 * r.step_per_body, r.cand_per_body, r.active_per_body);
      std::fclose(fp);
    }
  }
  PetscCall(PetscFinalize());
  return 0;
}
