// A deformable mesh as a body kind of the contact engine (mesh_adapter.hpp).
#include "mesh_adapter.hpp"
#include "surface.hpp"
#include "../model/deformable_impl.hpp"
#include "../model/deformable_object.hpp"
#include <fdem/deformable.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <tuple>

namespace fdem::contact {
PetscErrorCode MeshAdapter::Create(FDEMDeformable d, Cells which, Pairs pairs, Spheres spheres, MeshAdapter **out) {
  PetscInt  nc, nlocal;
  MPI_Comm  comm;
  DM        dm;
  PetscBool joints;
  PetscFunctionBegin;
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nlocal, nullptr, nullptr, nullptr, nullptr)); // also checks set-up
  PetscCall(FDEMDeformableGetDM(d, &dm));
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCall(fdem::model::DeformableHasJoints(d, &joints));
  MeshAdapter *m = new (std::nothrow) MeshAdapter();
  PetscCheck(m, PETSC_COMM_SELF, PETSC_ERR_MEM, "Out of memory");
  m->d_         = d;
  m->which_     = which;
  m->fractured_ = joints;
  m->weights_   = spheres == Spheres::Weighted;
  m->stable_    = joints && spheres == Spheres::None;
  AllCells &A   = m->all_;
  A.conn.resize(4 * (size_t)nc);
  A.body.resize(nc);
  A.gid.resize(nc);
  A.ngid.resize(nlocal);
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nlocal, A.conn.data(), A.body.data(), A.gid.data(), A.ngid.data()));
  if (!d->boundary_made) { // (the mesh does not change after set-up)
    std::vector<char> shared;
    PetscCall(fdem::model::DeformableSharedNodes(d, shared));
    PetscCall(BoundaryFaces(comm, A.conn, A.ngid, shared, d->boundary_faces));
  }
  d->boundary_made = true;
  A.surf = d->boundary_faces;
  if (which == Cells::BoundaryVertex) PetscCall(BoundaryNodes(d, A.conn, A.surf, nlocal, A.bnode));
  PetscCall(FDEMDeformableGetBodyName(d, 0, &m->nbodies_, nullptr));
  PetscBool dc = PETSC_TRUE; // (read for every mesh, so that -help lists it whatever the scene)
  PetscOptionsBegin(comm, nullptr, "fdem contact of fracturable bodies", "FDEMDeformableContact");
  PetscCall(PetscOptionsBool("-fdem_joint_damaged_contact", "The tetrahedra at a joint that has softened (a point beyond its peak) take part in the deformable bodies' contact with themselves and each other, and so do neighbours by an edge or a vertex once a joint has softened (false: only once it has broken; cheaper, but a crack's sides that slide before it breaks meet deeply overlapped; doc/fracture.md). The contact with rigid bodies and spheres never needs them", "", dc, &dc, nullptr));
  PetscOptionsEnd();
  if (joints) { // the cells of fracturable bodies are chosen by the fracture topology
    // an engine that pairs the mesh only with other kinds has no crack's sides to keep apart:
    // it lists the cells with a free face (or vertex), and lists again only where joints break
    m->damaged_cells_ = dc && pairs == Pairs::WithItself;
    const fdem::model::FractureTopology *t;
    PetscCall(fdem::model::DeformableFractureTopology(d, &t));
    m->fracturable_ = t->fracturable;
    m->nbroken_     = t->nbroken;
    m->ndamaged_    = t->ndamaged;
    m->broken_      = t->broken_pairs;
    PetscCall(m->Shares(*t));
    m->Select(t);
  } else {
    m->Select(nullptr);
    m->all_ = AllCells(); // not needed again
  }
  m->body_force_.assign(3 * (size_t)m->nbodies_, 0);
  *out = m;
  PetscFunctionReturn(0);
}

// The weights of a sphere's contacts with the copies of vertices and edges, from the surface
// of the fracture topology t (the faces Select gives the contact). Without spheres to weigh,
// nothing (they cost a rendezvous over every vertex and edge of the fracturable cells).
PetscErrorCode MeshAdapter::Shares(const fdem::model::FractureTopology &t) {
  const AllCells            &A = all_;
  PetscFunctionBegin;
  if (!weights_) PetscFunctionReturn(0);
  std::vector<unsigned char> surface(A.body.size(), 0);
  for (size_t e = 0; e < surface.size(); ++e)
    if (t.fracturable[A.body[e]]) surface[e] = (unsigned char)(t.cell_free[e] & 0xF & A.surf[e]);
  PetscCall(fdem::model::DeformableFeatureShares(d_, t, surface, share_));
  PetscFunctionReturn(0);
}

