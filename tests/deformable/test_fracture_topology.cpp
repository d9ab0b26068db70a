// The fracture topology on any number of ranks (doc/fracture.md, "Broken joints",
// "Fragments"): a box of 12 x 4 x 4 cubes of 0.1 m (6 tetrahedra each), its three lower
// layers a fracturable body "rock", its top layer two bodies that are not fracturable, "plate"
// (x < 0.6) and "lid" (x > 0.6), which share their nodes at x = 0.6 with each other. Chosen
// joints of the rock are broken by hand: every joint of the plane x = 0.6 (a cut through the
// rock), every joint around a closed pocket of 2 x 2 x 1 cubes (0.1 < x, y < 0.3,
// 0.1 < z < 0.2), and the joints of the plane z = 0.2 where x > 0.7 and y < 0.2 (a crack that
// does not run through: its faces stay glued at its tip). Asserted, on 1, 2 and 3 ranks:
//  1. 5 fragments: the rock left of the cut without the pocket (68 cubes), the pocket (4),
//     the rock right of the cut (72), the plate (24) and the lid (24); every cell's fragment
//     id is the smallest cell id of its region; FDEMDeformableGetFragments gives them ordered
//     by body and id, with each fragment's body, id, cell count (exactly) and mass (rho times
//     its volume, to 1e-12 relative), and its count alone gives 5; each rank's share
//     (FDEMDeformableGetLocalFragments) is exactly the fragments of that list whose id is
//     the rank modulo the ranks, in order, bitwise the same;
//  2. every cell's fragment, free faces, vertex flag and node keys, the number of broken
//     joints and the broken pairs that touch the rank's cells are those of the same mesh held
//     whole by one rank (PETSC_COMM_SELF), by cell and node id;
//  3. on more than one rank, some fragment of the rock and some body that is not fracturable
//     have cells on several ranks (so the labels had to cross ranks for 1 and 2 to hold);
//  4. the weights of a sphere's contacts with the copies of the rock's vertices and edges
//     (DeformableFeatureShares, the free faces as the surface) are 1 over the distinct copies
//     of the input vertex (edge) on the surface, counted here over the whole mesh.
// With -zone, the rock is fracturable only in the zone 0.1 < x < 0.7 (FDEMDeformableAddFractureZone):
// the cut and the pocket lie in it (the pocket's wall x = 0.1 on its edge, joints between split
// and unsplit tetrahedra), the half crack outside it (no joints there). The same 5 fragments
// and 1 and 2 hold, and the rock's cells outside the zone (72 cubes) are the unsplit ones.
#include "common.hpp"
#include "../common/reference.hpp"
#include "../../src/model/deformable_impl.hpp"
#include "../../src/model/deformable_object.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <set>

namespace {
using fdem::kernels::Vec3;
constexpr double rho_rock = 2000, rho_top = 7800;

// 0: the rock left of the cut, around the pocket; 1: the pocket; 2: the rock right of the cut;
// 3: the plate; 4: the lid.
int Region(const Vec3 &c) {
  if (c.z > 0.3) return c.x < 0.6 ? 3 : 4;
  if (c.x > 0.1 && c.x < 0.3 && c.y > 0.1 && c.y < 0.3 && c.z > 0.1 && c.z < 0.2) return 1;
  return c.x < 0.6 ? 0 : 2;
}
const int    kBody[5]  = {0, 0, 0, 1, 2};
const int    kCubes[5] = {68, 4, 72, 24, 24};
const double kRho[5]   = {rho_rock, rho_rock, rho_rock, rho_top, rho_top};

PetscErrorCode Make(MPI_Comm comm, FDEMDeformable *out) {
  FDEMDeformable d;
  PetscFunctionBeginUser;
  fdem::kernels::TetMesh M = fdem::kernels::MakeBoxMesh(Vec3(0, 0, 0), Vec3(1.2, 0.4, 0.4), 12, 4, 4);
  M.body_names             = {"rock", "plate", "lid"};
  M.body.resize(M.tets.size());
  for (size_t e = 0; e < M.tets.size(); ++e) {
    Vec3 c(0, 0, 0);
    for (int a = 0; a < 4; ++a) c = c + 0.25 * M.nodes[M.tets[e][a]];
    M.body[e] = c.z < 0.3 ? 0 : c.x < 0.6 ? 1 : 2;
  }
  PetscCall(FDEMDeformableCreate(comm, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", 1e9, 0.25, rho_rock, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableAddMaterial(d, "steel", 2e11, 0.3, rho_top, 0, FDEM_MATERIAL_MUNJIZA_CST));
  PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1e6, 3e6, 30, 50, 200, 1e10));
  PetscCall(SetKernelMesh(d, M));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "rock", "rock"));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "plate", "steel"));
  PetscCall(FDEMDeformableSetBodyMaterial(d, "lid", "steel"));
  PetscBool zone = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-zone", &zone, nullptr));
  if (zone) {
    const PetscReal lo[3] = {0.1, -1, -1}, hi[3] = {0.7, 1, 1};
    PetscCall(FDEMDeformableAddFractureZone(d, "rock", lo, hi));
  }
  PetscCall(FDEMDeformableSetUp(d));
  *out = d;
  PetscFunctionReturn(0);
}

