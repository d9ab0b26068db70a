// HDF5 + XDMF output of rigid bodies (see include/fdem/rigid.h and doc/rigid.md).
//
// Every call writes one group /step_NNNNNN of base.h5 (PetscViewerHDF5, all
// ranks' local bodies, collective) with
//   vertices  (Nv x 3) real  : skin nodes moved to the body's pose, x + R p
//   velocity  (Nv x 3) real  : the rigid velocity of each node, v + omega x (R p)
//   cells     (Nt x 3) int   : surface triangles, global (0-based) vertex numbers
//   body_id   (Nt x 1) int   : the id of the body a triangle belongs to
// and the attribute "time" on the group; then rank 0 rewrites base.xmf, an
// XDMF temporal collection of every step written so far (rb->outputs), which
// ParaView opens with its XDMF reader. Bodies without a mesh
// (FDEMRigidAddBody) are drawn as an octahedron of their bounding radius
// whose vertices lie on the principal axes, so their orientation shows.
#include "rigid_impl.hpp"
#include "../util/output.hpp"
#include <fdem/kernels/rotation.hpp>

#include <petscviewerhdf5.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;
using Skin = fdem::model::Skin;

PetscErrorCode FDEMRigidWriteHDF5(FDEMRigid rb, const char *base, PetscInt step, PetscReal t) {
  PetscInt                n;
  fdem::model::RigidFields f;
  std::vector<PetscReal>  X, V;
  std::vector<PetscInt>   cells, bid;
  PetscFunctionBegin;
  PetscCheck(base && base[0], rb->comm, PETSC_ERR_ARG_NULL, "FDEMRigidWriteHDF5: no file base name");
  PetscCheck(step >= 0, rb->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMRigidWriteHDF5: step %" PetscInt_FMT " must be non-negative", step);
  for (const auto &o : rb->outputs)
    PetscCheck(o.step != step, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMRigidWriteHDF5: step %" PetscInt_FMT " was already written to %s.h5", step, base);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  // local vertex count first, to number the vertices globally
  PetscInt nvloc = 0, ntloc = 0;
  for (PetscInt b = 0; b < n; ++b) {
    const Skin &s = f.skin[b] >= 0 ? rb->skins[f.skin[b]] : fdem::model::UnitOctahedron();
    nvloc += (PetscInt)s.nodes.size();
    ntloc += (PetscInt)s.faces.size();
  }
  PetscInt voff = 0;
  PetscCallMPI(MPI_Exscan(&nvloc, &voff, 1, MPIU_INT, MPI_SUM, rb->comm));
  if (rb->rank == 0) voff = 0; // MPI_Exscan leaves rank 0's result undefined
  X.reserve(3 * nvloc);
  V.reserve(3 * nvloc);
  cells.reserve(3 * ntloc);
  bid.reserve(ntloc);
  PetscInt vnext = voff;
  for (PetscInt b = 0; b < n; ++b) {
    const bool  mesh  = f.skin[b] >= 0;
    const Skin &s     = mesh ? rb->skins[f.skin[b]] : fdem::model::UnitOctahedron();
    const double scale = mesh ? 1.0 : f.radius[b];
    Mat3        R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R.m[r][c] = f.R[9 * b + 3 * r + c];
    const Vec3 x(f.x[3 * b], f.x[3 * b + 1], f.x[3 * b + 2]), v(f.v[3 * b], f.v[3 * b + 1], f.v[3 * b + 2]);
    const Vec3 w = fdem::kernels::BodyOmega(R, Vec3(f.I[3 * b], f.I[3 * b + 1], f.I[3 * b + 2]), Vec3(f.H[3 * b], f.H[3 * b + 1], f.H[3 * b + 2]));
    for (const Vec3 &p : s.nodes) {
      const Vec3 r  = R * (scale * p);
      const Vec3 xp = x + r, vp = v + fdem::kernels::cross(w, r);
      X.insert(X.end(), {xp[0], xp[1], xp[2]});
      V.insert(V.end(), {vp[0], vp[1], vp[2]});
    }
    for (const auto &tri : s.faces) {
      cells.insert(cells.end(), {vnext + tri[0], vnext + tri[1], vnext + tri[2]});
      bid.push_back(f.id[b]);
    }
    vnext += (PetscInt)s.nodes.size();
  }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));

  PetscInt loc[2] = {nvloc, ntloc}, glob[2];
  PetscCall(MPIU_Allreduce(loc, glob, 2, MPIU_INT, MPI_SUM, rb->comm));
  PetscCheck(glob[0] > 0, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMRigidWriteHDF5: there are no bodies to write");

  PetscViewer viewer;
  char        file[PETSC_MAX_PATH_LEN], group[64];
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s.h5", base));
  PetscCall(PetscSNPrintf(group, sizeof(group), "/step_%06d", (int)step));
  PetscCall(PetscViewerHDF5Open(rb->comm, file, rb->outputs.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &viewer));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  PetscCall(fdem::output::WriteReal(rb->comm, viewer, "vertices", X, 3));
  PetscCall(fdem::output::WriteReal(rb->comm, viewer, "velocity", V, 3));
  PetscCall(fdem::output::WriteInt(rb->comm, viewer, "cells", cells, 3));
  PetscCall(fdem::output::WriteInt(rb->comm, viewer, "body_id", bid, 1));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "time", PETSC_REAL, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "step", PETSC_INT, &step));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));

  rb->outputs.push_back({step, t, glob[0], glob[1]});
  {
    std::vector<fdem::output::XdmfStep> steps;
    for (const auto &o : rb->outputs) steps.push_back({o.step, o.t, (long long)o.nvert, (long long)o.ntri});
    PetscCall(fdem::output::WriteXDMF(rb->comm, "FDEMRigidWriteHDF5", base, "rigid bodies", "Triangle", 3, steps, {{"velocity", "Vector", "Node", 3, true}, {"body_id", "Scalar", "Cell", 1, false}}));
  }
  PetscFunctionReturn(0);
}
