// Internal: the ghost (halo) exchange shared by the contact models. A rank lists,
// per other rank, which of its items that rank needs; HaloExchange tells every rank
// what it receives, and HaloSF turns that into a PetscSF moving one item per ghost (roots:
// this rank's items, leaves: its ghosts in rank order), in a unit made by HaloUnit (a record
// of consecutive numbers: PETSc packs it as one block).
#pragma once
#include <petscsf.h>

#include <vector>

namespace fdem {
// send[s]: local indices of the items rank s needs (send[rank] is ignored unless `self`: a
// rank's own items as ghosts of itself, e.g. periodic images). On return ghosts[i] = (owner
// rank, index there) of this rank's i-th ghost, grouped by owner in rank order. Collective:
// MPI_Alltoall of counts, MPI_Alltoallv of indices.
PetscErrorCode HaloExchange(MPI_Comm comm, const std::vector<std::vector<PetscInt>> &send, std::vector<PetscSFNode> &ghosts, bool self = false);
// *sf (destroyed first if set): nroot roots, ghosts.size() leaves; leaf i is root
// ghosts[i].index of rank ghosts[i].rank. Collective.
PetscErrorCode HaloSF(MPI_Comm comm, PetscInt nroot, const std::vector<PetscSFNode> &ghosts, PetscSF *sf);
// *unit: count consecutive `base`s, committed (free it with MPI_Type_free).
PetscErrorCode HaloUnit(PetscInt count, MPI_Datatype base, MPI_Datatype *unit);
} // namespace fdem