// Breaks, on the rank that holds it, every joint whose face separates two regions (points just
// off its centroid on either side) and the joints of the crack z = 0.2, x > 0.7, y < 0.2.
PetscErrorCode Break(FDEMDeformable d) {
  std::vector<PetscScalar> x;
  PetscFunctionBeginUser;
  PetscCall(LocalReference(d, x));
  for (size_t j = 0; j < d->jnode_a.size(); ++j) {
    Vec3 p[3];
    for (int i = 0; i < 3; ++i) p[i] = Vec3(x[3 * d->jnode_a[j][i]], x[3 * d->jnode_a[j][i] + 1], x[3 * d->jnode_a[j][i] + 2]);
    const Vec3   c = (1.0 / 3) * (p[0] + p[1] + p[2]), n = cross(p[1] - p[0], p[2] - p[0]);
    const Vec3   off = (1e-3 / norm(n)) * n;
    const bool   crack = std::fabs(c.z - 0.2) < 1e-9 && std::fabs(n.x) + std::fabs(n.y) < 1e-12 && c.x > 0.7 && c.y < 0.2;
    if (Region(c + off) != Region(c - off) || crack)
      for (auto &s : d->jstate[j]) s.SetDamage(1);
  }
  PetscFunctionReturn(0);
}

// The answer of one cell by node id: (node id, key, face opposite it free) for its 4 nodes,
// sorted, then the fragment and the vertex flag.
struct CellAnswer {
  std::array<std::array<PetscInt, 3>, 4> nodes;
  PetscInt                               fragment, onfree;
  bool operator==(const CellAnswer &o) const { return nodes == o.nodes && fragment == o.fragment && onfree == o.onfree; }
};

