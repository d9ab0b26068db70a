// Internal: what other layers (src/scene) use of the deformable model, for a
// combined state assembled elsewhere. Behaviour is that of
// FDEMDeformableSetUpTS's RHS. The object itself is in deformable_object.hpp.
#pragma once
#include <fdem/deformable.h>

#include <array>
#include <vector>

namespace fdem::model {
// dv/dt of the owned nodes (3 per owned node) from owned positions xo and
// velocities vo (vo feeds the viscous term and the external-force hook; may be
// null): (f_int + f_ext)/m + g, 0 at fixed nodes. The one implementation of
// this rule; FDEMDeformableSetUpTS's RHS calls it too. Collective.
PetscErrorCode DeformableAcceleration(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *ao);
// This rank's cells as local node indices (the indexing of the hook's
// xloc/vloc/floc, 3 entries per local node), the global vertex number of
// every local node, and the number of local nodes.
PetscErrorCode DeformableGetLocalCells(FDEMDeformable d, std::vector<std::array<int, 4>> &cells, std::vector<PetscInt> &node_global, PetscInt *nlocal);
// Per owned node: 1 if fixed (FDEMDeformableFixNodes*).
PetscErrorCode DeformableGetFixed(FDEMDeformable d, const std::vector<char> **fixed);
// The TS of the last FDEMDeformableSetUpTS (NULL if none; not referenced).
PetscErrorCode DeformableGetTS(FDEMDeformable d, TS *ts);
} // namespace fdem::model