// A cell of a body that is not fracturable takes part when it has a boundary face (or, for
// Cells::BoundaryVertex, a boundary vertex), its node ids those of the mesh. A cell of a
// fracturable body takes part when it has a free face (on the body's outer surface or on a
// broken joint; or a vertex on such a face) or a damaged joint face (a point beyond its peak),
// its node ids the node keys of the topology. Before any joint softens, these are the cells at
// the surface of the unsplit body. The damaged cells take part so that the two sides of a
// crack that slides or opens before it breaks through cannot pass through each other unseen,
// to be met deeply overlapped when it breaks (doc/fracture.md, "Broken joints").
void MeshAdapter::Select(const fdem::model::FractureTopology *t) {
  const AllCells &A  = all_;
  const size_t    nc = A.body.size();
  // the cells taken and their surfaces first, so that the lists are allocated once; with
  // stable listings, a cell at a joint of a body whose joints are inserted during the run is
  // taken idle when nothing else takes it (a listing then changes at a rebuild, not each time
  // a joint softens or breaks: the engine keeps its search)
  const bool stable = t && stable_;
  if (stable && SelectChanged(*t)) return;
  auto &taken = taken_; // (kept: a selection is made each time joints soften or break)
  taken.clear();
  for (size_t e = 0; e < nc; ++e) {
    char surf;
    bool on, idle;
    Take((PetscInt)e, t, stable, &surf, &on, &idle);
    if (on || idle) taken.push_back({(PetscInt)e, surf, idle});
  }
  // the same cells as the listing before (stable listings): their records are brought up to date
  // in place, and the engine copies only those that changed (RefreshInPlace)
  refreshed_.clear();
  in_place_ = stable && taken.size() == cell_.size() && !prims_.empty();
  for (size_t i = 0; in_place_ && i < taken.size(); ++i) in_place_ = std::get<0>(taken[i]) == cell_[i];
  if (in_place_) {
    for (size_t i = 0; i < taken.size(); ++i) {
      const auto &[e, surf, idle] = taken[i];
      const CellState s           = State(e, surf, idle, t);
      if (s == state_[i]) continue;
      state_[i] = s;
      s.Apply(prims_[i]);
      faces_[i] = surf;
      refreshed_.push_back((int)i);
    }
    version_ = t->version;
    return;
  }
  conn_.clear();
  prims_.clear();
  faces_.clear();
  state_.clear();
  conn_.reserve(taken.size());
  prims_.reserve(taken.size());
  faces_.reserve(taken.size());
  cell_.clear();
  if (t) cell_.reserve(taken.size()), state_.reserve(taken.size());
  for (const auto &[e, surf, idle] : taken) {
    static const Primitive blank; // (copied, then filled in place: value-initialising each one zeroed it first)
    prims_.push_back(blank);
    Primitive &p = prims_.back(); // (a selection is made each time joints soften or break)
    p.body = A.body[e];
    p.elem = A.gid[e];
    p.key  = A.gid[e];
    p.mat  = p.body < (PetscInt)gmat_.size() ? gmat_[p.body] : -1;
    const CellState s = State(e, surf, idle, t);
    s.Apply(p);
    if (t && t->fracturable[A.body[e]] && !share_.empty()) std::copy(share_.begin() + 10 * e, share_.begin() + 10 * (e + 1), p.share);
    conn_.push_back({A.conn[4 * e], A.conn[4 * e + 1], A.conn[4 * e + 2], A.conn[4 * e + 3]});
    if (t) cell_.push_back(e), state_.push_back(s);
    faces_.push_back(surf);
  }
  slot_.clear();
  if (stable) {
    slot_.assign(nc, -1);
    for (size_t i = 0; i < cell_.size(); ++i) slot_[cell_[i]] = (PetscInt)i;
  }
  version_ = t ? t->version : 0;
}

