// Internal: the ghost (halo) exchange shared by the contact models. A rank lists,
// per other rank, which of its items that rank needs; HaloExchange tells every rank
// what it receives, and HaloSF turns that into a PetscSF moving `unit` consecutive
// numbers per item (roots: this rank's items, leaves: its ghosts in rank order).
#pragma once
#include <petscsf.h>

#include <vector>

namespace fdem {
// send[s]: local indices of the items rank s needs (send[rank] is ignored unless `self`: a
// rank's own items as ghosts of itself, e.g. periodic images). On return ghosts[i] = (owner
// rank, index there) of this rank's i-th ghost, grouped by owner in rank order. Collective:
// MPI_Alltoall of counts, MPI_Alltoallv of indices.
PetscErrorCode HaloExchange(MPI_Comm comm, const std::vector<std::vector<PetscInt>> &send, std::vector<PetscSFNode> &ghosts, bool self = false);
// *sf (destroyed first if set): nroot * unit roots, ghosts.size() * unit leaves; leaf
// unit * i + k is root unit * ghosts[i].index + k of rank ghosts[i].rank. Collective.
PetscErrorCode HaloSF(MPI_Comm comm, PetscInt nroot, const std::vector<PetscSFNode> &ghosts, PetscInt unit, PetscSF *sf);
} // namespace fdem
