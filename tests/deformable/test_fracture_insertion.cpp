// Joints inserted during a run (doc/fracture.md, "Joints inserted during a run"), on any
// number of ranks. A box of 6 x 2 x 2 cubes of 0.1 m (144 tetrahedra), body "rock" of a
// fracturable material with an insertion ratio of 0.5 (f_t = 1 MPa, E = 1 GPa, nu = 0).
//  1. Model A splits the tetrahedra with centroid x < 0.2 (FDEMDeformableAddFractureCells),
//     model B those with x < 0.4. A's state (every node its own position and velocity, every
//     joint point its own damage, shear damage and last energies, every joint its own
//     dissipated energy) is written to an HDF5 file as the driver's checkpoint does and loaded
//     into B: each node of B (a tetrahedron's corner) has the state of the node that corner
//     had in A, each joint of B that A had the state of that joint's point on the same edge,
//     and each new joint is intact (damage 0, last energies -1, nothing dissipated). The
//     expected values come from the input mesh split both ways by the kernel
//     (SplitForJoints), so they check that the models' node and joint ids are the split's.
//  2. FDEMDeformableGetFractureCells gives B's cells; FDEMDeformableReadFractureCells gives
//     A's from the file.
//  3. FindCellsToSplit on A: at the reference state, none; stretched along x so that
//     sigma_xx = 0.4 f_t, none (above the default look-ahead's 0.375, but cells ahead alone ask
//     for no insertion); at 0.6 f_t (ratio 0.6 >= 0.5), every whole tetrahedron. Columns at
//     0.6, 0.3 and 0.4 f_t: the first two (the third is ahead, but not linked to the first);
//     at 0.6, 0.4 and 0.4: all three.
//  4. Errors: loading B's state into A (a checkpoint that split tetrahedra A keeps whole),
//     a ratio of 1.5, a cell of a body without insertion, a cell outside the mesh.
//  5. The criterion (StrengthRatio) on random stresses against eigenvalues by Jacobi
//     rotations, and its test without eigenvalues (SurelyBelow) never wrong.
//  6. Joints inserted into a stressed body start at their face's traction: the box under a
//     uniform stretch and shear (sigma_xx = 0.3 f_t, sigma_xy = 0.2 f_t in the rock), a model
//     that split nothing saved and loaded into A at that state: every copy of an interior node
//     of the rock has a net force below 1e-6 of a face's load (the continuum's: 0), where the
//     joints inserted unloaded (-fdem_insert_prestress false) leave more than a tenth of it;
//     the joints' stored energy, counted from the insertion, is 0 there. A's state (A split
//     between x = 0.1 and 0.3 here) then loaded into B (A's joints keep their offsets, those at
//     x = 0.1 with their sides swapped; B's new joints get
//     theirs): the same; B's state restarted into a model of the same split gives B's forces
//     to the bit, and so does a checkpoint written before B's new joints started.
//  7. A model set up with what A derived from the input mesh (FDEMDeformableReuseSetUp) is
//     the model set up alone; one with another joint penalty makes its own.
//  8. A model continued from A without a file (FDEMDeformableContinueNodeVector and
//     ContinueJointState) equals, to the bit, one loaded from A's checkpoint, into B's split
//     and into A's; continuing a model that split more is refused.
#include "common.hpp"
#include "../../src/model/deformable_object.hpp"

#include <fdem/kernels/joint_mesh.hpp>
#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

namespace {
using fdem::kernels::Vec3;

fdem::kernels::TetMesh Box() {
  fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh(Vec3(0, 0, 0), Vec3(0.6, 0.2, 0.2), 6, 2, 2);
  M.body_names             = {"rock", "steel"};
  M.body.resize(M.tets.size());
  for (size_t e = 0; e < M.tets.size(); ++e) { // the last column of cubes is a body without fracture
    Vec3 c(0, 0, 0);
    for (int a = 0; a < 4; ++a) c = c + 0.25 * M.nodes[M.tets[e][a]];
    M.body[e] = c.x > 0.5 ? 1 : 0;
  }
  return M;
}

// The tetrahedra of the rock with centroid xmin < x < xmax.
std::vector<PetscInt> CellsBelow(const fdem::kernels::TetMesh &M, double xmax, double xmin = -1) {
  std::vector<PetscInt> c;
  for (size_t e = 0; e < M.tets.size(); ++e) {
    Vec3 s(0, 0, 0);
    for (int a = 0; a < 4; ++a) s = s + 0.25 * M.nodes[M.tets[e][a]];
    if (s.x < xmax && s.x > xmin && M.body[e] == 0) c.push_back((PetscInt)e);
  }
  return c;
}

// (On an error *out holds the model made so far, for the caller to destroy.)
// reuse: a model whose set-up products to offer (FDEMDeformableReuseSetUp); penalty: rock's joint penalty.
PetscErrorCode Make(MPI_Comm comm, const std::vector<PetscInt> &cells, PetscReal ratio, FDEMDeformable *out, FDEMDeformable reuse = nullptr, PetscReal penalty = 1e10) {
  FDEMDeformable d;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, &d));
  *out = d;
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.0, 2000, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableAddMaterial(d, "steel", 2e11, 0.3, 7800, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e6, 3e6, 30, 50, 200, penalty));
  if (reuse) PetscCall(FDEMDeformableReuseSetUp(d, reuse));
  PetscCall(SetKernelMesh(d, Box()));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "rock", "rock"));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "steel", "steel"));
  PetscCall(FDEMDeformableSetFractureInsertion(d, "rock", ratio));
  PetscCall(FDEMDeformableAddFractureCells(d, (PetscInt)cells.size(), cells.data()));
  PetscCall(FDEMDeformableSetUp(d));
  PetscFunctionReturn(0);
}

