// Patch test through the whole PETSc pipeline (METIS partition, DMPlex
// distribution, local element data, DMLocalToGlobal ADD_VALUES assembly, TS
// splits): an irregular box mesh under a uniform finite deformation x = A X
// must show the same Cauchy stress in every cell (= the material law at F = A)
// and zero force at every interior node, for each material model; one -ts_type
// cd step must leave the interior nodes at rest. Also checks the lumped masses
// (sum = rho V) and the global ids (every node and cell exactly once).
#include "common.hpp"
#include <fdem/kernels/cst.hpp>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

static const double A[3][3] = {{1.012, 0.004, -0.002}, {0.003, 0.991, 0.005}, {-0.001, 0.002, 1.007}};

static PetscErrorCode Stretch(PetscInt, const PetscReal X[3], PetscReal x[3], void *) {
  for (int r = 0; r < 3; ++r) x[r] = A[r][0] * X[0] + A[r][1] * X[1] + A[r][2] * X[2];
  return 0;
}

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  const Vec3 lo(0, 0, 0), hi(1.0, 0.8, 0.6);
  const int  nx = 5, ny = 4, nz = 3;
  // irregular mesh: interior nodes moved by up to 0.25 h (deterministic)
  fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh(lo, hi, nx, ny, nz);
  auto interior = [&](const Vec3 &p) {
    bool in = true;
    for (int k = 0; k < 3; ++k) in = in && p[k] > lo[k] + 1e-9 && p[k] < hi[k] - 1e-9;
    return in;
  };
  for (size_t i = 0; i < M.nodes.size(); ++i)
    if (interior(M.nodes[i]))
      for (int k = 0; k < 3; ++k) M.nodes[i][k] += 0.25 * 0.2 * std::sin(12.9898 * (double)i + 78.233 * k + 1.7);
  const double V = 1.0 * 0.8 * 0.6, rho = 2.5;

  for (int model = 0; model < 3; ++model) {
    FDEMDeformable d;
    PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
    PetscCall(FDEMDeformableAddMaterial(d, "rock", 1000.0, 0.3, rho, 0.0, (FDEMMaterialModel)model));
    PetscCall(SetKernelMesh(d, M));
    PetscCall(FDEMDeformableSetFromOptions(d));
    PetscCall(FDEMDeformableSetUp(d));
    PetscInt cl, cg, no, ng, nids;
    const PetscInt *ids;
    PetscCall(FDEMDeformableGetSizes(d, &cl, &cg, &no, &ng));
    CHECK(cg == (PetscInt)M.tets.size() && ng == (PetscInt)M.nodes.size(), "sizes: %d cells %d nodes", (int)cg, (int)ng);
    // every node owned exactly once, every cell held exactly once
    {
      std::vector<PetscInt> cnt(ng, 0), all(ng), ccnt(cg, 0), call(cg);
      PetscCall(FDEMDeformableGetNodeIds(d, &nids, &ids));
      for (PetscInt k = 0; k < nids; ++k) cnt[ids[k]]++;
      PetscCall(FDEMDeformableGetCellIds(d, &nids, &ids));
      for (PetscInt k = 0; k < nids; ++k) ccnt[ids[k]]++;
      PetscCall(MPIU_Allreduce(cnt.data(), all.data(), (int)ng, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
      PetscCall(MPIU_Allreduce(ccnt.data(), call.data(), (int)cg, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
      for (PetscInt i = 0; i < ng; ++i) CHECK(all[i] == 1, "node %d owned %d times", (int)i, (int)all[i]);
      for (PetscInt i = 0; i < cg; ++i) CHECK(call[i] == 1, "cell %d held %d times", (int)i, (int)call[i]);
      PetscInt mn, mx;
      PetscCall(MPIU_Allreduce(&cl, &mn, 1, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
      PetscCall(MPIU_Allreduce(&cl, &mx, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "model %s: %d cells, %d nodes; cells per rank %d..%d\n", FDEMMaterialModels[model], (int)cg, (int)ng, (int)mn, (int)mx));
    }
    PetscReal mass;
    PetscCall(FDEMDeformableGetMomentum(d, nullptr, &mass, nullptr, nullptr, nullptr));
    CHECK(std::fabs(mass - rho * V) < 1e-12 * rho * V, "total lumped mass %.15g, expected rho V = %.15g", (double)mass, rho * V);

    PetscCall(FDEMDeformableSetPositionField(d, Stretch, nullptr));
    Vec F, Xr, S;
    PetscCall(FDEMDeformableGetReferencePositions(d, &Xr));
    PetscCall(VecDuplicate(Xr, &F));
    PetscCall(FDEMDeformableComputeForces(d, 0.0, nullptr, F));
    // exact stress
    fdem::kernels::Material mat;
    mat.E = 1000.0; mat.nu = 0.3; mat.rho = rho; mat.model = model;
    Mat3 Fm;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) Fm.m[r][c] = A[r][c];
    const Mat3   T  = fdem::kernels::CauchyStress(mat, Fm);
    const double Te[6] = {T(0, 0), T(1, 1), T(2, 2), T(0, 1), T(1, 2), T(0, 2)};
    double       Tmax = 0;
    for (double t : Te) Tmax = std::fmax(Tmax, std::fabs(t));
    PetscCall(FDEMDeformableComputeCellStress(d, nullptr, &S));
    const PetscScalar *s, *f, *X;
    PetscInt           ns;
    PetscReal          loc[3] = {0, 0, 0}, glob[3];
    PetscCall(VecGetLocalSize(S, &ns));
    PetscCall(VecGetArrayRead(S, &s));
    for (PetscInt i = 0; i < ns; ++i) loc[0] = std::fmax(loc[0], std::fabs(s[i] - Te[i % 6]));
    PetscCall(VecRestoreArrayRead(S, &s));
    PetscCall(VecGetArrayRead(F, &f));
    PetscCall(VecGetArrayRead(Xr, &X));
    for (PetscInt k = 0; k < no; ++k) {
      const Vec3   p(X[3 * k], X[3 * k + 1], X[3 * k + 2]);
      const double fn = std::sqrt(f[3 * k] * f[3 * k] + f[3 * k + 1] * f[3 * k + 1] + f[3 * k + 2] * f[3 * k + 2]);
      if (interior(p)) loc[1] = std::fmax(loc[1], fn);
      else loc[2] = std::fmax(loc[2], fn);
    }
    PetscCall(VecRestoreArrayRead(Xr, &X));
    PetscCall(VecRestoreArrayRead(F, &f));
    PetscCall(MPIU_Allreduce(loc, glob, 3, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
    const double h = 0.2, fscale = Tmax * h * h;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  max |T - T(A)| / max|T| = %.2e, max interior |f| / (|T| h^2) = %.2e, max boundary |f| / (|T| h^2) = %.2e\n", glob[0] / Tmax, glob[1] / fscale, glob[2] / fscale));
    CHECK(glob[0] < 1e-10 * Tmax, "stress not uniform: %g", (double)(glob[0] / Tmax));
    CHECK(glob[1] < 1e-10 * fscale, "interior force not zero: %g", (double)(glob[1] / fscale));
    CHECK(glob[2] > 1e-3 * fscale, "boundary forces vanish: %g", (double)(glob[2] / fscale));
    PetscReal fsum[3];
    {
      PetscReal sums[3];
      for (int c = 0; c < 3; ++c) PetscCall(VecStrideSum(F, c, &sums[c]));
      for (int c = 0; c < 3; ++c) fsum[c] = sums[c];
    }
    CHECK(std::fabs(fsum[0]) + std::fabs(fsum[1]) + std::fabs(fsum[2]) < 1e-11 * fscale * ng, "net internal force not zero");

    // one -ts_type pv step from rest (drift-kick-drift: the kick sees x = A X): interior velocities stay zero
    TS  ts;
    Vec U;
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, TSFDEMPV));
    PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
    PetscCall(TSSetTimeStep(ts, 1e-4));
    PetscCall(TSSetMaxSteps(ts, 1));
    PetscCall(TSSetMaxTime(ts, 1.0));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(TSSetFromOptions(ts));
    PetscCall(TSSolve(ts, U));
    {
      const PetscScalar *u;
      PetscReal          vl[2] = {0, 0}, vg[2];
      PetscCall(VecGetArrayRead(U, &u));
      PetscCall(VecGetArrayRead(Xr, &X));
      for (PetscInt k = 0; k < no; ++k) {
        const Vec3 p(X[3 * k], X[3 * k + 1], X[3 * k + 2]);
        for (int c = 0; c < 3; ++c) vl[interior(p) ? 0 : 1] = std::fmax(vl[interior(p) ? 0 : 1], std::fabs(u[3 * no + 3 * k + c]));
      }
      PetscCall(VecRestoreArrayRead(Xr, &X));
      PetscCall(VecRestoreArrayRead(U, &u));
      PetscCall(MPIU_Allreduce(vl, vg, 2, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "  after one pv step: max interior |v| = %.2e, max boundary |v| = %.2e\n", vg[0], vg[1]));
      CHECK(vg[0] < 1e-10 * vg[1] && vg[1] > 0, "interior nodes moved in a uniform state");
    }
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
    PetscCall(VecDestroy(&S));
    PetscCall(VecDestroy(&F));
    PetscCall(FDEMDeformableDestroy(&d));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "patch test passed\n"));
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
