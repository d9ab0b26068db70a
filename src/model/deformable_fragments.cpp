// Deformable bodies, broken joints and fragments (doc/fracture.md): the topology of a
// fractured mesh, which the contact adapter (src/contact/mesh_adapter.cpp) and
// FDEMDeformableGetFragments use.
//
// A joint is broken when all three of its points are. The topology is computed where the
// cells are, without gathering the mesh anywhere. Each rank first works out what it can
// alone: the faces of its cells that are free (on the body's surface or on a broken joint)
// and the broken joints that touch its cells, with one reduction over the joint-face SF (the
// rank of tetrahedron b learns which of its faces are glued by an intact joint held elsewhere,
// and the partner of a broken one); then two union-finds over its own nodes and cells: node
// keys (copies glued by intact joints) and fragments (cells of one body sharing a node or held
// by an intact joint). Unsplit cells of a body with fracture zones share nodes like those of
// a body that is not fracturable, and their nodes may be glued to split copies. Every class
// carries a label, the smallest global id known to be in it. The classes that reach other
// ranks are completed in two stages: one exchange of labels (triangle b's node
// labels over the joint SF, tetrahedron b's cell label over the joint-face SF, both to the
// joint's rank) for the intact joints that straddle two ranks, and one over a second SF for
// the nodes that cells of a body share across ranks (built by a rendezvous on each node's id),
// link each class at a rank boundary to the classes it touches elsewhere; a node that ranks
// share also links its class on each rank to its own id. The labels and links form a graph
// that SettleClasses spreads over the ranks (label L on rank L % size) and settles there in
// rounds whose number grows with the logarithm of the longest chain of classes, giving every
// class its component's smallest label and flag. So every class ends with the smallest
// id in it, a fragment's id the same on any number of ranks. FDEMDeformableGetLocalFragments
// sums each fragment's mass, momentum and cells where its cells are and meets the sums at the
// rank id % size (a rendezvous), so each rank holds its share; FDEMDeformableGetFragments
// gathers the shares on every rank. Cost of the topology: a pass over the rank's cells,
// nodes and joints, a reduction and a broadcast over the joint-face SF, one broadcast over
// the straddling joints, the rendezvous and two exchanges over the shared nodes, and the
// rounds of SettleClasses (for nodes and for cells), each a few all-to-all exchanges of the
// rank's share of the graph and one MPI_Allreduce. Memory per rank: its cells, nodes and
// joints, the classes at its rank boundaries and its share of their graph; no rank holds
// the whole graph (before 2026-11-29 rank 0 gathered it).
#include "deformable_impl.hpp"
#include "deformable_object.hpp"

#include <petscsf.h>

#include <algorithm>
#include <climits>
#include <numeric>
#include <unordered_map>

using namespace fdem::model::deformable;

namespace {
// Items of W integers each, sent to ranks and answered: Send delivers every item to its rank
// (grouped by sender), Reply sends the receivers' answers (V integers per item, in the order
// Send delivered them) back to the senders, in the senders' order. Collective.
struct Router {
  MPI_Comm                 comm;
  PetscMPIInt              size;
  std::vector<PetscMPIInt> sc, rc, sd, rd; // items sent to / received from each rank, and their offsets
  std::vector<PetscInt>    slot;           // per item sent: its place in the send order

  Router(MPI_Comm c, PetscMPIInt n) : comm(c), size(n), sc(n), rc(n), sd(n + 1), rd(n + 1) {}
  PetscErrorCode Send(const std::vector<PetscMPIInt> &dest, int W, const std::vector<PetscInt> &items, std::vector<PetscInt> &recv) {
    PetscFunctionBegin;
    std::fill(sc.begin(), sc.end(), 0);
    for (PetscMPIInt r : dest) ++sc[r];
    PetscCallMPI(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm));
    sd[0] = rd[0] = 0;
    for (int r = 0; r < size; ++r) sd[r + 1] = sd[r] + sc[r], rd[r + 1] = rd[r] + rc[r];
    std::vector<PetscMPIInt> at(sd.begin(), sd.end() - 1);
    slot.resize(dest.size());
    for (std::size_t i = 0; i < dest.size(); ++i) slot[i] = at[dest[i]]++;
    std::vector<PetscInt> buf((std::size_t)W * dest.size());
    for (std::size_t i = 0; i < dest.size(); ++i)
      for (int k = 0; k < W; ++k) buf[(std::size_t)W * slot[i] + k] = items[(std::size_t)W * i + k];
    recv.resize((std::size_t)W * rd[size]);
    PetscCall(Move(W, buf, sc, sd, recv, rc, rd));
    PetscFunctionReturn(0);
  }
  PetscErrorCode Reply(int V, const std::vector<PetscInt> &answers, std::vector<PetscInt> &back) {
    std::vector<PetscInt> buf((std::size_t)V * sd[size]);
    PetscFunctionBegin;
    PetscCall(Move(V, answers, rc, rd, buf, sc, sd));
    back.resize((std::size_t)V * slot.size());
    for (std::size_t i = 0; i < slot.size(); ++i)
      for (int k = 0; k < V; ++k) back[(std::size_t)V * i + k] = buf[(std::size_t)V * slot[i] + k];
    PetscFunctionReturn(0);
  }

private:
  PetscErrorCode Move(int W, const std::vector<PetscInt> &out, const std::vector<PetscMPIInt> &oc, const std::vector<PetscMPIInt> &od, std::vector<PetscInt> &in, const std::vector<PetscMPIInt> &ic, const std::vector<PetscMPIInt> &id) {
    std::vector<PetscMPIInt> c1(size), d1(size), c2(size), d2(size);
    PetscFunctionBegin;
    PetscCheck((long long)W * std::max(od[size], id[size]) <= INT_MAX, comm, PETSC_ERR_SUP, "DeformableFractureTopology: too many classes at the rank boundaries for one exchange");
    for (int r = 0; r < size; ++r) c1[r] = W * oc[r], d1[r] = W * od[r], c2[r] = W * ic[r], d2[r] = W * id[r];
    PetscCallMPI(MPI_Alltoallv(out.data(), c1.data(), d1.data(), MPIU_INT, in.data(), c2.data(), d2.data(), MPIU_INT, comm));
    PetscFunctionReturn(0);
  }
};

} // namespace