// The split the library makes of the box with `cells` split.
fdem::kernels::SplitMesh Split(const std::vector<PetscInt> &cells) {
  const fdem::kernels::TetMesh M = Box();
  std::vector<char>            flags(M.tets.size(), 0);
  for (PetscInt t : cells) flags[t] = 1;
  return fdem::kernels::SplitForJoints(M, {1, 0}, flags);
}

// The state each node and joint point gets in A, from its id.
double NodeValue(PetscInt id, int c, int which) { return 1e-3 * (id + 1) + 1e-5 * c + 0.5 * which; }
double PointDamage(PetscInt j, int q) { return 0.01 + 0.001 * j + 0.0001 * q; }

// A node state by id (NodeValue: which 0 positions, 1 velocities) in the natural vector
// *nat, named mesh_x or mesh_v.
PetscErrorCode NodeVector(FDEMDeformable d, int which, Vec *nat) {
  PetscInt        n;
  const PetscInt *ids;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetNodeIds(d, &n, &ids));
  PetscCall(VecCreateMPI(d->comm, PETSC_DECIDE, 3 * d->nnodes_global, nat));
  PetscCall(PetscObjectSetName((PetscObject)*nat, which ? "mesh_v" : "mesh_x"));
  for (PetscInt i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) PetscCall(VecSetValue(*nat, 3 * ids[i] + c, NodeValue(ids[i], c, which), INSERT_VALUES));
  PetscCall(VecAssemblyBegin(*nat));
  PetscCall(VecAssemblyEnd(*nat));
  PetscFunctionReturn(0);
}

// A's node state, by id, into the natural vectors mesh_x and mesh_v, and the joints' state (ids
// in the split's joint order).
PetscErrorCode Save(FDEMDeformable d, const char *file) {
  PetscViewer v;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(d->comm, file, FILE_MODE_WRITE, &v));
  for (int w = 0; w < 2; ++w) {
    Vec nat;
    PetscCall(NodeVector(d, w, &nat));
    PetscCall(VecView(nat, v));
    PetscCall(VecDestroy(&nat));
  }
  for (size_t j = 0; j < d->jstate.size(); ++j) {
    for (int q = 0; q < 3; ++q) {
      d->jstate[j][q].SetDamage(PointDamage(d->jgid[j], q));
      d->jstate[j][q].shear_damage = (float)(2 * PointDamage(d->jgid[j], q));
      d->jstate[j][q].last_tension = (float)(3 * PointDamage(d->jgid[j], q));
      d->jstate[j][q].last_shear   = (float)(4 * PointDamage(d->jgid[j], q));
    }
    d->jdiss[j] = 1e-3 * d->jgid[j];
  }
  PetscCall(FDEMDeformableViewJointState(d, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscFunctionReturn(0);
}

// The uniform deformation of part 6: x = X + (e X + g Y, g X, 0).
PetscErrorCode Sheared(PetscInt, const PetscReal X[3], PetscReal x[3], void *) {
  const double e = 3e-4, g = 2e-4; // sigma_xx = E e, sigma_xy = 2 G g = E g with nu = 0
  x[0] = X[0] + e * X[0] + g * X[1], x[1] = X[1] + g * X[0], x[2] = X[2];
  return 0;
}

// Writes d's joint state (and its inserted cells) to file.
PetscErrorCode SaveJoints(FDEMDeformable d, const char *file) {
  PetscViewer v;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(d->comm, file, FILE_MODE_WRITE, &v));
  PetscCall(FDEMDeformableViewJointState(d, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscFunctionReturn(0);
}

// Loads the joint state of file into d, sets d's positions to Sheared, and returns the
// largest net force on a copy of an interior node of the rock (reference 0 < X < 0.45,
// 0 < Y, Z < 0.2), the joints' stored energy, and the forces (*F, created).
PetscErrorCode ShearedForces(FDEMDeformable d, const char *file, PetscReal *fmax, PetscReal *stored, Vec *F) {
  PetscViewer        v;
  Vec                X;
  const PetscScalar *f, *Xa;
  PetscInt           n;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(d->comm, file, FILE_MODE_READ, &v));
  PetscCall(FDEMDeformableLoadJointState(d, v));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(FDEMDeformableSetPositionField(d, Sheared, nullptr));
  PetscCall(FDEMDeformableGetReferencePositions(d, &X));
  PetscCall(VecDuplicate(X, F));
  PetscCall(FDEMDeformableComputeForces(d, 0, nullptr, *F));
  { // the evaluation that makes the new joints' offsets adds their change; the next one is the kernel's alone
    Vec       F1;
    PetscReal diff, fmax0;
    PetscCall(VecDuplicate(X, &F1));
    PetscCall(FDEMDeformableComputeForces(d, 0, nullptr, F1));
    PetscCall(VecNorm(*F, NORM_INFINITY, &fmax0));
    PetscCall(VecAXPY(*F, -1, F1));
    PetscCall(VecNorm(*F, NORM_INFINITY, &diff));
    CHECK(diff <= 1e-9 * fmax0, "the forces of the evaluation that made the offsets and of the next: %g N apart (largest %g N)", diff, fmax0);
    PetscCall(VecCopy(F1, *F));
    PetscCall(VecDestroy(&F1));
  }
  PetscCall(FDEMDeformableGetJointEnergy(d, nullptr, stored, nullptr));
  PetscCall(VecGetLocalSize(X, &n));
  PetscCall(VecGetArrayRead(*F, &f));
  PetscCall(VecGetArrayRead(X, &Xa));
  *fmax = 0;
  for (PetscInt i = 0; i < n; i += 3) {
    const bool inner = Xa[i] > 0.05 && Xa[i] < 0.45 && Xa[i + 1] > 0.05 && Xa[i + 1] < 0.15 && Xa[i + 2] > 0.05 && Xa[i + 2] < 0.15;
    if (inner) *fmax = std::max(*fmax, std::sqrt(f[i] * f[i] + f[i + 1] * f[i + 1] + f[i + 2] * f[i + 2]));
  }
  PetscCall(VecRestoreArrayRead(X, &Xa));
  PetscCall(VecRestoreArrayRead(*F, &f));
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, fmax, 1, MPIU_REAL, MPI_MAX, d->comm));
  PetscFunctionReturn(0);
}

