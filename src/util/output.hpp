// Internal: HDF5 datasets through PetscViewerHDF5 and the XDMF index beside
// them, shared by the rigid-body and the deformable-mesh writers.
#pragma once
#include <petscis.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>
#include <string>
#include <vector>

namespace fdem::output {

// An (n x bs) real array / integer array as dataset `name` in the viewer's current group (collective).
PetscErrorCode WriteReal(MPI_Comm comm, PetscViewer viewer, const char *name, const std::vector<PetscReal> &a, PetscInt bs);
PetscErrorCode WriteInt(MPI_Comm comm, PetscViewer viewer, const char *name, const std::vector<PetscInt> &a, PetscInt bs);

struct XdmfStep {
  PetscInt  step;
  PetscReal t;
  long long nvert, ncell;
};
struct XdmfAttribute {
  const char *name, *type, *center; // e.g. "velocity", "Vector", "Node"
  int         comps;
  bool        real;
};
// Rewrites base.xmf on rank 0: a temporal collection with one grid per step,
// reading /step_NNNNNN/{cells,vertices,<attributes>} of base.h5 (the path
// relative to the .xmf). topology: "Triangle" or "Tetrahedron".
PetscErrorCode WriteXDMF(MPI_Comm comm, const char *caller, const char *base, const char *grid, const char *topology, int nodes_per_cell, const std::vector<XdmfStep> &steps,
                         const std::vector<XdmfAttribute> &attributes);

} // namespace fdem::output
