// Deformable bodies, joints inserted during a run (doc/fracture.md, "Joints inserted
// during a run"): a fracturable body with an insertion ratio starts split only in its
// fracture zones; the tetrahedra whose stress nears the strength are found between steps
// (FDEMDeformableFindCellsToSplit) and the caller builds the model again with them split
// (FDEMDeformableAddFractureCells), taking the old model's state (FDEMDeformableContinue*) or
// loading a checkpoint written before into the larger split: each copy of a node takes the
// state of the node its tetrahedron had, each joint that existed the state it had, and a new
// joint starts intact.
#include "../util/guard.hpp"
#include "deformable_impl.hpp"
#include "deformable_object.hpp"

#include <fdem/kernels/error.hpp>
#include <fdem/kernels/joint_mesh.hpp>
#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace fdem::model::deformable;

namespace {

// The split of the input mesh with the zones' tetrahedra and `cells` split (rank 0).
fdem::kernels::SplitMesh SplitWith(FDEMDeformable d, const std::vector<PetscInt> &cells) {
  std::vector<char> flags = d->box_split;
  for (PetscInt t : cells) flags[t] = 1;
  return d->insertion_input->splitter->Split(flags);
}

} // namespace

fdem::model::Strength::Strength(double tensile_strength, double cohesion, double friction_angle_degrees) : ft(tensile_strength), ccos(cohesion * std::cos(friction_angle_degrees * M_PI / 180)), sin(std::sin(friction_angle_degrees * M_PI / 180)) {}

// The largest principal stress and the Mohr-Coulomb ratio of a Cauchy stress (xx yy zz xy yz
// xz, tension positive) against a material: max(sigma_1 / f_t, ((s1 - s3) / 2) / (c cos phi -
// (s1 + s3) / 2 sin phi)), the second infinite where the tension leaves no shear strength.
double fdem::model::StrengthRatio(const PetscReal *T, const Strength &m) {
  // eigenvalues of the symmetric matrix (trigonometric form)
  const double xx = T[0], yy = T[1], zz = T[2], xy = T[3], yz = T[4], xz = T[5];
  const double p1 = xy * xy + yz * yz + xz * xz, q = (xx + yy + zz) / 3;
  double       s1, s3;
  if (p1 <= 1e-30 * (xx * xx + yy * yy + zz * zz)) {
    s1 = std::max({xx, yy, zz});
    s3 = std::min({xx, yy, zz});
  } else {
    const double p2 = (xx - q) * (xx - q) + (yy - q) * (yy - q) + (zz - q) * (zz - q) + 2 * p1, p = std::sqrt(p2 / 6);
    const double b00 = (xx - q) / p, b11 = (yy - q) / p, b22 = (zz - q) / p, b01 = xy / p, b12 = yz / p, b02 = xz / p;
    const double r   = 0.5 * (b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02));
    const double phi = r <= -1 ? M_PI / 3 : r >= 1 ? 0 : std::acos(r) / 3;
    s1               = q + 2 * p * std::cos(phi);
    s3               = q + 2 * p * std::cos(phi + 2 * M_PI / 3);
  }
  const double den = m.ccos - 0.5 * (s1 + s3) * m.sin;
  const double shear = den > 0 ? 0.5 * (s1 - s3) / den : HUGE_VAL;
  return std::max(s1 / m.ft, shear);
}

// True when StrengthRatio(T, m) is surely below r, from bounds on the principal stresses that
// need no eigenvalues (Gershgorin's discs: s1 <= U, s3 >= L, and s1 + s3 = tr - s2 <= tr - L),
// kept 1e-9 of r clear of it so that round-off cannot decide (most cells of a body are far
// from their strength: the trigonometric form is left for the others).
bool fdem::model::SurelyBelow(const PetscReal *T, const Strength &m, double r) {
  const double R0 = std::fabs(T[3]) + std::fabs(T[5]), R1 = std::fabs(T[3]) + std::fabs(T[4]), R2 = std::fabs(T[4]) + std::fabs(T[5]);
  const double U = std::max({T[0] + R0, T[1] + R1, T[2] + R2}), L = std::min({T[0] - R0, T[1] - R1, T[2] - R2});
  const double limit = r * (1 - 1e-9);
  if (!(U / m.ft < limit)) return false; // (also NaN)
  const double den = m.ccos - 0.5 * std::min(T[0] + T[1] + T[2] - L, 2 * U) * m.sin;
  return m.sin >= 0 && den > 0 && 0.5 * (U - L) / den < limit;
}

