// A deformable slab (fixed at its base, or free with -free) struck by a few
// rigid pebbles -- convex hulls of random points (fixed seed) -- in ONE TS
// (FDEMScene), with rigid-deformable contact. Runs under mpiexec; writes
// HDF5 + XDMF of the pebbles (FDEMRigidWriteHDF5) and of the slab
// (FDEMDeformableWriteHDF5) that ParaView opens, and checks itself:
//   - the pebbles bounce back (mean final vz > 0.3 m/s) and none still moves
//     into the slab (vz > -0.05; one that hits on a corner may turn its fall into spin);
//   - no tunnelling: no pebble's skin node ever goes deeper below the slab's
//     top than -max_depth (default 20% of the slab's element height);
//   - with -free: total linear momentum conserved to 1e-12 relative.
// Options: -npebbles 3 -T 0.03 -dt 2.5e-5 -ts_type cd|pefrl|... -output base -output_every 20
//          -fdem_contact_penalty (default 5e8) -fdem_contact_damping/_friction
#include <fdem.h>
#include <fdem/scene.h>
#include <fdem/kernels/massprops.hpp>

#include <cmath>
#include <random>
#include <vector>

using fdem::kernels::Vec3;

int main(int argc, char **argv) {
  PetscInt    npeb = 3, every = 20;
  PetscReal   T = 0.03, dt = 2.5e-5, max_depth = -1;
  PetscBool   free_block = PETSC_FALSE, out = PETSC_FALSE;
  char        base[PETSC_MAX_PATH_LEN] = "block_impact";
  PetscMPIInt size;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-npebbles", &npeb, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-T", &T, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-dt", &dt, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-max_depth", &max_depth, nullptr));
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-free", &free_block, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-output", base, sizeof(base), &out));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-output_every", &every, nullptr));

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
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMSceneSetUpTS(sc, ts, &Us));
  PetscCall(TSSetTimeStep(ts, dt));
  PetscCall(TSSetMaxTime(ts, 1e9));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSetTimeStep(ts, dt));
  TSType type;
  PetscCall(TSGetType(ts, &type));
  char rbase[PETSC_MAX_PATH_LEN], mbase[PETSC_MAX_PATH_LEN];
  PetscCall(PetscSNPrintf(rbase, sizeof(rbase), "%s_np%d_pebbles", base, size));
  PetscCall(PetscSNPrintf(mbase, sizeof(mbase), "%s_np%d_slab", base, size));

  PetscReal P0[3], L[3], E[4], E0;
  PetscCall(FDEMSceneGetInvariants(sc, Us, 0, P0, L, E));
  E0 = E[0] + E[1] + E[2];
  PetscReal      depth = 0, peakE = 0;
  PetscInt       maxact = 0;
  const PetscInt nsteps = (PetscInt)std::lround(T / dt);
  int            fails  = 0;
  for (PetscInt s = 0; s <= nsteps; s += every) {
    if (s > 0) {
      PetscCall(TSSetMaxSteps(ts, std::min(s, nsteps)));
      PetscCall(TSSolve(ts, Us));
    }
    PetscReal t;
    PetscCall(TSGetTime(ts, &t));
    PetscCall(FDEMSceneRestoreState(sc, Us));
    if (out) {
      PetscCall(FDEMRigidWriteHDF5(rb, rbase, s / every, t));
      PetscCall(FDEMDeformableWriteHDF5(d, nullptr, mbase, s / every, t));
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
  PetscCall(FDEMSceneGetInvariants(sc, Us, T, P1, L, E));
  const PetscReal E1 = E[0] + E[1] + E[2] + E[3];
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "block_impact (%s, %d ranks, %" PetscInt_FMT " pebbles, %s slab, %" PetscInt_FMT " fixed nodes): T = %g, dt = %g, peak contact energy %.3e J, max active pairs %" PetscInt_FMT "\n", type, size, npeb,
                        free_block ? "free" : "base-fixed", nfixed, (double)T, (double)dt, (double)peakE, maxact));
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
  if (out) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  wrote %s.h5/.xmf and %s.h5/.xmf\n", rbase, mbase));
  PetscCall(VecDestroy(&Us));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMSceneDestroy(&sc));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(PetscFinalize());
  return fails ? 1 : 0;
}