// Whether local cell e takes part (on) or is listed idle (stable listings), and its surface.
void MeshAdapter::Take(PetscInt e, const fdem::model::FractureTopology *t, bool stable, char *surface, bool *taken, bool *idle) const {
  const AllCells &A    = all_;
  const bool      frac = t && t->fracturable[A.body[e]];
  char            surf = A.surf[e];
  bool            on;
  if (frac) { // a split cell's faces are all boundary faces of the mesh (A.surf 0xF)
    surf = (char)(t->cell_free[e] & 0xF & surf);
    on   = surf != 0 || (which_ == Cells::BoundaryVertex && (t->cell_free[e] & 0x10)) || (damaged_cells_ && (t->cell_free[e] & 0x20));
    if (which_ == Cells::BoundaryVertex && (t->cell_free[e] & 0x40)) // unsplit, in a body with fracture zones
      for (int k = 0; k < 4; ++k) on = on || A.bnode[A.conn[4 * e + k]];
  } else {
    on = surf != 0;
    if (which_ == Cells::BoundaryVertex)
      for (int k = 0; k < 4; ++k) on = on || A.bnode[A.conn[4 * e + k]];
  }
  *surface = surf;
  *taken   = on;
  *idle    = !on && stable && frac && (t->cell_free[e] & 0x80);
}

// A stable listing made from topology answer version_, and t differs from it only in the cells
// t.changed (joints that softened): when each of those is listed, and stays so, only their
// records are brought up to date (in place, as Select's loop over every cell would).
bool MeshAdapter::SelectChanged(const fdem::model::FractureTopology &t) {
  if (t.changed_from == 0 || t.changed_from != version_ || slot_.empty() || prims_.empty()) return false;
  auto &taken = taken_; // (Select's scratch)
  taken.clear();
  for (PetscInt e : t.changed) {
    char surf;
    bool on, idle;
    Take(e, &t, true, &surf, &on, &idle);
    if ((on || idle) != (slot_[e] >= 0)) return false; // (a cell joins or leaves the listing)
    taken.push_back({e, surf, idle});
  }
  refreshed_.clear();
  for (const auto &[e, surf, idle] : taken) {
    const PetscInt  i = slot_[e];
    const CellState s = State(e, surf, idle, &t);
    if (s == state_[i]) continue;
    state_[i] = s;
    s.Apply(prims_[i]);
    faces_[i] = surf;
    refreshed_.push_back((int)i);
  }
  std::sort(refreshed_.begin(), refreshed_.end());
  in_place_ = true;
  version_  = t.version;
  return true;
}

// What fracture changes in the record of local cell e, taken with surface surf (idle: listed,
// in no pair), by topology t.
MeshAdapter::CellState MeshAdapter::State(PetscInt e, char surf, bool idle, const fdem::model::FractureTopology *t) const {
  const AllCells &A    = all_;
  const bool      frac = t && t->fracturable[A.body[e]];
  CellState       s;
  s.surface = (std::int32_t)(surf & 0xF);
  s.flags   = (frac && damaged_cells_ && (t->cell_free[e] & 0x20) ? 1 : 0) | (frac && !(t->cell_free[e] & 0x40) ? 2 : 0);
  // held by its fragment: an unsplit cell, or a split one none of whose joints is damaged
  // (with the damaged cells in contact): SelfPair
  const bool held = frac && ((t->cell_free[e] & 0x40) || (damaged_cells_ && !(t->cell_free[e] & 0x20)));
  s.group         = held ? (std::int64_t)t->cell_fragment[e] : -1;
  s.idle          = idle ? 1 : 0;
  for (int k = 0; k < 4; ++k) s.node[k] = frac ? t->cell_key[4 * e + k] : A.ngid[A.conn[4 * e + k]];
  return s;
}

bool MeshAdapter::RefreshInPlace(Primitive *mine, size_t n, std::vector<int> &changed) {
  if (!in_place_ || n != prims_.size()) return false;
  for (int i : refreshed_) state_[i].Apply(mine[i]);
  changed = refreshed_;
  return true;
}

bool MeshAdapter::SelfPair(const Primitive &a, const Primitive &b) const {
  // (Two tetrahedra of one fragment that are held in it, unsplit ones of a body with fracture
  // zones and split ones none of whose joints is damaged, carry the fragment's id as their
  // group, and the engine pairs no two of one group (Primitive::group) without asking here: no
  // crack lies between them, as in a body that is not fracturable. The fragments of a body
  // meet through cells of two fragments, and a crack's sides through its damaged cells, so an
  // intact fracturable body costs the contact what the same body unsplit does.)
  if (NeighbourPair(a, b)) return true;
  // the two sides of a broken joint (asked last: most pairs are decided above)
  const std::array<PetscInt, 2> k = {(PetscInt)std::min(a.key, b.key), (PetscInt)std::max(a.key, b.key)};
  return fractured_ && fracturable_[a.body] && std::binary_search(broken_.begin(), broken_.end(), k);
}

