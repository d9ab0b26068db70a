// Shared by the scene tests: the mesh nodes' (x, v) gathered by global id.
#pragma once
#include <fdem/deformable.h>

#include <vector>

// On rank 0 of comm: out[6 id + 0..5] = (x, v) of node id; empty on the other ranks. Collective.
inline PetscErrorCode GatherNodes(MPI_Comm comm, FDEMDeformable d, std::vector<PetscReal> &out) {
  PetscInt           n, N;
  const PetscInt    *ids;
  Vec                x, v;
  const PetscScalar *xa, *va;
  PetscMPIInt        size, rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(FDEMDeformableGetNodeIds(d, &n, &ids));
  PetscCall(FDEMDeformableGetSizes(d, nullptr, nullptr, nullptr, &N));
  PetscCall(FDEMDeformableGetPositions(d, &x));
  PetscCall(FDEMDeformableGetVelocities(d, &v));
  PetscCall(VecGetArrayRead(x, &xa));
  PetscCall(VecGetArrayRead(v, &va));
  std::vector<PetscReal> mine(7 * n);
  for (PetscInt k = 0; k < n; ++k) {
    mine[7 * k] = (PetscReal)ids[k];
    for (int c = 0; c < 3; ++c) {
      mine[7 * k + 1 + c] = PetscRealPart(xa[3 * k + c]);
      mine[7 * k + 4 + c] = PetscRealPart(va[3 * k + c]);
    }
  }
  PetscCall(VecRestoreArrayRead(v, &va));
  PetscCall(VecRestoreArrayRead(x, &xa));
  int              ln = 7 * (int)n;
  std::vector<int> cnt(size), dis(size + 1, 0);
  PetscCallMPI(MPI_Gather(&ln, 1, MPI_INT, cnt.data(), 1, MPI_INT, 0, comm));
  for (int r = 0; r < size; ++r) dis[r + 1] = dis[r] + cnt[r];
  std::vector<PetscReal> all(rank == 0 ? dis[size] : 0);
  PetscCallMPI(MPI_Gatherv(mine.data(), ln, MPIU_REAL, all.data(), cnt.data(), dis.data(), MPIU_REAL, 0, comm));
  out.assign(rank == 0 ? 6 * N : 0, 0);
  for (size_t i = 0; i < all.size(); i += 7)
    for (int c = 0; c < 6; ++c) out[6 * (size_t)all[i] + c] = all[i + 1 + c];
  PetscFunctionReturn(0);
}