// Sets d's stored positions to its reference positions X with x replaced by f(x).
template <class F>
PetscErrorCode MoveAlongX(FDEMDeformable d, F f) {
  Vec x, X;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(FDEMDeformableGetReferencePositions(d, &X));
  PetscCall(VecCopy(X, x));
  PetscScalar *a;
  PetscInt     n;
  PetscCall(VecGetLocalSize(x, &n));
  PetscCall(VecGetArray(x, &a));
  for (PetscInt i = 0; i < n; i += 3) a[i] = f(a[i]);
  PetscCall(VecRestoreArray(x, &a));
  PetscFunctionReturn(0);
}

// Stretched along x by strain eps[k] in the k-th column of cubes (0.1 m wide, by x of the
// reference): each tetrahedron's strain is its column's, exactly (its corners lie on the
// column's two planes).
PetscErrorCode StretchColumns(FDEMDeformable d, const std::array<double, 6> &eps) {
  return MoveAlongX(d, [&](double X) {
    double u = 0;
    for (int k = 0; k < 6; ++k) u += eps[k] * std::clamp(X - 0.1 * k, 0.0, 0.1);
    return X + u;
  });
}

// Stretched by (1 + e) along x.
PetscErrorCode Stretch(FDEMDeformable d, double e) {
  return MoveAlongX(d, [e](double X) { return X * (1 + e); });
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const fdem::kernels::TetMesh M = Box();
  const std::vector<PetscInt>  cellsA = CellsBelow(M, 0.2), cellsB = CellsBelow(M, 0.4);
  const fdem::kernels::SplitMesh sa = Split(cellsA), sb = Split(cellsB);
  char file[PETSC_MAX_PATH_LEN]; // in the working folder, one per rank count (the tests may run at once)
  PetscCall(PetscSNPrintf(file, sizeof file, "fracture_insertion_np%d.h5", (int)size));

  FDEMDeformable A, B;
  PetscCall(Make(PETSC_COMM_WORLD, cellsA, 0.5, &A));
  PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &B));
  CHECK(A->nnodes_global == (PetscInt)sa.mesh.nodes.size() && B->nnodes_global == (PetscInt)sb.mesh.nodes.size() && A->njoints_global == (PetscInt)sa.joints.size() && B->njoints_global == (PetscInt)sb.joints.size(),
        "nodes %" PetscInt_FMT " and %" PetscInt_FMT ", joints %" PetscInt_FMT " and %" PetscInt_FMT "; the split gives %zu, %zu, %zu, %zu", A->nnodes_global, B->nnodes_global, A->njoints_global, B->njoints_global, sa.mesh.nodes.size(), sb.mesh.nodes.size(), sa.joints.size(), sb.joints.size());
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "A: %zu cells split, %zu nodes, %zu joints; B: %zu cells split, %zu nodes, %zu joints\n", cellsA.size(), sa.mesh.nodes.size(), sa.joints.size(), cellsB.size(), sb.mesh.nodes.size(), sb.joints.size()));

  // 1. A's state loaded into B
  PetscCall(Save(A, file));
  {
    PetscViewer v;
    PetscInt    n;
    const PetscInt *ids;
    PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, file, FILE_MODE_READ, &v));
    PetscCall(FDEMDeformableGetNodeIds(B, &n, &ids));
    std::vector<PetscInt> from(sb.mesh.nodes.size(), -1); // B's node -> A's node, by the corners
    for (size_t t = 0; t < M.tets.size(); ++t)
      for (int k = 0; k < 4; ++k) from[sb.mesh.tets[t][k]] = sa.mesh.tets[t][k];
    PetscInt bad = 0;
    for (int w = 0; w < 2; ++w) {
      Vec                nat, loc;
      VecScatter         sc;
      const PetscScalar *a;
      PetscCall(VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, 3 * B->nnodes_global, &nat));
      PetscCall(PetscObjectSetName((PetscObject)nat, w ? "mesh_v" : "mesh_x"));
      PetscCall(FDEMDeformableLoadNodeVector(B, v, nat));
      PetscCall(VecScatterCreateToAll(nat, &sc, &loc));
      PetscCall(VecScatterBegin(sc, nat, loc, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(sc, nat, loc, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecGetArrayRead(loc, &a));
      for (PetscInt i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) bad += PetscRealPart(a[3 * ids[i] + c]) != NodeValue(from[ids[i]], c, w);
      PetscCall(VecRestoreArrayRead(loc, &a));
      PetscCall(VecScatterDestroy(&sc));
      PetscCall(VecDestroy(&loc));
      PetscCall(VecDestroy(&nat));
    }
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    CHECK(bad == 0, "%" PetscInt_FMT " node values of B are not those of the node their corner had in A", bad);

    PetscCall(FDEMDeformableLoadJointState(B, v));
    // B's joint -> A's joint by the face's input nodes, and the point on the same edge
    auto key = [](const fdem::kernels::SplitMesh &s, const fdem::kernels::JointFace &j) {
      std::array<int, 3> k = {s.parent[j.a[0]], s.parent[j.a[1]], s.parent[j.a[2]]};
      std::sort(k.begin(), k.end());
      return k;
    };
    std::map<std::array<int, 3>, PetscInt> ofA;
    for (size_t j = 0; j < sa.joints.size(); ++j) ofA[key(sa, sa.joints[j])] = (PetscInt)j;
    PetscInt badj = 0, fresh = 0, kept = 0;
    for (size_t j = 0; j < B->jstate.size(); ++j) {
      const auto &J  = sb.joints[B->jgid[j]];
      const auto  it = ofA.find(key(sb, J));
      if (it == ofA.end()) {
        ++fresh;
        for (int q = 0; q < 3; ++q) badj += B->jstate[j][q].D != 0 || B->jstate[j][q].shear_damage != 0 || B->jstate[j][q].last_tension != -1 || B->jstate[j][q].last_shear != -1;
        badj += B->jdiss[j] != 0;
        continue;
      }
      ++kept;
      const auto &I = sa.joints[it->second];
      for (int q = 0; q < 3; ++q) {
        const std::set<int> eb = {sb.parent[J.a[q]], sb.parent[J.a[(q + 1) % 3]]};
        int                 r  = -1;
        for (int p = 0; p < 3; ++p)
          if (std::set<int>{sa.parent[I.a[p]], sa.parent[I.a[(p + 1) % 3]]} == eb) r = p;
        const double D = PointDamage(it->second, r);
        badj += r < 0 || B->jstate[j][q].D != D || B->jstate[j][q].shear_damage != (float)(2 * D) || B->jstate[j][q].last_tension != (float)(3 * D) || B->jstate[j][q].last_shear != (float)(4 * D);
      }
      badj += B->jdiss[j] != 1e-3 * it->second;
    }
    PetscInt g[3] = {badj, fresh, kept};
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, g, 3, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    CHECK(g[0] == 0 && g[2] == (PetscInt)sa.joints.size() && g[1] + g[2] == (PetscInt)sb.joints.size(), "%" PetscInt_FMT " joint values of B wrong; %" PetscInt_FMT " joints kept (A had %zu), %" PetscInt_FMT " new", g[0], g[2], sa.joints.size(), g[1]);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "loaded into B: %" PetscInt_FMT " joints kept their state, %" PetscInt_FMT " new joints intact\n", g[2], g[1]));

    // 2. the inserted cells
    PetscInt        nb, na, *ca;
    const PetscInt *cb;
    PetscCall(FDEMDeformableGetFractureCells(B, &nb, &cb));
    CHECK(std::vector<PetscInt>(cb, cb + nb) == cellsB, "FDEMDeformableGetFractureCells: %" PetscInt_FMT " cells, expected B's %zu", nb, cellsB.size());
    PetscCall(FDEMDeformableReadFractureCells(PETSC_COMM_WORLD, v, &na, &ca));
    CHECK(std::vector<PetscInt>(ca, ca + na) == cellsA, "FDEMDeformableReadFractureCells: %" PetscInt_FMT " cells, expected A's %zu", na, cellsA.size());
    PetscCall(PetscFree(ca));
    PetscCall(PetscViewerDestroy(&v));
  }

  // 3. the cells to split at three stretches
  {
    const double ratios[3] = {0, 0.4, 0.6};
    PetscInt     whole = 0;
    for (size_t t = 0; t < M.tets.size(); ++t) whole += M.body[t] == 0 && !std::binary_search(cellsA.begin(), cellsA.end(), (PetscInt)t);
    for (double r : ratios) {
      PetscInt  n, *c;
      PetscCall(Stretch(A, r * 1e6 / 1e9));
      PetscCall(FDEMDeformableFindCellsToSplit(A, nullptr, &n, &c));
      bool ok = r < 0.5 ? n == 0 : n == whole;
      for (PetscInt i = 0; ok && i < n; ++i) ok = M.body[c[i]] == 0 && !std::binary_search(cellsA.begin(), cellsA.end(), c[i]);
      CHECK(ok, "stretched to sigma_xx = %g f_t: %" PetscInt_FMT " cells to split, expected %" PetscInt_FMT, r, n, r < 0.5 ? 0 : whole);
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "stretched to sigma_xx = %g f_t: %" PetscInt_FMT " cells to split\n", r, n));
      PetscCall(PetscFree(c));
    }
    // the look-ahead: sigma_xx = 0.6, 0.3 and 0.4 f_t in the whole rock's three columns (x from
    // 0.2 to 0.5): the first column reaches the ratio 0.5 and brings its neighbours (the second
    // column); the third is ahead (0.4 >= 0.75 * 0.5) but linked to the first only through the
    // second, which is not: it is left whole
    PetscInt  n, *c;
    PetscCall(StretchColumns(A, {0, 0, 0.6e-3, 0.3e-3, 0.4e-3, 0.4e-3}));
    PetscCall(FDEMDeformableFindCellsToSplit(A, nullptr, &n, &c));
    const std::vector<PetscInt> want = CellsBelow(M, 0.4, 0.2);
    std::vector<PetscInt>       got(c, c + n);
    std::sort(got.begin(), got.end());
    CHECK(got == want, "one column at 0.6 f_t, the next at 0.3 and the last at 0.4: %" PetscInt_FMT " cells to split, expected the %zu of the first two columns", n, want.size());
    PetscCall(PetscFree(c));
    // ... and with the middle column at 0.4 too, the chain reaches the last: the whole rock
    PetscCall(StretchColumns(A, {0, 0, 0.6e-3, 0.4e-3, 0.4e-3, 0.4e-3}));
    PetscCall(FDEMDeformableFindCellsToSplit(A, nullptr, &n, &c));
    CHECK(n == whole, "one column at 0.6 f_t, the next two at 0.4: %" PetscInt_FMT " cells to split, expected the whole rock's %" PetscInt_FMT, n, whole);
    PetscCall(PetscFree(c));
  }

  // 4. errors
  {
    PetscViewer v;
    PetscCall(Save(B, file)); // B split more than A: A cannot take it
    PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, file, FILE_MODE_READ, &v));
    PetscCall(ExpectError("a checkpoint that split tetrahedra the model keeps whole", "keeps whole", [&]() -> PetscErrorCode {
      Vec nat;
      PetscCall(VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, 3 * A->nnodes_global, &nat));
      PetscCall(PetscObjectSetName((PetscObject)nat, "mesh_x"));
      PetscErrorCode e = FDEMDeformableLoadNodeVector(A, v, nat);
      PetscCall(VecDestroy(&nat));
      return e;
    }));
    PetscCall(PetscViewerDestroy(&v));
    FDEMDeformable E = nullptr;
    PetscCall(ExpectError("a ratio of 1.5", {"rock", "(0, 1]"}, [&]() { return Make(PETSC_COMM_WORLD, {}, 1.5, &E); }));
    PetscCall(FDEMDeformableDestroy(&E));
    PetscInt steel = -1;
    for (size_t t = 0; t < M.tets.size() && steel < 0; ++t)
      if (M.body[t] == 1) steel = (PetscInt)t;
    PetscCall(ExpectError("a cell of a body without insertion", {"steel", "no joints inserted"}, [&]() { return Make(PETSC_COMM_WORLD, {steel}, 0.5, &E); }));
    PetscCall(FDEMDeformableDestroy(&E));
    PetscCall(ExpectError("a cell outside the mesh", {"tetrahedron 999", "not in the mesh"}, [&]() { return Make(PETSC_COMM_WORLD, {999}, 0.5, &E); }));
    PetscCall(FDEMDeformableDestroy(&E));
  }
  // 5. the criterion on 200 000 random stresses (entries up to 1e-3 to 3 f_t, some diagonal, some
  //    mostly compressive) against eigenvalues by Jacobi rotations: the ratio agrees to 1e-9,
  //    and the test without eigenvalues never says "below r" when the ratio is not
  {
    const fdem::model::Strength m(1.0e6, 2.0e6, 30);
    std::mt19937_64             rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    PetscInt nbad = 0, nwrong = 0, nskip = 0, nsmall = 0;
    double   worst = 0;
    for (int k = 0; k < 200000; ++k) {
      const double sc = 1.0e6 * std::pow(10.0, -3 + 3.5 * (0.5 + 0.5 * u(rng)));
      double       T[6];
      for (double &t : T) t = sc * u(rng);
      if (k % 5 == 0) T[3] = T[4] = T[5] = 0;                     // principal axes
      if (k % 5 == 1) T[0] -= 2 * sc, T[1] -= 2 * sc, T[2] -= 2 * sc; // mostly compressive: Mohr-Coulomb decides
      double A[3][3] = {{T[0], T[3], T[5]}, {T[3], T[1], T[4]}, {T[5], T[4], T[2]}};
      for (int sweep = 0; sweep < 60; ++sweep) { // Jacobi rotations
        int p = 0, q = 1;
        if (std::fabs(A[0][2]) > std::fabs(A[p][q])) p = 0, q = 2;
        if (std::fabs(A[1][2]) > std::fabs(A[p][q])) p = 1, q = 2;
        if (std::fabs(A[p][q]) <= 1e-18 * (std::fabs(A[0][0]) + std::fabs(A[1][1]) + std::fabs(A[2][2]))) break;
        const double th = 0.5 * std::atan2(2 * A[p][q], A[q][q] - A[p][p]), c = std::cos(th), sn = std::sin(th);
        for (int i = 0; i < 3; ++i) { // A <- A J, then J^T A
          const double a = A[i][p], b = A[i][q];
          A[i][p] = c * a - sn * b, A[i][q] = sn * a + c * b;
        }
        for (int j = 0; j < 3; ++j) {
          const double a = A[p][j], b = A[q][j];
          A[p][j] = c * a - sn * b, A[q][j] = sn * a + c * b;
        }
      }
      const double s1 = std::max({A[0][0], A[1][1], A[2][2]}), s3 = std::min({A[0][0], A[1][1], A[2][2]});
      const double den = 2.0e6 * std::cos(M_PI / 6) - 0.5 * (s1 + s3) * std::sin(M_PI / 6);
      const double ref = std::max(s1 / 1.0e6, den > 0 ? 0.5 * (s1 - s3) / den : HUGE_VAL), got = fdem::model::StrengthRatio(T, m);
      if (std::isfinite(ref) || std::isfinite(got)) {
        const double err = std::fabs(got - ref) / std::max(std::fabs(ref), 1e-3);
        worst = std::max(worst, err);
        nbad += !(err <= 1e-9);
      }
      const double r = 0.05 + 1.2 * (0.5 + 0.5 * u(rng));
      if (fdem::model::SurelyBelow(T, m, r)) {
        ++nskip;
        nwrong += !(ref < r);
      }
      nsmall += ref < 0.5 * r;
    }
    CHECK(nbad == 0, "the strength ratio of %" PetscInt_FMT " random stresses differs from the eigenvalues' by more than 1e-9 (worst %g)", nbad, worst);
    CHECK(nwrong == 0, "%" PetscInt_FMT " stresses were said surely below their ratio and are not", nwrong);
    CHECK(nskip > nsmall / 2, "the test without eigenvalues settles %" PetscInt_FMT " stresses; %" PetscInt_FMT " are below half their ratio", nskip, nsmall);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "criterion: ratio within %.2g of the eigenvalues'; %" PetscInt_FMT " of 200000 settled without them (%" PetscInt_FMT " below half their ratio)\n", worst, nskip, nsmall));
  }
  // 6. joints inserted under load start at their face's traction
  {
    FDEMDeformable Z, A6, B6, Boff, B6b;
    Vec            FA, FB, Foff, FBb;
    PetscReal      fA, fB, foff, fBb, eA, eB, eoff, eBb, dmax;
    const double   load = std::hypot(0.3e6, 0.2e6) * 0.5 * 0.1 * 0.1; // |traction| x a face's area
    PetscCall(Make(PETSC_COMM_WORLD, {}, 0.5, &Z));
    PetscCall(SaveJoints(Z, file));
    // A6 split between x = 0.1 and 0.3: at x = 0.1 the joints' triangle a is on the split side
    // (the larger ids), which B's split, with both sides split, gives to the other side
    PetscCall(Make(PETSC_COMM_WORLD, CellsBelow(M, 0.3, 0.1), 0.5, &A6));
    PetscCall(ShearedForces(A6, file, &fA, &eA, &FA));
    PetscCall(SaveJoints(A6, file));
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &B6));
    PetscCall(ShearedForces(B6, file, &fB, &eB, &FB));
    PetscCall(PetscOptionsSetValue(nullptr, "-fdem_insert_prestress", "false"));
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &Boff));
    PetscCall(PetscOptionsClearValue(nullptr, "-fdem_insert_prestress"));
    PetscCall(ShearedForces(Boff, file, &foff, &eoff, &Foff));
    // a checkpoint written before the new joints started (right after the load) starts them on restart
    {
      FDEMDeformable Bp, Bq;
      Vec            Fq;
      PetscReal      fq, eq, dq;
      PetscViewer    v;
      char           early[PETSC_MAX_PATH_LEN];
      PetscCall(PetscSNPrintf(early, sizeof early, "fracture_insertion_early_np%d.h5", (int)size));
      PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &Bp));
      PetscCall(SaveJoints(A6, early));
      PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, early, FILE_MODE_READ, &v));
      PetscCall(FDEMDeformableLoadJointState(Bp, v));
      PetscCall(PetscViewerDestroy(&v));
      PetscCall(SaveJoints(Bp, early));
      PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &Bq));
      PetscCall(ShearedForces(Bq, early, &fq, &eq, &Fq));
      PetscCall(VecAXPY(Fq, -1, FB));
      PetscCall(VecNorm(Fq, NORM_INFINITY, &dq));
      CHECK(dq == 0 && eq == eB, "restarted from a checkpoint written before the new joints started: forces %g N apart, stored energy %g J against %g J", dq, eq, eB);
      PetscCall(VecDestroy(&Fq));
      PetscCall(FDEMDeformableDestroy(&Bp));
      PetscCall(FDEMDeformableDestroy(&Bq));
    }
    PetscCall(SaveJoints(B6, file));
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &B6b));
    PetscCall(ShearedForces(B6b, file, &fBb, &eBb, &FBb));
    PetscCall(VecAXPY(FBb, -1, FB));
    PetscCall(VecNorm(FBb, NORM_INFINITY, &dmax));
    const double energy = (0.3e6 * 0.3e6 + 0.2e6 * 0.2e6) / 1e9 * 0.5 * 0.6 * 0.2 * 0.2; // of the strain in the box's volume
    CHECK(fA < 1e-6 * load && fB < 1e-6 * load, "net force on interior copies with the joints inserted at their faces' tractions: %g N (first insertion), %g N (second), a face's load %g N", fA, fB, load);
    CHECK(foff > 0.1 * load, "net force on interior copies with the joints inserted unloaded: %g N, a face's load %g N", foff, load);
    CHECK(std::fabs(eA) < 1e-9 * energy && std::fabs(eB) < 1e-9 * energy, "the joints' stored energy counted from their insertion: %g J and %g J", eA, eB);
    CHECK(dmax == 0 && eBb == eB, "restarted from B's state: forces %g N apart, stored energy %.17g J against %.17g J", dmax, eBb, eB);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "inserted under load: largest net force on an interior copy %.2g N and %.2g N (unloaded joints: %.3g N; a face's load %.3g N); stored energy from the insertion %.2g J, %.2g J\n", fA, fB, foff, load, eA, eB));
    for (Vec *w : {&FA, &FB, &Foff, &FBb}) PetscCall(VecDestroy(w));
    for (FDEMDeformable *w : {&Z, &A6, &B6, &Boff, &B6b}) PetscCall(FDEMDeformableDestroy(w));
  }
  // 7. a model set up with what its predecessor derived from the input mesh
  //    (FDEMDeformableReuseSetUp) is the model set up without it; one whose joints differ
  //    (another penalty) makes its own
  {
    FDEMDeformable R, Q, Q0;
    PetscReal      wB, wR, wQ, wQ0;
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &R, A));
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &Q, A, 4e10));
    PetscCall(Make(PETSC_COMM_WORLD, cellsB, 0.5, &Q0, nullptr, 4e10));
    for (auto [m, w] : {std::pair{B, &wB}, std::pair{R, &wR}, std::pair{Q, &wQ}, std::pair{Q0, &wQ0}}) PetscCall(FDEMDeformableGetJointFrequency(m, w));
    PetscInt differ = R->nnodes_global != B->nnodes_global || R->njoints_global != B->njoints_global || R->jlaw.size() != B->jlaw.size() || R->cell_gid != B->cell_gid || R->node_gid != B->node_gid;
    for (size_t j = 0; !differ && j < R->jlaw.size(); ++j) differ += std::memcmp(&R->jlaw[j], &B->jlaw[j], sizeof(fdem::kernels::JointLaw)) != 0 || R->jgid[j] != B->jgid[j];
    PetscInt shared[2] = {R->insertion_input == A->insertion_input, Q->insertion_input != A->insertion_input}; // (rank 0 holds them; elsewhere both null)
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &differ, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    PetscCallMPI(MPI_Bcast(shared, 2, MPIU_INT, 0, PETSC_COMM_WORLD));
    CHECK(differ == 0 && wR == wB && shared[0], "a model set up reusing A's input differs from B, set up alone (%" PetscInt_FMT " differences; joint frequency %.17g against %.17g; %s A's)", differ, wR, wB, shared[0] ? "shares" : "does not share");
    CHECK(shared[1] && wQ == wQ0 && wQ > 1.5 * wB, "a model with another joint penalty offered A's input: %s, joint frequency %.17g against %.17g set up alone (B: %g)", shared[1] ? "made its own" : "took it", wQ, wQ0, wB);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "set up reusing A's input: the same model as B (joint frequency %.6g /s); with 4 times the penalty it makes its own (%.6g /s)\n", wR, wQ));
    for (FDEMDeformable *w : {&R, &Q, &Q0}) PetscCall(FDEMDeformableDestroy(w));
  }
  // 8. a model continued from its predecessor without a file (FDEMDeformableContinueNodeVector,
  //    FDEMDeformableContinueJointState) gets what loading the predecessor's checkpoint gives,
  //    to the bit: into a larger split (B's) and into the same split (A's). A predecessor that
  //    split tetrahedra the model keeps whole is refused.
  {
    Vec nat[2];
    A->onset = 0.125; // (the contact energy taken over from removed joints, which A has none of)
    PetscCall(Save(A, file)); // (A's state of part 1)
    for (int w = 0; w < 2; ++w) PetscCall(NodeVector(A, w, &nat[w]));
    for (const auto &cells : {cellsB, cellsA}) {
      FDEMDeformable L, C; // loaded from the file, continued from A
      PetscViewer    v;
      PetscInt       differ = 0;
      PetscCall(Make(PETSC_COMM_WORLD, cells, 0.5, &L));
      PetscCall(Make(PETSC_COMM_WORLD, cells, 0.5, &C));
      PetscCall(PetscViewerHDF5Open(PETSC_COMM_WORLD, file, FILE_MODE_READ, &v));
      for (int w = 0; w < 2; ++w) {
        Vec       l, c;
        PetscBool eq;
        PetscCall(VecCreateMPI(PETSC_COMM_WORLD, PETSC_DECIDE, 3 * L->nnodes_global, &l));
        PetscCall(PetscObjectSetName((PetscObject)l, w ? "mesh_v" : "mesh_x"));
        PetscCall(VecDuplicate(l, &c));
        PetscCall(FDEMDeformableLoadNodeVector(L, v, l));
        PetscCall(FDEMDeformableContinueNodeVector(C, A, nat[w], c));
        PetscCall(VecEqual(l, c, &eq));
        differ += !eq;
        PetscCall(VecDestroy(&l));
        PetscCall(VecDestroy(&c));
      }
      PetscCall(FDEMDeformableLoadJointState(L, v));
      PetscCall(PetscViewerDestroy(&v));
      PetscCall(FDEMDeformableContinueJointState(C, A));
      PetscInt local = L->jstate.size() != C->jstate.size() || L->jdiss != C->jdiss || L->jgone != C->jgone || L->jfresh != C->jfresh || L->jofs.size() != C->jofs.size() || L->onset != C->onset;
      for (size_t j = 0; !local && j < L->jstate.size(); ++j) local += std::memcmp(L->jstate[j].data(), C->jstate[j].data(), sizeof L->jstate[j]) != 0;
      for (size_t j = 0; !local && j < L->jofs.size(); ++j) local += std::memcmp(&L->jofs[j], &C->jofs[j], sizeof L->jofs[j]) != 0;
      differ += local;
      PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &differ, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
      CHECK(differ == 0, "a model of %zu split cells continued from A differs from the one loaded from A's checkpoint (%" PetscInt_FMT " differences)", cells.size(), differ);
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "continued from A without a file, %zu cells split: the nodes and joints loading A's checkpoint gives (%" PetscInt_FMT " joints)\n", cells.size(), C->njoints_global));
      PetscCall(FDEMDeformableDestroy(&L));
      PetscCall(FDEMDeformableDestroy(&C));
    }
    PetscCall(ExpectError("continuing a model that split tetrahedra this one keeps whole", {"model continued from", "keeps whole"}, [&]() { return FDEMDeformableContinueJointState(A, B); }));
    for (Vec &w : nat) PetscCall(VecDestroy(&w));
  }
  PetscCall(FDEMDeformableDestroy(&A));
  PetscCall(FDEMDeformableDestroy(&B));
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