bool MeshAdapter::NeighbourPair(const Primitive &a, const Primitive &b) const {
  if (fractured_ && fracturable_[a.body] && (nbroken_ > 0 || (damaged_cells_ && ndamaged_ > 0))) {
    // Once a joint has softened, only a face glued by an intact joint (three shared node keys)
    // keeps two tetrahedra of a fracturable body apart; neighbours by an edge or a vertex are
    // paired (touching there, they barely overlap), so that two tetrahedra on the two sides of a
    // crack that is still glued at a node or an edge cannot pass through each other unseen.
    // With -fdem_joint_damaged_contact such neighbours are paired only when one of them is at a
    // damaged joint (a crack's side): two whose joints are all intact are held together by them.
    // Before any joint softens the usual rule holds, and an intact body feels no contact force.
    int shared = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (a.node[i] >= 0 && a.node[i] == b.node[j]) ++shared;
    if (shared == 0 || !damaged_cells_) return shared < 3;
    return shared < 3 && ((a.flags | b.flags) & 1);
  }
  return Adapter::SelfPair(a, b);
}

PetscErrorCode MeshAdapter::Pending(PetscBool *pending) {
  PetscInt n, nd;
  PetscFunctionBegin;
  *pending = PETSC_FALSE;
  if (!fractured_) PetscFunctionReturn(0);
  PetscCall(fdem::model::DeformableJointCounts(d_, &n, &nd)); // the same on every rank
  *pending = n != nbroken_ || (nd != ndamaged_ && damaged_cells_) ? PETSC_TRUE : PETSC_FALSE;
  surface_pending_ = n != nbroken_;
  pending_ = *pending == PETSC_TRUE ? 1 : 0;
  PetscFunctionReturn(0);
}

void MeshAdapter::OnsetEnergy(PetscReal e) { fdem::model::DeformableAddOnset(d_, e); }

