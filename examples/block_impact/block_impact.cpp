// A deformable slab (fixed at its base, or free with -free) struck by a few
// rigid pebbles -- convex hulls of random points (fixed seed) -- in ONE TS
// (FDEMScene), with rigid-deformable contact. Runs under mpiexec; writes
// HDF5 + XDMF of the pebbles (FDEMRigidWriteHDF5) and of the slab
// (FDEMDeformableWriteHDF5) that ParaView opens, and checks itself:
//   - the pebbles bounce back (mean final vz > 0.3 m/s) and none still moves
//     into the slab (vz > -0.05; one that hits on a corner may turn its fall into spin);
//   - no tunnelling: no pebble's skin node ever goes deeper below the slab's
//     top than -fdem_max_depth (default 20% of the slab's element height);
//   - with -fdem_free: total linear momentum conserved to 1e-12 relative.
// Options (doc/examples.md): -fdem_bodies 3 (pebbles) -ts_max_time 0.03 -ts_dt 2.5e-5
//   -ts_type cd|pefrl|... -fdem_free -fdem_max_depth -fdem_output DIR (default
//   out/block_impact: pebbles.h5/.xmf, slab.h5/.xmf; none: no files) -fdem_output_every 20
//   (steps between outputs and between the checks' samples)
//   -fdem_contact_penalty (default 5e8) -fdem_contact_damping/_friction
#include <fdem.h>
#include <fdem/scene.h>
#include <fdem/kernels/massprops.hpp>

#include "../common/options.hpp"

#include <cmath>
#include <random>
#include <vector>

using fdem::kernels::Vec3;

