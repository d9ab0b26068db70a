// Deformable bodies, input: the mesh setters (the mesh lives on rank 0 until
// FDEMDeformableSetUp distributes it) and the validation of mesh and
// materials on rank 0. See include/fdem/deformable.h and doc/deformable.md.
#include "../util/guard.hpp"
#include "deformable_object.hpp"

#include <fdem/kernels/error.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

using fdem::kernels::Vec3;
using namespace fdem::model::deformable;

namespace {

PetscErrorCode ResetMesh(FDEMDeformable d) {
  PetscFunctionBegin;
  d->mesh     = fdem::kernels::TetMesh();
  d->has_mesh = false;
  PetscFunctionReturn(0);
}

PetscErrorCode FinishMesh(FDEMDeformable d) {
  PetscFunctionBegin;
  d->has_mesh = true;
  if (d->mesh.body.empty()) d->mesh.body.assign(d->mesh.tets.size(), 0);
  if (d->mesh.body_names.empty()) d->mesh.body_names.push_back("body_0");
  PetscFunctionReturn(0);
}

// A mesh generator run on rank 0; its InputError becomes an error on every rank.
template <class Make>
PetscErrorCode Generate(FDEMDeformable d, Make &&make) {
  PetscFunctionBegin;
  PetscCall(ResetMesh(d));
  PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
    if (d->rank == 0) d->mesh = make();
    return 0;
  }));
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

} // namespace

void fdem::model::deformable::ValidateInput(FDEMDeformable d, std::vector<int> &mat_of_body) {
  using fdem::kernels::InputError;
  const auto &M = d->mesh;
  if (M.tets.empty()) throw InputError("the mesh has no tetrahedra");
  if (d->materials.empty()) throw InputError("no materials; add them with FDEMDeformableAddMaterial()");
  auto find = [&](const std::string &name) {
    for (size_t i = 0; i < d->materials.size(); ++i)
      if (d->materials[i].name == name) return (int)i;
    return -1;
  };
  std::string have;
  for (const auto &m : d->materials) have += (have.empty() ? "" : ", ") + m.name;
  mat_of_body.assign(M.NumBodies(), -1);
  for (int b = 0; b < M.NumBodies(); ++b) {
    const std::string &bn = M.body_names[b];
    auto               it = d->body_material.find(bn);
    std::string        want;
    if (it != d->body_material.end()) want = it->second;
    else if (find(bn) >= 0 || d->materials.size() > 1) want = bn;
    else want = d->materials[0].name;
    mat_of_body[b] = find(want);
    if (mat_of_body[b] < 0) throw InputError("body '" + bn + "' needs material '" + want + "', which is not in the material table (have: " + have + "); add it with FDEMDeformableAddMaterial() or map the body with FDEMDeformableSetBodyMaterial()");
  }
  for (const auto &kv : d->body_material) {
    bool found = false;
    for (const auto &bn : M.body_names) found = found || bn == kv.first;
    if (!found) throw InputError("FDEMDeformableSetBodyMaterial names body '" + kv.first + "', which is not in the mesh");
  }
  // the mesh's own checks; a model built again with more joints inserted (FDEMDeformableReuseSetUp)
  // has the mesh its predecessor checked
  if (d->reuse && SameMesh(d->reuse->mesh, M)) return;
  const int nn = (int)M.nodes.size();
  for (int i = 0; i < nn; ++i)
    if (!(std::isfinite(M.nodes[i].x) && std::isfinite(M.nodes[i].y) && std::isfinite(M.nodes[i].z))) {
      std::ostringstream o;
      o << "node " << i << " has a non-finite coordinate (" << M.nodes[i].x << ", " << M.nodes[i].y << ", " << M.nodes[i].z << ")";
      throw InputError(o.str());
    }
  const auto rep = fdem::kernels::FirstRepeatedTet(M.tets);
  if (rep[1] < M.tets.size())
    throw InputError("element " + std::to_string(rep[1]) + " of body '" + M.body_names[M.body[rep[1]]] + "' repeats element " + std::to_string(rep[0]) + ": the same tetrahedron given twice");
  for (size_t t = 0; t < M.tets.size(); ++t) {
    const auto &T = M.tets[t];
    const int   b = M.body[t];
    for (int a = 0; a < 4; ++a)
      if (T[a] < 0 || T[a] >= nn) throw InputError("element " + std::to_string(t) + " of body '" + M.body_names[b] + "': node " + std::to_string(T[a]) + " out of range [0, " + std::to_string(nn) + ")");
    const Vec3 &a0 = M.nodes[T[0]], &a1 = M.nodes[T[1]], &a2 = M.nodes[T[2]], &a3 = M.nodes[T[3]];
    const double six = 6 * fdem::kernels::TetSignedVolume(a0, a1, a2, a3);
    double       h   = 0;
    for (int a = 0; a < 4; ++a)
      for (int c = a + 1; c < 4; ++c) h = std::max(h, norm(M.nodes[T[a]] - M.nodes[T[c]]));
    if (!(six > 1e-12 * h * h * h)) {
      std::ostringstream o;
      o << "element " << t << " of body '" << M.body_names[b] << "' (nodes " << T[0] << " " << T[1] << " " << T[2] << " " << T[3] << "): reference volume " << six / 6
        << (six < 0 ? " is negative (inverted: need det[x1-x0, x2-x0, x3-x0] > 0)" : " is zero (degenerate tetrahedron)");
      throw InputError(o.str());
    }
  }
}