// Completes the classes c that reach other ranks. Each rank has its classes at rank boundaries
// (the classes of the elements in `boundary`), by label, with their flags, and the links
// `edges` (its class's label, the label of a class elsewhere that touches it), as the one
// exchange of labels with the neighbouring ranks gave them. A label names one class on a rank
// (the smallest global id in it), and a label met on two ranks is one class (a node both ranks
// hold), so the labels and the links form a graph, and every class must end with the smallest
// label of its component and the or of its flags. The graph is spread over the ranks, label L
// on rank L % size, and its components are found there in rounds, each with a fixed number of
// exchanges (Shiloach-Vishkin with min-label hooking): every label takes the smallest parent
// among its neighbours' (aggressive hooking) and gives it to its parent (hooking), then jumps to
// its grandparent (shortcutting); a round ends with an MPI_Allreduce of whether anything changed.
// A parent is always a label of the component and never grows, so the smallest label is its own
// parent throughout and the fixed point gives it to every label of its component; the jumps
// shorten chains geometrically, so the rounds grow with the logarithm of the longest chain of
// classes, not with its length. No rank holds more than its share of the graph.
PetscErrorCode fdem::model::SettleClasses(MPI_Comm comm, LabelClasses &c, const std::vector<PetscInt> &boundary, std::vector<std::array<PetscInt, 2>> &edges, PetscInt *nclasses, PetscInt *rounds) {
  PetscMPIInt size;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::unordered_map<PetscInt, PetscInt> at; // a boundary class's label -> its element
  for (PetscInt b : boundary) at.emplace(c.Label(b), b);
  // the labels this rank knows (its boundary classes and the links' ends), each sent once to
  // its host with the class's flag
  std::vector<PetscInt> mine;
  mine.reserve(at.size() + 2 * edges.size());
  for (const auto &a : at) mine.push_back(a.first);
  for (const auto &e : edges) mine.push_back(e[0]), mine.push_back(e[1]);
  std::sort(mine.begin(), mine.end());
  mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
  const auto host = [size](PetscInt L) { return (PetscMPIInt)(L % size); };
  const auto idx  = [](const std::vector<PetscInt> &v, PetscInt L) { return (std::size_t)(std::lower_bound(v.begin(), v.end(), L) - v.begin()); };
  std::vector<PetscMPIInt> dest(mine.size());
  std::vector<PetscInt>    items(2 * mine.size()), recv, back;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    const auto it = at.find(mine[i]);
    dest[i] = host(mine[i]), items[2 * i] = mine[i], items[2 * i + 1] = it == at.end() ? 0 : c.flag[c.Find(it->second)];
  }
  Router known(comm, size); // kept: every round asks the hosts about the same labels
  PetscCall(known.Send(dest, 2, items, recv));
  // the hosted labels: sorted, their parents f and flags
  std::vector<PetscInt> lab;
  for (std::size_t k = 0; k < recv.size(); k += 2) lab.push_back(recv[k]);
  std::sort(lab.begin(), lab.end());
  lab.erase(std::unique(lab.begin(), lab.end()), lab.end());
  std::vector<PetscInt> f = lab, flag(lab.size(), 0);
  for (std::size_t k = 0; k < recv.size(); k += 2) flag[idx(lab, recv[k])] |= recv[k + 1];
  // each link by the positions of its ends in `mine`
  std::vector<std::array<std::size_t, 2>> link(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) link[e] = {idx(mine, edges[e][0]), idx(mine, edges[e][1])};
  const auto asked = [&](std::vector<PetscInt> &out, const std::vector<PetscInt> &v) { // v at every label `known` delivered
    out.resize(recv.size() / 2);
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = v[idx(lab, recv[2 * k])];
  };
  std::vector<PetscInt> ans, m, got;
  PetscInt              n = 0;
  for (PetscBool changed = PETSC_TRUE; changed; ++n) {
    PetscCheck(n < 1000, comm, PETSC_ERR_PLIB, "DeformableFractureTopology: the classes at the rank boundaries did not settle in 1000 rounds");
    const std::vector<PetscInt> f0 = f;
    // aggressive hooking: the smallest parent among each label's neighbours, met at its host
    asked(ans, f);
    PetscCall(known.Reply(1, ans, back)); // back[i]: the parent of mine[i]
    m = back;
    for (const auto &l : link) m[l[0]] = std::min(m[l[0]], back[l[1]]), m[l[1]] = std::min(m[l[1]], back[l[0]]);
    {
      Router                   to_hosts(comm, size);
      std::vector<PetscMPIInt> d(mine.size());
      std::vector<PetscInt>    it(2 * mine.size());
      for (std::size_t i = 0; i < mine.size(); ++i) d[i] = host(mine[i]), it[2 * i] = mine[i], it[2 * i + 1] = m[i];
      PetscCall(to_hosts.Send(d, 2, it, got));
    }
    std::vector<PetscInt> mh = f;
    for (std::size_t k = 0; k < got.size(); k += 2) {
      PetscInt &x = mh[idx(lab, got[k])];
      x           = std::min(x, got[k + 1]);
    }
    // hooking: each label's parent takes the smallest it saw (f[f[v]] = min(f[f[v]], m[v]))
    {
      Router                   to_parents(comm, size);
      std::vector<PetscMPIInt> d(lab.size());
      std::vector<PetscInt>    it(2 * lab.size());
      for (std::size_t v = 0; v < lab.size(); ++v) d[v] = host(f0[v]), it[2 * v] = f0[v], it[2 * v + 1] = mh[v];
      PetscCall(to_parents.Send(d, 2, it, got));
    }
    for (std::size_t v = 0; v < lab.size(); ++v) f[v] = std::min(f[v], mh[v]);
    for (std::size_t k = 0; k < got.size(); k += 2) {
      PetscInt &x = f[idx(lab, got[k])];
      x           = std::min(x, got[k + 1]);
    }
    // shortcutting: each label jumps to its parent's parent
    {
      Router                   to_parents(comm, size);
      std::vector<PetscMPIInt> d(lab.size());
      std::vector<PetscInt>    it(lab.size());
      for (std::size_t v = 0; v < lab.size(); ++v) d[v] = host(f[v]), it[v] = f[v];
      PetscCall(to_parents.Send(d, 1, it, got));
      std::vector<PetscInt> grand(got.size());
      for (std::size_t k = 0; k < got.size(); ++k) grand[k] = f[idx(lab, got[k])];
      PetscCall(to_parents.Reply(1, grand, back));
      for (std::size_t v = 0; v < lab.size(); ++v) f[v] = std::min(f[v], back[v]);
    }
    PetscBool mine_changed = f == f0 ? PETSC_FALSE : PETSC_TRUE;
    PetscCallMPI(MPIU_Allreduce(&mine_changed, &changed, 1, MPIU_BOOL, MPI_LOR, comm));
  }
  // the flags: or-ed at each component's smallest label, then read back by every label
  {
    Router                   to_roots(comm, size);
    std::vector<PetscMPIInt> d(lab.size());
    std::vector<PetscInt>    it(2 * lab.size());
    for (std::size_t v = 0; v < lab.size(); ++v) d[v] = host(f[v]), it[2 * v] = f[v], it[2 * v + 1] = flag[v];
    PetscCall(to_roots.Send(d, 2, it, got));
    std::vector<PetscInt> rflag(lab.size(), 0), r(got.size() / 2);
    for (std::size_t k = 0; k < got.size(); k += 2) rflag[idx(lab, got[k])] |= got[k + 1];
    for (std::size_t k = 0; k < r.size(); ++k) r[k] = rflag[idx(lab, got[2 * k])];
    PetscCall(to_roots.Reply(1, r, back));
    flag = back;
  }
  // every class at this rank's boundaries: its component's smallest label and flag
  std::vector<PetscInt> both(2 * (recv.size() / 2));
  for (std::size_t k = 0; k < recv.size() / 2; ++k) {
    const std::size_t v = idx(lab, recv[2 * k]);
    both[2 * k] = f[v], both[2 * k + 1] = flag[v];
  }
  PetscCall(known.Reply(2, both, back));
  for (std::size_t i = 0; i < mine.size(); ++i) {
    const auto it = at.find(mine[i]);
    if (it != at.end()) c.Lower(it->second, back[2 * i], (char)back[2 * i + 1]);
  }
  PetscInt hosted = (PetscInt)lab.size();
  PetscCallMPI(MPIU_Allreduce(&hosted, nclasses, 1, MPIU_INT, MPI_SUM, comm));
  *rounds = n;
  PetscFunctionReturn(0);
}

