// Bad input gives collective errors that name what is wrong (run on 1 and 2
// ranks: no rank may hang while another fails).
#include "common.hpp"
#include "../../src/util/guard.hpp"

#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/error.hpp>

#include <cmath>
#include <cstdio>
#include <string>

namespace {
// two tetrahedra sharing a face; the second one given with the wrong orientation or flat
PetscErrorCode TwoTets(FDEMDeformable d, bool inverted, bool flat) {
  const PetscReal X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  PetscReal       Y[15];
  for (int i = 0; i < 15; ++i) Y[i] = X[i];
  if (flat) Y[14] = 0, Y[12] = 0.5, Y[13] = 0.5; // node 4 in the plane z = 0 ... on edge 1-2
  const PetscInt T[] = {0, 1, 2, 3, 1, 2, 3, 4};
  PetscInt       T2[8];
  for (int i = 0; i < 8; ++i) T2[i] = T[i];
  if (inverted) std::swap(T2[5], T2[6]);
  if (flat) {
    T2[4] = 1, T2[5] = 4, T2[6] = 2, T2[7] = 0; // 0, 1, 2, 4 coplanar
  }
  const PetscInt    body[] = {0, 1};
  const char *const names[] = {"anchor", "pebble"};
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableSetMesh(d, 5, flat ? Y : X, 2, T2, body, 2, names));
  PetscFunctionReturn(0);
}

PetscErrorCode Fresh(FDEMDeformable *d) {
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableDestroy(d));
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, d));
  PetscFunctionReturn(0);
}

