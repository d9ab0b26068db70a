// The boundary of a distributed tetrahedral mesh (see surface.hpp).
#include "surface.hpp"
#include "../model/deformable_impl.hpp"

#include <fdem/kernels/bucket_sort.hpp>

#include <algorithm>
#include <array>

PetscErrorCode fdem::contact::BoundaryFaces(MPI_Comm comm, const std::vector<PetscInt> &conn, const std::vector<PetscInt> &ngid, const std::vector<char> &shared, std::vector<char> &surf) {
  PetscMPIInt size;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  using Face = std::array<PetscInt, 3>;
  const PetscInt nc = (PetscInt)conn.size() / 4;
  // every local face (its sorted global node ids) with its cell and the node opposite it, sorted
  // so that the copies of a face are adjacent
  struct Side {
    Face     f;
    PetscInt eo; // 4 cell + o
  };
  std::vector<Side> sides(4 * (size_t)nc);
  for (PetscInt e = 0; e < nc; ++e)
    for (int o = 0; o < 4; ++o) {
      Side &sd = sides[4 * e + o];
      int   k  = 0;
      for (int a = 0; a < 4; ++a)
        if (a != o) sd.f[k++] = ngid[conn[4 * e + a]];
      std::sort(sd.f.begin(), sd.f.end());
      sd.eo = 4 * e + o;
    }
  fdem::kernels::BucketSort(sides, [](const Side &a) { return a.f[0]; }, [](const Side &a, const Side &b) { // (entry by entry: std::array's operators call memcmp)
    if (a.f[0] != b.f[0]) return a.f[0] < b.f[0];
    if (a.f[1] != b.f[1]) return a.f[1] < b.f[1];
    if (a.f[2] != b.f[2]) return a.f[2] < b.f[2];
    return a.eo < b.eo;
  });
  surf.assign(nc, 0);
  // a face held once on this rank is on the boundary unless another rank holds it too, which
  // needs its three nodes shared: each such face is counted on the rank its hash names, and
  // the count comes back
  std::vector<std::vector<Face>>                     sendf(size);
  std::vector<std::pair<PetscInt, int>>              mine; // (4 cell + o, its slot: index * size + rank)
  for (size_t i = 0; i < sides.size();) {
    size_t j = i + 1;
    while (j < sides.size() && sides[j].f == sides[i].f) ++j;
    const PetscInt eo = sides[i].eo;
    const bool     at = j - i == 1 && shared[conn[eo / 4 * 4 + (eo % 4 + 1) % 4]] && shared[conn[eo / 4 * 4 + (eo % 4 + 2) % 4]] && shared[conn[eo / 4 * 4 + (eo % 4 + 3) % 4]];
    if (j - i == 1 && !at) surf[eo / 4] |= (char)(1 << (eo % 4)); // face o (opposite node o) is on the boundary
    if (at) {
      const Face              &f = sides[i].f;
      const unsigned long long h = (unsigned long long)f[0] * 73856093ULL ^ (unsigned long long)f[1] * 19349663ULL ^ (unsigned long long)f[2] * 83492791ULL;
      const int                r = (int)(h % (unsigned long long)size);
      mine.push_back({sides[i].eo, (int)sendf[r].size() * size + r});
      sendf[r].push_back(f);
    }
    i = j;
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
  // how many ranks sent each face: the received faces sorted, each counted
  const size_t            nr = (size_t)rd[size] / 3;
  std::vector<size_t>     order(nr);
  std::vector<PetscInt>   back(nr), got(sd[size] / 3);
  for (size_t i = 0; i < nr; ++i) order[i] = i;
  auto rface = [&](size_t i) { return Face{rbuf[3 * i], rbuf[3 * i + 1], rbuf[3 * i + 2]}; };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return rface(a) < rface(b); });
  for (size_t i = 0; i < nr;) {
    size_t j = i + 1;
    while (j < nr && rface(order[j]) == rface(order[i])) ++j;
    for (size_t k = i; k < j; ++k) back[order[k]] = (PetscInt)(j - i);
    i = j;
  }
  for (int r = 0; r <= size; ++r) {
    sd[r] /= 3;
    rd[r] /= 3;
  }
  for (int r = 0; r < size; ++r) {
    sc[r] = sd[r + 1] - sd[r];
    rc[r] = rd[r + 1] - rd[r];
  }
  PetscCallMPI(MPI_Alltoallv(back.data(), rc.data(), rd.data(), MPIU_INT, got.data(), sc.data(), sd.data(), MPIU_INT, comm));
  for (const auto &m : mine) {
    const int r = m.second % size, i = m.second / size;
    if (got[sd[r] + i] == 1) surf[m.first / 4] |= (char)(1 << (m.first % 4)); // face o (opposite node o) is on the boundary
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
  PetscCall(fdem::model::DeformableLocalToGlobal(d, l, ADD_VALUES, g));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, g, l));
  PetscCall(VecGetArray(l, &a));
  flag.assign(nlocal, 0);
  for (PetscInt i = 0; i < nlocal; ++i) flag[i] = PetscRealPart(a[3 * i]) > 0;
  PetscCall(VecRestoreArray(l, &a));
  PetscCall(DMRestoreGlobalVector(dm, &g));
  PetscCall(DMRestoreLocalVector(dm, &l));
  PetscFunctionReturn(0);
}
