// Deformable bodies, output: HDF5 + XDMF of the deforming mesh (ParaView).
// See doc/deformable.md.
#include "../util/output.hpp"
#include "deformable_object.hpp"

#include <petscsf.h>
#include <petscviewerhdf5.h>

#include <cmath>
#include <vector>

using namespace fdem::model::deformable;

// The largest damage of each local cell's joints (0 for a cell without joints; a broken
// point counts 1): each joint's largest point damage marks its tetrahedron a (local) and,
// through the joint-face SF (max), the face of tetrahedron b on that cell's rank.
// Collective when the mesh has joints.
static PetscErrorCode CellDamage(FDEMDeformable d, std::vector<PetscReal> &cd) {
  PetscFunctionBegin;
  const size_t nc = d->ed.size();
  cd.assign(nc, 0.0);
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  std::vector<PetscReal> face(12 * nc, 0.0), leaf(3 * d->jstate.size());
  for (size_t j = 0; j < d->jstate.size(); ++j) {
    PetscReal D = 0;
    for (const auto &p : d->jstate[j]) D = std::fmax(D, p.D); // 1 once broken
    for (int k = 0; k < 3; ++k) leaf[3 * j + k] = D;
    cd[d->jcell_a[j]] = std::fmax(cd[d->jcell_a[j]], D);
  }
  PetscCall(PetscSFReduceBegin(d->jfsf, MPIU_REAL, leaf.data(), face.data(), MPI_MAX));
  PetscCall(PetscSFReduceEnd(d->jfsf, MPIU_REAL, leaf.data(), face.data(), MPI_MAX));
  for (size_t e = 0; e < nc; ++e)
    for (int q = 0; q < 12; ++q) cd[e] = std::fmax(cd[e], face[12 * e + q]);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableWriteHDF5(FDEMDeformable d, Vec U, const char *base, PetscInt step, PetscReal t) {
  StateView              sv;
  const PetscScalar     *Xa, *sa;
  Vec                    S;
  std::vector<PetscReal> xv, dv, vv, st, vm, dmg;
  std::vector<PetscInt>  cells, body, rank, nid;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableWriteHDF5"));
  PetscCheck(base && base[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableWriteHDF5: no file base name");
  PetscCheck(step >= 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableWriteHDF5: step %" PetscInt_FMT " must be non-negative", step);
  for (const auto &o : d->outputs) PetscCheck(o.step != step, d->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMDeformableWriteHDF5: step %" PetscInt_FMT " was already written to %s.h5", step, base);
  PetscCall(FDEMDeformableComputeCellStress(d, U, &S));
  PetscCall(CellDamage(d, dmg));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->X, &Xa));
  const PetscInt n = 3 * d->nown;
  xv.assign(sv.xa, sv.xa + n);
  vv.assign(sv.va, sv.va + n);
  dv.resize(n);
  for (PetscInt i = 0; i < n; ++i) dv[i] = sv.xa[i] - Xa[i];
  PetscCall(VecRestoreArrayRead(d->X, &Xa));
  PetscCall(sv.Restore());
  nid = d->owned_gid;
  PetscCall(VecGetArrayRead(S, &sa));
  const size_t nc = d->ed.size();
  for (size_t e = 0; e < nc; ++e) {
    const auto &el = d->ed.elems[e];
    for (int a = 0; a < 4; ++a) cells.push_back(d->node_global[el.n[a]]);
    body.push_back(d->ed.body[e]);
    rank.push_back(d->rank);
    const double *T = &sa[6 * e]; // xx yy zz xy yz xz -> XDMF Tensor6 xx xy xz yy yz zz
    st.insert(st.end(), {T[0], T[3], T[5], T[1], T[4], T[2]});
    const double s1 = T[0] - T[1], s2 = T[1] - T[2], s3 = T[2] - T[0];
    vm.push_back(std::sqrt(0.5 * (s1 * s1 + s2 * s2 + s3 * s3) + 3 * (T[3] * T[3] + T[4] * T[4] + T[5] * T[5])));
  }
  PetscCall(VecRestoreArrayRead(S, &sa));
  PetscCall(VecDestroy(&S));

  PetscViewer viewer;
  char        file[PETSC_MAX_PATH_LEN], group[64];
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s.h5", base));
  PetscCall(PetscSNPrintf(group, sizeof(group), "/step_%06d", (int)step));
  PetscCall(PetscViewerHDF5Open(d->comm, file, d->outputs.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &viewer));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "vertices", xv, 3));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "displacement", dv, 3));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "velocity", vv, 3));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "node_id", nid, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "cells", cells, 4));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "stress", st, 6));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "von_mises", vm, 1));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "damage", dmg, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "body", body, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "rank", rank, 1));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "time", PETSC_REAL, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "step", PETSC_INT, &step));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  d->outputs.push_back({step, t, d->nnodes_global, d->ncells_global});
  {
    std::vector<fdem::output::XdmfStep> steps;
    for (const auto &o : d->outputs) steps.push_back({o.step, o.t, (long long)o.nvert, (long long)o.ncell});
    PetscCall(fdem::output::WriteXDMF(d->comm, "FDEMDeformableWriteHDF5", base, "deformable mesh", "Tetrahedron", 4, steps,
                                      {{"displacement", "Vector", "Node", 3, true},
                                       {"velocity", "Vector", "Node", 3, true},
                                       {"node_id", "Scalar", "Node", 1, false},
                                       {"stress", "Tensor6", "Cell", 6, true},
                                       {"von_mises", "Scalar", "Cell", 1, true},
                                       {"damage", "Scalar", "Cell", 1, true},
                                       {"body", "Scalar", "Cell", 1, false},
                                       {"rank", "Scalar", "Cell", 1, false}}));
  }
  PetscFunctionReturn(0);
}
