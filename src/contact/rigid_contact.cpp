// Contact between rigid bodies: halo of ghost bodies (PetscSF), tetrahedron
// cell search with a buffer, Munjiza's potential contact force, damping and
// friction; forces and torques returned to the rigid model's momentum RHS.
#include "../util/guard.hpp"
#include "../util/halo.hpp"
#include "params.hpp"
#include <fdem/contact.h>
#include <petscsf.h>
#include <fdem/ts.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/nbs.hpp>
#include <fdem/kernels/rotation.hpp>
#include "../model/rigid_impl.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

namespace {
constexpr int NS = 20; // per body: x(3) R(9) v(3) omega(3) fixed id
constexpr int NF = 6;  // per body: F(3) M(3)

PetscClassId  FDEM_CONTACT_CLASSID = 0;
PetscLogEvent EV_DETECT = 0, EV_FORCE = 0, EV_HALO = 0;
} // namespace

struct _n_FDEMContact {
  FDEMRigid                         rb;
  MPI_Comm                          comm;
  PetscMPIInt                       rank, size;
  PetscReal                         penalty = -1, buffer = -1;
  fdem::kernels::ContactDissipation diss;
  // per TS segment
  PetscInt               n = 0, ng = 0;           // local and ghost bodies
  PetscSF                sf_state = nullptr, sf_force = nullptr;
  std::vector<PetscReal> root_state, ghost_state, root_force, ghost_force;
  std::vector<PetscInt>  skin;                    // skin index of each combined body (local then ghosts)
  std::vector<PetscReal> radius;
  std::vector<PetscReal> ref_x, ref_R;            // local positions at the last search
  bool                   searched = false, checked_initial = false;
  // candidate pairs (combined body a, tet ta, body b, tet tb)
  std::vector<std::array<int, 4>> pairs;
  // world coordinates of each combined body's skin nodes (filled per evaluation)
  std::vector<std::vector<Vec3>> world;
  std::vector<int>               world_stamp;
  int                            stamp = 0;
  FDEMContactStats               stats{};
};

namespace {

const fdem::model::Skin *SkinOf(FDEMContact c, PetscInt ci) {
  const PetscInt s = c->skin[ci];
  return s >= 0 ? &c->rb->skins[s] : nullptr;
}

const PetscReal *StateOf(FDEMContact c, PetscInt ci) { return ci < c->n ? &c->root_state[NS * ci] : &c->ghost_state[NS * (ci - c->n)]; }

Mat3 Rot(const PetscReal *s) {
  Mat3 R;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) R.m[r][k] = s[3 + 3 * r + k];
  return R;
}

const std::vector<Vec3> &World(FDEMContact c, PetscInt ci) {
  if (c->world_stamp[ci] != c->stamp) {
    const auto      *sk = SkinOf(c, ci);
    const PetscReal *s  = StateOf(c, ci);
    const Mat3       R  = Rot(s);
    const Vec3       x(s[0], s[1], s[2]);
    auto            &w = c->world[ci];
    w.resize(sk->nodes.size());
    for (size_t i = 0; i < sk->nodes.size(); ++i) w[i] = x + R * sk->nodes[i];
    c->world_stamp[ci] = c->stamp;
  }
  return c->world[ci];
}

// Which ranks need a copy of a body at x: those whose slab lies within reach + (the largest radius on that rank).
void NeededBy(FDEMRigid rb, const PetscReal *x, PetscReal reach, const std::vector<PetscReal> &rmax_of, std::vector<PetscMPIInt> &ranks) {
  ranks.clear();
  if (rb->axis < 0 || rb->size == 1) return;
  const int       a = rb->axis;
  const PetscReal w = (rb->hi[a] - rb->lo[a]) / rb->size;
  for (PetscMPIInt s = 0; s < rb->size; ++s) {
    if (s == rb->rank) continue;
    PetscReal slo = rb->lo[a] + s * w, shi = slo + w;
    if (s == 0) slo = -PETSC_MAX_REAL;
    if (s == rb->size - 1) shi = PETSC_MAX_REAL;
    const PetscReal d = x[a] < slo ? slo - x[a] : (x[a] > shi ? x[a] - shi : 0);
    if (d <= reach + rmax_of[s]) ranks.push_back(s);
  }
}