PetscErrorCode Squeeze(PetscInt, const PetscReal X[3], PetscReal v[3], void *) {
  for (int k = 0; k < 3; ++k) v[k] = -50.0 * (X[k] - 0.5); // a violent implosion
  return 0;
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscMPIInt rank;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  FDEMDeformable d = nullptr;

  // an inverted tetrahedron: element 1 of body 'pebble'
  PetscCall(Fresh(&d));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(TwoTets(d, true, false));
  PetscCall(ExpectError("inverted tetrahedron", {"element 1", "body 'pebble'", "negative"}, [&]() { return FDEMDeformableSetUp(d); }));

  // the same tetrahedron twice (in-memory mesh): named, not a doubled mass
  PetscCall(Fresh(&d));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  {
    const PetscReal X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const PetscInt  T[] = {0, 1, 2, 3, 1, 0, 3, 2};
    PetscCall(FDEMDeformableSetMesh(d, 4, X, 2, T, nullptr, 1, nullptr));
  }
  PetscCall(ExpectError("repeated tetrahedron", {"element 1", "repeats element 0"}, [&]() { return FDEMDeformableSetUp(d); }));

  // a non-finite coordinate (in-memory mesh): named, not "reference volume nan"
  PetscCall(Fresh(&d));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  {
    const PetscReal X[] = {0, 0, 0, 1, 0, 0, 0, NAN, 0, 0, 0, 1};
    const PetscInt  T[] = {0, 1, 2, 3};
    PetscCall(FDEMDeformableSetMesh(d, 4, X, 1, T, nullptr, 1, nullptr));
  }
  PetscCall(ExpectError("non-finite coordinate", {"node 2", "non-finite"}, [&]() { return FDEMDeformableSetUp(d); }));

  // a zero-volume tetrahedron
  PetscCall(Fresh(&d));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(TwoTets(d, false, true));
  PetscCall(ExpectError("zero-volume tetrahedron", {"element 1", "body 'pebble'", "zero"}, [&]() { return FDEMDeformableSetUp(d); }));

  // a missing material: two materials in the table, neither named 'pebble' nor mapped
  PetscCall(Fresh(&d));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableAddMaterial(d, "steel", 2e11, 0.3, 7800, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "anchor", "steel"));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "pebble", "basalt"));
  PetscCall(TwoTets(d, false, false));
  PetscCall(ExpectError("missing material", {"body 'pebble'", "'basalt'", "not in the material table"}, [&]() { return FDEMDeformableSetUp(d); }));

  // fragments before set-up, and with nothing to return
  PetscCall(Fresh(&d));
  PetscCall(ExpectError("fragments before set-up", {"FDEMDeformableGetFragments", "FDEMDeformableSetUp"}, [&]() { return FDEMDeformableGetFragments(d, nullptr, nullptr, nullptr); }));
  PetscCall(FDEMDeformableAddMaterial(d, "granite", 5e10, 0.25, 2700, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(TwoTets(d, false, false));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(ExpectError("fragments with no output", {"FDEMDeformableGetFragments", "count or fragments"}, [&]() { return FDEMDeformableGetFragments(d, nullptr, nullptr, nullptr); }));

  // nu >= 0.5
  PetscCall(Fresh(&d));
  PetscCall(ExpectError("nu = 0.5", {"rubber", "Poisson"}, [&]() { return FDEMDeformableAddMaterial(d, "rubber", 1e6, 0.5, 1100, 0, FDEM_MATERIAL_NEO_HOOKEAN); }));

  // hexahedra in a .msh file
  {
    const char *path = "deformable_bad_hex.msh";
    if (rank == 0) {
      FILE *fp = std::fopen(path, "w");
      std::fprintf(fp, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n");
      for (int i = 0; i < 8; ++i) std::fprintf(fp, "%d %d %d %d\n", i + 1, i & 1, (i >> 1) & 1, (i >> 2) & 1);
      std::fprintf(fp, "$EndNodes\n$Elements\n1\n1 5 2 1 1 1 2 4 3 5 6 8 7\n$EndElements\n");
      std::fclose(fp);
    }
    PetscCallMPI(MPI_Barrier(PETSC_COMM_WORLD));
    PetscCall(Fresh(&d));
    PetscCall(ExpectError("hexahedra in a .msh", {"deformable_bad_hex.msh", "hexahedron"}, [&]() { return FDEMDeformableSetMeshFromGmsh(d, path); }));
    if (rank == 0) std::remove(path);
  }

  // an element inverting during a run: the error names the element, its body and the time
  {
    PetscCall(Fresh(&d));
    PetscCall(FDEMDeformableAddMaterial(d, "box", 1.0, 0.3, 1.0, 0, FDEM_MATERIAL_MUNJIZA_CST));
    const PetscReal lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, 2, 2, 2));
    PetscCall(FDEMDeformableSetUp(d));
    PetscCall(FDEMDeformableSetVelocityField(d, Squeeze, nullptr));
    TS  ts;
    Vec U;
    PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
    PetscCall(TSSetType(ts, TSFDEMCD));
    PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
    PetscCall(TSSetTimeStep(ts, 0.005));
    PetscCall(TSSetMaxTime(ts, 1.0));
    PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
    PetscCall(ExpectError("inversion during a run", {"element", "of body 'box'", "inverted", "at t = "}, [&]() { return TSSolve(ts, U); }));
    PetscCall(VecDestroy(&U));
    PetscCall(TSDestroy(&ts));
  }
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "bad input test passed\n"));
  // the option names of FDEMMaterialModel are the rows of the material table, in order
  {
    const auto &models = fdem::kernels::MaterialModels();
    size_t      n      = 0;
    while (FDEMMaterialModels[n] && std::string(FDEMMaterialModels[n]) != "FDEMMaterialModel") ++n;
    CHECK(n == models.size(), "FDEMMaterialModels has %d names, the material table %d rows", (int)n, (int)models.size());
    for (size_t i = 0; i < n && i < models.size(); ++i) CHECK(std::string(FDEMMaterialModels[i]) == models[i].name, "model %d: option name %s, table %s", (int)i, FDEMMaterialModels[i], models[i].name);
    CHECK(std::string(FDEMMaterialModels[FDEM_MATERIAL_SMALL_STRAIN_LINEAR]) == "small_strain_linear", "the C enum and the table disagree");
  }
  // the error guard is collective: an exception on the last rank only stops every rank, with its message
  {
    PetscMPIInt size;
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    PetscCall(ExpectError("exception on the last rank", {"guard test: ", "thrown on the last rank"}, [&]() {
      return fdem::Guard(
        PETSC_COMM_WORLD,
        [&]() -> PetscErrorCode {
          if (rank == size - 1) throw fdem::kernels::InputError("thrown on the last rank");
          return 0;
        },
        PETSC_ERR_USER_INPUT, "guard test: ");
    }));
  }
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
