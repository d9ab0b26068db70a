// Deformable bodies, broken joints and fragments (doc/fracture.md): the
// topology of a fractured mesh, which the contact adapter
// (src/contact/mesh_adapter.cpp) and FDEMDeformableGetFragments use.
//
// A joint is broken when all three of its points are. The topology is computed
// on rank 0: every rank sends it its cells (id, body, node ids) and its joints
// (the node ids of both triangles, broken or not), rank 0 runs two union-finds
// and sends each rank the answer for its cells. This costs one gather of the
// mesh's cells and joints each time it is asked for (at set-up of a contact
// adapter, when the number of broken joints changes, and for each
// FDEMDeformableGetFragments), which is acceptable for the meshes fdem runs
// today; a distributed version (label propagation over the joint SF) would
// replace it for large ones.
#include "deformable_impl.hpp"
#include "deformable_object.hpp"

#include <petscsf.h>

#include <algorithm>
#include <numeric>
#include <unordered_map>

using namespace fdem::model::deformable;

namespace {
// Union-find whose root is the smallest member.
struct UnionFind {
  std::vector<PetscInt> p;
  explicit UnionFind(PetscInt n) : p(n) { std::iota(p.begin(), p.end(), (PetscInt)0); }
  PetscInt Find(PetscInt i) {
    while (p[i] != i) i = p[i] = p[p[i]];
    return i;
  }
  void Unite(PetscInt a, PetscInt b) {
    a = Find(a);
    b = Find(b);
    if (a < b) p[b] = a;
    else if (b < a) p[a] = b;
  }
};

bool JointBroken(const std::array<fdem::kernels::JointState, 3> &st) { return st[0].broken && st[1].broken && st[2].broken; }

std::vector<char> FracturableBodies(FDEMDeformable d) {
  std::vector<char> f(d->body_names.size(), 0);
  for (std::size_t b = 0; b < f.size(); ++b) f[b] = d->fracture.count(d->materials[d->material_of_body[b]].name) > 0;
  return f;
}
} // namespace

