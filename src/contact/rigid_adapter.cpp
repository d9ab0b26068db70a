// Rigid bodies as a body kind of the contact engine (rigid_adapter.hpp).
#include "rigid_adapter.hpp"
#include <fdem/kernels/rotation.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace fdem::contact {
using fdem::kernels::Mat3;
using fdem::model::RigidLayout;
using fdem::model::ToMat3;
using fdem::model::ToVec3;

static_assert(fdem::model::kHistoryBytes == kHistorySlots * sizeof(HistorySlot), "the rigid swarm's history field holds the engine's slots");

// Which faces of each skin tetrahedron lie on the skin's surface (bit o: the face opposite vertex
// o), and the flat face each surface face belongs to: surface faces that share an edge and lie in
// one plane (unit normals within 1e-12, in the body frame) are joined; the flat faces are
// numbered from 0 in the order of their first face (Primitive::facet).
static RigidAdapter::SkinFaces SurfaceFaces(const fdem::model::Skin &sk) {
  std::map<std::array<int, 3>, int> count;
  auto                              face = [&](const std::array<int, 4> &T, int o) {
    std::array<int, 3> f = {T[(o + 1) % 4], T[(o + 2) % 4], T[(o + 3) % 4]};
    std::sort(f.begin(), f.end());
    return f;
  };
  for (const auto &T : sk.tets)
    for (int o = 0; o < 4; ++o) ++count[face(T, o)];
  RigidAdapter::SkinFaces out;
  out.surface.assign(sk.tets.size(), 0);
  out.facet.assign(sk.tets.size(), {-1, -1, -1, -1});
  std::vector<int>  parent; // union-find over the surface faces
  std::vector<Vec3> normal;
  std::vector<std::array<int, 2>> where;
  std::map<std::array<int, 2>, std::vector<int>> by_edge;
  for (size_t t = 0; t < sk.tets.size(); ++t)
    for (int o = 0; o < 4; ++o) {
      if (count[face(sk.tets[t], o)] != 1) continue;
      out.surface[t] |= 1 << o;
      const auto &T = sk.tets[t];
      const Vec3  a = sk.nodes[T[(o + 1) % 4]], b = sk.nodes[T[(o + 2) % 4]], c = sk.nodes[T[(o + 3) % 4]];
      const Vec3  n = cross(b - a, c - a);
      const double len = norm(n);
      const int   f   = (int)parent.size();
      parent.push_back(f);
      normal.push_back(len > 0 ? (1.0 / len) * n : Vec3(0, 0, 0));
      where.push_back({(int)t, o});
      for (int m = 0; m < 3; ++m) {
        std::array<int, 2> e = {T[(o + 1 + m) % 4], T[(o + 1 + (m + 1) % 3) % 4]};
        if (e[0] > e[1]) std::swap(e[0], e[1]);
        by_edge[e].push_back(f);
      }
    }
  auto find = [&](int f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  for (const auto &kv : by_edge)
    for (size_t i = 0; i < kv.second.size(); ++i)
      for (size_t j = i + 1; j < kv.second.size(); ++j) {
        const int f = kv.second[i], g = kv.second[j];
        if (std::fabs(dot(normal[f], normal[g])) > 1 - 1e-12) { // a face's winding follows its tetrahedron's vertex order
          const int rf = find(f), rg = find(g);
          if (rf != rg) parent[std::max(rf, rg)] = std::min(rf, rg);
        }
      }
  std::vector<int> number(parent.size(), -1);
  int              next = 0;
  for (size_t f = 0; f < parent.size(); ++f) {
    const int r = find((int)f);
    if (number[r] < 0) number[r] = next++;
    out.facet[where[f][0]][where[f][1]] = number[r];
  }
  return out;
}

PetscErrorCode RigidAdapter::HistoryBegin() {
  PetscFunctionBegin;
  PetscCall(DMSwarmGetField(rb_->sw, "history", nullptr, nullptr, (void **)&hist_));
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::PairCounts(const PetscInt *n) {
  PetscReal *work;
  PetscFunctionBegin;
  if (!record_work_) PetscFunctionReturn(0);
  if (mesh_work_) {
    PetscInt nb;
    PetscCall(DMSwarmGetLocalSize(rb_->sw, &nb));
    rb_->mesh_work.assign((size_t)nb, 0);
    for (size_t i = 0; i < prim_body_.size(); ++i) rb_->mesh_work[body_[prim_body_[i]]] += (PetscReal)n[i];
    PetscFunctionReturn(0);
  }
  PetscCall(DMSwarmGetField(rb_->sw, "work", nullptr, nullptr, (void **)&work));
  for (PetscInt j : body_) work[j] = 0;
  for (size_t i = 0; i < prim_body_.size(); ++i) work[body_[prim_body_[i]]] += (PetscReal)n[i];
  PetscCall(DMSwarmRestoreField(rb_->sw, "work", nullptr, nullptr, (void **)&work));
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::HistoryEnd() {
  PetscFunctionBegin;
  PetscCall(DMSwarmRestoreField(rb_->sw, "history", nullptr, nullptr, (void **)&hist_));
  hist_ = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::List(std::vector<Primitive> &prims) {
  fdem::model::RigidFields f;
  std::int64_t             tmax = 1;
  PetscFunctionBegin;
  for (const auto &sk : rb_->skins) tmax = std::max<std::int64_t>(tmax, (std::int64_t)sk.Primitives());
  while (surface_.size() < rb_->skins.size()) surface_.push_back(SurfaceFaces(rb_->skins[surface_.size()]));
  body_.clear();
  sphere_.clear();
  clump_.clear();
  skin_.clear();
  radius_.clear();
  inv_inertia_.clear();
  prim_body_.clear();
  prim_tet_.clear();
  ball_.clear(); // (prims: appended to)
  PetscCall(fdem::model::RigidGetFields(rb_->sw, f));
  for (PetscInt b = 0; b < rb_->n; ++b) {
    const PetscInt id  = rb_->ids[b];
    const PetscInt mat = id < (PetscInt)rb_->gmat.size() ? rb_->gmat[id] : -1;
    if (f.skin[b] == fdem::model::kSphereSkin) {
      Primitive p;
      p.shape  = kSphere;
      p.fixed  = rb_->fixed[b] ? 1 : 0;
      p.body   = id;
      p.key    = (std::int64_t)id * tmax;
      p.mat    = (std::int32_t)mat;
      p.radius = f.radius[b];
      p.mass   = p.fixed ? 0 : f.mass[b];
      prims.push_back(p);
      prim_body_.push_back((int)body_.size());
      prim_tet_.push_back(-1);
      ball_.push_back({});
      body_.push_back(b);
      sphere_.push_back(1);
      clump_.push_back(0);
      skin_.push_back(-1);
      radius_.push_back(f.radius[b]);
      inv_inertia_.push_back(1.0 / rb_->inertia[3 * b]);
      continue;
    }
    if (f.skin[b] < 0) continue;
    const auto &sk = rb_->skins[f.skin[b]];
    for (size_t k = 0; k < sk.balls.size(); ++k) { // a clump: a sphere primitive per ball
      Primitive p;
      p.shape  = kSphere;
      p.fixed  = rb_->fixed[b] ? 1 : 0;
      p.body   = id;
      p.elem   = (PetscInt)k;
      p.key    = (std::int64_t)id * tmax + (std::int64_t)k;
      p.mat    = (std::int32_t)mat;
      p.radius = sk.balls[k][3];
      p.mass   = p.fixed ? 0 : f.mass[b];
      p.flags  = 1; // a clump's sphere (BodyName)
      p.offset  = std::sqrt(sk.balls[k][0] * sk.balls[k][0] + sk.balls[k][1] * sk.balls[k][1] + sk.balls[k][2] * sk.balls[k][2]);
      p.inertia = std::min({rb_->inertia[3 * b], rb_->inertia[3 * b + 1], rb_->inertia[3 * b + 2]});
      prims.push_back(p);
      prim_body_.push_back((int)body_.size());
      prim_tet_.push_back(-1);
      ball_.push_back(sk.balls[k]);
    }
    for (size_t t = 0; t < sk.tets.size(); ++t) {
      Primitive p;
      p.fixed   = rb_->fixed[b] ? 1 : 0;
      p.body    = id;
      p.elem    = (PetscInt)t;
      p.key     = (std::int64_t)id * tmax + (std::int64_t)t;
      p.mat     = (std::int32_t)mat;
      p.mass    = p.fixed ? 0 : f.mass[b];
      p.surface = surface_[f.skin[b]].surface[t];
      for (int o = 0; o < 4; ++o) p.facet[o] = surface_[f.skin[b]].facet[t][o];
      p.push    = p.surface; // the faces shared by two skin tetrahedra cancel in the body's force and torque
      for (int k = 0; k < 4; ++k) p.node[k] = sk.tets[t][k]; // the skin's node numbers (a sphere's surface contacts)
      prims.push_back(p);
      prim_body_.push_back((int)body_.size());
      prim_tet_.push_back((int)t);
      ball_.push_back({});
    }
    body_.push_back(b);
    sphere_.push_back(0);
    clump_.push_back(sk.balls.empty() ? 0 : 1);
    skin_.push_back(f.skin[b]);
    if (sk.balls.empty()) radius_.push_back(f.radius[b]);
    else { // a clump sphere's box moves with its centre only: the lever of Move is the farthest centre
      PetscReal far = 0;
      for (const auto &ball : sk.balls) far = std::max(far, std::sqrt(ball[0] * ball[0] + ball[1] * ball[1] + ball[2] * ball[2]));
      radius_.push_back(far);
    }
    inv_inertia_.push_back(0); // not used
  }
  PetscCall(fdem::model::RigidRestoreFields(rb_->sw, f));
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::Gather(const std::vector<int> *which, Vertices *x, Vertices *v) {
  const RigidLayout L(rb_->n);
  const size_t      n    = which ? which->size() : prim_body_.size();
  int               last = -1;
  Vec3              xc, vc, w;
  Mat3              R;
  PetscFunctionBegin;
  PetscCheck(!v || u_ || n == 0, rb_->comm, PETSC_ERR_ARG_WRONGSTATE, "Contact: damping or friction needs the rigid bodies' velocities, which this force evaluation did not provide");
  for (size_t m = 0; m < n; ++m) {
    const int i = which ? (*which)[m] : (int)m, j = prim_body_[i];
    if (sphere_[j]) { // centre; velocity and angular velocity (the engine reads no more of a sphere's record)
      const PetscInt b = body_[j];
      x[i][0]          = ToVec3(L.x(q_, b));
      if (v) {
        v[i][0] = ToVec3(L.v(u_, b));
        v[i][1] = inv_inertia_[j] * ToVec3(L.H(u_, b)); // I = I 1: omega = H / I
      }
      continue;
    }
    const auto &sk = rb_->skins[skin_[j]];
    if (j != last) { // the primitives of a body are consecutive: its skin nodes once
      const PetscInt b = body_[j];
      last             = j;
      xc               = ToVec3(L.x(q_, b));
      R                = ToMat3(L.R(q_, b));
      if (!clump_[j]) {
        world_.resize(sk.nodes.size());
        for (size_t k = 0; k < sk.nodes.size(); ++k) world_[k] = xc + R * sk.nodes[k];
      }
      if (v) {
        vc = ToVec3(L.v(u_, b));
        w  = fdem::kernels::BodyOmega(R, Vec3(rb_->inertia[3 * b], rb_->inertia[3 * b + 1], rb_->inertia[3 * b + 2]), ToVec3(L.H(u_, b)));
      }
    }
    if (clump_[j]) { // a sphere of a clump: centre; velocity and angular velocity
      const auto &ball = ball_[i];
      const Vec3  r    = R * Vec3(ball[0], ball[1], ball[2]);
      x[i][0]          = xc + r;
      if (v) {
        v[i][0] = vc + cross(w, r);
        v[i][1] = w;
      }
      continue;
    }
    const auto &T = sk.tets[prim_tet_[i]];
    for (int k = 0; k < 4; ++k) {
      x[i][k] = world_[T[k]];
      if (v) v[i][k] = vc + cross(w, x[i][k] - xc);
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::SphereStates(int n, const int *which, const int *to, fdem::kernels::SphereState *s) {
  const RigidLayout L(rb_->n);
  PetscFunctionBegin;
  PetscCheck(u_ || n == 0, rb_->comm, PETSC_ERR_ARG_WRONGSTATE, "Contact: spheres need the rigid bodies' velocities, which this force evaluation did not provide");
  int  last = -1; // the clump whose R and omega are at hand (its spheres often come in a row)
  Mat3 R;
  Vec3 w;
  for (int m = 0; m < n; ++m) {
    const int      j = prim_body_[which[m]];
    const PetscInt b = body_[j];
    if (clump_[j]) { // a sphere of a clump, at x + R p, moving at v + omega x R p
      if (j != last) {
        last = j;
        R    = ToMat3(L.R(q_, b));
        w    = fdem::kernels::BodyOmega(R, Vec3(rb_->inertia[3 * b], rb_->inertia[3 * b + 1], rb_->inertia[3 * b + 2]), ToVec3(L.H(u_, b)));
      }
      const auto &ball = ball_[which[m]];
      const Vec3  r    = R * Vec3(ball[0], ball[1], ball[2]);
      s[to[m]]         = fdem::kernels::SphereState{ToVec3(L.x(q_, b)) + r, ToVec3(L.v(u_, b)) + cross(w, r), w, ball[3]};
      continue;
    }
    // I = I 1: omega = H / I
    s[to[m]] = fdem::kernels::SphereState{ToVec3(L.x(q_, b)), ToVec3(L.v(u_, b)), inv_inertia_[j] * ToVec3(L.H(u_, b)), radius_[j]};
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::AddSphereForces(int n, const int *which, const int *from, const fdem::kernels::SphereSum *f) {
  const RigidLayout L(rb_->n);
  int               last = -1; // the clump whose R is at hand
  Mat3              R;
  PetscFunctionBegin;
  for (int m = 0; m < n; ++m) {
    const int                       j = prim_body_[which[m]];
    const PetscInt                  b = body_[j];
    const fdem::kernels::SphereSum &g = f[from[m]];
    Vec3                            M = g.t;
    if (clump_[j]) { // the force acts at the sphere's centre, x + R p
      if (j != last) last = j, R = ToMat3(L.R(q_, b));
      const auto &ball = ball_[which[m]];
      M += cross(R * Vec3(ball[0], ball[1], ball[2]), g.f);
    }
    for (int d = 0; d < 3; ++d) {
      L.F(fm_, b)[d] += g.f[d];
      L.M(fm_, b)[d] += M[d];
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::Scatter(const std::vector<int> &which, const Vertices *x, const Vertices *f) {
  const RigidLayout L(rb_->n);
  PetscFunctionBegin;
  for (size_t m = 0; m < which.size();) { // the primitives of a body are consecutive
    const int      j = prim_body_[which[m]];
    const PetscInt b = body_[j];
    Vec3           F, M;
    if (sphere_[j]) { // force on the centre and torque (a sphere is one primitive)
      F = f[which[m]][0];
      M = f[which[m]][1];
      ++m;
    }
    const Vec3 xc = sphere_[j] ? Vec3() : ToVec3(L.x(q_, b));
    for (; m < which.size() && prim_body_[which[m]] == j; ++m) {
      const int i = which[m];
      if (clump_[j]) { // a sphere of a clump: the force on its centre and a torque
        F += f[i][0];
        M += f[i][1] + cross(x[i][0] - xc, f[i][0]);
        continue;
      }
      for (int k = 0; k < 4; ++k) {
        F += f[i][k];
        M += cross(x[i][k] - xc, f[i][k]);
      }
    }
    for (int d = 0; d < 3; ++d) {
      L.F(fm_, b)[d] += F[d];
      L.M(fm_, b)[d] += M[d];
    }
  }
  PetscFunctionReturn(0);
}

// |x - x0| + r |R - R0|_F bounds the displacement of every skin node of listed body j since
// the last search (|R - R0|_2 <= |R - R0|_F).
PetscReal RigidAdapter::Move(size_t j) const {
  const RigidLayout  L(rb_->n);
  const PetscScalar *x = L.x(q_, body_[j]), *R = L.R(q_, body_[j]);
  const PetscReal   *r = &refx_[3 * j], *r9 = &refR_[9 * j];
  PetscReal          dx = 0, dR = 0;
  for (int k = 0; k < 3; ++k) dx += PetscSqr(PetscRealPart(x[k]) - r[k]);
  if (sphere_[j]) return std::sqrt(dx); // a sphere's surface does not move as it turns
  for (int k = 0; k < 9; ++k) dR += PetscSqr(PetscRealPart(R[k]) - r9[k]);
  return std::sqrt(dx) + radius_[j] * std::sqrt(dR);
}

PetscErrorCode RigidAdapter::MoveRatio(PetscReal *ratio) {
  const RigidLayout L(rb_->n);
  PetscReal         worst = 0;
  PetscFunctionBegin;
  for (size_t j = 0; j < body_.size() && j < margin_.size(); ++j) {
    const PetscReal m = margin_[j];
    if (sphere_[j]) { // the root and the division only for a new worst
      const PetscScalar *x  = L.x(q_, body_[j]);
      const PetscReal   *r  = &refx_[3 * j];
      const PetscReal    d2 = PetscSqr(PetscRealPart(x[0]) - r[0]) + PetscSqr(PetscRealPart(x[1]) - r[1]) + PetscSqr(PetscRealPart(x[2]) - r[2]);
      if (d2 > worst * worst * (m * m)) worst = m > 0 ? std::sqrt(d2) / m : PETSC_MAX_REAL;
      continue;
    }
    const PetscReal d = Move(j);
    worst             = std::max(worst, m > 0 ? d / m : d > 0 ? PETSC_MAX_REAL : 0);
  }
  *ratio = worst;
  PetscFunctionReturn(0);
}

// A body that moved d in the n evaluations since the last search is given room for
// kLookahead more at that pace: half + kLookahead d / n (half: never less, and at the first search).
PetscErrorCode RigidAdapter::Margins(PetscReal half, PetscInt evaluations, PetscReal *m) {
  constexpr PetscReal kLookahead = 10;
  PetscFunctionBegin;
  const bool seen = evaluations > 0 && refx_.size() == 3 * body_.size();
  margin_.assign(body_.size(), half);
  if (seen)
    for (size_t j = 0; j < body_.size(); ++j) margin_[j] = half + kLookahead * Move(j) / (PetscReal)evaluations;
  for (size_t i = 0; i < prim_body_.size(); ++i) m[i] = margin_[prim_body_[i]];
  PetscFunctionReturn(0);
}

PetscErrorCode RigidAdapter::Searched() {
  const RigidLayout L(rb_->n);
  PetscFunctionBegin;
  refx_.resize(3 * body_.size());
  refR_.resize(9 * body_.size());
  for (size_t j = 0; j < body_.size(); ++j) {
    for (int k = 0; k < 3; ++k) refx_[3 * j + k] = PetscRealPart(L.x(q_, body_[j])[k]);
    for (int k = 0; k < 9; ++k) refR_[9 * j + k] = PetscRealPart(L.R(q_, body_[j])[k]);
  }
  PetscFunctionReturn(0);
}

// A flat contact over the body's cross-section A ~ (2 r)^2 pressed into skin tetrahedra of
// size L (6 r^3 / skin tetrahedra)^(1/3): k ~ penalty A / L, omega^2 = k / m (largest over
// the bodies that can move and touch).
PetscErrorCode RigidAdapter::Frequency2(PetscReal penalty, PetscReal *w2) {
  fdem::model::RigidFields f;
  PetscInt                 n;
  PetscFunctionBegin;
  *w2 = 0;
  PetscCall(DMSwarmGetLocalSize(rb_->sw, &n));
  PetscCall(fdem::model::RigidGetFields(rb_->sw, f));
  for (PetscInt b = 0; b < n; ++b) {
    if (f.fixed[b] || f.skin[b] < 0 || rb_->skins[f.skin[b]].tets.empty()) continue; // spheres and clumps: the granular laws' own check
    const PetscReal r = f.radius[b];
    const PetscReal L = PetscPowReal(std::max<PetscReal>(1e-300, 6 * r * r * r / (PetscReal)rb_->skins[f.skin[b]].tets.size()), 1.0 / 3);
    *w2               = std::max(*w2, penalty * 4 * r * r / (L * f.mass[b]));
  }
  PetscCall(fdem::model::RigidRestoreFields(rb_->sw, f));
  PetscFunctionReturn(0);
}

// A clump's spheres carry flag 1 (List), ghosts included.
std::string RigidAdapter::BodyName(const Primitive &p) const { return (p.shape != kSphere ? "rigid body " : p.flags & 1 ? "clump " : "sphere ") + std::to_string((long long)p.body); }
std::string RigidAdapter::ElementName(const Primitive &p) const {
  if (p.shape == kSphere) return p.flags & 1 ? "ball " + std::to_string((long long)p.elem) : std::string("ball");
  return "skin tetrahedron " + std::to_string((long long)p.elem);
}

// A tenth of each local body's bounding radius.
PetscErrorCode RigidAdapter::BufferProposal(PetscReal *sum, PetscInt *count) {
  fdem::model::RigidFields f;
  PetscFunctionBegin;
  *sum   = 0;
  *count = rb_->n;
  PetscCall(fdem::model::RigidGetFields(rb_->sw, f));
  for (PetscInt b = 0; b < rb_->n; ++b) *sum += f.radius[b];
  PetscCall(fdem::model::RigidRestoreFields(rb_->sw, f));
  *sum *= 0.1;
  PetscFunctionReturn(0);
}

PetscErrorCode SetGranularTable(FDEMRigid rb, Engine &engine, int tag) {
  const int                 n = (int)rb->gmats.size();
  std::vector<fdem::kernels::GranularPair> table((size_t)n * n);
  PetscFunctionBegin;
  if (rb->gtable_n == (size_t)n && rb->gtable.size() == (size_t)n * n) { // made before (the Hertz damping is a root search)
    engine.SetGranular(rb->gtable, n, tag);
    PetscFunctionReturn(0);
  }
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const std::string what = "granular materials '" + rb->gmat_names[a] + "' and '" + rb->gmat_names[b] + "'";
      try {
        table[(size_t)a * n + b] = fdem::kernels::MixGranular(rb->gmats[a], rb->gmats[b], what.c_str());
      } catch (const std::exception &) {
        table[(size_t)a * n + b] = fdem::kernels::GranularPair{}; // empty: an error names the bodies if a sphere meets them
      }
    }
  rb->gtable   = table;
  rb->gtable_n = (size_t)n;
  engine.SetGranular(std::move(table), n, tag);
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