// The inserted tetrahedra saved in a checkpoint ("fracture_cells": their count, then their
// ids); *has false when it has none (a run without insertion, or an earlier fdem's).
PetscErrorCode fdem::model::deformable::ReadInsertedCells(MPI_Comm comm, PetscViewer viewer, std::vector<PetscInt> &cells, bool *has) {
  PetscBool hdf5, h = PETSC_FALSE;
  Vec       v, v0;
  PetscFunctionBegin;
  cells.clear();
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERHDF5, &hdf5));
  if (hdf5) PetscCall(PetscViewerHDF5HasDataset(viewer, "/fracture_cells", &h));
  *has = h;
  if (!h) PetscFunctionReturn(0);
  VecScatter sc;
  PetscCall(VecCreate(comm, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, "fracture_cells"));
  PetscCall(VecLoad(v, viewer));
  PetscCall(VecScatterCreateToAll(v, &sc, &v0));
  PetscCall(VecScatterBegin(sc, v, v0, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, v, v0, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt           N;
  const PetscScalar *a;
  PetscCall(VecGetSize(v0, &N));
  PetscCall(VecGetArrayRead(v0, &a));
  const double n  = N > 0 ? PetscRealPart(a[0]) : -1;
  bool         ok = N > 0 && n == N - 1;
  for (PetscInt i = 1; ok && i < N; ++i) {
    const double c = PetscRealPart(a[i]);
    ok             = c >= 0 && c == std::floor(c) && c < 9e15 && (i == 1 || c > PetscRealPart(a[i - 1]));
    if (ok) cells.push_back((PetscInt)c);
  }
  PetscCall(VecRestoreArrayRead(v0, &a));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&v0));
  PetscCall(VecDestroy(&v));
  PetscCheck(ok, comm, PETSC_ERR_FILE_UNEXPECTED, "the checkpoint's fracture_cells is not a count followed by that many increasing tetrahedron ids");
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::ViewInsertedCells(FDEMDeformable d, PetscViewer viewer) {
  Vec v;
  PetscFunctionBegin;
  if (d->insertion.empty()) PetscFunctionReturn(0);
  const PetscInt n = (PetscInt)d->inserted.size();
  PetscCall(VecCreateMPI(d->comm, d->rank == 0 ? n + 1 : 0, n + 1, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, "fracture_cells"));
  if (d->rank == 0) {
    PetscScalar *a;
    PetscCall(VecGetArray(v, &a));
    a[0] = (PetscScalar)n;
    for (PetscInt i = 0; i < n; ++i) a[i + 1] = (PetscScalar)d->inserted[i];
    PetscCall(VecRestoreArray(v, &a));
  }
  PetscCall(VecView(v, viewer));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::SavedState::Has(const char *name, bool *has) const {
  PetscBool hdf5, h = PETSC_TRUE;
  PetscFunctionBegin;
  *has = true;
  if (!viewer) PetscFunctionReturn(0);
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERHDF5, &hdf5));
  if (hdf5) PetscCall(PetscViewerHDF5HasDataset(viewer, (std::string("/") + name).c_str(), &h));
  *has = h;
  PetscFunctionReturn(0);
}