PetscErrorCode RunExample(int *status) {
  namespace ex = fdem::examples;
  PetscInt    npeb = 3;
  PetscReal   max_depth = -1;
  PetscBool   free_block = PETSC_FALSE, has_depth;
  ex::Output  out{"out/block_impact", 20};
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Block impact; time steps: -ts_dt (2.5e-5), -ts_max_time (0.03), -ts_type (cd)", "");
  PetscCall(PetscOptionsInt("-fdem_bodies", "number of pebbles", "", npeb, &npeb, nullptr));
  PetscCall(PetscOptionsBool("-fdem_free", "free slab (default: fixed at its base); checks momentum conservation", "", free_block, &free_block, nullptr));
  PetscCall(PetscOptionsReal("-fdem_max_depth", "fail if a pebble point goes deeper below the slab top (default 20% of the element height)", "", max_depth, &max_depth, &has_depth));
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (HDF5 + XDMF) and between the checks' samples");
  PetscOptionsEnd();
  PetscCall(ex::CheckInt("-fdem_bodies", npeb, 1, 1000));
  if (has_depth) PetscCall(ex::CheckPositive("-fdem_max_depth", max_depth));
  PetscCall(ex::SetUpOutput(out));
  const PetscInt every = out.every;

  // the slab [0,1] x [0,1] x [0,0.2], 8 x 8 x 2 Kuhn cells
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 0.2}, top = hi[2];
  const PetscInt  nz    = 2;
  if (max_depth < 0) max_depth = 0.2 * (hi[2] - lo[2]) / nz;
  FDEMDeformable d;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "slab", 5e7, 0.3, 1000, 0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, 8, 8, nz));
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCall(FDEMDeformableSetUp(d));
  PetscInt nfixed = 0;
  if (!free_block) {
    const PetscReal flo[3] = {-1, -1, -1e-9}, fhi[3] = {2, 2, 1e-9};
    PetscCall(FDEMDeformableFixNodesInBox(d, flo, fhi, &nfixed));
  }
  // pebbles: hulls of 12 random points in a ball of radius ~0.07, above the slab, falling at 1-1.5 m/s
  FDEMRigid rb;
  const PetscReal dlo[3] = {0, 0, 0}, dhi[3] = {1, 0.9, 0.9};
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, dlo, dhi)); // slabs along x: pebbles spread over the ranks
  PetscCall(FDEMRigidSetFromOptions(rb));
  std::mt19937                           gen(20240607);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<std::vector<Vec3>>         skin; // body-frame skin nodes of each pebble
  for (PetscInt p = 0; p < npeb; ++p) {
    std::vector<Vec3> pts, nodes;
    std::vector<std::array<int, 4>> tets;
    while (pts.size() < 12) {
      Vec3 q(U(gen), U(gen), U(gen));
      if (norm(q) <= 1) pts.push_back(0.07 * q);
    }
    fdem::kernels::MakeConvexPolyhedronTets(pts, nodes, tets);
    // body frame = principal axes about the centre of mass (as FDEMRigidAddBodyFromMesh): keep it for the depth check
    const auto mp   = fdem::kernels::ComputeMassProperties(nodes, tets, 2600, "pebble");
    double     zmin = 0;
    skin.emplace_back();
    for (const auto &q : nodes) {
      zmin = std::min(zmin, q.z - mp.com.z);
      skin.back().push_back(transpose(mp.principal_axes) * (q - mp.com));
    }
    std::vector<PetscReal> X;
    std::vector<PetscInt>  Tt;
    for (const auto &q : nodes) X.insert(X.end(), {q.x, q.y, q.z});
    for (const auto &t : tets) Tt.insert(Tt.end(), t.begin(), t.end());
    // the lowest point 3 mm above the slab (the mesh is placed unrotated: Q = identity)
    const PetscReal x[3] = {(p + 0.5) / npeb, 0.5 + 0.2 * U(gen), top - zmin + 0.003};
    const PetscReal v[3] = {0.1 * U(gen), 0.1 * U(gen), -1.0 - 0.25 * (1 + U(gen))};
    const PetscReal w[3] = {5 * U(gen), 5 * U(gen), 5 * U(gen)};
    PetscCall(FDEMRigidAddBodyFromMesh(rb, "pebble", (PetscInt)nodes.size(), X.data(), (PetscInt)tets.size(), Tt.data(), 2600, x, nullptr, v, w, nullptr));
  }
  FDEMScene sc;
  PetscCall(FDEMSceneCreate(PETSC_COMM_WORLD, &sc));
  PetscCall(FDEMSceneSetRigid(sc, rb));
  PetscCall(FDEMSceneSetDeformable(sc, d));
  PetscCall(FDEMSceneSetContact(sc, 5e8, 0, 0, -1));
  PetscCall(FDEMSceneSetFromOptions(sc));
  TS  ts;
  Vec Us;
  PetscReal T, dt;
  PetscInt  max_steps;
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(ex::SetTimeDefaults(ts, TSFDEMCD, 2.5e-5, 0.03));
  PetscCall(FDEMSceneSetUpTS(sc, ts, &Us));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(ex::GetTimeSettings(ts, &dt, &T, &max_steps));
  PetscCheck(T / dt <= 1e9, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "Options -ts_max_time %g / -ts_dt %g: %g steps is more than 1e9", (double)T, (double)dt, (double)(T / dt));
  // the loop below counts steps, round(T / dt) of them, and moves the TS's step limit itself
  PetscCall(TSSetMaxTime(ts, 1e9));
  TSType type;
  PetscCall(TSGetType(ts, &type));
  const std::string rbase = out.path("pebbles"), mbase = out.path("slab");

  PetscReal P0[3], L[3], E[4], E0;
  PetscCall(FDEMSceneGetInvariants(sc, Us, 0, P0, L, E));
  E0 = E[0] + E[1] + E[2];
  PetscReal      depth = 0, peakE = 0;
  PetscInt       maxact = 0;
  const PetscInt nsteps = std::min((PetscInt)std::lround(T / dt), max_steps);
  int            fails  = 0;
  for (PetscInt s = 0; s <= nsteps; s += every) {
    if (s > 0) {
      PetscCall(TSSetMaxSteps(ts, std::min(s, nsteps)));
      PetscCall(TSSolve(ts, Us));
    }
    PetscReal t;
    PetscCall(TSGetTime(ts, &t));
    PetscCall(FDEMSceneRestoreState(sc, Us));
    if (out.on()) {
      PetscCall(FDEMRigidWriteHDF5(rb, rbase.c_str(), s / every, t));
      PetscCall(FDEMDeformableWriteHDF5(d, nullptr, mbase.c_str(), s / every, t));
    }
    FDEMSceneContactStats cst;
    PetscCall(FDEMSceneGetContactStats(sc, &cst));
    peakE  = std::max(peakE, cst.energy);
    maxact = std::max(maxact, cst.active_pairs);
    // tunnelling: the lowest skin node of each pebble (x + R p) vs the slab top
    PetscInt n;
    PetscCall(FDEMRigidGetNumBodies(rb, nullptr, &n));
    for (PetscInt id = 0; id < n; ++id) {
      FDEMRigidBodyState st;
      PetscCall(FDEMRigidGetBodyState(rb, id, &st));
      for (const auto &p : skin[id]) {
        const PetscReal z = st.x[2] + st.R[6] * p.x + st.R[7] * p.y + st.R[8] * p.z;
        depth             = std::max(depth, top - z);
      }
    }
    if (s == nsteps) break;
  }
  PetscReal P1[3];
  PetscReal tend;
  PetscInt  steps;
  PetscCall(TSGetTime(ts, &tend));
  PetscCall(TSGetStepNumber(ts, &steps));
  PetscCall(FDEMSceneGetInvariants(sc, Us, T, P1, L, E));
  const PetscReal E1 = E[0] + E[1] + E[2] + E[3];
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "block_impact (%s, %d ranks, %" PetscInt_FMT " pebbles, %s slab, %" PetscInt_FMT " fixed nodes): %" PetscInt_FMT " steps of %g to t = %g, peak contact energy %.3e J, max active pairs %" PetscInt_FMT "\n", type, size, npeb,
                        free_block ? "free" : "base-fixed", nfixed, steps, (double)dt, (double)tend, (double)peakE, maxact));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  energy %.6e -> %.6e J (rel change %.2e; undamped: the contact model's small loss)\n", (double)E0, (double)E1, (double)((E1 - E0) / E0)));
  // checks
  PetscInt n;
  PetscReal vzmean = 0;
  PetscCall(FDEMRigidGetNumBodies(rb, nullptr, &n));
  for (PetscInt id = 0; id < n; ++id) {
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(rb, id, &st));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  pebble %" PetscInt_FMT " (rank %d): z = %.4f, v = (%.3f, %.3f, %.3f)\n", id, st.rank, (double)st.x[2], (double)st.v[0], (double)st.v[1], (double)st.v[2]));
    vzmean += st.v[2] / n;
    if (!(st.v[2] > -0.05)) { // a pebble that hit on a corner may turn its fall into spin, but none may still go in
      fails++;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: pebble %" PetscInt_FMT " still moves into the slab (vz = %g)\n", id, (double)st.v[2]));
    }
  }
  if (!(vzmean > 0.3)) {
    fails++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: the pebbles did not bounce back (mean vz = %g)\n", (double)vzmean));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  deepest pebble point below the slab top: %.2e m (limit %.2e)\n", (double)depth, (double)max_depth));
  if (!(depth < max_depth)) {
    fails++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: a pebble went %g deep into the slab (tunnelling?)\n", (double)depth));
  }
  if (maxact == 0) {
    fails++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: no contact happened\n"));
  }
  if (free_block) {
    const PetscReal P0n = std::sqrt(P0[0] * P0[0] + P0[1] * P0[1] + P0[2] * P0[2]);
    PetscReal       dP  = 0;
    for (int k = 0; k < 3; ++k) dP = std::max(dP, (PetscReal)std::fabs(P1[k] - P0[k]));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  free slab: linear momentum drift %.2e (relative)\n", (double)(dP / P0n)));
    if (!(dP / P0n < 1e-12)) {
      fails++;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: momentum drifts by %g\n", (double)(dP / P0n)));
    }
  }
  if (out.on()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  wrote %s.h5/.xmf and %s.h5/.xmf\n", rbase.c_str(), mbase.c_str()));
  PetscCall(VecDestroy(&Us));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  *status = fails ? 1 : 0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