namespace {
// A joint with a point beyond its peak (softening or broken).
bool JointDamaged(const std::array<fdem::kernels::JointState, 3> &st) { return st[0].D > 0 || st[1].D > 0 || st[2].D > 0; }

std::vector<char> FracturableBodies(FDEMDeformable d) {
  std::vector<char> f(d->body_names.size(), 0);
  for (std::size_t b = 0; b < f.size(); ++b) f[b] = d->fracture.count(d->materials[d->material_of_body[b]].name) > 0;
  return f;
}


// An SF whose leaves are the given keys (two ints each) and whose roots are the distinct keys,
// one root each on the rank key[0] % size (a rendezvous): leaves with one key share a root.
// root_keys (may be null) gets this rank's roots' keys, sorted, in the order of the roots.
PetscErrorCode KeySF(MPI_Comm comm, const std::vector<std::array<PetscInt, 2>> &keys, PetscSF *sf, std::vector<std::array<PetscInt, 2>> *root_keys = nullptr) {
  PetscMPIInt size;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::vector<PetscMPIInt> sc(size, 0), rc(size), sd(size + 1, 0), rd(size + 1, 0), at(size);
  for (const auto &k : keys) sc[k[0] % size] += 2;
  PetscCallMPI(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r) {
    sd[r + 1] = sd[r] + sc[r];
    rd[r + 1] = rd[r] + rc[r];
  }
  std::vector<PetscInt> sbuf(sd[size]), rbuf(rd[size]), where(keys.size());
  std::copy(sd.begin(), sd.end() - 1, at.begin());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const int r = (int)(keys[i][0] % size);
    where[i]    = at[r];
    sbuf[at[r]] = keys[i][0], sbuf[at[r] + 1] = keys[i][1];
    at[r] += 2;
  }
  PetscCallMPI(MPI_Alltoallv(sbuf.data(), sc.data(), sd.data(), MPIU_INT, rbuf.data(), rc.data(), rd.data(), MPIU_INT, comm));
  std::vector<std::array<PetscInt, 2>> mine(rd[size] / 2);
  for (std::size_t i = 0; i < mine.size(); ++i) mine[i] = {rbuf[2 * i], rbuf[2 * i + 1]};
  std::vector<std::array<PetscInt, 2>> roots = mine;
  std::sort(roots.begin(), roots.end());
  roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
  for (std::size_t i = 0; i < mine.size(); ++i) rbuf[2 * i] = rbuf[2 * i + 1] = (PetscInt)(std::lower_bound(roots.begin(), roots.end(), mine[i]) - roots.begin());
  PetscCallMPI(MPI_Alltoallv(rbuf.data(), rc.data(), rd.data(), MPIU_INT, sbuf.data(), sc.data(), sd.data(), MPIU_INT, comm));
  std::vector<PetscSFNode> remote(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    remote[i].rank  = (PetscInt)(keys[i][0] % size);
    remote[i].index = sbuf[where[i]];
  }
  PetscCall(PetscSFCreate(comm, sf));
  PetscCall(PetscSFSetGraph(*sf, (PetscInt)roots.size(), (PetscInt)keys.size(), nullptr, PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(*sf));
  if (root_keys) *root_keys = std::move(roots);
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode fdem::model::DeformableSharedNodes(FDEMDeformable d, std::vector<char> &shared) {
  Vec          l, g;
  PetscScalar *a;
  PetscFunctionBegin;
  PetscCall(DMGetLocalVector(d->dm, &l));
  PetscCall(DMGetGlobalVector(d->dm, &g));
  PetscCall(VecSet(l, 1));
  PetscCall(VecSet(g, 0));
  PetscCall(fdem::model::DeformableLocalToGlobal(d, l, ADD_VALUES, g));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, g, l));
  PetscCall(VecGetArray(l, &a));
  shared.assign(d->nlocal, 0);
  for (PetscInt i = 0; i < d->nlocal; ++i) shared[i] = PetscRealPart(a[3 * i]) > 1.5;
  PetscCall(VecRestoreArray(l, &a));
  PetscCall(DMRestoreGlobalVector(d->dm, &g));
  PetscCall(DMRestoreLocalVector(d->dm, &l));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableHasJoints(FDEMDeformable d, PetscBool *has) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableHasJoints"));
  *has = d->njoints_global > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

void fdem::model::DeformableAddOnset(FDEMDeformable d, PetscReal e) { d->onset += e; }

PetscErrorCode fdem::model::DeformableJointCounts(FDEMDeformable d, PetscInt *nbroken, PetscInt *ndamaged) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableJointCounts"));
  *nbroken = *ndamaged = 0;
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  PetscInt n[2] = {0, 0}, all[2];
  for (const auto &st : d->jstate) n[0] += fdem::kernels::JointBroken(st.data()) ? 1 : 0, n[1] += JointDamaged(st) ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(n, all, 2, MPIU_INT, MPI_SUM, d->comm));
  *nbroken = all[0], *ndamaged = all[1];
  PetscFunctionReturn(0);
}

