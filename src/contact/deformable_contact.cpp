// Contact between deformable bodies: surface tetrahedra of all ranks gathered
// (MPI_Allgatherv), cell search over bounding spheres with a buffer,
// Munjiza's potential contact force both ways, damping and friction with
// nodal velocities; nodal forces into the FE force vector (the external-force
// hook of FDEMDeformable). See include/fdem/deformable_contact.h and
// doc/contact_deformable.md.
#include "../util/guard.hpp"
#include <fdem/deformable_contact.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/nbs.hpp>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

namespace {
PetscClassId  FDEM_DCONTACT_CLASSID = 0;
PetscLogEvent EV_SURFACE = 0, EV_GATHER = 0, EV_DETECT = 0, EV_FORCE = 0;
constexpr int NI = 6; // static data per gathered tetrahedron: gid, body, node gids (4)
} // namespace

struct _n_FDEMDeformableContact {
  FDEMDeformable                    d;
  MPI_Comm                          comm;
  PetscMPIInt                       rank = 0, size = 1;
  PetscReal                         penalty = -1, buffer = -1;
  fdem::kernels::ContactDissipation diss;
  PetscBool                         self = PETSC_FALSE;
  PetscInt                          nbodies  = 0;
  // this rank's surface tetrahedra: local node indices, positions at the last search
  std::vector<std::array<PetscInt, 4>> lconn;
  std::vector<PetscReal>               ref_x;
  // all surface tetrahedra (gathered, rank-major): static data, owner and index there
  PetscInt               ntot = 0;
  std::vector<int>       count, displ;    // per rank, in tetrahedra
  std::vector<PetscInt>  gstat;           // NI per tetrahedron
  std::vector<int>       grank, gindex;
  std::vector<PetscReal> gx, gv;          // 12 per tetrahedron
  std::vector<int>       cnt12, dis12;
  // candidate pairs (gathered indices; the first is this rank's and has the smaller gid)
  std::vector<std::array<int, 2>> pairs;
  std::vector<int>                leaf_of; // gathered index -> leaf slot, -1 if none
  PetscSF                         sf = nullptr;
  std::vector<PetscReal>          leaf_f, root_f;
  bool                            searched = false, checked_initial = false;
  std::vector<PetscReal>          body_force; // 3 per body, last evaluation (all ranks)
  FDEMDeformableContactStats      stats{};
};

namespace {

Tet4 GatheredTet(FDEMDeformableContact c, int i) {
  const PetscReal *p = &c->gx[12 * (size_t)i];
  return {Vec3(p[0], p[1], p[2]), Vec3(p[3], p[4], p[5]), Vec3(p[6], p[7], p[8]), Vec3(p[9], p[10], p[11])};
}

// Surface tetrahedra: local cells with a face that belongs to one cell in the
// whole mesh. Faces seen once on this rank may be shared with a cell of
// another rank: they are counted at a home rank chosen by hashing.
PetscErrorCode FindSurface(FDEMDeformableContact c, const std::vector<PetscInt> &conn, const std::vector<PetscInt> &ngid, std::vector<char> &surf) {
  using Face = std::array<PetscInt, 3>;
  const PetscInt nc = (PetscInt)conn.size() / 4;
  PetscFunctionBegin;
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
  std::vector<std::vector<int>>  send(c->size);
  std::vector<std::vector<Face>> sendf(c->size);
  std::map<Face, int>            slot;
  for (const auto &kv : local)
    if (kv.second == 1) {
      const unsigned long long h = (unsigned long long)kv.first[0] * 73856093ULL ^ (unsigned long long)kv.first[1] * 19349663ULL ^ (unsigned long long)kv.first[2] * 83492791ULL;
      const int                r = (int)(h % (unsigned long long)c->size);
      slot[kv.first]           = (int)sendf[r].size() * c->size + r;
      sendf[r].push_back(kv.first);
    }
  std::vector<int> sc(c->size), rc(c->size), sd(c->size + 1, 0), rd(c->size + 1, 0);
  for (int r = 0; r < c->size; ++r) sc[r] = 3 * (int)sendf[r].size();
  PetscCallMPI(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, c->comm));
  for (int r = 0; r < c->size; ++r) {
    sd[r + 1] = sd[r] + sc[r];
    rd[r + 1] = rd[r] + rc[r];
  }
  std::vector<PetscInt> sbuf(sd[c->size]), rbuf(rd[c->size]);
  for (int r = 0; r < c->size; ++r)
    for (size_t i = 0; i < sendf[r].size(); ++i)
      for (int k = 0; k < 3; ++k) sbuf[sd[r] + 3 * i + k] = sendf[r][i][k];
  PetscCallMPI(MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPIU_INT, rbuf.data(), rc.data(), rd.data(), MPIU_INT, c->comm));
  std::map<Face, int> home;
  for (int i = 0; i < rd[c->size]; i += 3) home[{rbuf[i], rbuf[i + 1], rbuf[i + 2]}]++;
  std::vector<PetscInt> back(rd[c->size] / 3), got(sd[c->size] / 3);
  for (int i = 0; i < rd[c->size]; i += 3) back[i / 3] = home[{rbuf[i], rbuf[i + 1], rbuf[i + 2]}];
  for (int r = 0; r <= c->size; ++r) {
    sd[r] /= 3;
    rd[r] /= 3;
  }
  for (int r = 0; r < c->size; ++r) {
    sc[r] = sd[r + 1] - sd[r];
    rc[r] = rd[r + 1] - rd[r];
  }
  PetscCallMPI(MPI_Alltoallv(back.data(), rc.data(), rd.data(), MPIU_INT, got.data(), sc.data(), sd.data(), MPIU_INT, c->comm));
  surf.assign(nc, 0);
  for (PetscInt e = 0; e < nc; ++e)
    for (int o = 0; o < 4; ++o) {
      auto it = slot.find(face(e, o));
      if (it == slot.end()) continue;
      const int r = it->second % c->size, i = it->second / c->size;
      if (got[sd[r] + i] == 1) surf[e] = 1;
    }
  PetscFunctionReturn(0);
}