PetscErrorCode Answers(FDEMDeformable d, const fdem::model::FractureTopology &t, std::map<PetscInt, CellAnswer> &out, std::vector<Vec3> *centroid) {
  PetscInt                 nc, nl;
  std::vector<PetscScalar> x;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, nullptr, nullptr, nullptr, nullptr));
  std::vector<PetscInt> conn(4 * (size_t)nc), cgid(nc), ngid(nl);
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, conn.data(), nullptr, cgid.data(), ngid.data()));
  PetscCall(LocalReference(d, x));
  if (centroid) centroid->assign(nc, Vec3(0, 0, 0));
  for (PetscInt e = 0; e < nc; ++e) {
    CellAnswer A;
    for (int a = 0; a < 4; ++a) {
      A.nodes[a] = {ngid[conn[4 * e + a]], t.cell_key[4 * e + a], (PetscInt)(t.cell_free[e] >> a & 1)};
      if (centroid) (*centroid)[e] = (*centroid)[e] + 0.25 * Vec3(x[3 * conn[4 * e + a]], x[3 * conn[4 * e + a] + 1], x[3 * conn[4 * e + a] + 2]);
    }
    std::sort(A.nodes.begin(), A.nodes.end());
    A.fragment   = t.cell_fragment[e];
    A.onfree     = t.cell_free[e] >> 4 & 1;
    out[cgid[e]] = A;
  }
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscMPIInt size, rank;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  FDEMDeformable d, s;
  PetscCall(Make(PETSC_COMM_WORLD, &d));
  PetscCall(Make(PETSC_COMM_SELF, &s)); // the same mesh whole on every rank: the reference
  PetscCall(Break(d));
  PetscCall(Break(s));
  fdem::model::FractureTopology t, ts;
  PetscCall(fdem::model::DeformableFractureTopology(d, t));
  PetscCall(fdem::model::DeformableFractureTopology(s, ts));
  std::map<PetscInt, CellAnswer> mine, whole;
  std::vector<Vec3>              centroid;
  PetscCall(Answers(d, t, mine, &centroid));
  PetscCall(Answers(s, ts, whole, nullptr));

  // 1. the fragments the cut must give, numbered by body and smallest cell id
  const PetscInt nc = (PetscInt)centroid.size();
  PetscInt       low[5], glow[5];
  std::fill(low, low + 5, PETSC_MAX_INT);
  std::vector<int> region(nc);
  for (PetscInt e = 0; e < nc; ++e) {
    region[e]         = Region(centroid[e]);
    low[region[e]]    = std::min(low[region[e]], d->cell_gid[e]);
  }
  PetscCallMPI(MPIU_Allreduce(low, glow, 5, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  int order[5] = {0, 1, 2, 3, 4}, id[5];
  std::sort(order, order + 5, [&](int a, int b) { return kBody[a] != kBody[b] ? kBody[a] < kBody[b] : glow[a] < glow[b]; });
  for (int k = 0; k < 5; ++k) id[order[k]] = k;
  PetscInt wrong = 0, gwrong;
  for (PetscInt e = 0; e < nc; ++e) wrong += t.cell_fragment[e] != glow[region[e]];
  PetscCallMPI(MPIU_Allreduce(&wrong, &gwrong, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  CHECK(gwrong == 0, "%" PetscInt_FMT " cells do not have the fragment id of their region (its smallest cell id)", gwrong);
  PetscInt      nf, nmine, ncount;
  FDEMFragment *f, *m;
  PetscCall(FDEMDeformableGetFragments(d, nullptr, &nf, &f));
  PetscCall(FDEMDeformableGetFragments(d, nullptr, &ncount, nullptr));
  CHECK(nf == 5 && ncount == 5, "%" PetscInt_FMT " fragments (%" PetscInt_FMT " counted alone), expected 5", nf, ncount);
  if (nf == 5)
    for (int r = 0; r < 5; ++r) {
      const FDEMFragment &F = f[id[r]];
      const double        m = kRho[r] * kCubes[r] * 1e-3;
      CHECK(F.body == kBody[r] && F.id == glow[r] && F.cells == 6 * kCubes[r] && std::fabs(F.mass - m) <= 1e-12 * m, "fragment %d (region %d): body %" PetscInt_FMT ", id %" PetscInt_FMT ", %" PetscInt_FMT " cells, mass %.15g; expected body %d, id %" PetscInt_FMT ", %d cells, mass %.15g", id[r], r, F.body, F.id, F.cells,
            (double)F.mass, kBody[r], glow[r], 6 * kCubes[r], m);
    }
  // each rank's share: the fragments whose id is the rank modulo the ranks, each the same
  // (bitwise: the same sums in the same order) as in the whole list
  PetscCall(FDEMDeformableGetLocalFragments(d, nullptr, &nmine, &m));
  PetscInt bad = 0, expect = 0, gbad;
  for (PetscInt k = 0; k < nf; ++k) expect += f[k].id % size == rank;
  bad += nmine != expect;
  for (PetscInt k = 0; k < nmine; ++k) {
    const FDEMFragment *F = std::find_if(f, f + nf, [&](const FDEMFragment &g) { return g.id == m[k].id; });
    bad += m[k].id % size != rank || F == f + nf || std::memcmp(F, &m[k], sizeof(FDEMFragment)) != 0 || (k > 0 && !(m[k - 1].body < m[k].body || (m[k - 1].body == m[k].body && m[k - 1].id < m[k].id)));
  }
  PetscCallMPI(MPIU_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  CHECK(gbad == 0, "%" PetscInt_FMT " of the ranks' shares of the fragments (FDEMDeformableGetLocalFragments) are not the fragments of the whole list whose id is the rank modulo %d, in order", gbad, size);
  PetscCall(PetscFree(m));
  PetscCall(PetscFree(f));

  // 2. the same answer as one rank holding the whole mesh
  PetscInt differ = 0, gdiffer;
  for (const auto &kv : mine) differ += !(kv.second == whole.at(kv.first));
  std::vector<std::array<PetscInt, 2>> pairs;
  for (const auto &p : ts.broken_pairs)
    if (mine.count(p[0]) || mine.count(p[1])) pairs.push_back(p);
  differ += pairs != t.broken_pairs;
  differ += t.nbroken != ts.nbroken;
  PetscCallMPI(MPIU_Allreduce(&differ, &gdiffer, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  CHECK(gdiffer == 0, "%" PetscInt_FMT " cells (or the count of broken joints or the broken pairs of a rank) differ from one rank's answer", gdiffer);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " broken joints, %" PetscInt_FMT " fragments on %d rank(s)\n", t.nbroken, nf, size));

  // the unsplit cells (bit 6): the rock outside the zone with -zone, none without
  {
    PetscBool zone = PETSC_FALSE;
    PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-zone", &zone, nullptr));
    PetscInt unsplit = 0, gunsplit, outside = 0, goutside;
    for (PetscInt e = 0; e < nc; ++e) {
      unsplit += t.cell_free[e] >> 6 & 1;
      outside += region[e] <= 2 && (centroid[e].x < 0.1 || centroid[e].x > 0.7);
    }
    PetscCallMPI(MPIU_Allreduce(&unsplit, &gunsplit, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    PetscCallMPI(MPIU_Allreduce(&outside, &goutside, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    CHECK(gunsplit == (zone ? 6 * 72 : 0) && (!zone || goutside == 6 * 72), "%" PetscInt_FMT " unsplit cells of the rock, expected %d (%" PetscInt_FMT " outside the zone)", gunsplit, zone ? 6 * 72 : 0, goutside);
  }

  // 4. the weights of a sphere's contacts with the copies of vertices and edges
  //    (DeformableFeatureShares), the surface the free faces: 1 over the distinct copies of the
  //    input vertex (edge) that a free face holds, the same as counted here over the whole mesh
  {
    std::vector<unsigned char> surf(nc), swhole(ts.cell_free.size());
    for (PetscInt e = 0; e < nc; ++e) surf[e] = t.cell_free[e] & 0xF;
    for (size_t e = 0; e < swhole.size(); ++e) swhole[e] = ts.cell_free[e] & 0xF;
    std::vector<float> w;
    PetscCall(fdem::model::DeformableFeatureShares(d, t, surf, w));
    // the whole mesh: the copies (split-mesh node ids) on the surface of each input vertex and edge
    std::map<std::array<PetscInt, 2>, std::set<std::array<PetscInt, 2>>> copies;
    const auto in = [&](PetscInt e, int a) { return s->local_input[s->ed.elems[e].n[a]]; };
    const auto id = [&](PetscInt e, int a) { return s->node_gid[s->ed.elems[e].n[a]]; };
    for (size_t e = 0; e < swhole.size(); ++e) {
      if (s->ed.body[e] != 0) continue;
      for (int a = 0; a < 4; ++a)
        if (swhole[e] & ~(1u << a)) copies[{in(e, a), -1}].insert({id(e, a), -1});
      for (const auto &k : fdem::kernels::kTetEdges)
        if (swhole[e] & ~(1u << k[0]) & ~(1u << k[1])) copies[{std::min(in(e, k[0]), in(e, k[1])), std::max(in(e, k[0]), in(e, k[1]))}].insert({std::min(id(e, k[0]), id(e, k[1])), std::max(id(e, k[0]), id(e, k[1]))});
    }
    std::map<std::array<PetscInt, 2>, PetscInt> at; // (cell id, node id) -> whole mesh cell
    PetscInt differ4 = 0, below = 0, g4[2], l4[2];
    for (PetscInt e = 0; e < nc; ++e) {
      const auto lin = [&](int a) { return d->local_input[d->ed.elems[e].n[a]]; };
      for (int f = 0; f < 10; ++f) {
        std::array<PetscInt, 2> key;
        if (f < 4) key = {lin(f), -1};
        else {
          const int qa = fdem::kernels::kTetEdges[f - 4][0], qb = fdem::kernels::kTetEdges[f - 4][1];
          key = {std::min(lin(qa), lin(qb)), std::max(lin(qa), lin(qb))};
        }
        const auto  it     = copies.find(key);
        const float expect = d->ed.body[e] != 0 || it == copies.end() || it->second.size() < 2 ? 1.0f : (float)(1.0 / (double)it->second.size());
        differ4 += w[10 * (size_t)e + f] != expect;
        below += w[10 * (size_t)e + f] < 1;
      }
    }
    l4[0] = differ4, l4[1] = below;
    PetscCallMPI(MPIU_Allreduce(l4, g4, 2, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    CHECK(g4[0] == 0 && g4[1] > 0, "%" PetscInt_FMT " weights of copies of vertices and edges differ from 1 over the distinct copies on the surface counted over the whole mesh (%" PetscInt_FMT " below 1)", g4[0], g4[1]);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " weights of vertices and edges below 1\n", g4[1]));
  }

  // 3. fragments across ranks
  if (size > 1) {
    PetscInt here[5] = {0, 0, 0, 0, 0}, ranks[5];
    for (PetscInt e = 0; e < nc; ++e) here[region[e]] = 1;
    PetscCallMPI(MPIU_Allreduce(here, ranks, 5, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ranks holding each region: %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT "\n", ranks[0], ranks[1], ranks[2], ranks[3], ranks[4]));
    CHECK(std::max({ranks[0], ranks[1], ranks[2]}) > 1 && std::max(ranks[3], ranks[4]) > 1, "no fragment spans ranks: the test does not test the exchange");
  }
  PetscCall(FDEMDeformableDestroy(&s));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
