// The numbering a mesh comes with changes nothing but the ids: the same irregular box given
// with its nodes and tetrahedra in their own order and in a random order, deformed by the
// same field of the reference positions, must give every node the same internal force and
// lumped mass, and every cell the same stress, matched through the permutation of the ids,
// to round-off (the local cells run along a Hilbert curve and the local nodes are numbered
// by first use, whatever the input order; doc/deformable.md, "Data layout on each rank").
// The force sums run in other orders, so agreement is to 1e-12 of the largest value, not to
// the bit.
#include "common.hpp"

#include <algorithm>
#include <numeric>
#include <random>

using fdem::kernels::Vec3;

// a smooth, non-uniform deformation of the reference positions (independent of the ids)
static PetscErrorCode Deform(PetscInt, const PetscReal X[3], PetscReal x[3], void *) {
  x[0] = X[0] + 0.01 * std::sin(3 * X[1] + 1) + 0.004 * X[0] * X[2];
  x[1] = X[1] + 0.008 * std::cos(2 * X[2]) - 0.003 * X[0];
  x[2] = X[2] + 0.006 * std::sin(4 * X[0] + 2 * X[1]);
  return 0;
}

struct Fields {
  std::vector<PetscReal> force, mass; // 3 per node, by node id
  std::vector<PetscReal> stress;      // 6 per cell, by cell id
};

// Sets up the mesh, deforms it, and gathers the forces, masses and stresses by id on every rank.
static PetscErrorCode Evaluate(const fdem::kernels::TetMesh &M, Fields &out) {
  FDEMDeformable  d;
  Vec             x, F, m, S;
  PetscInt        n;
  const PetscInt *ids;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1.0e9, 0.25, 2500.0, 0.0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(SetKernelMesh(d, M));
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableSetPositionField(d, Deform, nullptr));
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(FDEMDeformableGetMasses(d, &m));
  PetscCall(VecDuplicate(x, &F));
  PetscCall(FDEMDeformableComputeForces(d, 0.0, nullptr, F));
  PetscCall(FDEMDeformableComputeCellStress(d, nullptr, &S));
  std::vector<PetscReal> f(3 * M.nodes.size(), 0), mm(3 * M.nodes.size(), 0), s(6 * M.tets.size(), 0);
  const PetscScalar     *fa, *ma, *sa;
  PetscCall(FDEMDeformableGetNodeIds(d, &n, &ids));
  PetscCall(VecGetArrayRead(F, &fa));
  PetscCall(VecGetArrayRead(m, &ma));
  for (PetscInt k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) f[3 * ids[k] + c] = fa[3 * k + c], mm[3 * ids[k] + c] = ma[3 * k + c];
  PetscCall(VecRestoreArrayRead(m, &ma));
  PetscCall(VecRestoreArrayRead(F, &fa));
  PetscCall(FDEMDeformableGetCellIds(d, &n, &ids));
  PetscCall(VecGetArrayRead(S, &sa));
  for (PetscInt e = 0; e < n; ++e)
    for (int c = 0; c < 6; ++c) s[6 * ids[e] + c] = sa[6 * e + c];
  PetscCall(VecRestoreArrayRead(S, &sa));
  out.force.resize(f.size());
  out.mass.resize(mm.size());
  out.stress.resize(s.size());
  // each node is owned and each cell held by one rank: the sums put every value in place everywhere
  PetscCallMPI(MPIU_Allreduce(f.data(), out.force.data(), (PetscMPIInt)f.size(), MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD));
  PetscCallMPI(MPIU_Allreduce(mm.data(), out.mass.data(), (PetscMPIInt)mm.size(), MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD));
  PetscCallMPI(MPIU_Allreduce(s.data(), out.stress.data(), (PetscMPIInt)s.size(), MPIU_REAL, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(VecDestroy(&S));
  PetscCall(VecDestroy(&F));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  const Vec3             lo(0, 0, 0), hi(1.0, 0.7, 0.5);
  fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh(lo, hi, 8, 6, 5);
  for (size_t i = 0; i < M.nodes.size(); ++i) { // irregular: interior nodes moved by up to 0.2 h
    bool in = true;
    for (int k = 0; k < 3; ++k) in = in && M.nodes[i][k] > lo[k] + 1e-9 && M.nodes[i][k] < hi[k] - 1e-9;
    if (in)
      for (int k = 0; k < 3; ++k) M.nodes[i][k] += 0.02 * std::sin(12.9898 * (double)i + 78.233 * k + 1.7);
  }
  // the same mesh numbered at random: node i becomes pn[i], new tetrahedron e is old pt[e]
  std::mt19937_64     rng(2026);
  std::vector<size_t> pn(M.nodes.size()), pt(M.tets.size());
  std::iota(pn.begin(), pn.end(), 0);
  std::iota(pt.begin(), pt.end(), 0);
  std::shuffle(pn.begin(), pn.end(), rng);
  std::shuffle(pt.begin(), pt.end(), rng);
  fdem::kernels::TetMesh P = M;
  for (size_t i = 0; i < M.nodes.size(); ++i) P.nodes[pn[i]] = M.nodes[i];
  for (size_t e = 0; e < M.tets.size(); ++e)
    for (int a = 0; a < 4; ++a) P.tets[e][a] = (int)pn[M.tets[pt[e]][a]];

  Fields A, B;
  PetscCall(Evaluate(M, A));
  PetscCall(Evaluate(P, B));
  double fmax = 0, df = 0, mmax = 0, dm = 0, smax = 0, ds = 0;
  for (size_t i = 0; i < M.nodes.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      fmax = std::max(fmax, std::fabs(A.force[3 * i + c]));
      df   = std::max(df, std::fabs(A.force[3 * i + c] - B.force[3 * pn[i] + c]));
      mmax = std::max(mmax, std::fabs(A.mass[3 * i + c]));
      dm   = std::max(dm, std::fabs(A.mass[3 * i + c] - B.mass[3 * pn[i] + c]));
    }
  for (size_t e = 0; e < M.tets.size(); ++e)
    for (int c = 0; c < 6; ++c) {
      smax = std::max(smax, std::fabs(B.stress[6 * e + c]));
      ds   = std::max(ds, std::fabs(B.stress[6 * e + c] - A.stress[6 * pt[e] + c]));
    }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%zu nodes, %zu tetrahedra, numbered at random against in order: largest force difference %.2e of %.3e N, mass %.2e of %.3e kg, stress %.2e of %.3e Pa\n",
                        M.nodes.size(), M.tets.size(), df, fmax, dm, mmax, ds, smax));
  CHECK(fmax > 1e3, "the deformation gives no force (%g N)", fmax);
  CHECK(df <= 1e-12 * fmax, "the nodal forces depend on the numbering: %g N of %g N", df, fmax);
  CHECK(dm <= 1e-12 * mmax, "the lumped masses depend on the numbering: %g kg of %g kg", dm, mmax);
  CHECK(ds <= 1e-12 * smax, "the cell stresses depend on the numbering: %g Pa of %g Pa", ds, smax);
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