// Whether the saved state was written with another split than this model's (the checkpoint's
// inserted tetrahedra in `old`); an error when it split a tetrahedron this model keeps whole.
PetscErrorCode fdem::model::deformable::SavedSplitDiffers(FDEMDeformable d, const SavedState &saved, std::vector<PetscInt> &old, bool *differs) {
  bool has;
  PetscFunctionBegin;
  if (saved.viewer) PetscCall(ReadInsertedCells(d->comm, saved.viewer, old, &has));
  else old = saved.from->inserted, has = !saved.from->insertion.empty(); // (what ViewInsertedCells would save)
  *differs = has && old != d->inserted;
  if (!has && !d->inserted.empty()) *differs = true; // saved before any insertion, or by an earlier fdem
  if (*differs) {
    const char *what = saved.viewer ? "the checkpoint" : "the model continued from";
    PetscCheck(!d->insertion.empty(), d->comm, PETSC_ERR_FILE_UNEXPECTED, "%s has joints inserted during its run (fracture_cells), but this model inserts none: load it into a model with the same insertion bodies", what);
    PetscCheck(std::includes(d->inserted.begin(), d->inserted.end(), old.begin(), old.end()), d->comm, PETSC_ERR_FILE_UNEXPECTED, "%s split tetrahedra that this model keeps whole (fracture_cells): give them to FDEMDeformableAddFractureCells", what);
  }
  PetscFunctionReturn(0);
}

// rank 0: the nodes and joints of the split with `old` inserted that this model's nodes and
// joints come from (made once for each `old`: the node vectors and the joint fields of a load
// all use them). Each node of this model is a tetrahedron's corner, which has a node in that
// split; a joint comes from the joint of that split on the same face (if any), each of its
// points (the midpoint of edge (q, q+1) of triangle a) from that joint's point on the same
// edge (triangle a may be on the other side now).
static void Origins(FDEMDeformable d, const std::vector<PetscInt> &old) {
  if (d->origin_nodes >= 0 && d->origin_of == old) return;
  // the two splits: those the models kept, or made again
  const auto record = [&](const std::vector<PetscInt> &cells) {
    const fdem::kernels::SplitMesh s = SplitWith(d, cells);
    return std::make_shared<const SplitRecord>(SplitRecord{cells, s.mesh.tets, s.parent, s.joints});
  };
  const auto pa = d->origin_split && d->origin_split->inserted == old ? d->origin_split : record(old);
  const auto pb = d->own_split && d->own_split->inserted == d->inserted ? d->own_split : record(d->inserted);
  const SplitRecord &a = *pa, &b = *pb;
  d->node_origin.assign(b.parent.size(), -1);
  for (std::size_t t = 0; t < b.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) d->node_origin[b.tets[t][k]] = a.tets[t][k];
  auto key = [](const SplitRecord &s, const fdem::kernels::JointFace &j) {
    std::array<int, 3> k = {s.parent[j.a[0]], s.parent[j.a[1]], s.parent[j.a[2]]};
    std::sort(k.begin(), k.end());
    return k;
  };
  auto edge = [](const SplitRecord &s, const fdem::kernels::JointFace &j, int q) {
    const int u = s.parent[j.a[q]], w = s.parent[j.a[(q + 1) % 3]];
    return std::make_pair(std::min(u, w), std::max(u, w));
  };
  d->joint_origin.assign(b.joints.size(), JointOrigin{});
  std::size_t i = 0;
  for (std::size_t j = 0; j < b.joints.size(); ++j) { // both in the order of their sorted face keys
    const auto kb = key(b, b.joints[j]);
    while (i < a.joints.size() && key(a, a.joints[i]) < kb) ++i;
    if (i == a.joints.size() || key(a, a.joints[i]) != kb) continue;
    d->joint_origin[j].joint = (PetscInt)i;
    for (int q = 0; q < 3; ++q)
      for (int r = 0; r < 3; ++r)
        if (edge(a, a.joints[i], r) == edge(b, b.joints[j], q)) d->joint_origin[j].point[q] = r;
  }
  d->origin_of     = old;
  d->origin_nodes  = (PetscInt)a.parent.size();
  d->origin_joints = (PetscInt)a.joints.size();
  d->origin_split.reset(); // (the maps are made)
}

void fdem::model::deformable::NodeOrigins(FDEMDeformable d, const std::vector<PetscInt> &old, std::vector<PetscInt> &from, PetscInt *nold) {
  Origins(d, old);
  from  = d->node_origin;
  *nold = d->origin_nodes;
}