// Rebuild the ghost set (PetscSF) and the candidate tetrahedron pairs from the current root states.
PetscErrorCode Search(FDEMContact c) {
  FDEMRigid rb = c->rb;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_DETECT, 0, 0, 0, 0));
  const PetscInt n = c->n;
  // the largest body radius held by each rank: rank s needs my body b when b comes within
  // r_b + (largest radius on s) + buffer of s's slab (a big fixed floor then widens the halo of its own rank only)
  PetscReal              rmax = 0;
  std::vector<PetscReal> rmax_of(c->size);
  for (PetscInt b = 0; b < n; ++b) rmax = std::max(rmax, c->radius[b]);
  PetscCallMPI(MPI_Allgather(&rmax, 1, MPIU_REAL, rmax_of.data(), 1, MPIU_REAL, c->comm));
  // 1. who needs which of my bodies
  std::vector<std::vector<PetscInt>> send(c->size);
  std::vector<PetscMPIInt>           ranks;
  for (PetscInt b = 0; b < n; ++b) {
    NeededBy(rb, &c->root_state[NS * b], c->radius[b] + c->buffer, rmax_of, ranks);
    for (PetscMPIInt s : ranks) send[s].push_back(b);
  }
  std::vector<PetscSFNode> ghosts;
  PetscCall(fdem::HaloExchange(c->comm, send, ghosts));
  // 2. the SFs: leaves = ghost copies, roots = my bodies (NS reals each for states, NF for forces)
  c->ng = (PetscInt)ghosts.size();
  PetscCall(fdem::HaloSF(c->comm, n, ghosts, NS, &c->sf_state));
  PetscCall(fdem::HaloSF(c->comm, n, ghosts, NF, &c->sf_force));
  c->ghost_state.assign(NS * c->ng, 0);
  c->ghost_force.assign(NF * c->ng, 0);
  PetscCall(PetscSFBcastBegin(c->sf_state, MPIU_REAL, c->root_state.data(), c->ghost_state.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(c->sf_state, MPIU_REAL, c->root_state.data(), c->ghost_state.data(), MPI_REPLACE));
  // ghost skins and radii (static body data, replicated skins)
  {
    std::vector<PetscReal> root_static(2 * n), ghost_static(2 * c->ng);
    for (PetscInt b = 0; b < n; ++b) {
      root_static[2 * b]     = (PetscReal)c->skin[b];
      root_static[2 * b + 1] = c->radius[b];
    }
    PetscSF sf = nullptr;
    PetscCall(fdem::HaloSF(c->comm, n, ghosts, 2, &sf));
    PetscCall(PetscSFBcastBegin(sf, MPIU_REAL, root_static.data(), ghost_static.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(sf, MPIU_REAL, root_static.data(), ghost_static.data(), MPI_REPLACE));
    PetscCall(PetscSFDestroy(&sf));
    c->skin.resize(n + c->ng);
    c->radius.resize(n + c->ng);
    for (PetscInt i = 0; i < c->ng; ++i) {
      c->skin[n + i]   = (PetscInt)ghost_static[2 * i];
      c->radius[n + i] = ghost_static[2 * i + 1];
    }
  }
  c->world.assign(n + c->ng, {});
  c->world_stamp.assign(n + c->ng, -1);
  c->stamp++;
  // 3. candidate tetrahedron pairs by a cell search over all skin tetrahedra (bounding spheres + buffer/2)
  std::vector<double>             centres, radii;
  std::vector<std::array<int, 2>> owner; // (combined body, tet)
  double                          dmax = 0;
  for (PetscInt ci = 0; ci < n + c->ng; ++ci) {
    const auto *sk = SkinOf(c, ci);
    if (!sk) continue;
    const auto &w = World(c, ci);
    for (size_t t = 0; t < sk->tets.size(); ++t) {
      const auto &T  = sk->tets[t];
      const Vec3  ct = 0.25 * (w[T[0]] + w[T[1]] + w[T[2]] + w[T[3]]);
      double      r  = 0;
      for (int k = 0; k < 4; ++k) r = std::max(r, norm(w[T[k]] - ct));
      r += 0.5 * c->buffer;
      centres.insert(centres.end(), {ct.x, ct.y, ct.z});
      radii.push_back(r);
      owner.push_back({(int)ci, (int)t});
      dmax = std::max(dmax, 2 * r);
    }
  }
  c->pairs.clear();
  { // fdem::Guard is collective: every rank enters it
    PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
      if (radii.empty()) return 0;
      fdem::kernels::CellSearch        cs;
      std::vector<std::pair<int, int>> tp;
      cs.Build(centres.data(), radii.data(), (int)radii.size(), dmax * (1 + 1e-12));
      cs.FindPairs(tp);
      for (auto &pr : tp) {
        const auto A = owner[pr.first], B = owner[pr.second];
        if (A[0] == B[0]) continue;
        const PetscReal *sa = StateOf(c, A[0]), *sb = StateOf(c, B[0]);
        if (sa[18] > 0 && sb[18] > 0) continue; // fixed against fixed
        // each body pair is computed once: by the rank holding the body with the smaller id
        const bool a_first = sa[19] < sb[19];
        const int  first   = a_first ? A[0] : B[0];
        if (first >= c->n) continue;
        c->pairs.push_back({A[0], A[1], B[0], B[1]});
      }
      return 0;
    }));
  }
  c->ref_x.resize(3 * n);
  c->ref_R.resize(9 * n);
  for (PetscInt b = 0; b < n; ++b) {
    for (int k = 0; k < 3; ++k) c->ref_x[3 * b + k] = c->root_state[NS * b + k];
    for (int k = 0; k < 9; ++k) c->ref_R[9 * b + k] = c->root_state[NS * b + 3 + k];
  }
  c->searched = true;
  c->stats.searches++;
  c->stats.candidate_pairs = (PetscInt)c->pairs.size();
  c->stats.ghosts          = c->ng;
  PetscCall(PetscLogEventEnd(EV_DETECT, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// The contact hook of the rigid model: q = local positions [x(3n) | R(9n)], FM += [F(3n) | M(3n)].
PetscErrorCode ContactForces(FDEMRigid rb, PetscReal, const PetscScalar *q, PetscScalar *FM, void *ctx) {
  FDEMContact    c = (FDEMContact)ctx;
  const PetscInt n = rb->n;
  PetscFunctionBegin;
  PetscCheck(c->penalty > 0, c->comm, PETSC_ERR_ARG_WRONGSTATE, "Contact: the penalty is not set; give -fdem_contact_penalty <Pa> (a positive modulus)");
  // 1. root states: positions from q, velocities from the current solution
  {
    const PetscScalar *u;
    PetscCall(VecGetArrayRead(rb->U, &u));
    for (PetscInt b = 0; b < n; ++b) {
      PetscReal *s = &c->root_state[NS * b];
      for (int k = 0; k < 3; ++k) s[k] = PetscRealPart(q[3 * b + k]);
      for (int k = 0; k < 9; ++k) s[3 + k] = PetscRealPart(q[3 * n + 9 * b + k]);
      for (int k = 0; k < 3; ++k) s[12 + k] = PetscRealPart(u[12 * n + 3 * b + k]);
      const Vec3 w = fdem::kernels::BodyOmega(Rot(s), Vec3(rb->inertia[3 * b], rb->inertia[3 * b + 1], rb->inertia[3 * b + 2]),
                                              Vec3(PetscRealPart(u[15 * n + 3 * b]), PetscRealPart(u[15 * n + 3 * b + 1]), PetscRealPart(u[15 * n + 3 * b + 2])));
      for (int k = 0; k < 3; ++k) s[15 + k] = w[k];
      s[18] = (PetscReal)rb->fixed[b];
      s[19] = (PetscReal)rb->ids[b];
    }
    PetscCall(VecRestoreArrayRead(rb->U, &u));
  }
  // 2. re-search when some body moved more than half the buffer since the last search
  PetscReal move = c->searched ? 0 : PETSC_MAX_REAL, gmove;
  if (c->searched)
    for (PetscInt b = 0; b < n; ++b) {
      PetscReal dx = 0, dR = 0;
      for (int k = 0; k < 3; ++k) dx += PetscSqr(c->root_state[NS * b + k] - c->ref_x[3 * b + k]);
      for (int k = 0; k < 9; ++k) dR += PetscSqr(c->root_state[NS * b + 3 + k] - c->ref_R[9 * b + k]);
      move = std::max(move, std::sqrt(dx) + c->radius[b] * std::sqrt(dR)); // |R - R0|_2 <= |R - R0|_F
    }
  PetscCallMPI(MPI_Allreduce(&move, &gmove, 1, MPIU_REAL, MPI_MAX, c->comm));
  if (gmove > 0.5 * c->buffer) PetscCall(Search(c));
  else {
    PetscCall(PetscLogEventBegin(EV_HALO, 0, 0, 0, 0));
    PetscCall(PetscSFBcastBegin(c->sf_state, MPIU_REAL, c->root_state.data(), c->ghost_state.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(c->sf_state, MPIU_REAL, c->root_state.data(), c->ghost_state.data(), MPI_REPLACE));
    PetscCall(PetscLogEventEnd(EV_HALO, 0, 0, 0, 0));
    c->stamp++;
  }
  // 3. the pairs
  PetscCall(PetscLogEventBegin(EV_FORCE, 0, 0, 0, 0));
  c->root_force.assign(NF * n, 0);
  c->ghost_force.assign(NF * c->ng, 0);
  PetscReal             energy = 0;
  PetscInt              active = 0;
  std::array<double, 5> deep{0, -1, -1, -1, -1}; // worst initial overlap: ratio to the limit, bodies, tetrahedra
  PetscCall(fdem::Guard(c->comm, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc;
    std::array<Vec3, 4>           fa, fb, va, vb;
    for (const auto &pr : c->pairs) {
      const auto &wa = World(c, pr[0]), &wb = World(c, pr[2]);
      const auto &Ta = SkinOf(c, pr[0])->tets[pr[1]], &Tb = SkinOf(c, pr[2])->tets[pr[3]];
      const Tet4  a{wa[Ta[0]], wa[Ta[1]], wa[Ta[2]], wa[Ta[3]]}, b{wb[Tb[0]], wb[Tb[1]], wb[Tb[2]], wb[Tb[3]]};
      if (!fdem::kernels::PotentialContactForce(a, b, c->penalty, c->penalty, pc)) continue;
      active++;
      energy += pc.energy;
      const PetscReal *sa = StateOf(c, pr[0]), *sb = StateOf(c, pr[2]);
      const Vec3       xa(sa[0], sa[1], sa[2]), xb(sb[0], sb[1], sb[2]);
      if (!c->checked_initial) {
        // deep initial interpenetration: overlap energy above that of 10% of the smaller tetrahedron at mid potential
        const double va6 = std::fabs(dot(a[1] - a[0], cross(a[2] - a[0], a[3] - a[0]))), vb6 = std::fabs(dot(b[1] - b[0], cross(b[2] - b[0], b[3] - b[0])));
        const double ratio = pc.energy / (0.1 * std::min(va6, vb6) / 6 * c->penalty / 8);
        if (ratio > deep[0]) deep = {ratio, sa[19], sb[19], (double)pr[1], (double)pr[3]};
      }
      fa = pc.fa;
      fb = pc.fb;
      if (c->diss.normal_damping > 0 || c->diss.friction > 0 || c->diss.tangential_viscosity > 0) {
        const Vec3 vA(sa[12], sa[13], sa[14]), wA(sa[15], sa[16], sa[17]), vB(sb[12], sb[13], sb[14]), wB(sb[15], sb[16], sb[17]);
        for (int k = 0; k < 4; ++k) {
          va[k] = vA + cross(wA, a[k] - xa);
          vb[k] = vB + cross(wB, b[k] - xb);
        }
        std::array<Vec3, 4> da, db;
        fdem::kernels::ContactDampingFriction(a, b, va, vb, pc, c->diss, da, db);
        for (int k = 0; k < 4; ++k) {
          fa[k] += da[k];
          fb[k] += db[k];
        }
      }
      auto add = [&](PetscInt ci, const Tet4 &t, const std::array<Vec3, 4> &f, const Vec3 &xc) {
        PetscReal *out = ci < c->n ? &c->root_force[NF * ci] : &c->ghost_force[NF * (ci - c->n)];
        for (int k = 0; k < 4; ++k) {
          const Vec3 m = cross(t[k] - xc, f[k]);
          for (int d = 0; d < 3; ++d) {
            out[d] += f[k][d];
            out[3 + d] += m[d];
          }
        }
      };
      add(pr[0], a, fa, xa);
      add(pr[2], b, fb, xb);
    }
    return 0;
  }));
  if (!c->checked_initial) { // collective: every rank stops with the same message
    double worst;
    PetscCallMPI(MPI_Allreduce(&deep[0], &worst, 1, MPI_DOUBLE, MPI_MAX, c->comm));
    if (worst > 1) {
      std::array<double, 4> mine{-1, -1, -1, -1}, ids;
      if (deep[0] == worst) mine = {deep[1], deep[2], deep[3], deep[4]};
      PetscCallMPI(MPI_Allreduce(mine.data(), ids.data(), 4, MPI_DOUBLE, MPI_MAX, c->comm));
      SETERRQ(c->comm, PETSC_ERR_USER_INPUT, "Contact: bodies %d and %d start interpenetrating deeply (their skin tetrahedra %d and %d overlap %.1f times more than allowed); separate them", (int)ids[0], (int)ids[1],
              (int)ids[2], (int)ids[3], worst);
    }
  }
  // forces on ghosts go back to their owners and are summed
  PetscCall(PetscSFReduceBegin(c->sf_force, MPIU_REAL, c->ghost_force.data(), c->root_force.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(c->sf_force, MPIU_REAL, c->ghost_force.data(), c->root_force.data(), MPI_SUM));
  for (PetscInt b = 0; b < n; ++b)
    for (int d = 0; d < 3; ++d) {
      FM[3 * b + d] += c->root_force[NF * b + d];
      FM[3 * n + 3 * b + d] += c->root_force[NF * b + 3 + d];
    }
  c->checked_initial = true;
  c->stats.evaluations++;
  c->stats.active_pairs = active;
  PetscCallMPI(MPI_Allreduce(&energy, &c->stats.energy, 1, MPIU_REAL, MPI_SUM, c->comm));
  PetscCall(PetscLogEventEnd(EV_FORCE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// At FDEMRigidSetUpTS: the local bodies changed (migration): start over.
PetscErrorCode ContactSetUp(FDEMRigid rb, void *ctx) {
  FDEMContact         c = (FDEMContact)ctx;
  fdem::model::RigidFields f;
  PetscFunctionBegin;
  c->n = rb->n;
  c->root_state.assign(NS * c->n, 0);
  c->skin.resize(c->n);
  c->radius.resize(c->n);
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < c->n; ++b) {
    c->skin[b]   = f.skin[b];
    c->radius[b] = f.radius[b];
  }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  if (c->buffer < 0) {
    PetscReal s[2] = {0, (PetscReal)c->n}, g[2];
    for (PetscInt b = 0; b < c->n; ++b) s[0] += c->radius[b];
    PetscCallMPI(MPI_Allreduce(s, g, 2, MPIU_REAL, MPI_SUM, c->comm));
    c->buffer = g[1] > 0 ? 0.1 * g[0] / g[1] : 0;
  }
  c->searched = false;
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FDEMContactCreate(FDEMRigid rb, FDEMContact *out) {
  PetscFunctionBegin;
  if (!FDEM_CONTACT_CLASSID) {
    PetscCall(PetscClassIdRegister("FDEM Contact", &FDEM_CONTACT_CLASSID));
    PetscCall(PetscLogEventRegister("FDEMContactDetect", FDEM_CONTACT_CLASSID, &EV_DETECT));
    PetscCall(PetscLogEventRegister("FDEMContactForce", FDEM_CONTACT_CLASSID, &EV_FORCE));
    PetscCall(PetscLogEventRegister("FDEMContactHalo", FDEM_CONTACT_CLASSID, &EV_HALO));
  }
  FDEMContact c = new (std::nothrow) _n_FDEMContact();
  PetscCheck(c, rb->comm, PETSC_ERR_MEM, "Out of memory");
  c->rb   = rb;
  c->comm = rb->comm;
  c->rank = rb->rank;
  c->size = rb->size;
  PetscCheck(!rb->contact_fn, rb->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMContactCreate: these rigid bodies already have contact attached");
  rb->contact_fn    = ContactForces;
  rb->contact_setup = ContactSetUp;
  rb->contact_ctx   = c;
  *out              = c;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactDestroy(FDEMContact *c) {
  PetscFunctionBegin;
  if (!*c) PetscFunctionReturn(0);
  PetscCall(PetscSFDestroy(&(*c)->sf_state));
  PetscCall(PetscSFDestroy(&(*c)->sf_force));
  if ((*c)->rb && (*c)->rb->contact_ctx == *c) {
    (*c)->rb->contact_fn    = nullptr;
    (*c)->rb->contact_setup = nullptr;
    (*c)->rb->contact_ctx   = nullptr;
  }
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactSetPenalty(FDEMContact c, PetscReal penalty) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::CheckPenalty(c->comm, "Contact", penalty));
  c->penalty = penalty;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactSetDissipation(FDEMContact c, PetscReal damping, PetscReal friction, PetscReal tangential_viscosity) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::SetDissipation(c->comm, "Contact", damping, friction, tangential_viscosity, c->diss));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactSetBuffer(FDEMContact c, PetscReal buffer) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::CheckBuffer(c->comm, "Contact", buffer));
  c->buffer = buffer;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactSetFromOptions(FDEMContact c) {
  PetscReal pen = c->penalty, damp = c->diss.normal_damping, mu = c->diss.friction, ct = c->diss.tangential_viscosity, buf = c->buffer;
  PetscBool fp, fb;
  PetscFunctionBegin;
  PetscOptionsBegin(c->comm, nullptr, "fdem contact", "FDEMContact");
  PetscCall(PetscOptionsReal("-fdem_contact_penalty", "Penalty (Pa): a face pushed a depth d into a tetrahedron of height H feels ~ penalty d/H", "FDEMContactSetPenalty", pen, &pen, &fp));
  PetscCall(PetscOptionsReal("-fdem_contact_damping", "Normal contact damping (Pa s/m)", "FDEMContactSetDissipation", damp, &damp, nullptr));
  PetscCall(PetscOptionsReal("-fdem_contact_friction", "Coulomb friction coefficient", "FDEMContactSetDissipation", mu, &mu, nullptr));
  PetscCall(PetscOptionsReal("-fdem_contact_tangential_viscosity", "Tangential viscosity regularising stick (Pa s/m)", "FDEMContactSetDissipation", ct, &ct, nullptr));
  PetscCall(PetscOptionsReal("-fdem_contact_buffer", "Search buffer (length); re-search after a move of half of it", "FDEMContactSetBuffer", buf, &buf, &fb));
  PetscOptionsEnd();
  if (fp) PetscCall(FDEMContactSetPenalty(c, pen));
  PetscCall(FDEMContactSetDissipation(c, damp, mu, ct));
  if (fb) PetscCall(FDEMContactSetBuffer(c, buf));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactGetStats(FDEMContact c, FDEMContactStats *s) {
  PetscFunctionBegin;
  *s = c->stats;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMContactCheckTimeStep(FDEMContact c, const char *scheme, PetscReal dt, PetscReal *ratio) {
  FDEMRigid                rb = c->rb;
  fdem::model::RigidFields f;
  PetscInt                 n;
  PetscReal                loc[2] = {PETSC_MAX_REAL, 0}, glob[2];
  FDEMSchemeInfo           info;
  PetscBool                found;
  PetscFunctionBegin;
  PetscCheck(c->penalty > 0, c->comm, PETSC_ERR_ARG_WRONGSTATE, "Contact: the penalty is not set; give -fdem_contact_penalty <Pa>");
  PetscCall(FDEMSchemeInfoFind(scheme, &found, &info));
  PetscCheck(found, c->comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "Contact: %s is not an fdem TS type", scheme);
  PetscCall(DMSwarmGetLocalSize(rb->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb->sw, f));
  for (PetscInt b = 0; b < n; ++b) {
    if (f.fixed[b]) continue;
    // a flat contact over the body's cross-section A ~ (2 r)^2 pressed into skin tetrahedra of
    // height L: pressure penalty d / L, stiffness k ~ penalty A / L
    const PetscReal r = f.radius[b];
    PetscReal       L = r;
    if (f.skin[b] >= 0) L = PetscPowReal(std::max(1e-300, 6 * r * r * r / (PetscReal)rb->skins[f.skin[b]].tets.size()), 1.0 / 3);
    loc[0] = std::min(loc[0], f.mass[b] * L / (4 * r * r)); // m / (A / L): the smallest gives the highest frequency
  }
  PetscCall(fdem::model::RigidRestoreFields(rb->sw, f));
  PetscCallMPI(MPI_Allreduce(loc, glob, 1, MPIU_REAL, MPI_MIN, c->comm));
  const PetscReal omega = glob[0] < PETSC_MAX_REAL ? std::sqrt(c->penalty / glob[0]) : 0; // sqrt(k / m)
  const PetscReal r     = info.kcrit > 0 ? omega * dt / info.kcrit : PETSC_MAX_REAL;
  if (ratio) *ratio = r;
  if (r > 0.5)
    PetscCall(PetscPrintf(c->comm,
                          "WARNING fdem contact: the contact frequency omega_c ~ sqrt(penalty A / (L m)) = %g makes omega_c dt = %g, %.0f%% of the stability limit K_crit = %.4f of -ts_type %s; reduce dt below %g "
                          "or the penalty\n",
                          (double)omega, (double)(omega * dt), (double)(100 * r), (double)info.kcrit, scheme, (double)(0.5 * info.kcrit / omega)));
  PetscFunctionReturn(0);
}