PetscErrorCode FDEMDeformableSetMesh(FDEMDeformable d, PetscInt nnodes, const PetscReal nodes[], PetscInt ntets, const PetscInt tets[], const PetscInt body[], PetscInt nbodies, const char *const names[]) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMesh"));
  PetscCall(ResetMesh(d));
  if (d->rank == 0) {
    auto &M = d->mesh;
    M.nodes.resize(nnodes);
    for (PetscInt i = 0; i < nnodes; ++i) M.nodes[i] = Vec3(nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]);
    M.tets.resize(ntets);
    M.body.assign(ntets, 0);
    PetscInt nb = PetscMax(nbodies, 1);
    for (PetscInt e = 0; e < ntets; ++e) {
      for (int k = 0; k < 4; ++k) M.tets[e][k] = (int)tets[4 * e + k];
      if (body) {
        PetscCheck(body[e] >= 0 && body[e] < nb, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMesh: element %" PetscInt_FMT " has body %" PetscInt_FMT ", not in [0, %" PetscInt_FMT ")", e, body[e], nb);
        M.body[e] = (int)body[e];
      }
    }
    for (PetscInt b = 0; b < nb; ++b) M.body_names.push_back(names && names[b] ? std::string(names[b]) : "body_" + std::to_string(b));
  }
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshBox(FDEMDeformable d, const PetscReal lo[3], const PetscReal hi[3], PetscInt nx, PetscInt ny, PetscInt nz) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshBox"));
  PetscCheck(nx > 0 && ny > 0 && nz > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshBox: cell counts must be positive");
  PetscCall(Generate(d, [&]() { return fdem::kernels::MakeBoxMesh(Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2]), (int)nx, (int)ny, (int)nz); }));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshBeam(FDEMDeformable d, PetscReal L, PetscReal W, PetscReal H, PetscInt n) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshBeam"));
  PetscCheck(L > 0 && W > 0 && H > 0 && n > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshBeam: sizes and n must be positive");
  PetscCall(Generate(d, [&]() { return fdem::kernels::MakeBeamMesh(L, W, H, (int)n); }));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshCylinder(FDEMDeformable d, PetscReal radius, PetscReal height, PetscInt n_radial, PetscInt n_axial) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshCylinder"));
  PetscCheck(radius > 0 && height > 0 && n_radial > 0 && n_axial > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshCylinder: sizes and counts must be positive");
  PetscCall(Generate(d, [&]() { return fdem::kernels::MakeCylinderMesh(radius, height, (int)n_radial, (int)n_axial); }));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshFromGmsh(FDEMDeformable d, const char *path) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshFromGmsh"));
  PetscCall(ResetMesh(d));
  PetscCall(fdem::Guard(
    d->comm,
    [&]() -> PetscErrorCode {
      if (d->rank == 0) d->mesh = fdem::kernels::ReadGmsh(path ? path : "");
      return 0;
    },
    PETSC_ERR_FILE_UNEXPECTED, "FDEMDeformableSetMeshFromGmsh: "));
  for (const auto &w : d->mesh.warnings) PetscCall(PetscPrintf(PETSC_COMM_SELF, "WARNING: %s\n", w.c_str())); // rank 0 holds the mesh
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}
