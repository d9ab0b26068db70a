// The boundary of a distributed tetrahedral mesh (see surface.hpp).
#include "surface.hpp"

#include <algorithm>
#include <array>
#include <map>

PetscErrorCode fdem::contact::BoundaryFaces(MPI_Comm comm, const std::vector<PetscInt> &conn, const std::vector<PetscInt> &ngid, std::vector<char> &surf) {
  PetscMPIInt size;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  using Face = std::array<PetscInt, 3>;
  const PetscInt nc = (PetscInt)conn.size() / 4;
  std::map<Face, int> local;
  auto                face = [&](PetscInt e, int o) {
    Face f;
    int  k = 0;
    for (int a = 0; a < 4; ++a)
      if (a != o) f[k++] = ngid[conn[4 * e + a]];
    std::sort(f.begin(), f.end());
    return f;
  };
  for (PetscInt e = 0; e < nc; ++e)
    for (int o = 0; o < 4; ++o) local[face(e, o)]++;
  std::vector<Face>              once;
  std::vector<std::vector<int>>  send(size);
  std::vector<std::vector<Face>> sendf(size);
  std::map<Face, int>            slot;
  for (const auto &kv : local)
    if (kv.second == 1) {
      const unsigned long long h = (unsigned long long)kv.first[0] * 73856093ULL ^ (unsigned long long)kv.first[1] * 19349663ULL ^ (unsigned long long)kv.first[2] * 83492791ULL;
      const int                r = (int)(h % (unsigned long long)size);
      slot[kv.first]           = (int)sendf[r].size() * size + r;
      sendf[r].push_back(kv.first);
    }
  std::vector<int> sc(size), rc(size), sd(size + 1, 0), rd(size + 1, 0);
  for (int r = 0; r < size; ++r) sc[r] = 3 * (int)sendf[r].size();
  PetscCallMPI(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r) {
    sd[r + 1] = sd[r] + sc[r];
    rd[r + 1] = rd[r] + rc[r];
  }
  std::vector<PetscInt> sbuf(sd[size]), rbuf(rd[size]);
  for (int r = 0; r < size; ++r)
    for (size_t i = 0; i < sendf[r].size(); ++i)
      for (int k = 0; k < 3; ++k) sbuf[sd[r] + 3 * i + k] = sendf[r][i][k];
  PetscCallMPI(MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPIU_INT, rbuf.data(), rc.data(), rd.data(), MPIU_INT, comm));
  std::map<Face, int> home;
  for (int i = 0; i < rd[size]; i += 3) home[{rbuf[i], rbuf[i + 1], rbuf[i + 2]}]++;
  std::vector<PetscInt> back(rd[size] / 3), got(sd[size] / 3);
  for (int i = 0; i < rd[size]; i += 3) back[i / 3] = home[{rbuf[i], rbuf[i + 1], rbuf[i + 2]}];
  for (int r = 0; r <= size; ++r) {
    sd[r] /= 3;
    rd[r] /= 3;
  }
  for (int r = 0; r < size; ++r) {
    sc[r] = sd[r + 1] - sd[r];
    rc[r] = rd[r + 1] - rd[r];
  }
  PetscCallMPI(MPI_Alltoallv(back.data(), rc.data(), rd.data(), MPIU_INT, got.data(), sc.data(), sd.data(), MPIU_INT, comm));
  surf.assign(nc, 0);
  for (PetscInt e = 0; e < nc; ++e)
    for (int o = 0; o < 4; ++o) {
      auto it = slot.find(face(e, o));
      if (it == slot.end()) continue;
      const int r = it->second % size, i = it->second / size;
      if (got[sd[r] + i] == 1) surf[e] |= (char)(1 << o); // face o (opposite node o) is on the boundary
    }
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::contact::BoundaryNodes(FDEMDeformable d, const std::vector<PetscInt> &conn, const std::vector<char> &surf, PetscInt nlocal, std::vector<char> &flag) {
  DM           dm;
  Vec          l, g;
  PetscScalar *a;
  PetscFunctionBegin;
  PetscCall(FDEMDeformableGetDM(d, &dm));
  PetscCall(DMGetLocalVector(dm, &l));
  PetscCall(DMGetGlobalVector(dm, &g));
  PetscCall(VecSet(l, 0));
  PetscCall(VecGetArray(l, &a));
  for (size_t e = 0; e < surf.size(); ++e)
    for (int o = 0; o < 4; ++o)
      if (surf[e] & (1 << o))
        for (int q = 0; q < 4; ++q)
          if (q != o) a[3 * conn[4 * e + q]] = 1;
  PetscCall(VecRestoreArray(l, &a));
  PetscCall(VecSet(g, 0));
  PetscCall(DMLocalToGlobal(dm, l, ADD_VALUES, g));
  PetscCall(DMGlobalToLocal(dm, g, INSERT_VALUES, l));
  PetscCall(VecGetArray(l, &a));
  flag.assign(nlocal, 0);
  for (PetscInt i = 0; i < nlocal; ++i) flag[i] = PetscRealPart(a[3 * i]) > 0;
  PetscCall(VecRestoreArray(l, &a));
  PetscCall(DMRestoreGlobalVector(dm, &g));
  PetscCall(DMRestoreLocalVector(dm, &l));
  PetscFunctionReturn(0);
}
