// A combined scene (rigid bodies + deformable mesh) in one TS, and contact
// between rigid skins and the mesh's surface tetrahedra; see include/fdem/scene.h
// and doc/scene.md.
#include "../util/guard.hpp"
#include "../model/deformable_impl.hpp"
#include "../model/rigid_impl.hpp"
#include <fdem/scene.h>
#include <fdem/ts.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/nbs.hpp>
#include <fdem/kernels/rotation.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

namespace {
constexpr int NS = 20; // gathered rigid state per body: x(3) R(9) v(3) omega(3) fixed id

PetscClassId  FDEM_SCENE_CLASSID = 0;
PetscLogEvent EV_RHS = 0, EV_SEARCH = 0, EV_CONTACT = 0;

Mat3 Rot(const PetscReal *R) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = R[3 * r + c];
  return M;
}

struct RDContact {
  PetscReal                         penalty = -1, buffer = -1;
  fdem::kernels::ContactDissipation diss;
  // mesh side (this rank): cells in contact, as local node indices, and the nodes they use
  std::vector<std::array<int, 4>> cells;
  std::vector<int>                nodes;
  std::vector<PetscReal>          node_ref; // positions of `nodes` at the last search
  // rigid side (all bodies of all ranks, in rank order)
  PetscInt                        nbodies = 0;
  std::vector<int>                counts, displs; // bodies per rank
  std::vector<PetscInt>           skin;
  std::vector<PetscReal>          radius, state, state_ref, FM, FMsum;
  std::vector<std::vector<Vec3>>  world;
  std::vector<std::array<int, 3>> pairs; // (mesh cell, body, skin tet)
  bool                            searched = false;
  FDEMSceneContactStats           stats{};
  fdem::kernels::CellSearch       cs;
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
PetscErrorCode ContactSetUp(FDEMScene s) {
  RDContact &c = s->c;
  PetscFunctionBegin;
  // 1. mesh cells near the boundary: boundary faces are faces of one cell only
  std::vector<std::array<int, 4>> cells;
  std::vector<PetscInt>           ng;
  PetscInt                        nlocal;
  PetscCall(fdem::model::DeformableGetLocalCells(s->dfm, cells, ng, &nlocal));
  std::map<std::array<PetscInt, 3>, int> local;
  for (const auto &T : cells)
    for (int f = 0; f < 4; ++f) {
      std::array<PetscInt, 3> k = {ng[T[(f + 1) % 4]], ng[T[(f + 2) % 4]], ng[T[(f + 3) % 4]]};
      std::sort(k.begin(), k.end());
      local[k]++;
    }
  std::vector<PetscInt> single;
  for (const auto &kv : local)
    if (kv.second == 1) single.insert(single.end(), kv.first.begin(), kv.first.end());
  // faces on a partition boundary are single on two ranks: count them over all ranks
  PetscMPIInt         ln = (PetscMPIInt)single.size();
  std::vector<int>    cnt(s->size), dis(s->size + 1, 0);
  PetscCallMPI(MPI_Allgather(&ln, 1, MPI_INT, cnt.data(), 1, MPI_INT, s->comm));
  for (int r = 0; r < s->size; ++r) dis[r + 1] = dis[r] + cnt[r];
  std::vector<PetscInt> all(dis[s->size]);
  PetscCallMPI(MPI_Allgatherv(single.data(), ln, MPIU_INT, all.data(), cnt.data(), dis.data(), MPIU_INT, s->comm));
  std::map<std::array<PetscInt, 3>, int> global;
  for (size_t i = 0; i < all.size(); i += 3) global[{all[i], all[i + 1], all[i + 2]}]++;
  std::set<PetscInt> bnodes;
  for (const auto &kv : global)
    if (kv.second == 1) bnodes.insert(kv.first.begin(), kv.first.end());
  // cells with a vertex on the boundary take part (a rigid corner may enter through an edge)
  c.cells.clear();
  std::vector<char> used(nlocal, 0);
  for (const auto &T : cells) {
    bool on = false;
    for (int k = 0; k < 4; ++k) on = on || bnodes.count(ng[T[k]]);
    if (!on) continue;
    c.cells.push_back(T);
    for (int k = 0; k < 4; ++k) used[T[k]] = 1;
  }
  c.nodes.clear();
  for (PetscInt l = 0; l < nlocal; ++l)
    if (used[l]) c.nodes.push_back((int)l);
  PetscInt nsc = (PetscInt)c.cells.size();
  PetscCallMPI(MPIU_Allreduce(&nsc, &c.stats.surface_cells, 1, MPIU_INT, MPI_SUM, s->comm));
  // 2. the rigid bodies of every rank: skin and radius
  PetscMPIInt nrl = (PetscMPIInt)s->nr;
  c.counts.assign(s->size, 0);
  c.displs.assign(s->size + 1, 0);
  PetscCallMPI(MPI_Allgather(&nrl, 1, MPI_INT, c.counts.data(), 1, MPI_INT, s->comm));
  for (int r = 0; r < s->size; ++r) c.displs[r + 1] = c.displs[r] + c.counts[r];
  c.nbodies = c.displs[s->size];
  std::vector<PetscReal> mine(2 * s->nr), theirs(2 * c.nbodies);
  {
    fdem::model::RigidFields f;
    PetscCall(fdem::model::RigidGetFields(s->rb->sw, f));
    for (PetscInt b = 0; b < s->nr; ++b) {
      mine[2 * b]     = (PetscReal)f.skin[b];
      mine[2 * b + 1] = f.radius[b];
    }
    PetscCall(fdem::model::RigidRestoreFields(s->rb->sw, f));
  }
  std::vector<int> c2(s->size), d2(s->size);
  for (int r = 0; r < s->size; ++r) {
    c2[r] = 2 * c.counts[r];
    d2[r] = 2 * c.displs[r];
  }
  PetscCallMPI(MPI_Allgatherv(mine.data(), 2 * nrl, MPIU_REAL, theirs.data(), c2.data(), d2.data(), MPIU_REAL, s->comm));
  c.skin.resize(c.nbodies);
  c.radius.resize(c.nbodies);
  for (PetscInt g = 0; g < c.nbodies; ++g) {
    c.skin[g]   = (PetscInt)theirs[2 * g];
    c.radius[g] = theirs[2 * g + 1];
  }
  c.state.assign(NS * c.nbodies, 0);
  c.FM.assign(6 * c.nbodies, 0);
  c.FMsum.assign(6 * c.nbodies, 0);
  c.world.assign(c.nbodies, {});
  // 3. default buffer: 20% of the mean bounding radius of the rigid skin tetrahedra
  if (c.buffer < 0) {
    PetscReal sum[2] = {0, 0}, gsum[2];
    for (PetscInt g = 0; g < c.nbodies; ++g) {
      if (c.skin[g] < 0) continue;
      const auto &sk = s->rb->skins[c.skin[g]];
      for (const auto &T : sk.tets) {
        const Vec3 ct = 0.25 * (sk.nodes[T[0]] + sk.nodes[T[1]] + sk.nodes[T[2]] + sk.nodes[T[3]]);
        double     r  = 0;
        for (int k = 0; k < 4; ++k) r = std::max(r, norm(sk.nodes[T[k]] - ct));
        sum[0] += r / s->size; // every rank adds the same: divide so the global sum counts it once
        sum[1] += 1.0 / s->size;
      }
    }
    PetscCallMPI(MPIU_Allreduce(sum, gsum, 2, MPIU_REAL, MPIU_SUM, s->comm));
    c.buffer = gsum[1] > 0 ? 0.2 * gsum[0] / gsum[1] : 0;
  }
  c.stats.buffer = c.buffer;
  c.searched     = false;
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- contact evaluation
PetscErrorCode ContactSearch(FDEMScene s, const PetscScalar *xl) {
  RDContact &c = s->c;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_SEARCH, 0, 0, 0, 0));
  std::vector<double> centres, radii;
  std::vector<int>    kind; // >= 0: mesh cell; < 0: -(1 + index into rig)
  std::vector<std::array<int, 2>> rig;
  double                          dmax = 0;
  auto add = [&](const Vec3 *p0, const Vec3 *p1, const Vec3 *p2, const Vec3 *p3, int k) {
    const Vec3 ct = 0.25 * (*p0 + *p1 + *p2 + *p3);
    double     r  = std::max({norm(*p0 - ct), norm(*p1 - ct), norm(*p2 - ct), norm(*p3 - ct)}) + 0.5 * c.buffer;
    centres.insert(centres.end(), {ct.x, ct.y, ct.z});
    radii.push_back(r);
    kind.push_back(k);
    dmax = std::max(dmax, 2 * r);
  };
  for (size_t e = 0; e < c.cells.size(); ++e) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Vec3(xl[3 * c.cells[e][k]], xl[3 * c.cells[e][k] + 1], xl[3 * c.cells[e][k] + 2]);
    add(&p[0], &p[1], &p[2], &p[3], (int)e);
  }
  for (PetscInt g = 0; g < c.nbodies; ++g) {
    if (c.skin[g] < 0) continue;
    const auto &sk = s->rb->skins[c.skin[g]];
    const auto &w  = c.world[g];
    for (size_t t = 0; t < sk.tets.size(); ++t) {
      const auto &T = sk.tets[t];
      rig.push_back({(int)g, (int)t});
      add(&w[T[0]], &w[T[1]], &w[T[2]], &w[T[3]], -(int)rig.size());
    }
  }
  c.pairs.clear();
  if (!c.cells.empty() && !rig.empty()) {
    PetscCall(fdem::Guard(s->comm, [&]() -> PetscErrorCode {
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
      return 0;
    }));
    std::sort(c.pairs.begin(), c.pairs.end()); // a fixed order: results do not depend on the search's
  }
  c.node_ref.resize(3 * c.nodes.size());
  for (size_t i = 0; i < c.nodes.size(); ++i)
    for (int k = 0; k < 3; ++k) c.node_ref[3 * i + k] = PetscRealPart(xl[3 * c.nodes[i] + k]);
  c.state_ref = c.state;
  c.searched  = true;
  c.stats.searches++;
  c.stats.candidate_pairs = (PetscInt)c.pairs.size();
  PetscCall(PetscLogEventEnd(EV_SEARCH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Contact forces at the current mesh positions xl (local, ghosted) and rigid
// positions s->cur_rq: nodal forces into fl, rigid (F, M) summed over ranks into c.FMsum.
PetscErrorCode ContactForces(FDEMScene s, const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl) {
  RDContact     &c  = s->c;
  const PetscInt nr = s->nr;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_CONTACT, 0, 0, 0, 0));
  // 1. every rank gets every rigid body's state
  std::vector<PetscReal> mine(NS * nr);
  for (PetscInt b = 0; b < nr; ++b) {
    PetscReal *st = &mine[NS * b];
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
  {
    std::vector<int> cn(s->size), ds(s->size);
    for (int r = 0; r < s->size; ++r) {
      cn[r] = NS * c.counts[r];
      ds[r] = NS * c.displs[r];
    }
    PetscCallMPI(MPI_Allgatherv(mine.data(), NS * (int)nr, MPIU_REAL, c.state.data(), cn.data(), ds.data(), MPIU_REAL, s->comm));
  }
  for (PetscInt g = 0; g < c.nbodies; ++g) {
    if (c.skin[g] < 0) continue;
    const auto      &sk = s->rb->skins[c.skin[g]];
    const PetscReal *st = &c.state[NS * g];
    const Mat3       R  = Rot(&st[3]);
    const Vec3       x(st[0], st[1], st[2]);
    c.world[g].resize(sk.nodes.size());
    for (size_t i = 0; i < sk.nodes.size(); ++i) c.world[g][i] = x + R * sk.nodes[i];
  }
  // 2. re-search when something moved more than half the buffer since the last search
  PetscReal move = c.searched ? 0 : PETSC_MAX_REAL;
  if (c.searched) {
    for (size_t i = 0; i < c.nodes.size(); ++i) {
      PetscReal d = 0;
      for (int k = 0; k < 3; ++k) d += PetscSqr(PetscRealPart(xl[3 * c.nodes[i] + k]) - c.node_ref[3 * i + k]);
      move = std::max(move, std::sqrt(d));
    }
    for (PetscInt g = 0; g < c.nbodies; ++g) {
      PetscReal dx = 0, dR = 0;
      for (int k = 0; k < 3; ++k) dx += PetscSqr(c.state[NS * g + k] - c.state_ref[NS * g + k]);
      for (int k = 0; k < 9; ++k) dR += PetscSqr(c.state[NS * g + 3 + k] - c.state_ref[NS * g + 3 + k]);
      move = std::max(move, std::sqrt(dx) + c.radius[g] * std::sqrt(dR));
    }
  }
  if (move > 0.5 * c.buffer) PetscCall(ContactSearch(s, xl));
  // 3. the pairs: mesh cell a (this rank) against rigid skin tet b
  std::fill(c.FM.begin(), c.FM.end(), 0.0);
  PetscReal energy = 0;
  PetscInt  active = 0;
  PetscCall(fdem::Guard(s->comm, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc;
    const bool                    dissipative = c.diss.normal_damping > 0 || c.diss.friction > 0 || c.diss.tangential_viscosity > 0;
    for (const auto &pr : c.pairs) {
      const auto      &A  = c.cells[pr[0]];
      const auto      &sk = s->rb->skins[c.skin[pr[1]]];
      const auto      &B  = sk.tets[pr[2]];
      const auto      &w  = c.world[pr[1]];
      const PetscReal *st = &c.state[NS * pr[1]];
      Tet4             a, b;
      for (int k = 0; k < 4; ++k) {
        a[k] = Vec3(xl[3 * A[k]], xl[3 * A[k] + 1], xl[3 * A[k] + 2]);
        b[k] = w[B[k]];
      }
      if (!fdem::kernels::PotentialContactForce(a, b, c.penalty, c.penalty, pc)) continue;
      active++;
      energy += pc.energy;
      std::array<Vec3, 4> fa = pc.fa, fb = pc.fb;
      const Vec3          xb(st[0], st[1], st[2]);
      if (dissipative) {
        std::array<Vec3, 4> va, vb, da, db;
        const Vec3          vB(st[12], st[13], st[14]), wB(st[15], st[16], st[17]);
        for (int k = 0; k < 4; ++k) {
          va[k] = vl ? Vec3(vl[3 * A[k]], vl[3 * A[k] + 1], vl[3 * A[k] + 2]) : Vec3(0, 0, 0);
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
      PetscReal *out = &c.FM[6 * pr[1]];
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
  // 4. rigid forces and torques summed over ranks (each pair was computed by the rank holding the mesh cell)
  PetscCallMPI(MPIU_Allreduce(c.FM.data(), c.FMsum.data(), (PetscMPIInt)(6 * c.nbodies), MPIU_REAL, MPIU_SUM, s->comm));
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
    const PetscInt nr = s->nr, g0 = s->c.displs[s->rank];
    for (PetscInt b = 0; b < nr; ++b) {
      if (rb->fixed[b]) continue;
      for (int k = 0; k < 3; ++k) {
        a[3 * b + k] += s->c.FMsum[6 * (g0 + b) + k] / rb->mass[b];
        a[3 * nr + 3 * b + k] += s->c.FMsum[6 * (g0 + b) + 3 + k];
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
  PetscCheck(std::isfinite(damping) && damping >= 0, s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the contact damping must be >= 0, got %g", (double)damping);
  PetscCheck(std::isfinite(friction) && friction >= 0, s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the friction coefficient must be >= 0, got %g", (double)friction);
  PetscCheck(std::isfinite(buffer), s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the search buffer must be finite");
  s->c.penalty             = penalty > 0 ? penalty : -1;
  s->c.diss.normal_damping = damping;
  s->c.diss.friction       = friction;
  s->c.buffer              = buffer;
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
  PetscCheck(ct >= 0 && std::isfinite(ct), s->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMScene: the tangential viscosity must be >= 0, got %g", (double)ct);
  PetscCall(FDEMSceneSetContact(s, pen, damp, mu, buf));
  s->c.diss.tangential_viscosity = ct;
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