PetscErrorCode MeshAdapter::Changed(PetscBool *changed) {
  PetscBool pending;
  PetscFunctionBegin;
  *changed = PETSC_FALSE;
  if (pending_ >= 0) pending = pending_ ? PETSC_TRUE : PETSC_FALSE; // the engine asked at this evaluation: one reduction, not two
  else PetscCall(Pending(&pending));
  pending_ = -1;
  if (!pending) PetscFunctionReturn(0);
  const fdem::model::FractureTopology *t;
  PetscCall(fdem::model::DeformableFractureTopology(d_, &t));
  if (t->nbroken != nbroken_) PetscCall(Shares(*t)); // the surface changes only where joints break
  nbroken_  = t->nbroken;
  ndamaged_ = t->ndamaged;
  broken_   = t->broken_pairs;
  Select(t);
  *changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshAdapter::List(std::vector<Primitive> &prims) {
  PetscFunctionBegin;
  prims.insert(prims.end(), prims_.begin(), prims_.end());
  PetscFunctionReturn(0);
}

PetscErrorCode MeshAdapter::Gather(const std::vector<int> *which, Vertices *x, Vertices *v) {
  const size_t n = which ? which->size() : conn_.size();
  PetscFunctionBegin;
  PetscCheck(!v || vl_ || !require_v_, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "Contact: damping or friction needs the nodal velocities, which this force evaluation did not provide");
  for (size_t m = 0; m < n; ++m) {
    const size_t t = which ? (size_t)(*which)[m] : m;
    for (int q = 0; q < 4; ++q) {
      const PetscInt a = 3 * conn_[t][q];
      x[t][q]          = Vec3(PetscRealPart(xl_[a]), PetscRealPart(xl_[a + 1]), PetscRealPart(xl_[a + 2]));
      if (v) v[t][q] = vl_ ? Vec3(PetscRealPart(vl_[a]), PetscRealPart(vl_[a + 1]), PetscRealPart(vl_[a + 2])) : Vec3(0, 0, 0);
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshAdapter::Scatter(const std::vector<int> &which, const Vertices *, const Vertices *f) {
  PetscFunctionBegin;
  std::fill(body_force_.begin(), body_force_.end(), 0);
  for (int t : which)
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j) {
        fl_[3 * conn_[t][k] + j] += f[t][k][j];
        body_force_[3 * prims_[t].body + j] += f[t][k][j];
      }
  PetscFunctionReturn(0);
}

// Every cell gets half the buffer (a fast node of a mesh is rare; its cells are small).
PetscErrorCode MeshAdapter::Margins(PetscReal half, PetscInt, PetscReal *m) {
  PetscFunctionBegin;
  half_ = half;
  for (size_t t = 0; t < conn_.size(); ++t) m[t] = half;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshAdapter::MoveRatio(PetscReal *ratio) {
  PetscReal move2 = 0; // the largest squared move (its root is the largest move: one root, not one a node)
  PetscFunctionBegin;
  for (size_t i = 0; i < ref_node_.size(); ++i) {
    const PetscInt   a = 3 * ref_node_[i];
    const PetscReal *r = &ref_x_[3 * i];
    move2              = std::max(move2, PetscSqr(PetscRealPart(xl_[a]) - r[0]) + PetscSqr(PetscRealPart(xl_[a + 1]) - r[1]) + PetscSqr(PetscRealPart(xl_[a + 2]) - r[2]));
  }
  const PetscReal move = PetscSqrtReal(move2);
  *ratio               = half_ > 0 ? move / half_ : move > 0 ? PETSC_MAX_REAL : 0;
  PetscFunctionReturn(0);
}

// The nodes of the listed cells, each once (a node is the corner of many cells: the test of
// every evaluation reads each once), and their positions now.
PetscErrorCode MeshAdapter::Searched() {
  PetscFunctionBegin;
  PetscInt n = 0;
  for (const auto &c : conn_) n = std::max(n, 1 + *std::max_element(c.begin(), c.end()));
  std::vector<char> used(n, 0);
  for (const auto &c : conn_)
    for (PetscInt a : c) used[a] = 1;
  ref_node_.clear();
  for (PetscInt a = 0; a < n; ++a)
    if (used[a]) ref_node_.push_back(a);
  ref_x_.resize(3 * ref_node_.size());
  for (size_t i = 0; i < ref_node_.size(); ++i)
    for (int k = 0; k < 3; ++k) ref_x_[3 * i + k] = PetscRealPart(xl_[3 * ref_node_[i] + k]);
  PetscFunctionReturn(0);
}

// Contact stiffness of each boundary node: a boundary face of area A pressed a depth d into
// its tetrahedron of height H over it feels ~ penalty (d / H) A, shared by its three nodes,
// so k = sum over the node's boundary faces of penalty A / (3 H). Both tetrahedra of a pair
// push (contactor and target, x2) and an equal body on the other side halves the effective
// mass (x2): omega^2 = 4 k / m with m the node's lumped mass (flat contact of equal bodies,
// the stiffest case), at the mesh's stored positions.
PetscErrorCode MeshAdapter::Frequency2(PetscReal penalty, PetscReal *w2) {
  DM                       dm;
  Vec                      X, M, Xl, Kl, Kg;
  const PetscScalar       *xa, *ma, *kg;
  PetscScalar             *kl;
  const std::vector<char> *fixed;
  PetscFunctionBegin;
  *w2 = 0;
  PetscCall(FDEMDeformableGetDM(d_, &dm));
  PetscCall(FDEMDeformableGetPositions(d_, &X));
  PetscCall(FDEMDeformableGetMasses(d_, &M));
  PetscCall(fdem::model::DeformableGetFixed(d_, &fixed));
  PetscCall(DMGetLocalVector(dm, &Xl));
  PetscCall(DMGetLocalVector(dm, &Kl));
  PetscCall(DMGetGlobalVector(dm, &Kg));
  PetscCall(fdem::model::DeformableGlobalToLocal(d_, X, Xl));
  PetscCall(VecSet(Kl, 0));
  PetscCall(VecGetArrayRead(Xl, &xa));
  PetscCall(VecGetArray(Kl, &kl));
  for (size_t t = 0; t < conn_.size(); ++t) {
    const auto &T = conn_[t];
    Vec3        P[4];
    for (int q = 0; q < 4; ++q) P[q] = Vec3(PetscRealPart(xa[3 * T[q]]), PetscRealPart(xa[3 * T[q] + 1]), PetscRealPart(xa[3 * T[q] + 2]));
    const double V = std::fabs(dot(P[1] - P[0], cross(P[2] - P[0], P[3] - P[0]))) / 6;
    for (int o = 0; o < 4; ++o) {
      if (!(faces_[t] & (1 << o))) continue;
      const int    i = (o + 1) % 4, j = (o + 2) % 4, k = (o + 3) % 4;
      const double A = 0.5 * norm(cross(P[j] - P[i], P[k] - P[i]));
      if (!(V > 0) || !(A > 0)) continue;
      const double H = 3 * V / A;
      for (int q : {i, j, k}) kl[3 * T[q]] += penalty * A / (3 * H);
    }
  }
  PetscCall(VecRestoreArray(Kl, &kl));
  PetscCall(VecRestoreArrayRead(Xl, &xa));
  PetscCall(VecSet(Kg, 0));
  PetscCall(fdem::model::DeformableLocalToGlobal(d_, Kl, ADD_VALUES, Kg));
  PetscCall(VecGetArrayRead(Kg, &kg));
  PetscCall(VecGetArrayRead(M, &ma));
  for (size_t n = 0; n < fixed->size(); ++n) {
    const PetscReal k = PetscRealPart(kg[3 * n]), m = PetscRealPart(ma[3 * n]);
    if ((*fixed)[n] || !(k > 0) || !(m > 0)) continue; // fixed nodes do not move
    *w2 = std::max(*w2, 4 * k / m);
  }
  PetscCall(VecRestoreArrayRead(M, &ma));
  PetscCall(VecRestoreArrayRead(Kg, &kg));
  PetscCall(DMRestoreGlobalVector(dm, &Kg));
  PetscCall(DMRestoreLocalVector(dm, &Kl));
  PetscCall(DMRestoreLocalVector(dm, &Xl));
  PetscFunctionReturn(0);
}

std::string MeshAdapter::BodyName(const Primitive &p) const {
  const char *name = nullptr;
  if (FDEMDeformableGetBodyName(d_, p.body, nullptr, &name) || !name) return "deformable body " + std::to_string((long long)p.body);
  return std::string("deformable body '") + name + "'";
}
std::string MeshAdapter::ElementName(const Primitive &p) const { return "element " + std::to_string((long long)p.elem); }

// A quarter of each cell's diameter in the reference configuration. Collective.
PetscErrorCode MeshAdapter::BufferProposal(PetscReal *sum, PetscInt *count) {
  DM                 dm;
  Vec                X, Xl;
  const PetscScalar *xa;
  PetscFunctionBegin;
  *sum   = 0;
  *count = 0;
  // the longest edge of a cell, from the local reference positions
  const auto diameter = [](const PetscScalar *xa, const PetscInt T[4]) {
    PetscReal diam = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        PetscReal dd = 0;
        for (int k = 0; k < 3; ++k) dd += PetscSqr(PetscRealPart(xa[3 * T[a] + k] - xa[3 * T[b] + k]));
        diam = std::max(diam, PetscSqrtReal(dd));
      }
    return diam;
  };
  // with joints the listing changes often and the cells do not: each cell's once, from the
  // local reference positions kept at the first call (collective, as fractured_ is the same on
  // every rank; Select then lists cell_)
  const bool cached = fractured_;
  if (!cached || !diam_made_) {
    PetscCall(FDEMDeformableGetDM(d_, &dm));
    PetscCall(FDEMDeformableGetReferencePositions(d_, &X));
    PetscCall(DMGetLocalVector(dm, &Xl));
    PetscCall(fdem::model::DeformableGlobalToLocal(d_, X, Xl));
    PetscCall(VecGetArrayRead(Xl, &xa));
    if (cached) {
      PetscInt n;
      PetscCall(VecGetLocalSize(Xl, &n));
      xref_.assign(xa, xa + n);
      diam_.assign(all_.body.size(), -1);
      diam_made_ = true;
    } else
      for (size_t i = 0; i < conn_.size(); ++i) {
        if (prims_[i].idle) continue; // (the buffer of the cells in contact, as without idle ones)
        ++*count;
        *sum += diameter(xa, conn_[i].data());
      }
    PetscCall(VecRestoreArrayRead(Xl, &xa));
    PetscCall(DMRestoreLocalVector(dm, &Xl));
  }
  if (cached)
    for (size_t i = 0; i < conn_.size(); ++i) {
      if (state_[i].idle) continue; // (prims_[i].idle, from the compact array: a listing made in place asks again)
      PetscReal &D = diam_[cell_[i]];
      if (D < 0) D = diameter(xref_.data(), conn_[i].data());
      ++*count;
      *sum += D;
    }
  *sum *= 0.25;
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
