// Contact between deformable bodies: a halo of ghost surface tetrahedra within
// the search distance (PetscSF), cell search over bounding spheres with a buffer,
// Munjiza's potential contact force both ways, damping and friction with
// nodal velocities; nodal forces into the FE force vector (the external-force
// hook of FDEMDeformable). See include/fdem/deformable_contact.h and
// doc/contact_deformable.md.
#include "../model/deformable_impl.hpp"
#include "../util/guard.hpp"
#include "../util/halo.hpp"
#include "params.hpp"
#include "surface.hpp"
#include <fdem/deformable_contact.h>
#include <fdem/ts.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/nbs.hpp>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

namespace {
PetscClassId  FDEM_DCONTACT_CLASSID = 0;
PetscLogEvent EV_SURFACE = 0, EV_GATHER = 0, EV_DETECT = 0, EV_FORCE = 0;
constexpr int NI = 6; // static data per gathered tetrahedron: gid, body, node gids (4)
constexpr int NBOX_DEPTH = 3, NBOX = 1 << NBOX_DEPTH, BW = 7; // boxes describing a rank's region, numbers per box
} // namespace

struct _n_FDEMDeformableContact {
  FDEMDeformable                    d;
  MPI_Comm                          comm;
  PetscMPIInt                       rank = 0, size = 1;
  PetscReal                         penalty = -1, buffer = -1;
  fdem::kernels::ContactDissipation diss;
  PetscBool                         self    = PETSC_FALSE;
  PetscInt                          nbodies = 0;
  // this rank's surface tetrahedra: local node indices, static data (NI each), current positions
  // and velocities (12 each), positions at the last search
  std::vector<std::array<PetscInt, 4>> lconn;
  std::vector<PetscInt>                lstat;
  std::vector<char>                    lfaces; // bit o: the face opposite node o is on the boundary
  std::vector<PetscReal>               lx, lv, ref_x;
  // ghosts: other ranks' surface tetrahedra within the search distance of this rank's ones
  PetscInt               ng = 0;
  std::vector<PetscInt>  gstat;  // NI each
  std::vector<PetscReal> gx, gv; // 12 each
  PetscSF                sf = nullptr; // roots: 12 reals per own tetrahedron, leaves: 12 per ghost
  // candidate pairs in the numbering [own | ghost]; the first is this rank's and has the smaller gid
  std::vector<std::array<int, 2>> pairs;
  std::vector<PetscReal>          leaf_f, root_f;
  bool                            searched = false, checked_initial = false;
  TS                              checked_ts = nullptr; // the TS whose time step was checked (not referenced)
  std::vector<PetscReal>          body_force; // 3 per body: this rank's pairs at the last evaluation
  FDEMDeformableContactStats      stats{};
};