// The parts of the fracture topology that the joints' states do not change (TopologyCache).
// Collective.
static PetscErrorCode MakeTopologyCache(FDEMDeformable d, const std::vector<char> &fracturable, bool sharing) {
  const PetscInt nc = (PetscInt)d->ed.size(), nl = d->nlocal, nbodies = (PetscInt)fracturable.size();
  auto           c  = std::make_unique<fdem::model::TopologyCache>();
  const auto     node = [&](PetscInt e, int a) { return (PetscInt)d->ed.elems[e].n[a]; };
  PetscFunctionBegin;
  c->shared.assign(nl, 0);
  if (sharing) PetscCall(fdem::model::DeformableSharedNodes(d, c->shared));
  std::vector<int> uses(nl, 0);
  for (PetscInt e = 0; e < nc; ++e)
    for (int a = 0; a < 4; ++a) ++uses[node(e, a)];
  c->split.assign(nc, 0);
  for (PetscInt e = 0; e < nc; ++e) {
    bool lone = fracturable[d->ed.body[e]] != 0;
    for (int a = 0; a < 4 && lone; ++a) lone = uses[node(e, a)] == 1 && !c->shared[node(e, a)];
    c->split[e] = lone;
  }
  // cells of one body sharing a node (a split node has one cell): the first cell at each node,
  // and a map for the nodes that cells of a second body share
  c->cells = fdem::model::LabelClasses(d->cell_gid);
  std::vector<PetscInt>                   first(nl, -1);
  std::unordered_map<long long, PetscInt> other;
  for (PetscInt e = 0; e < nc; ++e)
    if (!c->split[e])
      for (int a = 0; a < 4; ++a) {
        const PetscInt f = first[node(e, a)];
        if (f < 0) first[node(e, a)] = e;
        else if (d->ed.body[f] == d->ed.body[e]) c->cells.Unite(f, e);
        else {
          const auto it = other.emplace((long long)node(e, a) * nbodies + d->ed.body[e], e);
          if (!it.second) c->cells.Unite(it.first->second, e);
        }
      }
  for (PetscInt e = 0; e < nc; ++e) c->cells.Find(e); // every path compressed
  c->froot.assign(12 * (std::size_t)nc, 0);
  if (d->jfsf) { // the faces some joint's leaves reach (a reduction into the zeroed roots: no degree arrays)
    PetscInt nleaves;
    PetscCall(PetscSFGetGraph(d->jfsf, nullptr, &nleaves, nullptr, nullptr));
    const std::vector<PetscInt> one(nleaves, 1);
    PetscCall(PetscSFReduceBegin(d->jfsf, MPIU_INT, one.data(), c->froot.data(), MPI_MAX));
    PetscCall(PetscSFReduceEnd(d->jfsf, MPIU_INT, one.data(), c->froot.data(), MPI_MAX));
    for (PetscInt r = 0; r < 12 * nc; r += 3)
      if (c->froot[r] || c->froot[r + 1] || c->froot[r + 2]) c->glued.push_back(r);
  }
  d->topology_cache = std::move(c);
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableFractureTopology(FDEMDeformable d, FractureTopology &t) {
  const FractureTopology *p;
  PetscFunctionBegin;
  PetscCall(DeformableFractureTopology(d, &p));
  t = *p;
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableFractureTopology(FDEMDeformable d, const FractureTopology **out) {
  constexpr PetscInt kNone = PETSC_MAX_INT, kNoFace = -3, kGlued = -2; // kNone: no label (MPI_MIN); kNoFace, kGlued: a face's joint (MPI_MAX)
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableFractureTopology"));
  // A joint once damaged (broken) stays so while it steps, so the counts name the sets: the
  // same counts, the same answer (the contact objects of a scene each ask at one evaluation)
  PetscInt nbroken, ndamaged;
  PetscCall(DeformableJointCounts(d, &nbroken, &ndamaged));
  if (d->topology_made && d->topology.nbroken == nbroken && d->topology.ndamaged == ndamaged) {
    *out = &d->topology;
    PetscFunctionReturn(0);
  }
  const PetscInt nc = (PetscInt)d->ed.size(), nl = d->nlocal, nj = (PetscInt)d->jnode_a.size();
  // The cells with a damaged joint face (bit 5 of cell_free): tetrahedron a of each damaged joint
  // here, and tetrahedron b wherever it is, over the joint-face SF (the third value of a face).
  // (A list, a cell perhaps more than once: an answer where only joints softened looks at these
  // cells alone.)
  const auto damaged_cells = [&](std::vector<PetscInt> &damaged) -> PetscErrorCode {
    damaged.clear();
    if (!d->jfsf) return 0;
    fdem::model::TopologyCache &tc = *d->topology_cache;
    std::vector<PetscInt>       fleaf(3 * (std::size_t)nj, kNoFace);
    for (PetscInt j = 0; j < nj; ++j)
      if (JointDamaged(d->jstate[j])) {
        damaged.push_back(d->jcell_a[j]);
        fleaf[3 * j + 2] = 1;
      }
    for (PetscInt r : tc.glued) tc.froot[r] = tc.froot[r + 1] = tc.froot[r + 2] = kNoFace;
    PetscCall(PetscSFReduceBegin(d->jfsf, MPIU_INT, fleaf.data(), tc.froot.data(), MPI_MAX));
    PetscCall(PetscSFReduceEnd(d->jfsf, MPIU_INT, fleaf.data(), tc.froot.data(), MPI_MAX));
    for (PetscInt r : tc.glued)
      if (tc.froot[r + 2] == 1) damaged.push_back(r / 12);
    return 0;
  };
  if (d->topology_made && d->topology.nbroken == nbroken) {
    // Only joints that softened: the broken ones are those of the last answer, and so are the
    // free faces, the node keys and the fragments; only the damaged cells change, and only by
    // joining (a joint once damaged stays so).
    std::vector<PetscInt> damaged;
    PetscCall(damaged_cells(damaged));
    auto &T    = d->topology;
    T.ndamaged = ndamaged;
    T.changed.clear();
    for (PetscInt e : damaged)
      if (!(T.cell_free[e] & 0x20)) {
        T.cell_free[e] |= 0x20;
        T.changed.push_back(e);
      }
    std::sort(T.changed.begin(), T.changed.end());
    T.changed_from = T.version++;
    *out = &T;
    PetscFunctionReturn(0);
  }
  FractureTopology t;
  t.fracturable          = FracturableBodies(d);
  const auto     frac    = [&](PetscInt e) { return t.fracturable[d->ed.body[e]] != 0; };
  const auto     node    = [&](PetscInt e, int a) { return (PetscInt)d->ed.elems[e].n[a]; };
  // Nodes shared across ranks (a body that is not fracturable, or the unsplit part of a body
  // with fracture zones; a split node has one cell, on one rank). A cell is split when none
  // of its nodes is another cell's, here or elsewhere. These, the cells' classes over shared
  // nodes and the faces that joints glue do not change while the joints step: made once.
  const bool sharing = d->size > 1 && (d->zoned || std::find(t.fracturable.begin(), t.fracturable.end(), 0) != t.fracturable.end());
  if (!d->topology_cache) PetscCall(MakeTopologyCache(d, t.fracturable, sharing));
  fdem::model::TopologyCache &tc = *d->topology_cache;
  const std::vector<char>    &shared = tc.shared;
  const auto split = [&](PetscInt e) { return tc.split[e] != 0; };
  const auto &ca = d->jcell_a; // each joint's tetrahedron a (split: its nodes are its own)
  // 1. Free faces and broken joints. Over the joint-face SF (jfsf) the rank of tetrahedron b
  //    learns, at the face a joint glues, whether an intact joint glues it (kGlued) or a broken
  //    one held by another rank faced tetrahedron a (that cell's id; a broken joint within the
  //    rank is listed once, by its own rank), whether the joint is intact and held by another
  //    rank (the face's nodes and its cell are then at a rank boundary). The damaged cells come
  //    after (damaged_cells).
  std::vector<unsigned char>           freef(nc, 0), damaged(nc, 0);
  std::vector<std::array<PetscInt, 2>> pairs;               // broken joints touching this rank's cells
  std::vector<PetscInt>                remote_j, remote_b, nbnd, cbnd; // intact joints to another rank; nodes of their triangles b here; nodes and cells glued to another rank
  std::vector<PetscInt>               &froot = tc.froot;
  std::vector<PetscInt>                fleaf(3 * (std::size_t)nj), root(3 * (std::size_t)nl), leaf(9 * (std::size_t)nj);
  for (PetscInt e = 0; e < nc; ++e)
    if (frac(e)) freef[e] = 0xF; // for an unsplit cell, its faces not glued; the contact adapter keeps those on the body's surface
  if (d->jfsf) {
    for (PetscInt j = 0; j < nj; ++j) {
      const bool broken = fdem::kernels::JointBroken(d->jstate[j].data()), remote = d->jnode_b[j][0] < 0;
      int        oa     = -1;
      for (int a = 0; a < 4; ++a) {
        bool in = false;
        for (int i = 0; i < 3; ++i) in = in || node(ca[j], a) == d->jnode_a[j][i];
        if (!in) oa = a;
      }
      const PetscInt gb = d->jtet_b[j][0];
      if (broken) pairs.push_back({std::min(d->cell_gid[ca[j]], gb), std::max(d->cell_gid[ca[j]], gb)});
      else freef[ca[j]] &= (unsigned char)~(1u << oa);
      if (!broken && remote) {
        for (int i = 0; i < 3; ++i) nbnd.push_back(d->jnode_a[j][i]);
        cbnd.push_back(ca[j]);
        remote_j.push_back(j);
      }
      fleaf[3 * j]     = !(broken && !remote) ? (broken ? d->cell_gid[ca[j]] : kGlued) : kNoFace;
      fleaf[3 * j + 1] = !broken && remote ? 1 : kNoFace;
      fleaf[3 * j + 2] = kNoFace; // (damaged_cells)
    }
    for (PetscInt r : tc.glued) froot[r] = froot[r + 1] = froot[r + 2] = kNoFace; // (the other roots get no leaf)
    PetscCall(PetscSFReduceBegin(d->jfsf, MPIU_INT, fleaf.data(), froot.data(), MPI_MAX));
    PetscCall(PetscSFReduceEnd(d->jfsf, MPIU_INT, fleaf.data(), froot.data(), MPI_MAX));
    for (PetscInt r : tc.glued) {
      const PetscInt  e = r / 12, o = (r % 12) / 3;
      const PetscInt *F = &froot[r];
      if (F[0] == kGlued) freef[e] &= (unsigned char)~(1u << o);
      else if (F[0] >= 0) pairs.push_back({std::min(F[0], d->cell_gid[e]), std::max(F[0], d->cell_gid[e])});
      if (F[1] == 1) {
        cbnd.push_back(e);
        for (int q = 0; q < 4; ++q)
          if (q != o) remote_b.push_back(node(e, q));
      }
    }
    std::sort(remote_b.begin(), remote_b.end());
    remote_b.erase(std::unique(remote_b.begin(), remote_b.end()), remote_b.end());
    nbnd.insert(nbnd.end(), remote_b.begin(), remote_b.end());
  }
  {
    std::vector<PetscInt> list;
    PetscCall(damaged_cells(list));
    for (PetscInt e : list) damaged[e] = 1;
  }
  std::sort(pairs.begin(), pairs.end());
  // 2. This rank's classes: node keys (the nodes of a split cell's free faces flagged) and fragments.
  LabelClasses nodes(std::vector<PetscInt>(d->node_gid.begin(), d->node_gid.begin() + nl)), cells = tc.cells;
  for (PetscInt e = 0; e < nc; ++e)
    if (split(e))
      for (int o = 0; o < 4; ++o)
        if (freef[e] >> o & 1)
          for (int q = 0; q < 4; ++q)
            if (q != o) nodes.flag[node(e, q)] = 1;
  for (PetscInt j = 0; j < nj; ++j)
    if (d->jnode_b[j][0] >= 0 && !fdem::kernels::JointBroken(d->jstate[j].data())) {
      for (int i = 0; i < 3; ++i) nodes.Unite(d->jnode_a[j][i], d->jnode_b[j][i]);
      cells.Unite(ca[j], d->jtet_b[j][2]);
    }
  // 3. Nodes that cells share with other ranks (a split node is on one rank): one root per
  //    (node id, body) on the rank node id % size.
  PetscSF               vsf = nullptr;
  std::vector<PetscInt> vcell; // a cell of the body at the node, per leaf
  if (sharing) {
    std::vector<std::array<PetscInt, 3>> k;
    for (PetscInt e = 0; e < nc; ++e)
      for (int a = 0; a < 4; ++a)
        if (shared[node(e, a)]) k.push_back({d->node_gid[node(e, a)], d->ed.body[e], e});
    std::sort(k.begin(), k.end());
    std::vector<std::array<PetscInt, 2>> keys;
    for (std::size_t i = 0; i < k.size(); ++i)
      if (i == 0 || k[i][0] != k[i - 1][0] || k[i][1] != k[i - 1][1]) keys.push_back({k[i][0], k[i][1]}), vcell.push_back(k[i][2]);
    PetscCall(KeySF(d->comm, keys, &vsf));
    cbnd.insert(cbnd.end(), vcell.begin(), vcell.end());
  }
  // 4. One exchange of labels with the neighbouring ranks links each class at a rank boundary
  //    to the classes it touches elsewhere; then the links of all ranks settle the classes
  //    (SettleClasses: the graph spread over the ranks, in rounds that grow with the
  //    logarithm of the longest chain of classes, whatever the shape of the fragments).
  std::vector<std::array<PetscInt, 2>> nedges, cedges; // (label here, label elsewhere)
  if (d->jsf_remote) { // triangle b's labels to the joint's rank: a link per straddling intact joint (the graph joins both ways)
    for (PetscInt l : remote_b) root[3 * l] = nodes.Label(l);
    for (PetscInt e = 0; e < nc; ++e) froot[12 * e] = froot[12 * e + 3] = froot[12 * e + 6] = froot[12 * e + 9] = cells.Label(e);
    PetscCall(PetscSFBcastBegin(d->jsf_remote, MPIU_INT, root.data(), leaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(d->jsf_remote, MPIU_INT, root.data(), leaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastBegin(d->jfsf, MPIU_INT, froot.data(), fleaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(d->jfsf, MPIU_INT, froot.data(), fleaf.data(), MPI_REPLACE));
    for (PetscInt j : remote_j) {
      for (int i = 0; i < 3; ++i) nedges.push_back({nodes.Label(d->jnode_a[j][i]), leaf[9 * j + 3 * i]});
      cedges.push_back({cells.Label(ca[j]), fleaf[3 * j]});
    }
  }
  if (vsf) { // the smallest label of every shared (node, body) to the cells that share it
    PetscInt              nvroot;
    std::vector<PetscInt> vleaf(vcell.size());
    PetscCall(PetscSFGetGraph(vsf, &nvroot, nullptr, nullptr, nullptr));
    std::vector<PetscInt> vroot(nvroot, kNone);
    for (std::size_t i = 0; i < vcell.size(); ++i) vleaf[i] = cells.Label(vcell[i]);
    PetscCall(PetscSFReduceBegin(vsf, MPIU_INT, vleaf.data(), vroot.data(), MPI_MIN));
    PetscCall(PetscSFReduceEnd(vsf, MPIU_INT, vleaf.data(), vroot.data(), MPI_MIN));
    PetscCall(PetscSFBcastBegin(vsf, MPIU_INT, vroot.data(), vleaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(vsf, MPIU_INT, vroot.data(), vleaf.data(), MPI_REPLACE));
    for (std::size_t i = 0; i < vcell.size(); ++i) cedges.push_back({cells.Label(vcell[i]), vleaf[i]});
    PetscCall(PetscSFDestroy(&vsf));
  }
  // A node that ranks share is one node: its class here and its classes elsewhere meet at
  // its id (unsplit nodes glued to split copies by joints have classes larger than
  // themselves since fracture zones).
  if (sharing)
    for (PetscInt l = 0; l < nl; ++l)
      if (shared[l]) {
        nbnd.push_back(l);
        if (nodes.Label(l) != d->node_gid[l]) nedges.push_back({nodes.Label(l), d->node_gid[l]});
      }
  if (d->size > 1) {
    PetscInt nn = 0, ncl = 0, rn = 0, rcl = 0;
    PetscCall(SettleClasses(d->comm, nodes, nbnd, nedges, &nn, &rn));
    PetscCall(SettleClasses(d->comm, cells, cbnd, cedges, &ncl, &rcl));
    if (d->rank == 0) PetscCall(PetscInfo(nullptr, "fracture topology: %" PetscInt_FMT " node and %" PetscInt_FMT " cell classes at the rank boundaries, settled in %" PetscInt_FMT " and %" PetscInt_FMT " rounds\n", nn, ncl, rn, rcl));
  }
  // 5. The answer per cell: its free faces and flags, its nodes' keys and its fragment's id
  //    (the smallest cell id in the fragment, the label of its class).
  t.nbroken      = nbroken;
  t.ndamaged     = ndamaged;
  t.broken_pairs = std::move(pairs);
  t.cell_free.resize(nc);
  t.cell_key.resize(4 * (std::size_t)nc);
  t.cell_fragment.resize(nc);
  std::vector<unsigned char> jointed(nc, 0), inserts(d->body_names.size(), 0); // a face is a joint, in a body with insertion
  for (std::size_t b = 0; b < inserts.size(); ++b) {
    const auto it = d->insertion.find(d->body_names[b]);
    inserts[b]    = it != d->insertion.end() && it->second > 0;
  }
  const auto inserting = [&](PetscInt e) { return (unsigned char)inserts[d->ed.body[e]]; };
  for (PetscInt j = 0; j < nj; ++j) jointed[ca[j]] = inserting(ca[j]);
  if (d->jfsf)
    for (PetscInt r : tc.glued) jointed[r / 12] = inserting(r / 12);
  for (PetscInt e = 0; e < nc; ++e) {
    bool onfree = false;
    for (int a = 0; a < 4; ++a) {
      t.cell_key[4 * e + a] = nodes.Label(node(e, a));
      onfree                = onfree || nodes.flag[nodes.Find(node(e, a))];
    }
    t.cell_free[e]     = (unsigned char)(freef[e] | (frac(e) && onfree ? 0x10 : 0) | (damaged[e] ? 0x20 : 0) | (frac(e) && !split(e) ? 0x40 : 0) | (jointed[e] ? 0x80 : 0));
    t.cell_fragment[e] = cells.Label(e);
  }
  t.version        = d->topology.version + 1;
  d->topology      = std::move(t);
  d->topology_made = true;
  *out             = &d->topology;
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableFeatureShares(FDEMDeformable d, const FractureTopology &t, const std::vector<unsigned char> &surface, std::vector<float> &share) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableFeatureShares"));
  const PetscInt nc = (PetscInt)d->ed.size();
  share.assign(10 * (std::size_t)nc, 1.0f);
  if (d->local_input.empty()) PetscFunctionReturn(0); // nothing was split: every node is one copy (the same on every rank)
  std::vector<PetscInt> cells; // the cells of fracturable bodies, 10 leaves each
  for (PetscInt e = 0; e < nc; ++e)
    if (t.fracturable[d->ed.body[e]]) cells.push_back(e);
  const auto input = [&](PetscInt e, int a) { return d->local_input[d->ed.elems[e].n[a]]; };
  const auto copy  = [&](PetscInt e, int a) { return d->node_gid[d->ed.elems[e].n[a]]; };
  if (!d->share_sf) { // leaves: (input node, -1) for a vertex, (smaller input node, larger) for an edge
    std::vector<std::array<PetscInt, 2>> keys(10 * cells.size());
    for (std::size_t k = 0; k < cells.size(); ++k) {
      for (int a = 0; a < 4; ++a) keys[10 * k + a] = {input(cells[k], a), -1};
      for (int m = 0; m < 6; ++m) {
        const PetscInt i = input(cells[k], fdem::kernels::kTetEdges[m][0]), j = input(cells[k], fdem::kernels::kTetEdges[m][1]);
        keys[10 * k + 4 + m] = {std::min(i, j), std::max(i, j)};
      }
    }
    PetscCall(KeySF(d->comm, keys, &d->share_sf));
  }
  // each leaf's copy (the split-mesh id of its node; of an edge, its two nodes' ids, smaller
  // first) when a surface face of its cell holds it, else (-1, -1), gathered at its input
  // vertex (edge), where the distinct copies are counted
  std::vector<PetscInt> leaf(20 * cells.size(), -1);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const PetscInt e = cells[k];
    const unsigned s = surface[e] & 0xF; // bit o: the face opposite vertex o
    for (int a = 0; a < 4; ++a)
      if (s & ~(1u << a)) leaf[20 * k + 2 * a] = copy(e, a); // a face that is not the one opposite a
    for (int m = 0; m < 6; ++m) {
      const int qa = fdem::kernels::kTetEdges[m][0], qb = fdem::kernels::kTetEdges[m][1];
      if (!(s & ~(1u << qa) & ~(1u << qb))) continue; // the faces holding edge (qa, qb) are the two opposite the others
      leaf[20 * k + 8 + 2 * m]     = std::min(copy(e, qa), copy(e, qb));
      leaf[20 * k + 8 + 2 * m + 1] = std::max(copy(e, qa), copy(e, qb));
    }
  }
  const PetscInt *degree;
  PetscInt        nroots, nmulti = 0;
  PetscCall(PetscSFGetGraph(d->share_sf, &nroots, nullptr, nullptr, nullptr));
  PetscCall(PetscSFComputeDegreeBegin(d->share_sf, &degree));
  PetscCall(PetscSFComputeDegreeEnd(d->share_sf, &degree));
  for (PetscInt r = 0; r < nroots; ++r) nmulti += degree[r];
  std::vector<PetscInt> multi(2 * (std::size_t)nmulti), count(2 * (std::size_t)nmulti, 0);
  PetscCall(PetscSFGatherBegin(d->share_sf, MPIU_2INT, leaf.data(), multi.data()));
  PetscCall(PetscSFGatherEnd(d->share_sf, MPIU_2INT, leaf.data(), multi.data()));
  std::vector<std::array<PetscInt, 2>> at; // one root's copies on the surface
  for (PetscInt r = 0, off = 0; r < nroots; off += degree[r], ++r) {
    at.clear();
    for (PetscInt i = off; i < off + degree[r]; ++i)
      if (multi[2 * i] >= 0) at.push_back({multi[2 * i], multi[2 * i + 1]});
    std::sort(at.begin(), at.end());
    const PetscInt n = (PetscInt)(std::unique(at.begin(), at.end()) - at.begin());
    for (PetscInt i = off; i < off + degree[r]; ++i) count[2 * i] = n;
  }
  PetscCall(PetscSFScatterBegin(d->share_sf, MPIU_2INT, count.data(), leaf.data()));
  PetscCall(PetscSFScatterEnd(d->share_sf, MPIU_2INT, count.data(), leaf.data()));
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (int f = 0; f < 10; ++f) share[10 * (std::size_t)cells[k] + f] = leaf[20 * k + 2 * f] > 1 ? (float)(1.0 / (double)leaf[20 * k + 2 * f]) : 1.0f;
  PetscFunctionReturn(0);
}

namespace {
// Orders fragments by body, then by id (the smallest cell id in them).
bool FragmentBefore(const FDEMFragment &a, const FDEMFragment &b) { return a.body != b.body ? a.body < b.body : a.id < b.id; }

// This rank's share of the fragments at the state U: those whose id is this rank modulo the
// number of ranks. Each rank sums mass, m x, m v and the cell count over its cells per
// fragment they belong to; the sums meet at the fragment's rank through a rendezvous SF on
// (id, body). Nothing per fragment of the whole mesh is held anywhere.
PetscErrorCode LocalFragments(FDEMDeformable d, Vec U, std::vector<FDEMFragment> &out) {
  const fdem::model::FractureTopology *tp;
  StateView                            sv;
  constexpr int                        kSums = 8; // mass, m x (3), m v (3), cells
  PetscFunctionBegin;
  PetscCall(fdem::model::DeformableFractureTopology(d, &tp));
  const fdem::model::FractureTopology &t = *tp;
  const std::size_t                    nc = d->ed.size();
  std::vector<std::array<PetscInt, 2>> keys(nc); // (id, body) of the fragments of this rank's cells
  for (std::size_t e = 0; e < nc; ++e) keys[e] = {t.cell_fragment[e], d->ed.body[e]};
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  // each tetrahedron puts a quarter of its mass rho V at each vertex (the lumped mass), so a
  // node shared by two bodies' fragments counts in each with its tetrahedra's share, and no
  // node is counted twice across ranks
  std::vector<PetscReal> leaf(kSums * keys.size(), 0.0);
  Vec                    Xl, Vl;
  const PetscScalar     *xl, *vl;
  PetscCall(sv.Get(d, U));
  PetscCall(DMGetLocalVector(d->dm, &Xl));
  PetscCall(DMGetLocalVector(d->dm, &Vl));
  PetscCall(VecPlaceArray(d->gwork, sv.xa));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, d->gwork, Xl));
  PetscCall(VecResetArray(d->gwork));
  PetscCall(VecPlaceArray(d->gwork, sv.va));
  PetscCall(fdem::model::DeformableGlobalToLocal(d, d->gwork, Vl));
  PetscCall(VecResetArray(d->gwork));
  PetscCall(sv.Restore());
  PetscCall(VecGetArrayRead(Xl, &xl));
  PetscCall(VecGetArrayRead(Vl, &vl));
  for (std::size_t e = 0; e < nc; ++e) {
    const auto     &el = d->ed.elems[e];
    const PetscReal q  = d->ed.materials[el.material].rho * el.V0 / 4;
    const auto      k  = std::lower_bound(keys.begin(), keys.end(), std::array<PetscInt, 2>{t.cell_fragment[e], d->ed.body[e]}) - keys.begin();
    PetscReal      *F  = &leaf[kSums * (std::size_t)k];
    F[0] += 4 * q;
    F[7] += 1;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) {
        F[1 + c] += q * PetscRealPart(xl[3 * el.n[a] + c]);
        F[4 + c] += q * PetscRealPart(vl[3 * el.n[a] + c]);
      }
  }
  PetscCall(VecRestoreArrayRead(Vl, &vl));
  PetscCall(VecRestoreArrayRead(Xl, &xl));
  PetscCall(DMRestoreLocalVector(d->dm, &Vl));
  PetscCall(DMRestoreLocalVector(d->dm, &Xl));
  // the rendezvous, widened to kSums values a key
  PetscSF                              ksf, sf;
  std::vector<std::array<PetscInt, 2>> mine;
  const PetscSFNode                   *kremote;
  PetscInt                             nroots;
  PetscCall(KeySF(d->comm, keys, &ksf, &mine));
  PetscCall(PetscSFGetGraph(ksf, &nroots, nullptr, nullptr, &kremote));
  std::vector<PetscSFNode> remote(kSums * keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
    for (int q = 0; q < kSums; ++q) remote[kSums * k + q] = {kremote[k].rank, kSums * kremote[k].index + q};
  PetscCall(PetscSFCreate(d->comm, &sf));
  PetscCall(PetscSFSetGraph(sf, kSums * nroots, (PetscInt)remote.size(), nullptr, PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFDestroy(&ksf));
  std::vector<PetscReal> root(kSums * (std::size_t)nroots, 0.0);
  PetscCall(PetscSFReduceBegin(sf, MPIU_REAL, leaf.data(), root.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(sf, MPIU_REAL, leaf.data(), root.data(), MPI_SUM));
  PetscCall(PetscSFDestroy(&sf));
  out.resize(mine.size());
  for (std::size_t f = 0; f < mine.size(); ++f) {
    FDEMFragment    &F = out[f];
    const PetscReal *g = &root[kSums * f];
    F.id               = mine[f][0];
    F.body             = mine[f][1];
    F.cells            = (PetscInt)g[7];
    F.mass             = g[0];
    for (int c = 0; c < 3; ++c) {
      F.x[c] = g[0] > 0 ? g[1 + c] / g[0] : 0;
      F.v[c] = g[0] > 0 ? g[4 + c] / g[0] : 0;
    }
  }
  std::sort(out.begin(), out.end(), FragmentBefore);
  PetscFunctionReturn(0);
}

// The array the API hands out (PetscMalloc1; NULL for none).
PetscErrorCode CopyOut(const std::vector<FDEMFragment> &v, FDEMFragment *fragments[]) {
  PetscFunctionBegin;
  *fragments = nullptr;
  if (!v.empty()) {
    PetscCall(PetscMalloc1(v.size(), fragments));
    std::copy(v.begin(), v.end(), *fragments);
  }
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode FDEMDeformableGetLocalFragments(FDEMDeformable d, Vec U, PetscInt *count, FDEMFragment *fragments[]) {
  std::vector<FDEMFragment> mine;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetLocalFragments"));
  PetscCheck(count || fragments, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableGetLocalFragments: give count or fragments (or both)");
  PetscCall(LocalFragments(d, U, mine));
  if (count) *count = (PetscInt)mine.size();
  if (fragments) PetscCall(CopyOut(mine, fragments));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetFragments(FDEMDeformable d, Vec U, PetscInt *count, FDEMFragment *fragments[]) {
  std::vector<FDEMFragment> mine;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetFragments"));
  PetscCheck(count || fragments, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableGetFragments: give count or fragments (or both)");
  if (!fragments) { // the count alone: the cells that name their fragment, over the ranks
    const fdem::model::FractureTopology *t;
    PetscInt                             n = 0;
    PetscCall(fdem::model::DeformableFractureTopology(d, &t));
    for (std::size_t e = 0; e < t->cell_fragment.size(); ++e) n += t->cell_fragment[e] == d->cell_gid[e];
    PetscCallMPI(MPIU_Allreduce(&n, count, 1, MPIU_INT, MPI_SUM, d->comm));
    PetscFunctionReturn(0);
  }
  PetscCall(LocalFragments(d, U, mine));
  const PetscMPIInt nmine = (PetscMPIInt)mine.size();
  // every rank's share to every rank, as bytes (the struct is PetscInt and PetscReal only)
  std::vector<PetscMPIInt> cnt(d->size), off(d->size + 1, 0);
  const PetscMPIInt        bytes = (PetscMPIInt)(nmine * sizeof(FDEMFragment));
  PetscCallMPI(MPI_Allgather(&bytes, 1, MPI_INT, cnt.data(), 1, MPI_INT, d->comm));
  long long sum = 0;
  for (int r = 0; r < d->size; ++r) sum += cnt[r];
  PetscCheck(sum <= INT_MAX, d->comm, PETSC_ERR_SUP, "FDEMDeformableGetFragments: %lld fragments are too many to give every rank; use FDEMDeformableGetLocalFragments (each rank its share)", sum / (long long)sizeof(FDEMFragment));
  for (int r = 0; r < d->size; ++r) off[r + 1] = off[r] + cnt[r];
  std::vector<FDEMFragment> all(off[d->size] / sizeof(FDEMFragment));
  PetscCallMPI(MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), cnt.data(), off.data(), MPI_BYTE, d->comm));
  std::sort(all.begin(), all.end(), FragmentBefore);
  if (count) *count = (PetscInt)all.size();
  PetscCall(CopyOut(all, fragments));
  PetscFunctionReturn(0);
}
