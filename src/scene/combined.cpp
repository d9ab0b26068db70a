// A combined scene (rigid bodies + deformable mesh) in one TS, and contact
// between rigid skins and the mesh's surface tetrahedra; see include/fdem/scene.h
// and doc/scene.md.
#include "../model/deformable_impl.hpp"
#include "../model/rigid_impl.hpp"
#include "../contact/surface.hpp"
#include "../util/guard.hpp"
#include "../util/halo.hpp"
#include "../contact/params.hpp"
#include <fdem/scene.h>
#include <fdem/deformable_contact.h> // FDEMDeformableGetLocalCells, FDEMDeformableGetBodyName
#include <fdem/ts.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/nbs.hpp>
#include <fdem/kernels/rotation.hpp>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

namespace {
constexpr int NS = 20; // rigid state per body, owner -> ghosts: x(3) R(9) v(3) omega(3) fixed id
constexpr int NF = 6;  // per body, ghosts -> owner: F(3) M(3) (moment about the centre of mass)

PetscClassId  FDEM_SCENE_CLASSID = 0;
PetscLogEvent EV_RHS = 0, EV_SEARCH = 0, EV_CONTACT = 0, EV_HALO = 0;

Mat3 Rot(const PetscReal *R) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = R[3 * r + c];
  return M;
}

struct RDContact {
  PetscReal                         penalty = -1, buffer = -1;
  fdem::kernels::ContactDissipation diss;
  // mesh side (this rank): cells in contact as local node indices, their global element ids and
  // bodies; the local nodes they use and those nodes' positions at the last search
  std::vector<std::array<int, 4>> cells;
  std::vector<PetscInt>           cell_gid, cell_body;
  std::vector<int>                nodes;
  std::vector<PetscReal>          node_ref;
  // rigid side, "combined" numbering: this rank's bodies (0..n-1, the SF roots), then ghost
  // copies of other ranks' bodies near this rank's mesh region (n..n+ng-1, the SF leaves)
  PetscInt                        n = 0, ng = 0;
  PetscSF                         sf_state = nullptr, sf_force = nullptr; // NS, NF reals per body
  std::vector<PetscReal>          root_state, ghost_state, root_force, ghost_force, ref_state;
  std::vector<PetscInt>           skin;   // skin index (-1: none)
  std::vector<PetscReal>          radius; // bounding radius of the skin about the centre of mass
  std::vector<char>               near;   // the body's sphere met this rank's region at the last search
  std::vector<std::vector<Vec3>>  world;  // skin nodes in world coordinates (near bodies)
  std::vector<std::array<int, 3>> pairs;  // (mesh cell, combined body, skin tet)
  bool                            searched = false, checked_initial = false, checked_dt = false;
  FDEMSceneContactStats           stats{};
  fdem::kernels::CellSearch       cs;

  PetscReal *State(PetscInt ci) { return ci < n ? &root_state[NS * ci] : &ghost_state[NS * (ci - n)]; }
  PetscReal *Force(PetscInt ci) { return ci < n ? &root_force[NF * ci] : &ghost_force[NF * (ci - n)]; }
};
} // namespace

struct _n_FDEMScene {
  MPI_Comm       comm;
  PetscMPIInt    rank = 0, size = 1;
  FDEMRigid      rb  = nullptr;
  FDEMDeformable dfm = nullptr;
  PetscInt       nr = 0, nd = 0, nr_global = 0;
  Vec            vr_state = nullptr, vr_q = nullptr, vr_a = nullptr; // sequential views of the rigid pieces
  TS             ts = nullptr; // the TS of FDEMSceneSetUpTS (not referenced; split RHS get sub-TS without a solution)
  bool           contact = false;
  RDContact      c;
  // the mesh's own external force, chained behind contact
  FDEMDeformableForceFn user_ext = nullptr;
  void                 *user_ext_ctx = nullptr;
  bool                  hooked = false;
  // during a force evaluation: rigid positions [x | R] and rigid state [x | R | v | H] (velocities)
  const PetscScalar *cur_rq = nullptr, *cur_ru = nullptr;
  bool               evaluating = false;
};