namespace {

inline int NOwn(FDEMDeformableContact c) { return (int)c->lconn.size(); }

// Tetrahedron i of [own | ghost].
Tet4 TetAt(FDEMDeformableContact c, int i) {
  const int        nl = NOwn(c);
  const PetscReal *p  = i < nl ? &c->lx[12 * (size_t)i] : &c->gx[12 * (size_t)(i - nl)];
  return {Vec3(p[0], p[1], p[2]), Vec3(p[3], p[4], p[5]), Vec3(p[6], p[7], p[8]), Vec3(p[9], p[10], p[11])};
}
const PetscReal *VelAt(FDEMDeformableContact c, int i) {
  const int nl = NOwn(c);
  return i < nl ? &c->lv[12 * (size_t)i] : &c->gv[12 * (size_t)(i - nl)];
}
const PetscInt *StatAt(FDEMDeformableContact c, int i) {
  const int nl = NOwn(c);
  return i < nl ? &c->lstat[NI * (size_t)i] : &c->gstat[NI * (size_t)(i - nl)];
}

// Copy this rank's surface tetrahedra out of the hook's local vectors.
void Pack(FDEMDeformableContact c, const PetscScalar *a, std::vector<PetscReal> &out) {
  const size_t nl = c->lconn.size();
  out.resize(12 * nl);
  for (size_t t = 0; t < nl; ++t)
    for (int q = 0; q < 4; ++q)
      for (int k = 0; k < 3; ++k) out[12 * t + 3 * q + k] = PetscRealPart(a[3 * c->lconn[t][q] + k]);
}

// Positions (and velocities) of the ghosts from their owners.
PetscErrorCode UpdateGhosts(FDEMDeformableContact c, bool with_v) {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_GATHER, 0, 0, 0, 0));
  c->gx.resize(12 * (size_t)c->ng);
  PetscCall(PetscSFBcastBegin(c->sf, MPIU_REAL, c->lx.data(), c->gx.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(c->sf, MPIU_REAL, c->lx.data(), c->gx.data(), MPI_REPLACE));
  if (with_v) {
    c->gv.resize(12 * (size_t)c->ng);
    PetscCall(PetscSFBcastBegin(c->sf, MPIU_REAL, c->lv.data(), c->gv.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(c->sf, MPIU_REAL, c->lv.data(), c->gv.data(), MPI_REPLACE));
  }
  PetscCall(PetscLogEventEnd(EV_GATHER, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Bounding sphere (with half the buffer) of a tetrahedron.
void Sphere(const Tet4 &T, PetscReal half_buffer, double ct[3], double *r) {
  const Vec3 m = 0.25 * (T[0] + T[1] + T[2] + T[3]);
  double     rr = 0;
  for (int k = 0; k < 4; ++k) rr = std::max(rr, norm(T[k] - m));
  for (int k = 0; k < 3; ++k) ct[k] = m[k];
  *r = rr + half_buffer;
}

// The halo and the candidate pairs. Each rank's region is a few boxes around the bounding
// spheres of its own surface tetrahedra; a tetrahedron whose sphere meets another
// rank's region is sent there as a ghost (PetscSF, rebuilt here). A pair whose
// spheres overlap then lies on the rank owning its tetrahedron with the smaller
// global id, which computes it; forces on ghosts go back through the same SF.
PetscErrorCode Search(FDEMDeformableContact c, bool with_v) {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_DETECT, 0, 0, 0, 0));
  const int           nl = NOwn(c);
  std::vector<double> centres(3 * (size_t)nl), radii(nl);
  for (int i = 0; i < nl; ++i) Sphere(TetAt(c, i), 0.5 * c->buffer, &centres[3 * (size_t)i], &radii[i]);
  // this rank's region: NBOX boxes from a k-d split of its tetrahedra (by centre, along the
  // longest extent) so that a rank holding two distant pieces does not claim the space between
  std::vector<double> box(BW * NBOX, INFINITY); // per box: lo, -hi (empty: +inf), the body of all its tetrahedra (-1: several)
  {
    std::vector<int> idx(nl);
    for (int i = 0; i < nl; ++i) idx[i] = i;
    std::function<void(int, int, int, int)> split = [&](int b, int e, int depth, int slot) {
      if (b >= e) return;
      if (depth == 0) {
        double *bx = &box[BW * slot];
        bx[6]      = (double)StatAt(c, idx[b])[1];
        for (int j = b; j < e; ++j) {
          const int i = idx[j];
          for (int k = 0; k < 3; ++k) {
            bx[k]     = std::min(bx[k], centres[3 * i + k] - radii[i]);
            bx[3 + k] = std::min(bx[3 + k], -(centres[3 * i + k] + radii[i]));
          }
          if ((double)StatAt(c, i)[1] != bx[6]) bx[6] = -1;
        }
        return;
      }
      double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      for (int j = b; j < e; ++j)
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], centres[3 * idx[j] + k]);
          hi[k] = std::max(hi[k], centres[3 * idx[j] + k]);
        }
      int ax = 0;
      for (int k = 1; k < 3; ++k)
        if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
      const int m = b + (e - b) / 2;
      std::nth_element(idx.begin() + b, idx.begin() + m, idx.begin() + e, [&](int u, int v) { return centres[3 * u + ax] < centres[3 * v + ax]; });
      split(b, m, depth - 1, 2 * slot);
      split(m, e, depth - 1, 2 * slot + 1);
    };
    split(0, nl, NBOX_DEPTH, 0);
  }
  std::vector<double> boxes(BW * NBOX * (size_t)c->size);
  PetscCallMPI(MPI_Allgather(box.data(), BW * NBOX, MPI_DOUBLE, boxes.data(), BW * NBOX, MPI_DOUBLE, c->comm));
  // 1. who needs which of my tetrahedra: those whose sphere meets a box of another rank
  //    (unless every tetrahedron in that box is of the same body and self-contact is off)
  std::vector<std::vector<PetscInt>> send(c->size);
  for (int s = 0; s < c->size; ++s) {
    if (s == c->rank) continue;
    for (int i = 0; i < nl; ++i)
      for (int q = 0; q < NBOX; ++q) {
        const double *b  = &boxes[BW * ((size_t)s * NBOX + q)];
        bool          in = c->self || b[6] != (double)StatAt(c, i)[1]; // no pairs within one body without self-contact
        for (int k = 0; k < 3 && in; ++k) in = centres[3 * i + k] + radii[i] >= b[k] && centres[3 * i + k] - radii[i] <= -b[3 + k];
        if (in) {
          send[s].push_back(i);
          break;
        }
      }
  }
  std::vector<PetscSFNode> ghosts;
  PetscCall(fdem::HaloExchange(c->comm, send, ghosts));
  // 2. the SF (12 reals per ghost) and the ghosts' static data (a one-off SF, NI integers each)
  c->ng = (PetscInt)ghosts.size();
  PetscCall(fdem::HaloSF(c->comm, nl, ghosts, 12, &c->sf));
  {
    PetscSF sfs = nullptr;
    c->gstat.resize(NI * (size_t)c->ng);
    PetscCall(fdem::HaloSF(c->comm, nl, ghosts, NI, &sfs));
    PetscCall(PetscSFBcastBegin(sfs, MPIU_INT, c->lstat.data(), c->gstat.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(sfs, MPIU_INT, c->lstat.data(), c->gstat.data(), MPI_REPLACE));
    PetscCall(PetscSFDestroy(&sfs));
  }
  PetscCall(UpdateGhosts(c, with_v));
  // 3. cell search over own + ghost tetrahedra
  const int N = nl + (int)c->ng;
  centres.resize(3 * (size_t)N);
  radii.resize(N);
  double dmax = 0;
  for (int i = nl; i < N; ++i) Sphere(TetAt(c, i), 0.5 * c->buffer, &centres[3 * (size_t)i], &radii[i]);
  for (int i = 0; i < N; ++i) dmax = std::max(dmax, 2 * radii[i]);
  c->pairs.clear();
  { // fdem::Guard is collective: every rank enters it
    PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
      if (nl == 0) return 0;
      fdem::kernels::CellSearch        cs;
      std::vector<std::pair<int, int>> tp;
      cs.Build(centres.data(), radii.data(), N, dmax * (1 + 1e-12));
      cs.FindPairs(tp);
      for (const auto &pr : tp) {
        int             a = pr.first, b = pr.second;
        const PetscInt *A = StatAt(c, a), *B = StatAt(c, b);
        if (A[1] == B[1]) { // same body: only with self-contact, and never neighbours
          if (!c->self) continue;
          bool share = false;
          for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) share = share || A[2 + i] == B[2 + j];
          if (share) continue;
        }
        if (B[0] < A[0]) std::swap(a, b); // a: the smaller global element id, computed by its rank
        if (a >= nl) continue;
        c->pairs.push_back({a, b});
      }
      return 0;
    }));
  }
  c->leaf_f.assign(12 * (size_t)c->ng, 0);
  c->root_f.assign(12 * (size_t)nl, 0);
  c->ref_x    = c->lx;
  c->searched = true;
  c->stats.searches++;
  c->stats.ghost_tets = c->ng;
  PetscInt np         = (PetscInt)c->pairs.size();
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
  { // once per TS of FDEMDeformableSetUpTS, at its first evaluation: the contact frequency against K_crit
    TS ts;
    PetscCall(fdem::model::DeformableGetTS(c->d, &ts));
    if (ts && ts != c->checked_ts) {
      TSType         type;
      PetscReal      dt;
      PetscBool      found;
      FDEMSchemeInfo info;
      c->checked_ts = ts;
      PetscCall(TSGetType(ts, &type));
      PetscCall(TSGetTimeStep(ts, &dt));
      PetscCall(FDEMSchemeInfoFind(type, &found, &info));
      if (found && dt > 0) PetscCall(FDEMDeformableContactCheckTimeStep(c, type, dt, nullptr));
    }
  }
  PetscCall(VecGetArrayRead(xloc, &xl));
  Pack(c, xl, c->lx);
  PetscCall(VecRestoreArrayRead(xloc, &xl));
  if (dissipative) {
    PetscCall(VecGetArrayRead(vloc, &vl));
    Pack(c, vl, c->lv);
    PetscCall(VecRestoreArrayRead(vloc, &vl));
  }
  // re-search when some surface node moved more than half the buffer since the last search
  const int nl   = NOwn(c);
  PetscReal move = c->searched ? 0 : PETSC_MAX_REAL, gmove;
  if (c->searched)
    for (int i = 0; i < 4 * nl; ++i) {
      const PetscReal *p = &c->lx[3 * (size_t)i], *q = &c->ref_x[3 * (size_t)i];
      move               = std::max(move, PetscSqrtReal(PetscSqr(p[0] - q[0]) + PetscSqr(p[1] - q[1]) + PetscSqr(p[2] - q[2])));
    }
  PetscCallMPI(MPI_Allreduce(&move, &gmove, 1, MPIU_REAL, MPI_MAX, c->comm));
  if (gmove > 0.5 * c->buffer) PetscCall(Search(c, dissipative));
  else PetscCall(UpdateGhosts(c, dissipative));

  PetscCall(PetscLogEventBegin(EV_FORCE, 0, 0, 0, 0));
  std::fill(c->leaf_f.begin(), c->leaf_f.end(), 0);
  std::fill(c->root_f.begin(), c->root_f.end(), 0);
  std::fill(c->body_force.begin(), c->body_force.end(), 0);
  PetscReal             sums[2] = {0, 0}; // energy, active pairs
  std::array<double, 3> deep{0, -1, -1};  // worst initial overlap ratio, the pair
  PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc;
    std::array<Vec3, 4>           fa, fb, va, vb, da, db;
    for (const auto &p : c->pairs) {
      const Tet4 a = TetAt(c, p[0]), b = TetAt(c, p[1]);
      if (!fdem::kernels::PotentialContactForce(a, b, c->penalty, c->penalty, pc)) continue;
      sums[0] += pc.energy;
      sums[1] += 1;
      if (!c->checked_initial) {
        // deep: overlap energy above that of 10% of the smaller tetrahedron at mid potential
        const double va6 = std::fabs(dot(a[1] - a[0], cross(a[2] - a[0], a[3] - a[0]))), vb6 = std::fabs(dot(b[1] - b[0], cross(b[2] - b[0], b[3] - b[0])));
        const double ratio = pc.energy / (0.1 * std::min(va6, vb6) / 6 * c->penalty / 8);
        if (ratio > deep[0]) deep = {ratio, (double)p[0], (double)p[1]};
      }
      fa = pc.fa;
      fb = pc.fb;
      if (dissipative) {
        const PetscReal *pa = VelAt(c, p[0]), *pb = VelAt(c, p[1]);
        for (int k = 0; k < 4; ++k) {
          va[k] = Vec3(pa[3 * k], pa[3 * k + 1], pa[3 * k + 2]);
          vb[k] = Vec3(pb[3 * k], pb[3 * k + 1], pb[3 * k + 2]);
        }
        fdem::kernels::ContactDampingFriction(a, b, va, vb, pc, c->diss, da, db);
        for (int k = 0; k < 4; ++k) {
          fa[k] += da[k];
          fb[k] += db[k];
        }
      }
      const PetscInt ba = StatAt(c, p[0])[1], bb = StatAt(c, p[1])[1];
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) {
          c->body_force[3 * ba + j] += fa[k][j];
          c->body_force[3 * bb + j] += fb[k][j];
        }
      PetscReal *oa = &c->root_f[12 * (size_t)p[0]];
      PetscReal *ob = p[1] < nl ? &c->root_f[12 * (size_t)p[1]] : &c->leaf_f[12 * (size_t)(p[1] - nl)];
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
        const PetscInt *A = StatAt(c, (int)deep[1]), *B = StatAt(c, (int)deep[2]);
        mine[0]           = A[1];
        mine[1]           = B[1];
        mine[2]           = A[0];
        mine[3]           = B[0];
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
  // forces on ghosts go back to their owners and are summed there
  PetscCall(PetscSFReduceBegin(c->sf, MPIU_REAL, c->leaf_f.data(), c->root_f.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(c->sf, MPIU_REAL, c->leaf_f.data(), c->root_f.data(), MPI_SUM));
  PetscCall(VecGetArray(floc, &fl));
  for (int t = 0; t < nl; ++t)
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j) fl[3 * c->lconn[t][k] + j] += c->root_f[12 * (size_t)t + 3 * k + j];
  PetscCall(VecRestoreArray(floc, &fl));
  PetscReal gsums[2];
  PetscCallMPI(MPI_Allreduce(sums, gsums, 2, MPIU_REAL, MPI_SUM, c->comm));
  c->stats.energy       = gsums[0];
  c->stats.active_pairs = (PetscInt)gsums[1];
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
  PetscCall(fdem::contact::BoundaryFaces(c->comm, conn, ngid, surf));
  for (PetscInt e = 0; e < nc; ++e) {
    if (!surf[e]) continue;
    c->lconn.push_back({conn[4 * e], conn[4 * e + 1], conn[4 * e + 2], conn[4 * e + 3]});
    c->lfaces.push_back(surf[e]);
    c->lstat.insert(c->lstat.end(), {gid[e], body[e], ngid[conn[4 * e]], ngid[conn[4 * e + 1]], ngid[conn[4 * e + 2]], ngid[conn[4 * e + 3]]});
  }
  PetscInt nl = (PetscInt)c->lconn.size(), ntot;
  PetscCallMPI(MPI_Allreduce(&nl, &ntot, 1, MPIU_INT, MPI_SUM, c->comm));
  c->stats.surface_tets = ntot;
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
    c->buffer = ntot > 0 ? 0.25 * g / (PetscReal)ntot : 0;
  }
  PetscCall(PetscLogEventEnd(EV_SURFACE, 0, 0, 0, 0));
  c->body_force.assign(3 * (size_t)c->nbodies, 0);
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
  PetscCall(fdem::contact::CheckPenalty(c->comm, "Deformable contact", penalty));
  c->penalty = penalty;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetDissipation(FDEMDeformableContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::SetDissipation(c->comm, "Deformable contact", damping, friction, tangential_viscosity, c->diss));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactSetBuffer(FDEMDeformableContact c, PetscReal buffer) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::CheckBuffer(c->comm, "Deformable contact", buffer));
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
  PetscCallMPI(MPI_Allreduce(&c->body_force[3 * body], F, 3, MPIU_REAL, MPI_SUM, c->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableContactCheckTimeStep(FDEMDeformableContact c, const char *scheme, PetscReal dt, PetscReal *ratio) {
  FDEMSchemeInfo           info;
  PetscBool                found;
  DM                       dm;
  Vec                      X, M, Xl, Kl, Kg;
  const PetscScalar       *xa, *ma, *kg;
  PetscScalar             *kl;
  const std::vector<char> *fixed;
  PetscReal                loc = 0, omega;
  PetscFunctionBegin;
  PetscCheck(c->penalty > 0, c->comm, PETSC_ERR_ARG_WRONGSTATE, "Deformable contact: the penalty is not set; give -fdem_dcontact_penalty <Pa>");
  PetscCheck(dt > 0 && std::isfinite(dt), c->comm, PETSC_ERR_ARG_OUTOFRANGE, "Deformable contact: the time step must be positive, got %g", (double)dt);
  PetscCall(FDEMSchemeInfoFind(scheme, &found, &info));
  PetscCheck(found, c->comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "Deformable contact: %s is not an fdem TS type", scheme);
  PetscCall(FDEMDeformableGetDM(c->d, &dm));
  PetscCall(FDEMDeformableGetPositions(c->d, &X));
  PetscCall(FDEMDeformableGetMasses(c->d, &M));
  PetscCall(fdem::model::DeformableGetFixed(c->d, &fixed));
  // Contact stiffness of each surface node: a boundary face of area A pressed a depth d into
  // its tetrahedron of height H over it feels ~ penalty (d / H) A, shared by its three nodes,
  // so k = sum over the node's boundary faces of penalty A / (3 H). Both tetrahedra of a pair
  // push (contactor and target, x2) and an equal body on the other side halves the effective
  // mass (x2): omega^2 = 4 k / m with m the node's lumped mass (flat contact of equal bodies,
  // the stiffest case).
  PetscCall(DMGetLocalVector(dm, &Xl));
  PetscCall(DMGetLocalVector(dm, &Kl));
  PetscCall(DMGetGlobalVector(dm, &Kg));
  PetscCall(DMGlobalToLocal(dm, X, INSERT_VALUES, Xl));
  PetscCall(VecSet(Kl, 0));
  PetscCall(VecGetArrayRead(Xl, &xa));
  PetscCall(VecGetArray(Kl, &kl));
  for (size_t t = 0; t < c->lconn.size(); ++t) {
    const auto &T = c->lconn[t];
    Vec3        P[4];
    for (int q = 0; q < 4; ++q) P[q] = Vec3(PetscRealPart(xa[3 * T[q]]), PetscRealPart(xa[3 * T[q] + 1]), PetscRealPart(xa[3 * T[q] + 2]));
    const double V = std::fabs(dot(P[1] - P[0], cross(P[2] - P[0], P[3] - P[0]))) / 6;
    for (int o = 0; o < 4; ++o) {
      if (!(c->lfaces[t] & (1 << o))) continue;
      const int    i = (o + 1) % 4, j = (o + 2) % 4, k = (o + 3) % 4;
      const double A = 0.5 * norm(cross(P[j] - P[i], P[k] - P[i]));
      if (!(V > 0) || !(A > 0)) continue;
      const double H = 3 * V / A;
      for (int q : {i, j, k}) kl[3 * T[q]] += c->penalty * A / (3 * H);
    }
  }
  PetscCall(VecRestoreArray(Kl, &kl));
  PetscCall(VecRestoreArrayRead(Xl, &xa));
  PetscCall(VecSet(Kg, 0));
  PetscCall(DMLocalToGlobal(dm, Kl, ADD_VALUES, Kg));
  PetscCall(VecGetArrayRead(Kg, &kg));
  PetscCall(VecGetArrayRead(M, &ma));
  for (size_t n = 0; n < fixed->size(); ++n) {
    const PetscReal k = PetscRealPart(kg[3 * n]), m = PetscRealPart(ma[3 * n]);
    if ((*fixed)[n] || !(k > 0) || !(m > 0)) continue; // fixed nodes do not move
    loc = std::max(loc, 4 * k / m);
  }
  PetscCall(VecRestoreArrayRead(M, &ma));
  PetscCall(VecRestoreArrayRead(Kg, &kg));
  PetscCall(DMRestoreGlobalVector(dm, &Kg));
  PetscCall(DMRestoreLocalVector(dm, &Kl));
  PetscCall(DMRestoreLocalVector(dm, &Xl));
  PetscCallMPI(MPI_Allreduce(&loc, &omega, 1, MPIU_REAL, MPI_MAX, c->comm));
  omega             = PetscSqrtReal(omega);
  const PetscReal r = info.kcrit > 0 ? omega * dt / info.kcrit : PETSC_MAX_REAL;
  if (ratio) *ratio = r;
  if (r > 0.5)
    PetscCall(PetscPrintf(c->comm,
                          "WARNING fdem deformable contact: the contact frequency omega_c ~ sqrt(4 k / m) = %g (k: penalty A / (3 H) summed over a surface node's boundary faces of area A and height H, m: its mass) makes "
                          "omega_c dt = %g, %.0f%% of the stability limit K_crit = %.4f of -ts_type %s; reduce dt below %g or the penalty\n",
                          (double)omega, (double)(omega * dt), (double)(100 * r), (double)info.kcrit, scheme, (double)(0.5 * info.kcrit / omega)));
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