PetscErrorCode fdem::model::DeformableHasJoints(FDEMDeformable d, PetscBool *has) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableHasJoints"));
  *has = d->njoints_global > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableBrokenJoints(FDEMDeformable d, PetscInt *nbroken) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableBrokenJoints"));
  *nbroken = 0;
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  PetscInt n = 0;
  for (const auto &st : d->jstate) n += JointBroken(st) ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(&n, nbroken, 1, MPIU_INT, MPI_SUM, d->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableFractureTopology(FDEMDeformable d, FractureTopology &t) {
  constexpr int CI = 6, JI = 7,
                OI = 6; // ints per cell and per joint sent to rank 0, per cell back
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableFractureTopology"));
  const PetscMPIInt size = d->size;
  const PetscInt    nc = (PetscInt)d->ed.size(), nj = (PetscInt)d->jnode_a.size();
  t.fracturable          = FracturableBodies(d);
  const PetscInt nbodies = (PetscInt)t.fracturable.size();
  // the global ids of triangle b's nodes, through the joint SF (roots: 3
  // entries per local node)
  std::vector<PetscScalar> bg(9 * (std::size_t)nj);
  if (d->njoints_global > 0) {
    std::vector<PetscScalar> roots(3 * (std::size_t)d->nlocal);
    for (PetscInt l = 0; l < d->nlocal; ++l)
      for (int k = 0; k < 3; ++k) roots[3 * l + k] = (PetscScalar)d->node_gid[l];
    PetscCall(PetscSFBcastBegin(d->jsf, MPIU_SCALAR, roots.data(), bg.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(d->jsf, MPIU_SCALAR, roots.data(), bg.data(), MPI_REPLACE));
  }
  std::vector<PetscInt> cells(CI * (std::size_t)nc), joints(JI * (std::size_t)nj);
  for (PetscInt e = 0; e < nc; ++e) {
    cells[CI * e]     = d->cell_gid[e];
    cells[CI * e + 1] = d->ed.body[e];
    for (int a = 0; a < 4; ++a) cells[CI * e + 2 + a] = d->node_gid[d->ed.elems[e].n[a]];
  }
  for (PetscInt j = 0; j < nj; ++j) {
    for (int i = 0; i < 3; ++i) {
      joints[JI * j + i]     = d->node_gid[d->jnode_a[j][i]];
      joints[JI * j + 3 + i] = (PetscInt)PetscRealPart(bg[9 * j + 3 * i]);
    }
    joints[JI * j + 6] = JointBroken(d->jstate[j]) ? 1 : 0;
  }
  // gather on rank 0
  PetscMPIInt              mine[2] = {(PetscMPIInt)(CI * nc), (PetscMPIInt)(JI * nj)};
  std::vector<PetscMPIInt> both(2 * size), cc(size), jc(size), co(size + 1, 0), jo(size + 1, 0);
  PetscCallMPI(MPI_Gather(mine, 2, MPI_INT, both.data(), 2, MPI_INT, 0, d->comm));
  for (int r = 0; r < size; ++r) {
    cc[r]     = both[2 * r];
    jc[r]     = both[2 * r + 1];
    co[r + 1] = co[r] + cc[r];
    jo[r + 1] = jo[r] + jc[r];
  }
  std::vector<PetscInt> C(d->rank == 0 ? co[size] : 0), J(d->rank == 0 ? jo[size] : 0);
  PetscCallMPI(MPI_Gatherv(cells.data(), mine[0], MPIU_INT, C.data(), cc.data(), co.data(), MPIU_INT, 0, d->comm));
  PetscCallMPI(MPI_Gatherv(joints.data(), mine[1], MPIU_INT, J.data(), jc.data(), jo.data(), MPIU_INT, 0, d->comm));
  // rank 0: the two union-finds
  std::vector<PetscInt> out;
  std::vector<PetscInt> head(2, 0); // nbroken, nfragments, then the fragments'
                                    // bodies, then the broken pairs
  std::vector<std::array<PetscInt, 2>> pairs;
  if (d->rank == 0) {
    const PetscInt        ncell = (PetscInt)C.size() / CI, njoint = (PetscInt)J.size() / JI, nn = d->nnodes_global;
    std::vector<PetscInt> node_cell(nn, -1), ord(ncell);
    for (PetscInt c = 0; c < ncell; ++c)
      for (int a = 0; a < 4; ++a) node_cell[C[CI * c + 2 + a]] = c; // a split node has one cell
    UnionFind nodes(nn), comps(ncell);
    // cells of one body sharing a node
    std::unordered_map<long long, PetscInt> first;
    for (PetscInt c = 0; c < ncell; ++c)
      for (int a = 0; a < 4; ++a) {
        const auto it = first.emplace((long long)C[CI * c + 2 + a] * nbodies + C[CI * c + 1], c);
        if (!it.second) comps.Unite(it.first->second, c);
      }
    std::vector<unsigned char> freef(ncell, 0);
    for (PetscInt c = 0; c < ncell; ++c)
      if (t.fracturable[C[CI * c + 1]]) freef[c] = 0xF;
    // the face of cell c made of the nodes tri: bit of the node of c not in tri
    auto face_bit = [&](PetscInt c, const PetscInt *tri) {
      for (int o = 0; o < 4; ++o) {
        const PetscInt n = C[CI * c + 2 + o];
        if (n != tri[0] && n != tri[1] && n != tri[2]) return (unsigned char)(1u << o);
      }
      return (unsigned char)0;
    };
    for (PetscInt j = 0; j < njoint; ++j) {
      const PetscInt *a = &J[JI * j], *b = &J[JI * j + 3];
      const PetscInt  ca = node_cell[a[0]], cb = node_cell[b[0]];
      PetscCheck(ca >= 0 && cb >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "DeformableFractureTopology: joint %" PetscInt_FMT " has a node in no cell", j);
      if (J[JI * j + 6]) {
        pairs.push_back({std::min(C[CI * ca], C[CI * cb]), std::max(C[CI * ca], C[CI * cb])});
        continue;
      }
      for (int i = 0; i < 3; ++i) nodes.Unite(a[i], b[i]);
      comps.Unite(ca, cb);
      freef[ca] &= (unsigned char)~face_bit(ca, a);
      freef[cb] &= (unsigned char)~face_bit(cb, b);
    }
    std::sort(pairs.begin(), pairs.end());
    // vertices on the free surface (by key)
    std::vector<char> onfree(nn, 0);
    for (PetscInt c = 0; c < ncell; ++c)
      for (int o = 0; o < 4; ++o)
        if (freef[c] >> o & 1)
          for (int q = 0; q < 4; ++q)
            if (q != o) onfree[nodes.Find(C[CI * c + 2 + q])] = 1;
    for (PetscInt c = 0; c < ncell; ++c)
      if (t.fracturable[C[CI * c + 1]])
        for (int q = 0; q < 4; ++q)
          if (onfree[nodes.Find(C[CI * c + 2 + q])]) freef[c] |= 0x10;
    // fragments numbered by body, then their smallest cell id (the same on any
    // number of ranks)
    std::vector<PetscInt> low(ncell, PETSC_MAX_INT);
    for (PetscInt c = 0; c < ncell; ++c) low[comps.Find(c)] = std::min(low[comps.Find(c)], C[CI * c]);
    std::vector<PetscInt> roots;
    for (PetscInt c = 0; c < ncell; ++c)
      if (comps.Find(c) == c) roots.push_back(c);
    std::sort(roots.begin(), roots.end(), [&](PetscInt u, PetscInt v) { return C[CI * u + 1] != C[CI * v + 1] ? C[CI * u + 1] < C[CI * v + 1] : low[u] < low[v]; });
    std::vector<PetscInt> id(ncell, -1);
    for (std::size_t k = 0; k < roots.size(); ++k) id[roots[k]] = (PetscInt)k;
    head[0] = (PetscInt)pairs.size();
    head[1] = (PetscInt)roots.size();
    for (PetscInt r : roots) head.push_back(C[CI * r + 1]);
    out.resize(OI * (std::size_t)ncell);
    for (PetscInt c = 0; c < ncell; ++c) {
      out[OI * c]     = id[comps.Find(c)];
      out[OI * c + 1] = freef[c];
      for (int a = 0; a < 4; ++a) out[OI * c + 2 + a] = nodes.Find(C[CI * c + 2 + a]);
    }
  }
  // back to every rank: the counts, the fragments' bodies and the broken pairs
  // to all, the cells to their ranks
  PetscCallMPI(MPI_Bcast(head.data(), 2, MPIU_INT, 0, d->comm));
  t.nbroken    = head[0];
  t.nfragments = head[1];
  head.resize(2 + (std::size_t)t.nfragments);
  PetscCallMPI(MPI_Bcast(head.data() + 2, (PetscMPIInt)t.nfragments, MPIU_INT, 0, d->comm));
  t.fragment_body.assign(head.begin() + 2, head.end());
  t.broken_pairs.resize(t.nbroken);
  PetscCallMPI(MPI_Bcast(t.nbroken ? (d->rank == 0 ? pairs.data() : t.broken_pairs.data()) : nullptr, (PetscMPIInt)(2 * t.nbroken), MPIU_INT, 0, d->comm));
  if (d->rank == 0) t.broken_pairs = pairs;
  for (int r = 0; r < size; ++r) {
    cc[r]     = cc[r] / CI * OI;
    co[r + 1] = co[r] + cc[r];
  }
  std::vector<PetscInt> back(OI * (std::size_t)nc);
  PetscCallMPI(MPI_Scatterv(out.data(), cc.data(), co.data(), MPIU_INT, back.data(), (PetscMPIInt)(OI * nc), MPIU_INT, 0, d->comm));
  t.cell_fragment.resize(nc);
  t.cell_free.resize(nc);
  t.cell_key.resize(4 * (std::size_t)nc);
  for (PetscInt e = 0; e < nc; ++e) {
    t.cell_fragment[e] = back[OI * e];
    t.cell_free[e]     = (unsigned char)back[OI * e + 1];
    for (int a = 0; a < 4; ++a) t.cell_key[4 * e + a] = back[OI * e + 2 + a];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetFragments(FDEMDeformable d, Vec U, PetscInt *count, FDEMFragment *fragments[]) {
  fdem::model::FractureTopology t;
  StateView                     sv;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetFragments"));
  PetscCheck(count || fragments, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableGetFragments: give count or fragments (or both)");
  PetscCall(fdem::model::DeformableFractureTopology(d, t));
  const PetscInt nf = t.nfragments;
  if (count) *count = nf;
  if (!fragments) PetscFunctionReturn(0);
  // per fragment: mass, m x (3), m v (3), cells; each tetrahedron puts a quarter of its mass
  // rho V at each vertex (the lumped mass), so a node shared by two bodies' fragments counts
  // in each with its tetrahedra's share, and no node is counted twice across ranks
  std::vector<PetscReal> loc(8 * (std::size_t)nf, 0.0), glob(8 * (std::size_t)nf);
  Vec                    Xl, Vl;
  const PetscScalar     *xl, *vl;
  PetscCall(sv.Get(d, U));
  PetscCall(DMGetLocalVector(d->dm, &Xl));
  PetscCall(DMGetLocalVector(d->dm, &Vl));
  PetscCall(VecPlaceArray(d->gwork, sv.xa));
  PetscCall(DMGlobalToLocal(d->dm, d->gwork, INSERT_VALUES, Xl));
  PetscCall(VecResetArray(d->gwork));
  PetscCall(VecPlaceArray(d->gwork, sv.va));
  PetscCall(DMGlobalToLocal(d->dm, d->gwork, INSERT_VALUES, Vl));
  PetscCall(VecResetArray(d->gwork));
  PetscCall(sv.Restore());
  PetscCall(VecGetArrayRead(Xl, &xl));
  PetscCall(VecGetArrayRead(Vl, &vl));
  for (std::size_t e = 0; e < d->ed.size(); ++e) {
    const auto     &el = d->ed.elems[e];
    const PetscReal q  = d->ed.materials[el.material].rho * el.V0 / 4;
    PetscReal      *F  = &loc[8 * (std::size_t)t.cell_fragment[e]];
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
  PetscCall(MPIU_Allreduce(loc.data(), glob.data(), (PetscMPIInt)loc.size(), MPIU_REAL, MPIU_SUM, d->comm));
  PetscCall(PetscMalloc1(nf, fragments));
  for (PetscInt f = 0; f < nf; ++f) {
    FDEMFragment &F = (*fragments)[f];
    const double *g = &glob[8 * f];
    F.body          = t.fragment_body[f];
    F.cells         = (PetscInt)g[7];
    F.mass          = g[0];
    for (int c = 0; c < 3; ++c) {
      F.x[c] = g[0] > 0 ? g[1 + c] / g[0] : 0;
      F.v[c] = g[0] > 0 ? g[4 + c] / g[0] : 0;
    }
  }
  PetscFunctionReturn(0);
}