void fdem::model::deformable::JointOrigins(FDEMDeformable d, const std::vector<PetscInt> &old, std::vector<JointOrigin> &from, PetscInt *nold) {
  Origins(d, old);
  from  = d->joint_origin;
  *nold = d->origin_joints;
}

// Maps `old`, a vector in the natural order of a split with fewer tetrahedra split (nold units
// of `per` entries), into nat, this model's natural layout: rank 0 gets old and fills each unit
// of the new one (fill(old, new)), which is then spread over nat's layout. Collective.
PetscErrorCode fdem::model::deformable::MapFromSplit(FDEMDeformable d, Vec old, Vec nat, PetscInt nold, PetscInt per, const std::function<void(const PetscScalar *, PetscScalar *)> &fill) {
  Vec         old0, new0;
  VecScatter  so, sn;
  const char *name;
  PetscInt    N;
  PetscFunctionBegin;
  PetscCall(PetscObjectGetName((PetscObject)nat, &name));
  PetscCall(VecGetSize(old, &N));
  PetscCheck(N == per * nold, d->comm, PETSC_ERR_FILE_UNEXPECTED, "the saved %s has %" PetscInt_FMT " entries; the split it was written with has %" PetscInt_FMT " x %" PetscInt_FMT " (another scene?)", name, N, nold, per);
  if (d->size == 1) { // both vectors are whole on rank 0 already: no copies through scatters
    const PetscScalar *o;
    PetscScalar       *n;
    PetscCall(VecSet(nat, 0));
    PetscCall(VecGetArrayRead(old, &o));
    PetscCall(VecGetArray(nat, &n));
    fill(o, n);
    PetscCall(VecRestoreArray(nat, &n));
    PetscCall(VecRestoreArrayRead(old, &o));
    PetscFunctionReturn(0);
  }
  PetscCall(VecScatterCreateToZero(old, &so, &old0));
  PetscCall(VecScatterBegin(so, old, old0, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(so, old, old0, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterCreateToZero(nat, &sn, &new0));
  if (d->rank == 0) {
    const PetscScalar *o;
    PetscScalar       *n;
    PetscCall(VecGetArrayRead(old0, &o));
    PetscCall(VecGetArray(new0, &n));
    fill(o, n);
    PetscCall(VecRestoreArray(new0, &n));
    PetscCall(VecRestoreArrayRead(old0, &o));
  }
  PetscCall(VecScatterBegin(sn, new0, nat, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sn, new0, nat, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterDestroy(&so));
  PetscCall(VecScatterDestroy(&sn));
  PetscCall(VecDestroy(&old0));
  PetscCall(VecDestroy(&new0));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetFractureInsertion(FDEMDeformable d, const char *body, PetscReal ratio) {
  PetscFunctionBegin;
  PetscCheck(body && body[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableSetFractureInsertion: the body needs a name");
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetFractureInsertion"));
  PetscCheck(ratio > 0 && ratio <= 1, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetFractureInsertion: body '%s': the stress ratio %g must be in (0, 1]", body, (double)ratio);
  d->insertion[body] = ratio;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableAddFractureCells(FDEMDeformable d, PetscInt n, const PetscInt cells[]) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableAddFractureCells"));
  PetscCheck(n >= 0 && (n == 0 || cells), d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableAddFractureCells: give n >= 0 tetrahedron ids");
  d->inserted.insert(d->inserted.end(), cells, cells + n);
  std::sort(d->inserted.begin(), d->inserted.end());
  d->inserted.erase(std::unique(d->inserted.begin(), d->inserted.end()), d->inserted.end());
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetFractureCells(FDEMDeformable d, PetscInt *n, const PetscInt *cells[]) {
  PetscFunctionBegin;
  *n = (PetscInt)d->inserted.size();
  if (cells) *cells = d->inserted.data();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableReadFractureCells(MPI_Comm comm, PetscViewer viewer, PetscInt *n, PetscInt *cells[]) {
  std::vector<PetscInt> c;
  bool                  has;
  PetscFunctionBegin;
  PetscCall(ReadInsertedCells(comm, viewer, c, &has));
  *n = (PetscInt)c.size();
  PetscCall(PetscMalloc1(c.size() + 1, cells));
  std::copy(c.begin(), c.end(), *cells);
  PetscFunctionReturn(0);
}

// A node vector of the saved state into nat (this model's natural layout): `old`, or without it
// the viewer's vector of nat's name.
static PetscErrorCode NodeVectorFrom(FDEMDeformable d, const SavedState &saved, Vec old, Vec nat) {
  std::vector<PetscInt> cells;
  bool                  differs;
  PetscFunctionBegin;
  PetscCall(SavedSplitDiffers(d, saved, cells, &differs));
  if (!differs) {
    if (old) PetscCall(VecCopy(old, nat));
    else PetscCall(VecLoad(nat, saved.viewer));
    PetscFunctionReturn(0);
  }
  std::vector<PetscInt> from;
  PetscInt              nold = 0;
  PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
    if (d->rank == 0) NodeOrigins(d, cells, from, &nold);
    return 0;
  }));
  PetscCallMPI(MPI_Bcast(&nold, 1, MPIU_INT, 0, d->comm));
  Vec loaded = nullptr;
  if (!old) {
    const char *name;
    PetscCall(PetscObjectGetName((PetscObject)nat, &name));
    PetscCall(VecCreate(d->comm, &loaded));
    PetscCall(PetscObjectSetName((PetscObject)loaded, name));
    PetscCall(VecLoad(loaded, saved.viewer));
  }
  PetscCall(MapFromSplit(d, old ? old : loaded, nat, nold, 3, [&](const PetscScalar *o, PetscScalar *n) {
    for (std::size_t i = 0; i < from.size(); ++i)
      for (int c = 0; c < 3; ++c) n[3 * i + c] = o[3 * from[i] + c];
  }));
  PetscCall(VecDestroy(&loaded));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableLoadNodeVector(FDEMDeformable d, PetscViewer viewer, Vec nat) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableLoadNodeVector"));
  PetscCall(NodeVectorFrom(d, SavedState{viewer, nullptr}, nullptr, nat));
  PetscFunctionReturn(0);
}

// Both set up, on the same communicator, of the same input mesh.
static PetscErrorCode CheckContinues(FDEMDeformable to, FDEMDeformable from, const char *fn) {
  PetscMPIInt cmp;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(to, fn));
  PetscCall(CheckSetUp(from, fn));
  PetscCallMPI(MPI_Comm_compare(to->comm, from->comm, &cmp));
  PetscCheck(cmp == MPI_IDENT || cmp == MPI_CONGRUENT, to->comm, PETSC_ERR_ARG_INCOMP, "%s: the two models are on different communicators", fn);
  PetscInt same = 1; // (rank 0 holds the input meshes)
  if (to->rank == 0) {
    const auto &a = to->insertion_input, &b = from->insertion_input;
    same = a == b || (a && b && SameInput(*a, b->key, b->mesh));
  }
  PetscCallMPI(MPI_Bcast(&same, 1, MPIU_INT, 0, to->comm));
  PetscCheck(same, to->comm, PETSC_ERR_ARG_INCOMP, "%s: the two models differ in their input mesh, insertion or fracture properties", fn);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContinueNodeVector(FDEMDeformable to, FDEMDeformable from, Vec from_natural, Vec to_natural) {
  PetscFunctionBegin;
  PetscCall(CheckContinues(to, from, "FDEMDeformableContinueNodeVector"));
  if (to->rank == 0) to->origin_split = from->own_split;
  PetscCall(NodeVectorFrom(to, SavedState{nullptr, from}, from_natural, to_natural));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContinueJointState(FDEMDeformable to, FDEMDeformable from) {
  PetscFunctionBegin;
  PetscCall(CheckContinues(to, from, "FDEMDeformableContinueJointState"));
  if (to->rank == 0) to->origin_split = from->own_split;
  PetscCall(LoadJointState(to, SavedState{nullptr, from}));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableFindCellsToSplit(FDEMDeformable d, Vec U, PetscInt *n, PetscInt *cells[]) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableFindCellsToSplit"));
  *n = 0;
  if (d->insertion.empty()) {
    PetscCall(PetscMalloc1(1, cells));
    PetscFunctionReturn(0);
  }
  if (d->body_insertion.empty()) {
    d->body_insertion.assign(d->body_names.size(), 0);
    for (std::size_t b = 0; b < d->body_names.size(); ++b) {
      const auto it = d->insertion.find(d->body_names[b]);
      if (it != d->insertion.end()) d->body_insertion[b] = it->second;
    }
  }
  // this rank's whole cells of insertion bodies at or above their ratio (those a fracture zone
  // split too: rank 0 knows which are), their stresses alone
  {
    StateView sv;
    PetscCall(sv.Get(d, U));
    PetscCall(LocalPositions(d, sv.xa, d->viscous ? sv.va : nullptr));
    PetscCall(sv.Restore());
  }
  const PetscScalar *xl, *vl = nullptr;
  PetscCall(VecGetArrayRead(d->xloc, &xl));
  if (d->viscous) PetscCall(VecGetArrayRead(d->vloc, &vl));
  std::vector<PetscInt> mine;
  std::vector<fdem::model::Strength> strength(d->body_insertion.size()); // per body (of insertion bodies)
  for (std::size_t b = 0; b < d->body_insertion.size(); ++b)
    if (d->body_insertion[b] > 0) {
      const auto &m = d->fracture.at(d->materials[d->material_of_body[b]].name);
      strength[b]   = fdem::model::Strength(m.tensile_strength, m.cohesion, m.friction_angle);
    }
  if (d->cell_inserted.size() != d->ed.size()) { // (the inserted cells do not change in a model)
    d->cell_inserted.assign(d->ed.size(), 0);
    for (std::size_t e = 0; e < d->ed.size(); ++e) d->cell_inserted[e] = std::binary_search(d->inserted.begin(), d->inserted.end(), d->cell_gid[e]);
  }
  // the stresses of the cells of materials that some insertion body has, run by run (the cells
  // are sorted by material), with the force kernel's batched loop (inverted: NaN, as the stress
  // output has it)
  std::vector<char> mat_inserts(d->materials.size(), 0);
  for (std::size_t b = 0; b < d->body_insertion.size(); ++b)
    if (d->body_insertion[b] > 0) mat_inserts[d->material_of_body[b]] = 1;
  // (in blocks of a run: the stresses are read while still in the cache, and the scratch is small)
  constexpr std::size_t kBlock = 1024;
  std::vector<double>  &S      = d->stress_scratch;
  for (std::size_t e0 = 0; e0 < d->ed.size();) {
    std::size_t e1 = e0;
    while (e1 < d->ed.size() && d->ed.elems[e1].material == d->ed.elems[e0].material && e1 - e0 < kBlock) ++e1;
    if (mat_inserts[d->ed.elems[e0].material]) {
      if (S.size() < 6 * (e1 - e0)) S.resize(6 * (e1 - e0));
      fdem::kernels::CellStresses(d->ed, xl, vl, S.data(), e0, e1);
      for (std::size_t e = e0; e < e1; ++e) {
        const int       b = d->ed.body[e];
        const PetscReal r = d->body_insertion[b];
        const double   *T = &S[6 * (e - e0)];
        if (r <= 0 || d->cell_inserted[e]) continue;
        const double r_ahead = r * (1 - d->insert_ahead);
        if (fdem::model::SurelyBelow(T, strength[b], r_ahead)) continue;
        const double q = fdem::model::StrengthRatio(T, strength[b]);
        if (q >= r) mine.push_back(d->cell_gid[e]);
        else if (q >= r_ahead) mine.push_back(-1 - d->cell_gid[e]); // (taken only when linked to a cell at r)
      }
    }
    e0 = e1;
  }
  if (d->viscous) PetscCall(VecRestoreArrayRead(d->vloc, &vl));
  PetscCall(VecRestoreArrayRead(d->xloc, &xl));
  // to rank 0, which drops the split ones and adds their neighbours (the cells sharing a node
  // with them) in the same bodies, so that a crack has room to run before the next insertion.
  // The cells ahead (-1 - id: at (1 - insert_ahead) of the ratio, below it) join when linked
  // to a cell that reached it: a rebuild costs about the same for a few cells more, and these
  // would each ask for one of their own a few searches later
  const PetscMPIInt      cnt = (PetscMPIInt)mine.size();
  std::vector<PetscMPIInt> cnts(d->size), off(d->size + 1, 0);
  PetscCallMPI(MPI_Gather(&cnt, 1, MPI_INT, cnts.data(), 1, MPI_INT, 0, d->comm));
  for (int r = 0; r < d->size; ++r) off[r + 1] = off[r] + (d->rank == 0 ? cnts[r] : 0);
  std::vector<PetscInt> all(off[d->size]), add;
  PetscCallMPI(MPI_Gatherv(mine.data(), cnt, MPIU_INT, all.data(), cnts.data(), off.data(), MPIU_INT, 0, d->comm));
  if (d->rank == 0) {
    const auto      &M = d->insertion_input->mesh;
    std::vector<char> hot(M.nodes.size(), 0), take(M.tets.size(), 0);
    // from the cells at the ratio, through chains of cells ahead that share a node: the region
    // of high stress around each place the stress reached the ratio, not every cell ahead in
    // the body (their nodes, hot, then bring their neighbours)
    std::vector<PetscInt>                 queue;
    std::vector<std::pair<int, PetscInt>> ahead; // (node, cell ahead), sorted by node
    for (PetscInt c : all)
      if (const PetscInt t = c >= 0 ? c : -1 - c; d->tet_split[t]) continue; // (split by a zone)
      else if (c >= 0) queue.push_back(t);
      else
        for (int k : M.tets[t]) ahead.push_back({k, t});
    std::sort(ahead.begin(), ahead.end());
    std::vector<char> joined(M.tets.size(), 0);
    for (std::size_t i = 0; i < queue.size(); ++i)
      for (int k : M.tets[queue[i]]) {
        if (hot[k]) continue;
        hot[k] = 1;
        for (auto it = std::lower_bound(ahead.begin(), ahead.end(), std::make_pair(k, (PetscInt)-1)); it != ahead.end() && it->first == k; ++it)
          if (!joined[it->second]) joined[it->second] = 1, queue.push_back(it->second);
      }
    for (std::size_t t = 0; t < M.tets.size(); ++t)
      if (!d->tet_split[t] && d->body_insertion[M.body[t]] > 0)
        for (int k : M.tets[t]) take[t] = take[t] || hot[k];
    for (std::size_t t = 0; t < M.tets.size(); ++t)
      if (take[t]) add.push_back((PetscInt)t);
  }
  PetscInt na = (PetscInt)add.size();
  PetscCallMPI(MPI_Bcast(&na, 1, MPIU_INT, 0, d->comm));
  add.resize(na);
  PetscCallMPI(MPI_Bcast(add.data(), (PetscMPIInt)na, MPIU_INT, 0, d->comm));
  *n = na;
  PetscCall(PetscMalloc1(na + 1, cells));
  std::copy(add.begin(), add.end(), *cells);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableReuseSetUp(FDEMDeformable to, FDEMDeformable from) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(to, "FDEMDeformableReuseSetUp"));
  PetscCall(CheckSetUp(from, "FDEMDeformableReuseSetUp"));
  to->reuse = from->insertion_input; // (rank 0; SetUp checks that it fits)
  to->reuse_keys = from->cell_keys;  // (every rank; BuildLocal takes a key only where a centroid and the box match)
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContinueOutput(FDEMDeformable to, FDEMDeformable from) {
  PetscFunctionBegin;
  to->outputs = from->outputs;
  PetscFunctionReturn(0);
}
