// The ghost exchange shared by the contact models (see halo.hpp).
#include "halo.hpp"

#include <algorithm>

PetscErrorCode fdem::HaloExchange(MPI_Comm comm, const std::vector<std::vector<PetscInt>> &send, std::vector<PetscSFNode> &ghosts, bool self) {
  PetscMPIInt rank, size;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck((PetscMPIInt)send.size() == size, comm, PETSC_ERR_PLIB, "HaloExchange: %d send lists for %d ranks", (int)send.size(), (int)size);
  std::vector<int> scount(size), rcount(size), sdis(size + 1, 0), rdis(size + 1, 0);
  for (int s = 0; s < size; ++s) scount[s] = s == rank && !self ? 0 : (int)send[s].size();
  PetscCallMPI(MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm));
  for (int s = 0; s < size; ++s) {
    sdis[s + 1] = sdis[s] + scount[s];
    rdis[s + 1] = rdis[s] + rcount[s];
  }
  std::vector<PetscInt> sbuf(sdis[size]), rbuf(rdis[size]);
  for (int s = 0; s < size; ++s)
    if (s != rank || self) std::copy(send[s].begin(), send[s].end(), sbuf.begin() + sdis[s]);
  PetscCallMPI(MPI_Alltoallv(sbuf.data(), scount.data(), sdis.data(), MPIU_INT, rbuf.data(), rcount.data(), rdis.data(), MPIU_INT, comm));
  ghosts.resize(rdis[size]);
  for (int s = 0; s < size; ++s)
    for (int i = rdis[s]; i < rdis[s + 1]; ++i) ghosts[i] = {s, rbuf[i]};
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::HaloSF(MPI_Comm comm, PetscInt nroot, const std::vector<PetscSFNode> &ghosts, PetscSF *sf) {
  PetscFunctionBegin;
  PetscCall(PetscSFDestroy(sf));
  PetscCall(PetscSFCreate(comm, sf));
  PetscCall(PetscSFSetGraph(*sf, nroot, (PetscInt)ghosts.size(), nullptr, PETSC_COPY_VALUES, const_cast<PetscSFNode *>(ghosts.data()), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(*sf));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::HaloUnit(PetscInt count, MPI_Datatype base, MPI_Datatype *unit) {
  PetscFunctionBegin;
  PetscCallMPI(MPI_Type_contiguous((PetscMPIInt)count, base, unit));
  PetscCallMPI(MPI_Type_commit(unit));
  PetscFunctionReturn(0);
}
