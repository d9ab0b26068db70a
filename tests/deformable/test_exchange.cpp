// The model's exchanges between its global and local node vectors
// (fdem::model::DeformableGlobalToLocal and DeformableLocalToGlobal) give what PETSc's
// DMGlobalToLocal and DMLocalToGlobal of the model's DM give, to the bit: on one rank they
// copy (or add) instead, because there the local vectors are the global ones, and on more
// ranks they call the DM. Asserted on a whole box and on the same box fracturable (every
// tetrahedron with nodes of its own, joints between them), with vectors of distinct values:
//  1. global to local: every local entry the same as DMGlobalToLocal's;
//  2. local to global with INSERT_VALUES and with ADD_VALUES (into a vector that already
//     holds values): every owned entry the same as DMLocalToGlobal's;
//  3. on one rank both models take the copy (local_is_owned), on two ranks neither does (so
//     the 1- and 2-rank runs of this test try both ways).
#include "common.hpp"
#include "../../src/model/deformable_impl.hpp"
#include "../../src/model/deformable_object.hpp"

using fdem::kernels::Vec3;

// v[i] = a + i + b/(i+1) on this rank's entries (distinct and not round)
static PetscErrorCode Fill(Vec v, double a, double b) {
  PetscScalar *p;
  PetscInt     n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetArray(v, &p));
  for (PetscInt i = 0; i < n; ++i) p[i] = a + (double)i + b / (double)(i + 1);
  PetscCall(VecRestoreArray(v, &p));
  PetscFunctionReturn(0);
}

// the number of entries of u and w that differ (bitwise), summed over the ranks
static PetscErrorCode Differ(Vec u, Vec w, PetscInt *ndiff) {
  const PetscScalar *a, *b;
  PetscInt           n, m, k = 0;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(u, &n));
  PetscCall(VecGetLocalSize(w, &m));
  if (n != m) k = n + m;
  PetscCall(VecGetArrayRead(u, &a));
  PetscCall(VecGetArrayRead(w, &b));
  for (PetscInt i = 0; n == m && i < n; ++i) k += PetscRealPart(a[i]) == PetscRealPart(b[i]) ? 0 : 1;
  PetscCall(VecRestoreArrayRead(w, &b));
  PetscCall(VecRestoreArrayRead(u, &a));
  PetscCallMPI(MPIU_Allreduce(&k, ndiff, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscFunctionReturn(0);
}

static PetscErrorCode Check(const char *what, bool fracturable, PetscInt *copies) {
  FDEMDeformable d;
  DM             dm;
  Vec            g, l, l2, g1, g2;
  PetscInt       nd;
  PetscFunctionBeginUser;
  fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh(Vec3(0, 0, 0), Vec3(0.6, 0.4, 0.3), 6, 4, 3);
  M.body_names             = {"rock"};
  M.body.assign(M.tets.size(), 0);
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.25, 2500, 0, FDEM_MATERIAL_MUNJIZA_CST));
  if (fracturable) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e6, 3e6, 30, 50, 200, 1e10));
  PetscCall(SetKernelMesh(d, M));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "rock", "rock"));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableGetDM(d, &dm));
  PetscInt mine = d->local_is_owned ? 1 : 0;
  PetscCallMPI(MPIU_Allreduce(&mine, copies, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(DMCreateGlobalVector(dm, &g));
  PetscCall(DMCreateLocalVector(dm, &l));
  PetscCall(VecDuplicate(l, &l2));
  PetscCall(VecDuplicate(g, &g1));
  PetscCall(VecDuplicate(g, &g2));

  PetscCall(Fill(g, 1.5, 0.37));
  PetscCall(VecSet(l, -7));
  PetscCall(VecSet(l2, -9));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, g, l));
  PetscCall(DMGlobalToLocal(dm, g, INSERT_VALUES, l2));
  PetscCall(Differ(l, l2, &nd));
  CHECK(nd == 0, "%s: global to local: %" PetscInt_FMT " local entries differ from DMGlobalToLocal's", what, nd);

  const InsertMode modes[2] = {INSERT_VALUES, ADD_VALUES};
  for (InsertMode mode : modes) {
    PetscCall(Fill(l, -3.25, 0.91));
    PetscCall(Fill(g1, 10.0, 0.13));
    PetscCall(VecCopy(g1, g2));
    PetscCall(fdem::model::DeformableLocalToGlobal(d, l, mode, g1));
    PetscCall(DMLocalToGlobal(dm, l, mode, g2));
    PetscCall(Differ(g1, g2, &nd));
    CHECK(nd == 0, "%s: local to global (%s): %" PetscInt_FMT " entries differ from DMLocalToGlobal's", what, mode == ADD_VALUES ? "ADD_VALUES" : "INSERT_VALUES", nd);
  }
  PetscCall(VecDestroy(&g2));
  PetscCall(VecDestroy(&g1));
  PetscCall(VecDestroy(&l2));
  PetscCall(VecDestroy(&l));
  PetscCall(VecDestroy(&g));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscInt    whole, split;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(Check("whole box", false, &whole));
  PetscCall(Check("fracturable box", true, &split));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d rank(s): ranks whose local vectors are the global ones: whole box %" PetscInt_FMT ", fracturable box %" PetscInt_FMT "\n", size, whole, split));
  if (size == 1) CHECK(whole == 1 && split == 1, "on one rank the exchanges should be copies (whole %" PetscInt_FMT ", fracturable %" PetscInt_FMT ")", whole, split);
  else CHECK(whole == 0 && split == 0, "on %d ranks no rank should take the copy (whole %" PetscInt_FMT ", fracturable %" PetscInt_FMT ")", size, whole, split);
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
