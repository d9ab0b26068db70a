// Deformable bodies, diagnostics (collective): cell stress, energies,
// momentum, the state of one node, the smallest det F. See doc/deformable.md.
#include "deformable_object.hpp"

#include <algorithm>
#include <cmath>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;
using namespace fdem::model::deformable;

// positions of all local nodes at a state
PetscErrorCode fdem::model::deformable::LocalPositions(FDEMDeformable d, const PetscScalar *xo, const PetscScalar *vo) {
  PetscFunctionBegin;
  PetscCall(VecPlaceArray(d->gwork, xo));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, d->gwork, d->xloc));
  PetscCall(VecResetArray(d->gwork));
  if (vo) {
    PetscCall(VecPlaceArray(d->gwork, vo));
    PetscCall(fdem::model::DeformableGlobalToLocal(d, d->gwork, d->vloc));
    PetscCall(VecResetArray(d->gwork));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableComputeCellStress(FDEMDeformable d, Vec U, Vec *S) {
  StateView    sv;
  PetscScalar *s, *xl, *vl = nullptr;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableComputeCellStress"));
  PetscCall(sv.Get(d, U));
  PetscCall(LocalPositions(d, sv.xa, d->viscous ? sv.va : nullptr));
  PetscCall(sv.Restore());
  PetscCall(VecCreateMPI(d->comm, 6 * (PetscInt)d->ed.size(), PETSC_DETERMINE, S));
  PetscCall(VecSetBlockSize(*S, 6));
  PetscCall(PetscObjectSetName((PetscObject)*S, "stress"));
  PetscCall(VecGetArray(*S, &s));
  PetscCall(VecGetArray(d->xloc, &xl));
  if (d->viscous) PetscCall(VecGetArray(d->vloc, &vl));
  for (size_t e = 0; e < d->ed.size(); ++e) {
    double T[6];
    if (!fdem::kernels::CellStress(d->ed, e, xl, vl, T)) std::fill(T, T + 6, NAN);
    for (int k = 0; k < 6; ++k) s[6 * e + k] = T[k];
  }
  if (d->viscous) PetscCall(VecRestoreArray(d->vloc, &vl));
  PetscCall(VecRestoreArray(d->xloc, &xl));
  PetscCall(VecRestoreArray(*S, &s));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetEnergy(FDEMDeformable d, Vec U, PetscReal *kinetic, PetscReal *strain, PetscReal *gravity) {
  StateView          sv;
  const PetscScalar *ma, *xl;
  PetscReal          loc[3] = {0, 0, 0}, glob[3];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetEnergy"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->m, &ma));
  for (PetscInt i = 0; i < 3 * d->nown; ++i) {
    loc[0] += 0.5 * ma[i] * sv.va[i] * sv.va[i];
    loc[2] -= ma[i] * d->g[i % 3] * sv.xa[i];
  }
  PetscCall(VecRestoreArrayRead(d->m, &ma));
  if (strain) PetscCall(LocalPositions(d, sv.xa, nullptr)); // (collective: NULL or not on every rank)
  PetscCall(sv.Restore());
  if (strain) {
    PetscCall(VecGetArrayRead(d->xloc, &xl));
    for (const auto &el : d->ed.elems) {
      const Vec3 x0(xl[3 * el.n[0]], xl[3 * el.n[0] + 1], xl[3 * el.n[0] + 2]);
      Vec3       e[3];
      for (int a = 1; a < 4; ++a) e[a - 1] = Vec3(xl[3 * el.n[a]], xl[3 * el.n[a] + 1], xl[3 * el.n[a] + 2]) - x0;
      Mat3 Xi;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) Xi.m[r][c] = el.Xinv[3 * r + c];
      const Mat3 F = Mat3::columns(e[0], e[1], e[2]) * Xi;
      loc[1] += el.V0 * fdem::kernels::MaterialModels()[d->materials[el.material].model].energy(d->ed.coeffs[el.material], F);
    }
    PetscCall(VecRestoreArrayRead(d->xloc, &xl));
  }
  PetscCall(MPIU_Allreduce(loc, glob, 3, MPIU_REAL, MPIU_SUM, d->comm));
  if (kinetic) *kinetic = glob[0];
  if (strain) *strain = glob[1];
  if (gravity) *gravity = glob[2];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetMomentum(FDEMDeformable d, Vec U, PetscReal *mass, PetscReal com[3], PetscReal P[3], PetscReal L[3]) {
  StateView          sv;
  const PetscScalar *ma;
  PetscReal          loc[10] = {0}, glob[10];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetMomentum"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->m, &ma));
  for (PetscInt k = 0; k < d->nown; ++k) {
    const double mk = ma[3 * k];
    const Vec3   x(sv.xa[3 * k], sv.xa[3 * k + 1], sv.xa[3 * k + 2]), v(sv.va[3 * k], sv.va[3 * k + 1], sv.va[3 * k + 2]);
    const Vec3   l = mk * cross(x, v);
    loc[0] += mk;
    for (int c = 0; c < 3; ++c) {
      loc[1 + c] += mk * x[c];
      loc[4 + c] += mk * v[c];
      loc[7 + c] += l[c];
    }
  }
  PetscCall(VecRestoreArrayRead(d->m, &ma));
  PetscCall(sv.Restore());
  PetscCall(MPIU_Allreduce(loc, glob, 10, MPIU_REAL, MPIU_SUM, d->comm));
  if (mass) *mass = glob[0];
  for (int c = 0; c < 3; ++c) {
    if (com) com[c] = glob[1 + c] / glob[0];
    if (P) P[c] = glob[4 + c];
    if (L) L[c] = glob[7 + c];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetNodeState(FDEMDeformable d, Vec U, PetscInt id, PetscReal x[3], PetscReal v[3]) {
  StateView sv;
  PetscReal loc[7] = {0}, glob[7];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetNodeState"));
  PetscCall(sv.Get(d, U));
  auto it = d->owned_of_gid.find(id);
  if (it != d->owned_of_gid.end()) {
    const PetscInt k = it->second;
    loc[0]           = 1;
    for (int c = 0; c < 3; ++c) {
      loc[1 + c] = sv.xa[3 * k + c];
      loc[4 + c] = sv.va[3 * k + c];
    }
  }
  PetscCall(sv.Restore());
  PetscCall(MPIU_Allreduce(loc, glob, 7, MPIU_REAL, MPIU_SUM, d->comm));
  PetscCheck(glob[0] == 1, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableGetNodeState: no node with id %" PetscInt_FMT " (the mesh has %" PetscInt_FMT " nodes)", id, d->nnodes_global);
  for (int c = 0; c < 3; ++c) {
    if (x) x[c] = glob[1 + c];
    if (v) v[c] = glob[4 + c];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetMinJacobian(FDEMDeformable d, Vec U, PetscReal *Jmin, PetscInt *element) {
  StateView          sv;
  const PetscScalar *xl;
  struct {
    double v;
    int    r;
  } loc = {INFINITY, 0}, glob;
  PetscInt best = -1;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetMinJacobian"));
  PetscCall(sv.Get(d, U));
  PetscCall(LocalPositions(d, sv.xa, nullptr));
  PetscCall(sv.Restore());
  PetscCall(VecGetArrayRead(d->xloc, &xl));
  for (size_t e = 0; e < d->ed.size(); ++e) {
    const double J = ElementJ(d->ed.elems[e], xl);
    if (J < loc.v) {
      loc.v = J;
      best  = d->cell_gid[e];
    }
  }
  PetscCall(VecRestoreArrayRead(d->xloc, &xl));
  loc.r = d->rank;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MINLOC, d->comm));
  PetscCallMPI(MPI_Bcast(&best, 1, MPIU_INT, glob.r, d->comm));
  if (Jmin) *Jmin = glob.v;
  if (element) *element = best;
  PetscFunctionReturn(0);
}