namespace {

// Offsets in the combined state.
inline PetscInt OffRigid(FDEMScene s) { return 3 * s->nd; }
inline PetscInt OffDefV(FDEMScene s) { return 3 * s->nd + 18 * s->nr; }

// ---------------------------------------------------------------- contact set-up
// At FDEMSceneSetUpTS: the mesh cells taking part, and this rank's rigid bodies (which may have
// changed since the last TS: FDEMRigidMigrate). The halo is rebuilt at the first evaluation.
PetscErrorCode ContactSetUp(FDEMScene s) {
  RDContact &c = s->c;
  PetscInt   nc, nlocal;
  PetscFunctionBegin;
  // 1. mesh cells near the boundary: boundary faces are faces of one cell only
  PetscCall(FDEMDeformableGetLocalCells(s->dfm, &nc, &nlocal, nullptr, nullptr, nullptr, nullptr));
  std::vector<PetscInt> conn(4 * nc), body(nc), gid(nc), ng(nlocal);
  PetscCall(FDEMDeformableGetLocalCells(s->dfm, &nc, &nlocal, conn.data(), body.data(), gid.data(), ng.data()));
  std::vector<char> surf, bnode;
  PetscCall(fdem::contact::BoundaryFaces(s->comm, conn, ng, surf));
  PetscCall(fdem::contact::BoundaryNodes(s->dfm, conn, surf, nlocal, bnode));
  // cells with a vertex on the boundary take part (a rigid corner may enter through an edge)
  c.cells.clear();
  c.cell_gid.clear();
  c.cell_body.clear();
  std::vector<char> used(nlocal, 0);
  for (PetscInt e = 0; e < nc; ++e) {
    bool on = false;
    for (int k = 0; k < 4; ++k) on = on || bnode[conn[4 * e + k]];
    if (!on) continue;
    c.cells.push_back({(int)conn[4 * e], (int)conn[4 * e + 1], (int)conn[4 * e + 2], (int)conn[4 * e + 3]});
    c.cell_gid.push_back(gid[e]);
    c.cell_body.push_back(body[e]);
    for (int k = 0; k < 4; ++k) used[conn[4 * e + k]] = 1;
  }
  c.nodes.clear();
  for (PetscInt l = 0; l < nlocal; ++l)
    if (used[l]) c.nodes.push_back((int)l);
  PetscInt nsc = (PetscInt)c.cells.size();
  PetscCallMPI(MPIU_Allreduce(&nsc, &c.stats.surface_cells, 1, MPIU_INT, MPI_SUM, s->comm));
  // 2. this rank's rigid bodies: skin and radius; no ghosts until the first search
  c.n  = s->nr;
  c.ng = 0;
  c.root_state.assign(NS * c.n, 0);
  c.root_force.assign(NF * c.n, 0);
  c.ghost_state.clear();
  c.ghost_force.clear();
  c.skin.resize(c.n);
  c.radius.resize(c.n);
  {
    fdem::model::RigidFields f;
    PetscCall(fdem::model::RigidGetFields(s->rb->sw, f));
    for (PetscInt b = 0; b < c.n; ++b) {
      c.skin[b]   = f.skin[b];
      c.radius[b] = f.radius[b];
    }
    PetscCall(fdem::model::RigidRestoreFields(s->rb->sw, f));
  }
  PetscCall(PetscSFDestroy(&c.sf_state));
  PetscCall(PetscSFDestroy(&c.sf_force));
  // 3. default buffer: 20% of the mean bounding radius of the rigid skin tetrahedra (each body counted by its owner)
  if (c.buffer < 0) {
    PetscReal sum[2] = {0, 0}, gsum[2];
    for (PetscInt b = 0; b < c.n; ++b) {
      if (c.skin[b] < 0) continue;
      const auto &sk = s->rb->skins[c.skin[b]];
      for (const auto &T : sk.tets) {
        const Vec3 ct = 0.25 * (sk.nodes[T[0]] + sk.nodes[T[1]] + sk.nodes[T[2]] + sk.nodes[T[3]]);
        double     r  = 0;
        for (int k = 0; k < 4; ++k) r = std::max(r, norm(sk.nodes[T[k]] - ct));
        sum[0] += r;
        sum[1] += 1;
      }
    }
    PetscCallMPI(MPIU_Allreduce(sum, gsum, 2, MPIU_REAL, MPIU_SUM, s->comm));
    c.buffer = gsum[1] > 0 ? 0.2 * gsum[0] / gsum[1] : 0;
  }
  c.stats.buffer      = c.buffer;
  c.stats.ghost_bodies = 0;
  c.searched          = false;
  c.checked_initial   = false;
  c.checked_dt        = false;
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- contact evaluation
// This rank's bodies' states from the positions s->cur_rq = [x | R] and the state s->cur_ru = [x | R | v | H].
void PackStates(FDEMScene s) {
  RDContact     &c  = s->c;
  const PetscInt nr = s->nr;
  for (PetscInt b = 0; b < nr; ++b) {
    PetscReal *st = &c.root_state[NS * b];
    for (int k = 0; k < 3; ++k) st[k] = PetscRealPart(s->cur_rq[3 * b + k]);
    for (int k = 0; k < 9; ++k) st[3 + k] = PetscRealPart(s->cur_rq[3 * nr + 9 * b + k]);
    for (int k = 0; k < 3; ++k) st[12 + k] = PetscRealPart(s->cur_ru[12 * nr + 3 * b + k]);
    const Vec3 I(s->rb->inertia[3 * b], s->rb->inertia[3 * b + 1], s->rb->inertia[3 * b + 2]);
    const Vec3 H(PetscRealPart(s->cur_ru[15 * nr + 3 * b]), PetscRealPart(s->cur_ru[15 * nr + 3 * b + 1]), PetscRealPart(s->cur_ru[15 * nr + 3 * b + 2]));
    const Vec3 w = fdem::kernels::BodyOmega(Rot(&st[3]), I, H);
    for (int k = 0; k < 3; ++k) st[15 + k] = w[k];
    st[18] = (PetscReal)s->rb->fixed[b];
    st[19] = (PetscReal)s->rb->ids[b];
  }
}

// World coordinates of body ci's skin nodes from its current state.
void UpdateWorld(FDEMScene s, PetscInt ci) {
  RDContact       &c  = s->c;
  const auto      &sk = s->rb->skins[c.skin[ci]];
  const PetscReal *st = c.State(ci);
  const Mat3       R  = Rot(&st[3]);
  const Vec3       x(st[0], st[1], st[2]);
  c.world[ci].resize(sk.nodes.size());
  for (size_t i = 0; i < sk.nodes.size(); ++i) c.world[ci][i] = x + R * sk.nodes[i];
}

// Does the sphere (x, r) meet the box b = {lo(3), -hi(3)}?
bool Meets(const double *b, const PetscReal *x, PetscReal r) {
  for (int k = 0; k < 3; ++k)
    if (x[k] + r < b[k] || x[k] - r > -b[3 + k]) return false;
  return true;
}

// The halo and the candidate pairs. This rank's region is the box of the bounding spheres
// (+ buffer/2) of its contact cells; a body whose sphere (radius + buffer) meets another rank's
// region is sent there as a ghost. The SFs (rebuilt here) carry states to the ghosts at every
// evaluation and sum forces on ghosts back into their owners. A pair (mesh cell, skin tet) is
// computed by the rank that owns the cell: once.
PetscErrorCode ContactSearch(FDEMScene s, const PetscScalar *xl) {
  RDContact     &c = s->c;
  const PetscInt n = c.n;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_SEARCH, 0, 0, 0, 0));
  std::vector<double>             centres, radii;
  std::vector<int>                kind; // >= 0: mesh cell; < 0: -(1 + index into rig)
  std::vector<std::array<int, 2>> rig;  // (combined body, skin tet)
  double                          dmax = 0;
  auto add = [&](const Vec3 &p0, const Vec3 &p1, const Vec3 &p2, const Vec3 &p3, int k) {
    const Vec3 ct = 0.25 * (p0 + p1 + p2 + p3);
    double     r  = std::max({norm(p0 - ct), norm(p1 - ct), norm(p2 - ct), norm(p3 - ct)}) + 0.5 * c.buffer;
    centres.insert(centres.end(), {ct.x, ct.y, ct.z});
    radii.push_back(r);
    kind.push_back(k);
    dmax = std::max(dmax, 2 * r);
  };
  // 1. this rank's region
  double box[6] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY}; // lo, -hi
  for (size_t e = 0; e < c.cells.size(); ++e) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Vec3(PetscRealPart(xl[3 * c.cells[e][k]]), PetscRealPart(xl[3 * c.cells[e][k] + 1]), PetscRealPart(xl[3 * c.cells[e][k] + 2]));
    add(p[0], p[1], p[2], p[3], (int)e);
    for (int k = 0; k < 3; ++k) {
      box[k]     = std::min(box[k], centres[3 * e + k] - radii[e]);
      box[3 + k] = std::min(box[3 + k], -(centres[3 * e + k] + radii[e]));
    }
  }
  std::vector<double> boxes(6 * (size_t)s->size);
  PetscCallMPI(MPI_Allgather(box, 6, MPI_DOUBLE, boxes.data(), 6, MPI_DOUBLE, s->comm));
  // 2. who needs which of my bodies
  std::vector<std::vector<PetscInt>> send(s->size);
  for (PetscInt b = 0; b < n; ++b) {
    if (c.skin[b] < 0) continue;
    for (int r = 0; r < s->size; ++r)
      if (r != s->rank && Meets(&boxes[6 * (size_t)r], &c.root_state[NS * b], c.radius[b] + c.buffer)) send[r].push_back(b);
  }
  std::vector<PetscSFNode> ghosts;
  PetscCall(fdem::HaloExchange(s->comm, send, ghosts));
  // 3. the SFs: roots = my bodies, leaves = ghosts; and the ghosts' static data (skin, radius) once
  c.ng = (PetscInt)ghosts.size();
  {
    PetscCall(fdem::HaloSF(s->comm, n, ghosts, NS, &c.sf_state));
    PetscCall(fdem::HaloSF(s->comm, n, ghosts, NF, &c.sf_force));
    std::vector<PetscReal> root_static(2 * (size_t)n), ghost_static(2 * (size_t)c.ng);
    for (PetscInt b = 0; b < n; ++b) {
      root_static[2 * b]     = (PetscReal)c.skin[b];
      root_static[2 * b + 1] = c.radius[b];
    }
    PetscSF sf = nullptr;
    PetscCall(fdem::HaloSF(s->comm, n, ghosts, 2, &sf));
    PetscCall(PetscSFBcastBegin(sf, MPIU_REAL, root_static.data(), ghost_static.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(sf, MPIU_REAL, root_static.data(), ghost_static.data(), MPI_REPLACE));
    PetscCall(PetscSFDestroy(&sf));
    c.skin.resize(n + c.ng);
    c.radius.resize(n + c.ng);
    for (PetscInt i = 0; i < c.ng; ++i) {
      c.skin[n + i]   = (PetscInt)ghost_static[2 * i];
      c.radius[n + i] = ghost_static[2 * i + 1];
    }
  }
  c.ghost_state.assign(NS * (size_t)c.ng, 0);
  c.ghost_force.assign(NF * (size_t)c.ng, 0);
  PetscCall(PetscSFBcastBegin(c.sf_state, MPIU_REAL, c.root_state.data(), c.ghost_state.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(c.sf_state, MPIU_REAL, c.root_state.data(), c.ghost_state.data(), MPI_REPLACE));
  // 4. the skin tetrahedra of the bodies (own and ghost) whose sphere meets this rank's region
  c.near.assign(n + c.ng, 0);
  c.world.resize(n + c.ng);
  PetscInt nnear = 0;
  for (PetscInt ci = 0; ci < n + c.ng; ++ci) {
    if (c.skin[ci] < 0 || !Meets(box, c.State(ci), c.radius[ci] + c.buffer)) continue;
    c.near[ci] = 1;
    nnear++;
    UpdateWorld(s, ci);
    const auto &sk = s->rb->skins[c.skin[ci]];
    const auto &w  = c.world[ci];
    for (size_t t = 0; t < sk.tets.size(); ++t) {
      const auto &T = sk.tets[t];
      rig.push_back({(int)ci, (int)t});
      add(w[T[0]], w[T[1]], w[T[2]], w[T[3]], -(int)rig.size());
    }
  }
  c.pairs.clear();
  PetscCall(fdem::Guard(s->comm, [&]() -> PetscErrorCode {
    if (c.cells.empty() || rig.empty()) return 0;
    std::vector<std::pair<int, int>> tp;
    c.cs.Build(centres.data(), radii.data(), (int)radii.size(), dmax * (1 + 1e-12));
    c.cs.FindPairs(tp);
    for (const auto &pr : tp) {
      int a = kind[pr.first], b = kind[pr.second];
      if ((a >= 0) == (b >= 0)) continue;
      if (a < 0) std::swap(a, b);
      const auto &R = rig[-b - 1];
      c.pairs.push_back({a, R[0], R[1]});
    }
    std::sort(c.pairs.begin(), c.pairs.end()); // a fixed order: results do not depend on the search's
    return 0;
  }));
  c.node_ref.resize(3 * c.nodes.size());
  for (size_t i = 0; i < c.nodes.size(); ++i)
    for (int k = 0; k < 3; ++k) c.node_ref[3 * i + k] = PetscRealPart(xl[3 * c.nodes[i] + k]);
  c.ref_state = c.root_state;
  c.searched  = true;
  c.stats.searches++;
  c.stats.candidate_pairs = (PetscInt)c.pairs.size();
  c.stats.ghost_bodies    = c.ng;
  c.stats.near_bodies     = nnear;
  PetscCall(PetscLogEventEnd(EV_SEARCH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Contact forces at the current mesh positions xl (local, ghosted) and rigid positions
// s->cur_rq: nodal forces into fl; forces and moments on this rank's bodies into c.root_force
// (those computed on other ranks' ghost copies included).
PetscErrorCode ContactForces(FDEMScene s, const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl) {
  RDContact &c = s->c;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_CONTACT, 0, 0, 0, 0));
  PackStates(s);
  // 1. re-search when something moved more than half the buffer since the last search (all ranks
  //    together: the halo is rebuilt there), else refresh the ghosts' states
  PetscReal move = c.searched ? 0 : PETSC_MAX_REAL, gmove;
  if (c.searched) {
    for (size_t i = 0; i < c.nodes.size(); ++i) {
      PetscReal d = 0;
      for (int k = 0; k < 3; ++k) d += PetscSqr(PetscRealPart(xl[3 * c.nodes[i] + k]) - c.node_ref[3 * i + k]);
      move = std::max(move, std::sqrt(d));
    }
    for (PetscInt b = 0; b < c.n; ++b) {
      PetscReal dx = 0, dR = 0;
      for (int k = 0; k < 3; ++k) dx += PetscSqr(c.root_state[NS * b + k] - c.ref_state[NS * b + k]);
      for (int k = 0; k < 9; ++k) dR += PetscSqr(c.root_state[NS * b + 3 + k] - c.ref_state[NS * b + 3 + k]);
      move = std::max(move, std::sqrt(dx) + c.radius[b] * std::sqrt(dR)); // |R - R0|_2 <= |R - R0|_F
    }
  }
  PetscCallMPI(MPIU_Allreduce(&move, &gmove, 1, MPIU_REAL, MPI_MAX, s->comm));
  if (gmove > 0.5 * c.buffer) PetscCall(ContactSearch(s, xl));
  else {
    PetscCall(PetscLogEventBegin(EV_HALO, 0, 0, 0, 0));
    PetscCall(PetscSFBcastBegin(c.sf_state, MPIU_REAL, c.root_state.data(), c.ghost_state.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(c.sf_state, MPIU_REAL, c.root_state.data(), c.ghost_state.data(), MPI_REPLACE));
    PetscCall(PetscLogEventEnd(EV_HALO, 0, 0, 0, 0));
    for (PetscInt ci = 0; ci < c.n + c.ng; ++ci)
      if (c.near[ci]) UpdateWorld(s, ci);
  }
  // 2. the pairs: mesh cell a (this rank) against rigid skin tet b
  std::fill(c.root_force.begin(), c.root_force.end(), 0.0);
  std::fill(c.ghost_force.begin(), c.ghost_force.end(), 0.0);
  PetscReal             energy = 0;
  PetscInt              active = 0;
  std::array<double, 5> deep{0, -1, -1, -1, -1}; // worst initial overlap: ratio to the limit, pair index
  PetscCall(fdem::Guard(s->comm, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc;
    const bool                    dissipative = c.diss.normal_damping > 0 || c.diss.friction > 0 || c.diss.tangential_viscosity > 0;
    for (size_t ip = 0; ip < c.pairs.size(); ++ip) {
      const auto      &pr = c.pairs[ip];
      const auto      &A  = c.cells[pr[0]];
      const auto      &B  = s->rb->skins[c.skin[pr[1]]].tets[pr[2]];
      const auto      &w  = c.world[pr[1]];
      const PetscReal *st = c.State(pr[1]);
      Tet4             a, b;
      for (int k = 0; k < 4; ++k) {
        a[k] = Vec3(PetscRealPart(xl[3 * A[k]]), PetscRealPart(xl[3 * A[k] + 1]), PetscRealPart(xl[3 * A[k] + 2]));
        b[k] = w[B[k]];
      }
      if (!fdem::kernels::PotentialContactForce(a, b, c.penalty, c.penalty, pc)) continue;
      active++;
      energy += pc.energy;
      if (!c.checked_initial) {
        // deep: overlap energy above that of 10% of the smaller tetrahedron at mid potential
        const double va6 = std::fabs(dot(a[1] - a[0], cross(a[2] - a[0], a[3] - a[0]))), vb6 = std::fabs(dot(b[1] - b[0], cross(b[2] - b[0], b[3] - b[0])));
        const double ratio = pc.energy / (0.1 * std::min(va6, vb6) / 6 * c.penalty / 8);
        if (ratio > deep[0]) deep = {ratio, st[19], (double)c.cell_body[pr[0]], (double)c.cell_gid[pr[0]], (double)pr[2]};
      }
      std::array<Vec3, 4> fa = pc.fa, fb = pc.fb;
      const Vec3          xb(st[0], st[1], st[2]);
      if (dissipative) {
        std::array<Vec3, 4> va, vb, da, db;
        const Vec3          vB(st[12], st[13], st[14]), wB(st[15], st[16], st[17]);
        for (int k = 0; k < 4; ++k) {
          va[k] = vl ? Vec3(PetscRealPart(vl[3 * A[k]]), PetscRealPart(vl[3 * A[k] + 1]), PetscRealPart(vl[3 * A[k] + 2])) : Vec3(0, 0, 0);
          vb[k] = vB + cross(wB, b[k] - xb);
        }
        fdem::kernels::ContactDampingFriction(a, b, va, vb, pc, c.diss, da, db);
        for (int k = 0; k < 4; ++k) {
          fa[k] += da[k];
          fb[k] += db[k];
        }
      }
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d) fl[3 * A[k] + d] += fa[k][d];
      PetscReal *out = c.Force(pr[1]);
      for (int k = 0; k < 4; ++k) {
        const Vec3 m = cross(b[k] - xb, fb[k]);
        for (int d = 0; d < 3; ++d) {
          out[d] += fb[k][d];
          out[3 + d] += m[d];
        }
      }
    }
    return 0;
  }));
  if (!c.checked_initial) { // collective: every rank stops with the same message
    double worst;
    PetscCallMPI(MPI_Allreduce(&deep[0], &worst, 1, MPI_DOUBLE, MPI_MAX, s->comm));
    if (worst > 1) {
      std::array<double, 4> mine{-1, -1, -1, -1}, ids;
      if (deep[0] == worst) mine = {deep[1], deep[2], deep[3], deep[4]};
      PetscCallMPI(MPI_Allreduce(mine.data(), ids.data(), 4, MPI_DOUBLE, MPI_MAX, s->comm));
      const char *dname;
      PetscCall(FDEMDeformableGetBodyName(s->dfm, (PetscInt)ids[1], nullptr, &dname));
      SETERRQ(s->comm, PETSC_ERR_USER_INPUT,
              "Scene contact: rigid body %" PetscInt_FMT " and deformable body '%s' start interpenetrating deeply (rigid skin tetrahedron %" PetscInt_FMT " and mesh element %" PetscInt_FMT
              " overlap %.1f times more than allowed); separate them",
              (PetscInt)ids[0], dname, (PetscInt)ids[3], (PetscInt)ids[2], worst);
    }
    c.checked_initial = true;
  }
  // 3. forces on ghosts go back to their owners and are summed there
  PetscCall(PetscLogEventBegin(EV_HALO, 0, 0, 0, 0));
  PetscCall(PetscSFReduceBegin(c.sf_force, MPIU_REAL, c.ghost_force.data(), c.root_force.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(c.sf_force, MPIU_REAL, c.ghost_force.data(), c.root_force.data(), MPI_SUM));
  PetscCall(PetscLogEventEnd(EV_HALO, 0, 0, 0, 0));
  PetscReal loc[2] = {energy, (PetscReal)active}, glob[2];
  PetscCallMPI(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_SUM, s->comm));
  c.stats.energy       = glob[0];
  c.stats.active_pairs = (PetscInt)glob[1];
  c.stats.evaluations++;
  PetscCall(PetscLogEventEnd(EV_CONTACT, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
// The mesh's external-force hook while the scene runs: the mesh's own hook, then contact.
PetscErrorCode SceneExternalForce(FDEMDeformable dfm, PetscReal t, Vec xloc, Vec vloc, Vec floc, void *ctx) {
  FDEMScene s = (FDEMScene)ctx;
  PetscFunctionBegin;
  if (s->user_ext) PetscCall(s->user_ext(dfm, t, xloc, vloc, floc, s->user_ext_ctx));
  if (!s->evaluating || !s->contact) PetscFunctionReturn(0);
  const PetscScalar *xl, *vl = nullptr;
  PetscScalar       *fl;
  PetscCall(VecGetArrayRead(xloc, &xl));
  if (vloc) PetscCall(VecGetArrayRead(vloc, &vl));
  PetscCall(VecGetArray(floc, &fl));
  PetscCall(ContactForces(s, xl, vl, fl));
  PetscCall(VecRestoreArray(floc, &fl));
  if (vloc) PetscCall(VecRestoreArrayRead(vloc, &vl));
  PetscCall(VecRestoreArrayRead(xloc, &xl));
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- the split RHS and the drift
// Rigid pieces on views: positions q (= [x | R]), rigid state u (= [x | R | v | H]), accelerations a (= [F/m | M]).
PetscErrorCode RigidMomentum(FDEMScene s, TS ts, PetscReal t, const PetscScalar *q, const PetscScalar *u, PetscScalar *a) {
  FDEMRigid rb = s->rb;
  PetscFunctionBegin;
  PetscCall(VecPlaceArray(s->vr_q, q));
  PetscCall(VecPlaceArray(s->vr_a, a));
  PetscCall(VecPlaceArray(s->vr_state, u));
  rb->U = s->vr_state; // rigid-rigid contact reads the velocities there
  PetscCall(fdem::model::RigidRHSMomentum(ts, t, s->vr_q, s->vr_a, rb));
  PetscCall(VecResetArray(s->vr_state));
  PetscCall(VecResetArray(s->vr_a));
  PetscCall(VecResetArray(s->vr_q));
  if (s->contact) {
    const PetscInt nr = s->nr;
    for (PetscInt b = 0; b < nr; ++b) {
      if (rb->fixed[b]) continue;
      for (int k = 0; k < 3; ++k) {
        a[3 * b + k] += s->c.root_force[NF * b + k] / rb->mass[b];
        a[3 * nr + 3 * b + k] += s->c.root_force[NF * b + 3 + k];
      }
    }
  }
  PetscFunctionReturn(0);
}

// Forces at positions Q = [mesh x | rigid x, R], velocities from the TS's solution.
PetscErrorCode RHSMomentum(TS ts, PetscReal t, Vec Q, Vec A, void *ctx) {
  FDEMScene          s = (FDEMScene)ctx;
  const PetscScalar *q, *u;
  PetscScalar       *a;
  Vec                U;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_RHS, 0, 0, 0, 0));
  if (s->contact && !s->c.checked_dt) {
    // once per FDEMSceneSetUpTS, at the first force evaluation (the type and time step are final
    // by then): the contact frequency against the scheme's stability limit
    TSType         type;
    PetscReal      dt;
    PetscBool      found;
    FDEMSchemeInfo info;
    s->c.checked_dt = true;
    PetscCall(TSGetType(s->ts, &type));
    PetscCall(TSGetTimeStep(s->ts, &dt));
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    if (found && dt > 0) PetscCall(FDEMSceneCheckTimeStep(s, type, dt, &s->c.stats.dt_ratio));
  }
  PetscCall(TSGetSolution(s->ts, &U));
  PetscCall(VecGetArrayRead(Q, &q));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(A, &a));
  s->cur_rq     = q + 3 * s->nd;
  s->cur_ru     = u + OffRigid(s);
  s->evaluating = true;
  if (s->dfm) PetscCall(fdem::model::DeformableAcceleration(s->dfm, t, q, u + OffDefV(s), a + 6 * s->nr));
  if (s->rb) PetscCall(RigidMomentum(s, ts, t, q + 3 * s->nd, u + OffRigid(s), a));
  s->evaluating = false;
  PetscCall(VecRestoreArray(A, &a));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(Q, &q));
  PetscCall(PetscLogEventEnd(EV_RHS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Velocities of the positions P = [rigid v, H | mesh v] -> dQ = [mesh v | rigid v, [omega]x R] (R from the solution).
PetscErrorCode RHSPosition(TS ts, PetscReal, Vec P, Vec dQ, void *ctx) {
  FDEMScene          s = (FDEMScene)ctx;
  const PetscScalar *p, *u;
  PetscScalar       *dq;
  Vec                U;
  const PetscInt     nr = s->nr, nd = s->nd;
  PetscFunctionBegin;
  PetscCall(TSGetSolution(s->ts, &U));
  PetscCall(VecGetArrayRead(P, &p));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(dQ, &dq));
  for (PetscInt i = 0; i < 3 * nd; ++i) dq[i] = p[6 * nr + i];
  if (nr) fdem::model::RigidPositionRate(s->rb, p, &u[OffRigid(s) + 3 * nr], dq + 3 * nd);
  PetscCall(VecRestoreArray(dQ, &dq));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(VecRestoreArrayRead(P, &p));
  PetscFunctionReturn(0);
}

// Drift of length s: mesh x += s v (additive), rigid bodies by the rigid model's drift.
PetscErrorCode Drift(TS ts, PetscReal t, PetscReal h, Vec U, void *ctx) {
  FDEMScene    s = (FDEMScene)ctx;
  PetscScalar *u;
  PetscFunctionBegin;
  PetscCall(VecGetArray(U, &u));
  const PetscScalar *v = u + OffDefV(s);
  for (PetscInt i = 0; i < 3 * s->nd; ++i) u[i] += h * v[i];
  if (s->rb) {
    PetscCall(VecPlaceArray(s->vr_state, u + OffRigid(s)));
    PetscCall(fdem::model::RigidDrift(ts, t, h, s->vr_state, s->rb));
    PetscCall(VecResetArray(s->vr_state));
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode Unhook(FDEMScene s) {
  PetscFunctionBegin;
  if (s->hooked) PetscCall(FDEMDeformableSetExternalForce(s->dfm, s->user_ext, s->user_ext_ctx));
  s->hooked = false;
  PetscFunctionReturn(0);
}

} // namespace

// ---------------------------------------------------------------- public API
PetscErrorCode FDEMSceneCreate(MPI_Comm comm, FDEMScene *out) {
  PetscFunctionBegin;
  if (!FDEM_SCENE_CLASSID) {
    PetscCall(PetscClassIdRegister("FDEM Scene", &FDEM_SCENE_CLASSID));
    PetscCall(PetscLogEventRegister("FDEMSceneRHS", FDEM_SCENE_CLASSID, &EV_RHS));
    PetscCall(PetscLogEventRegister("FDEMSceneSearch", FDEM_SCENE_CLASSID, &EV_SEARCH));
    PetscCall(PetscLogEventRegister("FDEMSceneContact", FDEM_SCENE_CLASSID, &EV_CONTACT));
    PetscCall(PetscLogEventRegister("FDEMSceneHalo", FDEM_SCENE_CLASSID, &EV_HALO));
  }
  FDEMScene s = new (std::nothrow) _n_FDEMScene();
  PetscCheck(s, comm, PETSC_ERR_MEM, "Out of memory");
  s->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &s->rank));
  PetscCallMPI(MPI_Comm_size(comm, &s->size));
  *out = s;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneDestroy(FDEMScene *sp) {
  PetscFunctionBegin;
  if (!*sp) PetscFunctionReturn(0);
  FDEMScene s = *sp;
  PetscCall(Unhook(s));
  if (s->rb && s->rb->U == s->vr_state) s->rb->U = nullptr;
  PetscCall(VecDestroy(&s->vr_state));
  PetscCall(VecDestroy(&s->vr_q));
  PetscCall(VecDestroy(&s->vr_a));
  PetscCall(PetscSFDestroy(&s->c.sf_state));
  PetscCall(PetscSFDestroy(&s->c.sf_force));
  delete s;
  *sp = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetRigid(FDEMScene s, FDEMRigid rb) {
  PetscFunctionBegin;
  s->rb = rb;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetDeformable(FDEMScene s, FDEMDeformable dfm) {
  PetscFunctionBegin;
  PetscCall(Unhook(s));
  s->dfm = dfm;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetContact(FDEMScene s, PetscReal penalty, PetscReal damping, PetscReal friction, PetscReal buffer) {
  PetscFunctionBegin;
  PetscCheck(std::isfinite(penalty) && penalty >= 0, s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the contact penalty must be >= 0 (0: no contact), got %g", (double)penalty);
  PetscCheck(std::isfinite(buffer), s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the search buffer must be finite");
  PetscCall(fdem::contact::SetDissipation(s->comm, "FDEMScene contact", damping, friction, s->c.diss.tangential_viscosity, s->c.diss));
  s->c.penalty = penalty > 0 ? penalty : -1;
  s->c.buffer  = buffer;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetFromOptions(FDEMScene s) {
  PetscReal pen = s->c.penalty > 0 ? s->c.penalty : 0, damp = s->c.diss.normal_damping, mu = s->c.diss.friction, ct = s->c.diss.tangential_viscosity, buf = s->c.buffer;
  PetscFunctionBegin;
  PetscOptionsBegin(s->comm, nullptr, "fdem combined scene", "FDEMScene");
  PetscCall(PetscOptionsReal("-fdem_scene_contact_penalty", "Rigid-deformable contact penalty (Pa); 0 = no contact", "FDEMSceneSetContact", pen, &pen, nullptr));
  PetscCall(PetscOptionsReal("-fdem_scene_contact_damping", "Normal contact damping (Pa s/m)", "FDEMSceneSetContact", damp, &damp, nullptr));
  PetscCall(PetscOptionsReal("-fdem_scene_contact_friction", "Coulomb friction coefficient", "FDEMSceneSetContact", mu, &mu, nullptr));
  PetscCall(PetscOptionsReal("-fdem_scene_contact_tangential_viscosity", "Tangential viscosity regularising stick (Pa s/m)", "FDEMSceneSetContact", ct, &ct, nullptr));
  PetscCall(PetscOptionsReal("-fdem_scene_contact_buffer", "Search buffer (length; < 0: automatic)", "FDEMSceneSetContact", buf, &buf, nullptr));
  PetscOptionsEnd();
  PetscCall(FDEMSceneSetContact(s, pen, damp, mu, buf));
  PetscCall(fdem::contact::SetDissipation(s->comm, "FDEMScene contact", damp, mu, ct, s->c.diss));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneSetUpTS(FDEMScene s, TS ts, Vec *U) {
  PetscInt     start, nr = 0, nd = 0;
  PetscScalar *u;
  IS           isq, isp;
  PetscFunctionBegin;
  PetscCheck(s->rb || s->dfm, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneSetUpTS: the scene is empty; give it rigid bodies (FDEMSceneSetRigid) and/or a mesh (FDEMSceneSetDeformable)");
  if (s->rb) PetscCall(FDEMRigidGetNumBodies(s->rb, &nr, &s->nr_global));
  if (s->dfm) PetscCall(FDEMDeformableGetSizes(s->dfm, nullptr, nullptr, &nd, nullptr));
  s->nr = nr;
  s->nd = nd;
  PetscCall(VecCreateMPI(s->comm, 18 * nr + 6 * nd, PETSC_DETERMINE, U));
  PetscCall(PetscObjectSetName((PetscObject)*U, "scene state"));
  PetscCall(VecGetOwnershipRange(*U, &start, nullptr));
  PetscCall(VecGetArray(*U, &u));
  if (s->dfm) {
    Vec                x, v;
    const PetscScalar *xa, *va;
    PetscCall(FDEMDeformableGetPositions(s->dfm, &x));
    PetscCall(FDEMDeformableGetVelocities(s->dfm, &v));
    PetscCall(VecGetArrayRead(x, &xa));
    PetscCall(VecGetArrayRead(v, &va));
    for (PetscInt i = 0; i < 3 * nd; ++i) {
      u[i]              = xa[i];
      u[OffDefV(s) + i] = va[i];
    }
    PetscCall(VecRestoreArrayRead(v, &va));
    PetscCall(VecRestoreArrayRead(x, &xa));
  }
  if (s->rb) {
    FDEMRigid                rb = s->rb;
    fdem::model::RigidFields f;
    PetscScalar             *r = u + OffRigid(s);
    rb->n                      = nr;
    PetscCall(fdem::model::RigidGetFields(rb->sw, f));
    rb->mass.assign(f.mass, f.mass + nr);
    rb->inertia.assign(f.I, f.I + 3 * nr);
    rb->ids.assign(f.id, f.id + nr);
    rb->fixed.assign(f.fixed, f.fixed + nr);
    for (PetscInt i = 0; i < 3 * nr; ++i) {
      r[i]           = f.x[i];
      r[12 * nr + i] = f.v[i];
      r[15 * nr + i] = f.H[i];
    }
    for (PetscInt i = 0; i < 9 * nr; ++i) r[3 * nr + i] = f.R[i];
    PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
    PetscCall(VecDestroy(&s->vr_state));
    PetscCall(VecDestroy(&s->vr_q));
    PetscCall(VecDestroy(&s->vr_a));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 18 * nr, nullptr, &s->vr_state));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 12 * nr, nullptr, &s->vr_q));
    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, 6 * nr, nullptr, &s->vr_a));
  }
  PetscCall(VecRestoreArray(*U, &u));
  PetscCall(ISCreateStride(s->comm, 3 * nd + 12 * nr, start, 1, &isq));
  PetscCall(ISCreateStride(s->comm, 6 * nr + 3 * nd, start + 3 * nd + 12 * nr, 1, &isp));
  PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, s));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, s));
  // rotations are not additive: a scene with rigid bodies brings its own drift
  if (s->rb && s->nr_global > 0) PetscCall(FDEMTSSetDrift(ts, Drift, s));
  PetscCall(TSSetSolution(ts, *U));
  s->ts = ts;
  if (s->rb) {
    s->rb->U = s->vr_state;
    if (s->rb->contact_setup) PetscCall(s->rb->contact_setup(s->rb, s->rb->contact_ctx));
  }
  // rigid-deformable contact: only when asked for and there is something to touch
  s->contact = s->c.penalty > 0 && s->rb && s->dfm && s->nr_global > 0;
  PetscCall(Unhook(s));
  if (s->contact) {
    PetscCall(ContactSetUp(s));
    PetscCall(fdem::model::DeformableGetExternalForce(s->dfm, &s->user_ext, &s->user_ext_ctx));
    PetscCall(FDEMDeformableSetExternalForce(s->dfm, SceneExternalForce, s));
    s->hooked = true;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetLocalSizes(FDEMScene s, PetscInt *nr, PetscInt *nd) {
  PetscFunctionBegin;
  if (nr) *nr = s->nr;
  if (nd) *nd = s->nd;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneRestoreState(FDEMScene s, Vec U) {
  const PetscScalar *u;
  PetscInt           n;
  PetscFunctionBegin;
  PetscCall(VecGetLocalSize(U, &n));
  PetscCheck(n == 18 * s->nr + 6 * s->nd, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "FDEMScene: the state has %" PetscInt_FMT " local entries, expected %" PetscInt_FMT " (a vector from FDEMSceneSetUpTS)", n, 18 * s->nr + 6 * s->nd);
  PetscCall(VecGetArrayRead(U, &u));
  if (s->dfm) {
    Vec          x, v;
    PetscScalar *xa, *va;
    PetscCall(FDEMDeformableGetPositions(s->dfm, &x));
    PetscCall(FDEMDeformableGetVelocities(s->dfm, &v));
    PetscCall(VecGetArray(x, &xa));
    PetscCall(VecGetArray(v, &va));
    for (PetscInt i = 0; i < 3 * s->nd; ++i) {
      xa[i] = u[i];
      va[i] = u[OffDefV(s) + i];
    }
    PetscCall(VecRestoreArray(v, &va));
    PetscCall(VecRestoreArray(x, &xa));
  }
  if (s->rb && s->nr > 0) {
    fdem::model::RigidFields f;
    const PetscScalar       *r  = u + OffRigid(s);
    const PetscInt           nr = s->nr;
    PetscCall(fdem::model::RigidGetFields(s->rb->sw, f));
    for (PetscInt i = 0; i < 3 * nr; ++i) {
      f.x[i] = r[i];
      f.v[i] = r[12 * nr + i];
      f.H[i] = r[15 * nr + i];
    }
    for (PetscInt i = 0; i < 9 * nr; ++i) f.R[i] = r[3 * nr + i];
    PetscCall(fdem::model::RigidRestoreFields(s->rb->sw, f));
  }
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetInvariants(FDEMScene s, Vec U, PetscReal t, PetscReal P[3], PetscReal L[3], PetscReal E[4]) {
  PetscReal Pt[3] = {0, 0, 0}, Lt[3] = {0, 0, 0}, Et[4] = {0, 0, 0, 0};
  PetscFunctionBegin;
  PetscCall(FDEMSceneRestoreState(s, U));
  if (s->rb) PetscCall(FDEMRigidGetInvariants(s->rb, Pt, Lt, &Et[0]));
  if (s->dfm) {
    PetscReal m, com[3], Pd[3], Ld[3], grav;
    PetscCall(FDEMDeformableGetMomentum(s->dfm, nullptr, &m, com, Pd, Ld));
    PetscCall(FDEMDeformableGetEnergy(s->dfm, nullptr, &Et[1], &Et[2], &grav));
    for (int k = 0; k < 3; ++k) {
      Pt[k] += Pd[k];
      Lt[k] += Ld[k];
    }
  }
  if (s->contact) {
    // the contact energy at U: one force evaluation of the mesh with the rigid positions of U
    const PetscScalar *u;
    Vec                F, x;
    PetscCall(FDEMDeformableGetPositions(s->dfm, &x));
    PetscCall(VecDuplicate(x, &F));
    PetscCall(VecGetArrayRead(U, &u));
    s->cur_rq     = u + OffRigid(s);
    s->cur_ru     = u + OffRigid(s);
    s->evaluating = true;
    PetscCall(FDEMDeformableComputeForces(s->dfm, t, nullptr, F));
    s->evaluating = false;
    PetscCall(VecRestoreArrayRead(U, &u));
    PetscCall(VecDestroy(&F));
    Et[3] = s->c.stats.energy;
  }
  for (int k = 0; k < 3; ++k) {
    if (P) P[k] = Pt[k];
    if (L) L[k] = Lt[k];
  }
  if (E)
    for (int k = 0; k < 4; ++k) E[k] = Et[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMSceneGetContactStats(FDEMScene s, FDEMSceneContactStats *st) {
  PetscFunctionBegin;
  *st = s->c.stats;
  PetscFunctionReturn(0);
}


PetscErrorCode FDEMSceneCheckTimeStep(FDEMScene s, const char *scheme, PetscReal dt, PetscReal *ratio) {
  RDContact     &c = s->c;
  FDEMSchemeInfo info;
  PetscBool      found;
  PetscReal      loc[2] = {0, 0}, glob[2]; // the largest omega^2: rigid side, mesh side
  PetscFunctionBegin;
  PetscCheck(c.penalty > 0, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneCheckTimeStep: rigid-deformable contact is off; give a positive penalty (FDEMSceneSetContact or -fdem_scene_contact_penalty)");
  PetscCheck(s->contact, s->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMSceneCheckTimeStep: no rigid-deformable contact set up; call FDEMSceneSetUpTS first, with rigid bodies and a mesh in the scene");
  PetscCheck(dt > 0 && std::isfinite(dt), s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMSceneCheckTimeStep: the time step must be positive, got %g", (double)dt);
  PetscCall(FDEMSchemeInfoFind(scheme, &found, &info));
  PetscCheck(found, s->comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "FDEMSceneCheckTimeStep: %s is not an fdem TS type", scheme);
  { // rigid bodies: a flat contact over the cross-section A ~ (2 r)^2 pressed into skin tetrahedra of
    // height L feels k ~ penalty A / L (as FDEMContactCheckTimeStep); omega^2 = k / m
    fdem::model::RigidFields f;
    PetscInt                 n;
    PetscCall(DMSwarmGetLocalSize(s->rb->sw, &n));
    PetscCall(fdem::model::RigidGetFields(s->rb->sw, f));
    for (PetscInt b = 0; b < n; ++b) {
      if (f.fixed[b] || f.skin[b] < 0) continue;
      const PetscReal r = f.radius[b];
      const PetscReal L = PetscPowReal(std::max<PetscReal>(1e-300, 6 * r * r * r / (PetscReal)s->rb->skins[f.skin[b]].tets.size()), 1.0 / 3);
      loc[0]            = std::max(loc[0], c.penalty * 4 * r * r / (L * f.mass[b]));
    }
    PetscCall(fdem::model::RigidRestoreFields(s->rb->sw, f));
  }
  { // mesh: a face of area A pressed a depth d into a contact cell of height H over it feels
    // ~ penalty (d / H) A shared by 3 nodes: omega^2 = penalty A / (3 H m), m the smallest lumped
    // node mass (~ penalty / (rho H^2)); at the mesh's stored positions
    DM                 dm;
    Vec                X, M, Xl, Ml;
    const PetscScalar *xa, *ma;
    PetscCall(FDEMDeformableGetDM(s->dfm, &dm));
    PetscCall(FDEMDeformableGetPositions(s->dfm, &X));
    PetscCall(FDEMDeformableGetMasses(s->dfm, &M));
    PetscCall(DMGetLocalVector(dm, &Xl));
    PetscCall(DMGetLocalVector(dm, &Ml));
    PetscCall(DMGlobalToLocal(dm, X, INSERT_VALUES, Xl));
    PetscCall(DMGlobalToLocal(dm, M, INSERT_VALUES, Ml));
    PetscCall(VecGetArrayRead(Xl, &xa));
    PetscCall(VecGetArrayRead(Ml, &ma));
    for (const auto &T : c.cells) {
      Vec3 P[4];
      for (int q = 0; q < 4; ++q) P[q] = Vec3(PetscRealPart(xa[3 * T[q]]), PetscRealPart(xa[3 * T[q] + 1]), PetscRealPart(xa[3 * T[q] + 2]));
      const double V = std::fabs(dot(P[1] - P[0], cross(P[2] - P[0], P[3] - P[0]))) / 6;
      double       A = 0, m = PETSC_MAX_REAL;
      for (int o = 0; o < 4; ++o) A = std::max(A, 0.5 * norm(cross(P[(o + 2) % 4] - P[(o + 1) % 4], P[(o + 3) % 4] - P[(o + 1) % 4])));
      for (int q = 0; q < 4; ++q) m = std::min(m, (double)PetscRealPart(ma[3 * T[q]]));
      if (!(V > 0) || !(m > 0)) continue; // degenerate, or a node without mass
      loc[1] = std::max(loc[1], c.penalty * A * A / (9 * V * m)); // H = 3 V / A
    }
    PetscCall(VecRestoreArrayRead(Ml, &ma));
    PetscCall(VecRestoreArrayRead(Xl, &xa));
    PetscCall(DMRestoreLocalVector(dm, &Ml));
    PetscCall(DMRestoreLocalVector(dm, &Xl));
  }
  PetscCallMPI(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_MAX, s->comm));
  // the lighter side (per unit contact stiffness) oscillates fastest
  const PetscReal omega = std::sqrt(std::max(glob[0], glob[1]));
  const PetscReal r     = info.kcrit > 0 ? omega * dt / info.kcrit : PETSC_MAX_REAL;
  if (ratio) *ratio = r;
  if (r > 0.5)
    PetscCall(PetscPrintf(s->comm,
                          "WARNING fdem scene: the rigid-deformable contact frequency omega_c = %g (%s side) makes omega_c dt = %g, %.0f%% of the stability limit K_crit = %.4f of -ts_type %s; "
                          "reduce dt below %g or the penalty\n",
                          (double)omega, glob[0] >= glob[1] ? "rigid" : "mesh", (double)(omega * dt), (double)(100 * r), (double)info.kcrit, scheme, (double)(0.5 * info.kcrit / omega)));
  PetscFunctionReturn(0);
}