// Gather positions (and velocities) of every surface tetrahedron from the hook's local vectors.
PetscErrorCode Gather(FDEMDeformableContact c, const PetscScalar *xl, const PetscScalar *vl) {
  const size_t           nl = c->lconn.size();
  std::vector<PetscReal> mine(12 * nl);
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_GATHER, 0, 0, 0, 0));
  for (size_t t = 0; t < nl; ++t)
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 3; ++k) mine[12 * t + 3 * a + k] = PetscRealPart(xl[3 * c->lconn[t][a] + k]);
  c->gx.resize(12 * (size_t)c->ntot);
  PetscCallMPI(MPI_Allgatherv(mine.data(), (int)(12 * nl), MPIU_REAL, c->gx.data(), c->cnt12.data(), c->dis12.data(), MPIU_REAL, c->comm));
  if (vl) {
    for (size_t t = 0; t < nl; ++t)
      for (int a = 0; a < 4; ++a)
        for (int k = 0; k < 3; ++k) mine[12 * t + 3 * a + k] = PetscRealPart(vl[3 * c->lconn[t][a] + k]);
    c->gv.resize(12 * (size_t)c->ntot);
    PetscCallMPI(MPI_Allgatherv(mine.data(), (int)(12 * nl), MPIU_REAL, c->gv.data(), c->cnt12.data(), c->dis12.data(), MPIU_REAL, c->comm));
  }
  PetscCall(PetscLogEventEnd(EV_GATHER, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Candidate pairs from a cell search over the gathered tetrahedra, and the SF returning forces on other ranks' tetrahedra.
PetscErrorCode Search(FDEMDeformableContact c) {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_DETECT, 0, 0, 0, 0));
  const int         N = (int)c->ntot, mine0 = c->displ[c->rank], nl = (int)c->lconn.size();
  std::vector<double> centres(3 * (size_t)N), radii(N);
  double              dmax = 0, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < N; ++i) {
    const Tet4 T  = GatheredTet(c, i);
    const Vec3 ct = 0.25 * (T[0] + T[1] + T[2] + T[3]);
    double     r  = 0;
    for (int k = 0; k < 4; ++k) r = std::max(r, norm(T[k] - ct));
    r += 0.5 * c->buffer;
    for (int k = 0; k < 3; ++k) centres[3 * i + k] = ct[k];
    radii[i] = r;
    dmax     = std::max(dmax, 2 * r);
    if (i >= mine0 && i < mine0 + nl)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], ct[k] - r);
        hi[k] = std::max(hi[k], ct[k] + r);
      }
  }
  // only tetrahedra whose box meets the box of this rank's own ones can pair with them
  std::vector<int>    sel;
  std::vector<double> sc, sr;
  for (int i = 0; i < N && nl > 0; ++i) {
    bool in = true;
    for (int k = 0; k < 3; ++k) in = in && centres[3 * i + k] + radii[i] >= lo[k] && centres[3 * i + k] - radii[i] <= hi[k];
    if (!in) continue;
    sel.push_back(i);
    sc.insert(sc.end(), {centres[3 * i], centres[3 * i + 1], centres[3 * i + 2]});
    sr.push_back(radii[i]);
  }
  c->pairs.clear();
  if (!sel.empty()) {
    PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
      fdem::kernels::CellSearch        cs;
      std::vector<std::pair<int, int>> tp;
      cs.Build(sc.data(), sr.data(), (int)sr.size(), dmax * (1 + 1e-12));
      cs.FindPairs(tp);
      for (const auto &pr : tp) {
        int        a = sel[pr.first], b = sel[pr.second];
        const auto *A = &c->gstat[NI * (size_t)a], *B = &c->gstat[NI * (size_t)b];
        if (A[1] == B[1]) { // same body: only with self-contact, and never neighbours
          if (!c->self) continue;
          bool share = false;
          for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) share = share || A[2 + i] == B[2 + j];
          if (share) continue;
        }
        if (B[0] < A[0]) std::swap(a, b); // a: the smaller global element id, computed by its rank
        if (c->grank[a] != c->rank) continue;
        c->pairs.push_back({a, b});
      }
      return 0;
    }));
  }
  // SF: leaves = other ranks' tetrahedra in my pairs (12 force components), roots = my surface tetrahedra
  c->leaf_of.assign(N, -1);
  std::vector<PetscSFNode> remote;
  for (const auto &p : c->pairs) {
    const int b = p[1];
    if (c->grank[b] == c->rank || c->leaf_of[b] >= 0) continue;
    c->leaf_of[b] = (int)(remote.size() / 12);
    for (int k = 0; k < 12; ++k) remote.push_back({c->grank[b], 12 * (PetscInt)c->gindex[b] + k});
  }
  PetscCall(PetscSFDestroy(&c->sf));
  PetscCall(PetscSFCreate(c->comm, &c->sf));
  PetscCall(PetscSFSetGraph(c->sf, 12 * (PetscInt)nl, (PetscInt)remote.size(), nullptr, PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(c->sf));
  c->leaf_f.assign(remote.size(), 0);
  c->root_f.assign(12 * (size_t)nl, 0);
  c->ref_x.assign(c->gx.begin() + 12 * (size_t)mine0, c->gx.begin() + 12 * (size_t)(mine0 + nl));
  c->searched = true;
  c->stats.searches++;
  PetscInt np = (PetscInt)c->pairs.size();
  PetscCallMPI(MPI_Allreduce(&np, &c->stats.candidate_pairs, 1, MPIU_INT, MPI_SUM, c->comm));
  PetscCall(PetscLogEventEnd(EV_DETECT, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// The external-force hook of FDEMDeformable.
PetscErrorCode ContactForce(FDEMDeformable, PetscReal, Vec xloc, Vec vloc, Vec floc, void *ctx) {
  FDEMDeformableContact c = (FDEMDeformableContact)ctx;
  const PetscScalar    *xl, *vl = nullptr;
  PetscScalar          *fl;
  PetscFunctionBegin;
  PetscCheck(c->penalty > 0, c->comm, PETSC_ERR_ARG_WRONGSTATE, "Deformable contact: the penalty is not set; give -fdem_dcontact_penalty <Pa> (a positive modulus) or call FDEMDeformableContactSetPenalty()");
  const bool dissipative = c->diss.normal_damping > 0 || c->diss.friction > 0 || c->diss.tangential_viscosity > 0;
  PetscCheck(!dissipative || vloc, c->comm, PETSC_ERR_ARG_WRONGSTATE, "Deformable contact: damping or friction needs the nodal velocities, which this force evaluation did not provide");
  PetscCall(VecGetArrayRead(xloc, &xl));
  if (dissipative) PetscCall(VecGetArrayRead(vloc, &vl));
  PetscCall(Gather(c, xl, vl));
  if (dissipative) PetscCall(VecRestoreArrayRead(vloc, &vl));
  PetscCall(VecRestoreArrayRead(xloc, &xl));
  // re-search when some surface node moved more than half the buffer since the last search
  const int nl = (int)c->lconn.size(), mine0 = c->displ[c->rank];
  PetscReal move = c->searched ? 0 : PETSC_MAX_REAL, gmove;
  if (c->searched)
    for (int i = 0; i < 4 * nl; ++i) {
      const PetscReal *p = &c->gx[12 * (size_t)mine0 + 3 * i], *q = &c->ref_x[3 * i];
      move               = std::max(move, PetscSqrtReal(PetscSqr(p[0] - q[0]) + PetscSqr(p[1] - q[1]) + PetscSqr(p[2] - q[2])));
    }
  PetscCallMPI(MPI_Allreduce(&move, &gmove, 1, MPIU_REAL, MPI_MAX, c->comm));
  if (gmove > 0.5 * c->buffer) PetscCall(Search(c));

  PetscCall(PetscLogEventBegin(EV_FORCE, 0, 0, 0, 0));
  std::fill(c->leaf_f.begin(), c->leaf_f.end(), 0);
  std::fill(c->root_f.begin(), c->root_f.end(), 0);
  std::vector<PetscReal> bf(3 * (size_t)c->nbodies + 2, 0); // body forces, energy, active pairs
  std::array<double, 3>  deep{0, -1, -1};                    // worst initial overlap ratio, gathered tetrahedra
  PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc;
    std::array<Vec3, 4>           fa, fb, va, vb, da, db;
    for (const auto &p : c->pairs) {
      const Tet4 a = GatheredTet(c, p[0]), b = GatheredTet(c, p[1]);
      if (!fdem::kernels::PotentialContactForce(a, b, c->penalty, c->penalty, pc)) continue;
      bf[3 * c->nbodies] += pc.energy;
      bf[3 * c->nbodies + 1] += 1;
      if (!c->checked_initial) {
        // deep: overlap energy above that of 10% of the smaller tetrahedron at mid potential
        const double va6 = std::fabs(dot(a[1] - a[0], cross(a[2] - a[0], a[3] - a[0]))), vb6 = std::fabs(dot(b[1] - b[0], cross(b[2] - b[0], b[3] - b[0])));
        const double ratio = pc.energy / (0.1 * std::min(va6, vb6) / 6 * c->penalty / 8);
        if (ratio > deep[0]) deep = {ratio, (double)p[0], (double)p[1]};
      }
      fa = pc.fa;
      fb = pc.fb;
      if (dissipative) {
        for (int k = 0; k < 4; ++k) {
          va[k] = Vec3(c->gv[12 * (size_t)p[0] + 3 * k], c->gv[12 * (size_t)p[0] + 3 * k + 1], c->gv[12 * (size_t)p[0] + 3 * k + 2]);
          vb[k] = Vec3(c->gv[12 * (size_t)p[1] + 3 * k], c->gv[12 * (size_t)p[1] + 3 * k + 1], c->gv[12 * (size_t)p[1] + 3 * k + 2]);
        }
        fdem::kernels::ContactDampingFriction(a, b, va, vb, pc, c->diss, da, db);
        for (int k = 0; k < 4; ++k) {
          fa[k] += da[k];
          fb[k] += db[k];
        }
      }
      const PetscInt ba = c->gstat[NI * (size_t)p[0] + 1], bb = c->gstat[NI * (size_t)p[1] + 1];
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) {
          bf[3 * ba + j] += fa[k][j];
          bf[3 * bb + j] += fb[k][j];
        }
      PetscReal *oa = &c->root_f[12 * (size_t)c->gindex[p[0]]];
      PetscReal *ob = c->grank[p[1]] == c->rank ? &c->root_f[12 * (size_t)c->gindex[p[1]]] : &c->leaf_f[12 * (size_t)c->leaf_of[p[1]]];
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) {
          oa[3 * k + j] += fa[k][j];
          ob[3 * k + j] += fb[k][j];
        }
    }
    return 0;
  }));
  if (!c->checked_initial) { // collective: every rank stops with the same message
    double worst;
    PetscCallMPI(MPI_Allreduce(&deep[0], &worst, 1, MPI_DOUBLE, MPI_MAX, c->comm));
    if (worst > 1) {
      PetscInt mine[4] = {-1, -1, -1, -1}, ids[4];
      if (deep[0] == worst) {
        const PetscInt *A = &c->gstat[NI * (size_t)deep[1]], *B = &c->gstat[NI * (size_t)deep[2]];
        mine[0] = A[1];
        mine[1] = B[1];
        mine[2] = A[0];
        mine[3] = B[0];
      }
      PetscCallMPI(MPI_Allreduce(mine, ids, 4, MPIU_INT, MPI_MAX, c->comm));
      const char *na, *nb;
      PetscCall(FDEMDeformableGetBodyName(c->d, ids[0], nullptr, &na));
      PetscCall(FDEMDeformableGetBodyName(c->d, ids[1], nullptr, &nb));
      SETERRQ(c->comm, PETSC_ERR_USER_INPUT,
              "Deformable contact: bodies '%s' and '%s' start interpenetrating deeply (their elements %" PetscInt_FMT " and %" PetscInt_FMT " overlap %.1f times more than allowed); separate them", na, nb, ids[2], ids[3], worst);
    }
    c->checked_initial = true;
  }
  // forces on other ranks' tetrahedra go back to their owners and are summed there
  PetscCall(PetscSFReduceBegin(c->sf, MPIU_REAL, c->leaf_f.data(), c->root_f.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(c->sf, MPIU_REAL, c->leaf_f.data(), c->root_f.data(), MPI_SUM));
  PetscCall(VecGetArray(floc, &fl));
  for (int t = 0; t < nl; ++t)
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j) fl[3 * c->lconn[t][k] + j] += c->root_f[12 * (size_t)t + 3 * k + j];
  PetscCall(VecRestoreArray(floc, &fl));
  c->body_force.resize(bf.size());
  PetscCallMPI(MPI_Allreduce(bf.data(), c->body_force.data(), (int)bf.size(), MPIU_REAL, MPI_SUM, c->comm));
  c->stats.energy       = c->body_force[3 * c->nbodies];
  c->stats.active_pairs = (PetscInt)c->body_force[3 * c->nbodies + 1];
  c->stats.evaluations++;
  PetscCall(PetscLogEventEnd(EV_FORCE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FDEMDeformableContactCreate(FDEMDeformable dfm, FDEMDeformableContact *out) {
  PetscInt              nc, nlocal;
  std::vector<PetscInt> conn, body, gid, ngid;
  std::vector<char>     surf;
  PetscFunctionBegin;
  if (!FDEM_DCONTACT_CLASSID) {
    PetscCall(PetscClassIdRegister("FDEM Deformable Contact", &FDEM_DCONTACT_CLASSID));
    PetscCall(PetscLogEventRegister("FDEMDContSurface", FDEM_DCONTACT_CLASSID, &EV_SURFACE));
    PetscCall(PetscLogEventRegister("FDEMDContGather", FDEM_DCONTACT_CLASSID, &EV_GATHER));
    PetscCall(PetscLogEventRegister("FDEMDContDetect", FDEM_DCONTACT_CLASSID, &EV_DETECT));
    PetscCall(PetscLogEventRegister("FDEMDContForce", FDEM_DCONTACT_CLASSID, &EV_FORCE));
  }
  PetscCall(FDEMDeformableGetLocalCells(dfm, &nc, &nlocal, nullptr, nullptr, nullptr, nullptr)); // also checks set-up
  DM dm;
  PetscCall(FDEMDeformableGetDM(dfm, &dm));
  FDEMDeformableContact c = new (std::nothrow) _n_FDEMDeformableContact();
  PetscCheck(c, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  c->d = dfm;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &c->comm));
  PetscCallMPI(MPI_Comm_rank(c->comm, &c->rank));
  PetscCallMPI(MPI_Comm_size(c->comm, &c->size));
  PetscCall(FDEMDeformableGetBodyName(dfm, 0, &c->nbodies, nullptr));
  PetscCall(PetscLogEventBegin(EV_SURFACE, 0, 0, 0, 0));
  conn.resize(4 * (size_t)nc);
  body.resize(nc);
  gid.resize(nc);
  ngid.resize(nlocal);
  PetscCall(FDEMDeformableGetLocalCells(dfm, &nc, &nlocal, conn.data(), body.data(), gid.data(), ngid.data()));
  PetscCall(FindSurface(c, conn, ngid, surf));
  std::vector<PetscInt> mine;
  for (PetscInt e = 0; e < nc; ++e) {
    if (!surf[e]) continue;
    c->lconn.push_back({conn[4 * e], conn[4 * e + 1], conn[4 * e + 2], conn[4 * e + 3]});
    mine.insert(mine.end(), {gid[e], body[e], ngid[conn[4 * e]], ngid[conn[4 * e + 1]], ngid[conn[4 * e + 2]], ngid[conn[4 * e + 3]]});
  }
  const int nl = (int)c->lconn.size();
  c->count.resize(c->size);
  c->displ.assign(c->size + 1, 0);
  PetscCallMPI(MPI_Allgather(&nl, 1, MPI_INT, c->count.data(), 1, MPI_INT, c->comm));
  for (int r = 0; r < c->size; ++r) c->displ[r + 1] = c->displ[r] + c->count[r];
  c->ntot = c->displ[c->size];
  std::vector<int> cn(c->size), dn(c->size);
  c->cnt12.resize(c->size);
  c->dis12.resize(c->size);
  for (int r = 0; r < c->size; ++r) {
    cn[r]       = NI * c->count[r];
    dn[r]       = NI * c->displ[r];
    c->cnt12[r] = 12 * c->count[r];
    c->dis12[r] = 12 * c->displ[r];
  }
  c->gstat.resize(NI * (size_t)c->ntot);
  PetscCallMPI(MPI_Allgatherv(mine.data(), NI * nl, MPIU_INT, c->gstat.data(), cn.data(), dn.data(), MPIU_INT, c->comm));
  c->grank.resize(c->ntot);
  c->gindex.resize(c->ntot);
  for (int r = 0; r < c->size; ++r)
    for (int i = c->displ[r]; i < c->displ[r + 1]; ++i) {
      c->grank[i]  = r;
      c->gindex[i] = i - c->displ[r];
    }
  c->stats.surface_tets = c->ntot;
  // default buffer: a quarter of the mean diameter of the surface tetrahedra (reference configuration)
  {
    Vec                X, Xl;
    const PetscScalar *xa;
    PetscReal          s = 0, g;
    PetscCall(FDEMDeformableGetReferencePositions(dfm, &X));
    PetscCall(DMGetLocalVector(dm, &Xl));
    PetscCall(DMGlobalToLocal(dm, X, INSERT_VALUES, Xl));
    PetscCall(VecGetArrayRead(Xl, &xa));
    for (const auto &T : c->lconn) {
      PetscReal diam = 0;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
          PetscReal dd = 0;
          for (int k = 0; k < 3; ++k) dd += PetscSqr(PetscRealPart(xa[3 * T[a] + k] - xa[3 * T[b] + k]));
          diam = std::max(diam, PetscSqrtReal(dd));
        }
      s += diam;
    }
    PetscCall(VecRestoreArrayRead(Xl, &xa));
    PetscCall(DMRestoreLocalVector(dm, &Xl));
    PetscCallMPI(MPI_Allreduce(&s, &g, 1, MPIU_REAL, MPI_SUM, c->comm));
    c->buffer = c->ntot > 0 ? 0.25 * g / (PetscReal)c->ntot : 0;
  }
  PetscCall(PetscLogEventEnd(EV_SURFACE, 0, 0, 0, 0));
  c->body_force.assign(3 * (size_t)c->nbodies + 2, 0);
  PetscCall(FDEMDeformableSetExternalForce(dfm, ContactForce, c));
  *out = c;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactDestroy(FDEMDeformableContact *c) {
  PetscFunctionBegin;
  if (!*c) PetscFunctionReturn(0);
  PetscCall(PetscSFDestroy(&(*c)->sf));
  PetscCall(FDEMDeformableSetExternalForce((*c)->d, nullptr, nullptr));
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetPenalty(FDEMDeformableContact c, PetscReal penalty) {
  PetscFunctionBegin;
  PetscCheck(std::isfinite(penalty) && penalty > 0, c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the penalty must be positive and finite, got %g", (double)penalty);
  c->penalty = penalty;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetDissipation(FDEMDeformableContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity) {
  PetscFunctionBegin;
  PetscCheck(damping >= 0 && std::isfinite(damping), c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the damping must be >= 0, got %g", (double)damping);
  PetscCheck(friction >= 0 && std::isfinite(friction), c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the friction coefficient must be >= 0, got %g", (double)friction);
  PetscCheck(tangential_viscosity >= 0 && std::isfinite(tangential_viscosity), c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the tangential viscosity must be >= 0, got %g", (double)tangential_viscosity);
  c->diss.normal_damping       = damping;
  c->diss.friction             = friction;
  c->diss.tangential_viscosity = tangential_viscosity;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetBuffer(FDEMDeformableContact c, PetscReal buffer) {
  PetscFunctionBegin;
  PetscCheck(buffer >= 0 && std::isfinite(buffer), c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the search buffer must be >= 0, got %g", (double)buffer);
  c->buffer   = buffer;
  c->searched = false;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetSelfContact(FDEMDeformableContact c, PetscBool self) {
  PetscFunctionBegin;
  c->self     = self;
  c->searched = false;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetFromOptions(FDEMDeformableContact c) {
  PetscReal pen = c->penalty, damp = c->diss.normal_damping, mu = c->diss.friction, ct = c->diss.tangential_viscosity, buf = c->buffer;
  PetscBool fp, fb, self = c->self;
  PetscFunctionBegin;
  PetscOptionsBegin(c->comm, nullptr, "fdem deformable contact", "FDEMDeformableContact");
  PetscCall(PetscOptionsReal("-fdem_dcontact_penalty", "Penalty (Pa): a face pushed a depth d into a tetrahedron of height H feels ~ penalty d/H", "FDEMDeformableContactSetPenalty", pen, &pen, &fp));
  PetscCall(PetscOptionsReal("-fdem_dcontact_damping", "Normal contact damping (Pa s/m)", "FDEMDeformableContactSetDissipation", damp, &damp, nullptr));
  PetscCall(PetscOptionsReal("-fdem_dcontact_friction", "Coulomb friction coefficient", "FDEMDeformableContactSetDissipation", mu, &mu, nullptr));
  PetscCall(PetscOptionsReal("-fdem_dcontact_tangential_viscosity", "Tangential viscosity regularising stick (Pa s/m)", "FDEMDeformableContactSetDissipation", ct, &ct, nullptr));
  PetscCall(PetscOptionsReal("-fdem_dcontact_buffer", "Search buffer (length); re-search after a move of half of it", "FDEMDeformableContactSetBuffer", buf, &buf, &fb));
  PetscCall(PetscOptionsBool("-fdem_dcontact_self", "Self-contact between non-adjacent surface tetrahedra of one body", "FDEMDeformableContactSetSelfContact", self, &self, nullptr));
  PetscOptionsEnd();
  if (fp) PetscCall(FDEMDeformableContactSetPenalty(c, pen));
  PetscCall(FDEMDeformableContactSetDissipation(c, damp, mu, ct));
  if (fb) PetscCall(FDEMDeformableContactSetBuffer(c, buf));
  PetscCall(FDEMDeformableContactSetSelfContact(c, self));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactGetStats(FDEMDeformableContact c, FDEMDeformableContactStats *s) {
  PetscFunctionBegin;
  *s = c->stats;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactGetBodyForce(FDEMDeformableContact c, PetscInt body, PetscReal F[3]) {
  PetscFunctionBegin;
  PetscCheck(body >= 0 && body < c->nbodies, c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: no body %" PetscInt_FMT " (the mesh has %" PetscInt_FMT ")", body, c->nbodies);
  for (int k = 0; k < 3; ++k) F[k] = c->body_force[3 * body + k];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactComputeEnergy(FDEMDeformableContact c, Vec U, PetscReal *energy) {
  DM  dm;
  Vec F;
  PetscFunctionBegin;
  PetscCall(FDEMDeformableGetDM(c->d, &dm));
  PetscCall(DMGetGlobalVector(dm, &F));
  PetscCall(FDEMDeformableComputeForces(c->d, 0, U, F));
  PetscCall(DMRestoreGlobalVector(dm, &F));
  *energy = c->stats.energy;
  PetscFunctionReturn(0);
}
