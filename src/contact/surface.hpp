// Internal: the boundary of a distributed tetrahedral mesh, for contact (deformable
// contact and the rigid-deformable contact of FDEMScene).
#pragma once
#include <fdem/deformable.h>

#include <vector>

namespace fdem::contact {
// Faces of this rank's cells (conn: 4 local node indices per cell; ngid: the global id of
// every local node; shared: 1 for a local node that other ranks hold too) that belong to one
// cell of the whole mesh: surf[e] bit o is set when the face of cell e opposite its vertex o
// is on the boundary. A face seen once on a rank whose three nodes are shared may be shared
// with a cell of another rank: each such face is counted at a home rank chosen by hashing its
// node ids (one MPI_Alltoallv there and back), so the cost per rank is its own faces at the
// rank boundaries, never the whole surface. Collective.
PetscErrorCode BoundaryFaces(MPI_Comm comm, const std::vector<PetscInt> &conn, const std::vector<PetscInt> &ngid, const std::vector<char> &shared, std::vector<char> &surf);
// Local nodes on the mesh boundary (a node of a boundary face of any rank): flag[l] = 1.
// Boundary faces from BoundaryFaces; ranks agree through the DM (local-to-global ADD,
// global-to-local). Collective.
PetscErrorCode BoundaryNodes(FDEMDeformable d, const std::vector<PetscInt> &conn, const std::vector<char> &surf, PetscInt nlocal, std::vector<char> &flag);
} // namespace fdem::contact
