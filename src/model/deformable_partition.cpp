// Deformable bodies, set-up: the element partition (METIS on rank 0), the
// DMPlex built on rank 0 and distributed through a shell partitioner, and
// each rank's local layout (element data, vectors, lumped masses). See
// deformable_object.hpp for the layout and doc/deformable.md.
#include "../util/guard.hpp"
#include "deformable_object.hpp"

#include <fdem/kernels/error.hpp>

#include <metis.h>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

using fdem::kernels::Vec3;
using namespace fdem::model::deformable;

const char *const fdem::model::deformable::PartitionTypes[] = {"metis", "simple", "PartitionType", "", nullptr};

namespace {

// The METIS weight of an element of material `mat`: its model's relative cost.
idx_t Weight(FDEMDeformable d, int mat) { return fdem::kernels::MaterialModels()[d->materials[mat].model].cost; }

// A split tetrahedron (nodes of its own, about two joints) costs about as much as this many
// unsplit ones in a step (bench_fracturable: a body split everywhere 8 to 12 times the
// unsplit body; doc/fracture.md, "Fracture zones"): its partition weight's factor, so that
// a fracture zone or a fracturable body beside unsplit ones is spread over the ranks.
constexpr idx_t kSplitWeight = 10;

// Rank 0: one part per rank for every element (throws if METIS fails).
void Partition(FDEMDeformable d, const std::vector<int> &mat_of_body, std::vector<PetscInt> &part) {
  const auto &M  = d->mesh;
  // a split mesh is partitioned as the mesh it came from (its tetrahedra share no node)
  const auto &P  = d->split_parent;
  const int   nn = P.empty() ? (int)M.nodes.size() : 1 + *std::max_element(P.begin(), P.end());
  const idx_t ne = (idx_t)M.tets.size();
  part.assign(ne, 0);
  if (d->size == 1) return;
  if (d->partition == kPartSimple) {
    for (idx_t e = 0; e < ne; ++e) part[e] = (PetscInt)((long long)e * d->size / ne);
    return;
  }
  std::vector<idx_t> eptr(ne + 1), eind(4 * (size_t)ne), vwgt(ne), epart(ne), npart(nn);
  for (idx_t e = 0; e < ne; ++e) {
    eptr[e] = 4 * e;
    for (int a = 0; a < 4; ++a) eind[4 * (size_t)e + a] = P.empty() ? M.tets[e][a] : P[M.tets[e][a]];
    vwgt[e] = Weight(d, mat_of_body[M.body[e]]) * (!d->split_tet.empty() && d->split_tet[e] ? kSplitWeight : 1);
  }
  eptr[ne] = 4 * ne;
  idx_t ne_ = ne, nnodes = nn, ncommon = 3, nparts = d->size, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  const int st = METIS_PartMeshDual(&ne_, &nnodes, eptr.data(), eind.data(), vwgt.data(), nullptr, &ncommon, &nparts, nullptr, options, &objval, epart.data(), npart.data());
  if (st != METIS_OK) throw fdem::kernels::InputError("METIS_PartMeshDual failed (status " + std::to_string(st) + ")");
  for (idx_t e = 0; e < ne; ++e) part[e] = epart[e];
}

PetscErrorCode BroadcastStrings(MPI_Comm comm, PetscMPIInt rank, std::vector<std::string> &v) {
  std::string packed;
  int         len = 0;
  PetscFunctionBegin;
  if (rank == 0) {
    for (const auto &s : v) packed += s + '\n';
    len = (int)packed.size();
  }
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, 0, comm));
  packed.resize(len);
  if (len) PetscCallMPI(MPI_Bcast(&packed[0], len, MPI_CHAR, 0, comm));
  if (rank != 0) {
    v.clear();
    size_t s = 0;
    for (size_t e; (e = packed.find('\n', s)) != std::string::npos; s = e + 1) v.push_back(packed.substr(s, e - s));
  }
  PetscFunctionReturn(0);
}

// The boundary faces of a cell as bits in the order of its nodes' ids: bit r for the face
// opposite the node whose id is the r-th smallest of the four (a form that does not depend on
// the order in which DMPlex hands a cell's nodes back).
PetscInt BoundaryByNodeIds(const std::array<PetscInt, 4> &ids, char bits) {
  PetscInt code = 0;
  for (int k = 0; k < 4; ++k)
    if (bits & (1 << k)) {
      int r = 0;
      for (int q = 0; q < 4; ++q) r += ids[q] < ids[k] ? 1 : 0;
      code |= (PetscInt)1 << r;
    }
  return code;
}
char BoundaryFromNodeIds(const std::array<PetscInt, 4> &ids, PetscInt code) {
  char bits = 0;
  for (int k = 0; k < 4; ++k) {
    int r = 0;
    for (int q = 0; q < 4; ++q) r += ids[q] < ids[k] ? 1 : 0;
    if (code & ((PetscInt)1 << r)) bits |= (char)(1 << k);
  }
  return bits;
}

// cellsurf: per point of the chart (cells), BoundaryByNodeIds of the cell's boundary faces in the
// split mesh, or empty when the set-up did not split (contact::BoundaryFaces finds them then)
PetscErrorCode BuildLocal(FDEMDeformable d, const std::vector<PetscInt> &orig, const std::vector<PetscInt> &cellbody, const std::vector<PetscInt> &cellsurf, PetscInt nc_orig) {
  DM           dm = d->dm;
  PetscInt     pStart, pEnd, cStart, cEnd, vStart, vEnd, rstart;
  PetscSection s, gs, cs;
  Vec          coords;
  const PetscScalar *ca;
  PetscFunctionBegin;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMGetCoordinateSection(dm, &cs));
  PetscCall(DMGetCoordinatesLocal(dm, &coords));
  // local cells, sorted by material, then along a Hilbert curve through their
  // centroids, then by global id (the kernel's order): consecutive cells are
  // neighbours in space, whatever order the mesh was given in
  const PetscInt        nc = cEnd - cStart;
  std::vector<PetscInt> order(nc);
  auto                       keys = std::make_shared<fdem::model::deformable::CellKeys>();
  std::vector<std::uint64_t> &hkey = keys->key;
  hkey.resize(nc);
  {
    std::vector<Vec3> &cen = keys->centroid;
    Vec3              &lo = keys->lo, &hi = keys->hi;
    cen.resize(nc);
    lo = Vec3(1e300, 1e300, 1e300), hi = Vec3(-1e300, -1e300, -1e300);
    PetscCall(VecGetArrayRead(coords, &ca));
    for (PetscInt c = 0; c < nc; ++c) {
      const PetscInt *cone;
      PetscInt        csize, coff;
      PetscCall(DMPlexGetConeSize(dm, cStart + c, &csize));
      PetscCall(DMPlexGetCone(dm, cStart + c, &cone));
      Vec3 m(0, 0, 0);
      for (PetscInt k = 0; k < csize; ++k) {
        PetscCall(PetscSectionGetOffset(cs, cone[k], &coff));
        m += Vec3(ca[coff], ca[coff + 1], ca[coff + 2]);
      }
      cen[c] = m / (double)std::max<PetscInt>(csize, 1);
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], cen[c][k]), hi[k] = std::max(hi[k], cen[c][k]);
    }
    PetscCall(VecRestoreArrayRead(coords, &ca));
    // (a model built again after an insertion has the same cells, mostly in the same order)
    const auto same = [](const Vec3 &a, const Vec3 &b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    const auto *R   = d->reuse_keys && same(d->reuse_keys->lo, lo) && same(d->reuse_keys->hi, hi) ? d->reuse_keys.get() : nullptr;
    for (PetscInt c = 0; c < nc; ++c)
      hkey[c] = R && c < (PetscInt)R->key.size() && same(R->centroid[c], cen[c]) ? R->key[c] : fdem::kernels::HilbertKey(cen[c], lo, hi);
    d->reuse_keys.reset();
  }
  std::iota(order.begin(), order.end(), 0);
  auto matof = [&](PetscInt c) { return d->material_of_body[cellbody[cStart + c]]; };
  std::sort(order.begin(), order.end(), [&](PetscInt a, PetscInt b) {
    const int ma = matof(a), mb = matof(b);
    if (ma != mb) return ma < mb;
    return hkey[a] != hkey[b] ? hkey[a] < hkey[b] : orig[cStart + a] < orig[cStart + b];
  });
  if (!d->insertion.empty()) d->cell_keys = std::move(keys); // (the next model of the run takes them)
  PetscCall(PetscSectionCreate(d->comm, &s));
  PetscCall(PetscSectionSetChart(s, pStart, pEnd));
  for (PetscInt p = vStart; p < vEnd; ++p) PetscCall(PetscSectionSetDof(s, p, 3));
  {
    // number the vertices in the order the sorted cells first use them, so
    // that the kernel's gathers and sums run through the node vectors nearly
    // in order (neither a mesh file's numbering nor DMPlex's migrated one
    // need be local)
    std::vector<PetscInt> perm;
    std::vector<char>     seen(vEnd - vStart, 0);
    perm.reserve(pEnd - pStart);
    for (PetscInt p = pStart; p < pEnd; ++p)
      if (p < vStart || p >= vEnd) perm.push_back(p - pStart);
    for (PetscInt i = 0; i < nc; ++i) {
      const PetscInt *cone;
      PetscInt        csize;
      PetscCall(DMPlexGetConeSize(dm, cStart + order[i], &csize));
      PetscCall(DMPlexGetCone(dm, cStart + order[i], &cone));
      for (PetscInt k = 0; k < csize; ++k)
        if (cone[k] >= vStart && cone[k] < vEnd && !seen[cone[k] - vStart]) {
          seen[cone[k] - vStart] = 1;
          perm.push_back(cone[k] - pStart);
        }
    }
    for (PetscInt v = vStart; v < vEnd; ++v)
      if (!seen[v - vStart]) perm.push_back(v - pStart);
    IS isperm;
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, (PetscInt)perm.size(), perm.data(), PETSC_COPY_VALUES, &isperm));
    PetscCall(PetscSectionSetPermutation(s, isperm));
    PetscCall(ISDestroy(&isperm));
  }
  PetscCall(PetscSectionSetUp(s));
  PetscCall(DMSetLocalSection(dm, s));
  PetscCall(PetscSectionDestroy(&s));
  PetscCall(DMGetGlobalSection(dm, &gs));
  PetscCall(DMGetLocalSection(dm, &s));
  PetscCall(DMCreateGlobalVector(dm, &d->x));
  PetscCall(PetscObjectSetName((PetscObject)d->x, "positions"));
  PetscCall(VecGetOwnershipRange(d->x, &rstart, nullptr));
  PetscCall(VecGetSize(d->x, &d->nnodes_global));
  d->nnodes_global /= 3;
  PetscCall(VecGetLocalSize(d->x, &d->nown));
  d->nown /= 3;
  d->nlocal = vEnd - vStart;
  d->node_gid.assign(d->nlocal, -1);
  d->node_global.assign(d->nlocal, -1);
  d->owned_local.assign(d->nown, -1);
  d->owned_gid.assign(d->nown, -1);
  d->owned_of_gid.clear();
  std::vector<PetscInt> lof(vEnd - vStart); // local node of vertex
  PetscCall(VecGetArrayRead(coords, &ca));
  std::vector<Vec3> Xl(d->nlocal);
  for (PetscInt p = vStart; p < vEnd; ++p) {
    PetscInt off, goff, coff;
    PetscCall(PetscSectionGetOffset(s, p, &off));
    PetscCall(PetscSectionGetOffset(gs, p, &goff));
    PetscCall(PetscSectionGetOffset(cs, p, &coff));
    const PetscInt l = off / 3;
    lof[p - vStart]  = l;
    d->node_gid[l]   = orig[p] - nc_orig;
    Xl[l]            = Vec3(ca[coff], ca[coff + 1], ca[coff + 2]);
    const PetscInt g = goff >= 0 ? goff : -(goff + 1);
    d->node_global[l] = g / 3;
    if (goff >= 0) {
      const PetscInt k = (goff - rstart) / 3;
      d->owned_local[k] = l;
      d->owned_gid[k]   = d->node_gid[l];
      d->owned_of_gid[d->node_gid[l]] = k;
    }
  }
  PetscCall(VecRestoreArrayRead(coords, &ca));
  std::vector<std::array<int, 4>> tets(nc);
  std::vector<int>                tmat(nc), tbody(nc);
  d->cell_gid.resize(nc);
  for (PetscInt i = 0; i < nc; ++i) {
    const PetscInt  c = cStart + order[i];
    const PetscInt *cone, *ornt;
    PetscInt        csize;
    PetscCall(DMPlexGetConeSize(dm, c, &csize));
    PetscCheck(csize == 4, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %" PetscInt_FMT " has %" PetscInt_FMT " vertices", c, csize);
    PetscCall(DMPlexGetCone(dm, c, &cone));
    PetscCall(DMPlexGetConeOrientation(dm, c, &ornt));
    // DMPlex holds (n0, n2, n1, n3): undo the flip; fix by sign if PETSc reordered
    std::array<int, 4> T = {(int)lof[cone[0] - vStart], (int)lof[cone[2] - vStart], (int)lof[cone[1] - vStart], (int)lof[cone[3] - vStart]};
    if (fdem::kernels::TetSignedVolume(Xl[T[0]], Xl[T[1]], Xl[T[2]], Xl[T[3]]) < 0) std::swap(T[1], T[2]);
    tets[i]        = T;
    tbody[i]       = (int)cellbody[c];
    tmat[i]        = d->material_of_body[tbody[i]];
    d->cell_gid[i] = orig[c];
  }
  d->boundary_made = !cellsurf.empty();
  d->boundary_faces.assign(d->boundary_made ? nc : 0, 0);
  for (PetscInt i = 0; d->boundary_made && i < nc; ++i) {
    const auto &T = tets[i];
    d->boundary_faces[i] = BoundaryFromNodeIds({d->node_gid[T[0]], d->node_gid[T[1]], d->node_gid[T[2]], d->node_gid[T[3]]}, cellsurf[cStart + order[i]]);
  }
  PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
    d->ed = fdem::kernels::BuildElementData(Xl, tets, d->materials, tmat, tbody);
    return 0;
  }));
  d->viscous = false;
  for (int b = 0; b < (int)d->material_of_body.size(); ++b) d->viscous = d->viscous || d->materials[d->material_of_body[b]].mu_visc > 0;
  // vectors
  PetscCall(DMCreateLocalVector(dm, &d->xloc));
  PetscCall(VecDuplicate(d->xloc, &d->vloc));
  PetscCall(VecDuplicate(d->xloc, &d->floc));
  PetscCall(VecDuplicate(d->x, &d->v));
  PetscCall(VecDuplicate(d->x, &d->X));
  PetscCall(VecDuplicate(d->x, &d->m));
  PetscCall(VecDuplicate(d->x, &d->minv));
  PetscCall(DMCreateGlobalVector(dm, &d->gwork));
  PetscCall(PetscObjectSetName((PetscObject)d->v, "velocities"));
  PetscCall(PetscObjectSetName((PetscObject)d->X, "reference positions"));
  PetscCall(PetscObjectSetName((PetscObject)d->m, "lumped masses"));
  PetscScalar *xl, *fl;
  PetscCall(VecGetArray(d->xloc, &xl));
  PetscCall(VecGetArray(d->floc, &fl));
  for (PetscInt l = 0; l < d->nlocal; ++l)
    for (int k = 0; k < 3; ++k) {
      xl[3 * l + k] = Xl[l][k];
      fl[3 * l + k] = 0;
    }
  for (const auto &el : d->ed.elems) {
    const double q = d->materials[el.material].rho * el.V0 / 4;
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 3; ++k) fl[3 * el.n[a] + k] += q;
  }
  PetscCall(VecRestoreArray(d->xloc, &xl));
  PetscCall(VecRestoreArray(d->floc, &fl));
  d->local_is_owned = d->size == 1 && d->nlocal == d->nown;
  for (PetscInt k = 0; d->local_is_owned && k < d->nown; ++k) d->local_is_owned = d->owned_local[k] == k;
  PetscCall(fdem::model::DeformableLocalToGlobal(d, d->xloc, INSERT_VALUES, d->X));
  PetscCall(VecSet(d->m, 0));
  PetscCall(fdem::model::DeformableLocalToGlobal(d, d->floc, ADD_VALUES, d->m));
  PetscCall(VecCopy(d->X, d->x));
  PetscCall(VecSet(d->v, 0));
  PetscCall(VecCopy(d->m, d->minv));
  PetscCall(VecReciprocal(d->minv));
  d->fixed.assign(d->nown, 0);
  d->vfix.assign(3 * d->nown, 0);
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FDEMDeformableSetUp(FDEMDeformable d) {
  std::vector<PetscInt> part;
  std::vector<int>      mob;
  PetscInt              dims[3] = {0, 0, 0}; // ncells, nnodes, nbodies
  PetscFunctionBegin;
  if (d->setup) PetscFunctionReturn(0);
  {
    int has = d->has_mesh ? 1 : 0, all;
    PetscCallMPI(MPI_Allreduce(&has, &all, 1, MPI_INT, MPI_MIN, d->comm));
    PetscCheck(all, d->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMDeformableSetUp: no mesh; give one with FDEMDeformableSetMesh/SetMeshBox/SetMeshBeam/SetMeshCylinder/SetMeshFromGmsh");
  }
  PetscCall(fdem::Guard(
    d->comm,
    [&]() -> PetscErrorCode {
      if (d->rank != 0) return 0;
      ValidateInput(d, mob);
      SplitFracturable(d, mob); // fracturable bodies: their own nodes per tetrahedron, joints
      dims[0] = (PetscInt)d->mesh.tets.size();
      dims[1] = (PetscInt)d->mesh.nodes.size();
      dims[2] = (PetscInt)d->mesh.NumBodies();
      Partition(d, mob, part);
      return 0;
    },
    PETSC_ERR_USER_INPUT, "FDEMDeformableSetUp: "));
  PetscCallMPI(MPI_Bcast(dims, 3, MPIU_INT, 0, d->comm));
  d->ncells_global = dims[0];
  d->body_names    = d->mesh.body_names;
  PetscCall(BroadcastStrings(d->comm, d->rank, d->body_names));
  mob.resize(dims[2]);
  PetscCallMPI(MPI_Bcast(mob.data(), (int)dims[2], MPI_INT, 0, d->comm));
  d->material_of_body = mob;

  // serial DMPlex on rank 0, cells flipped to PETSc's orientation
  DM                     dm;
  const PetscInt         nc = d->rank == 0 ? dims[0] : 0, nv = d->rank == 0 ? dims[1] : 0;
  std::vector<PetscInt>  cells(4 * (size_t)nc);
  std::vector<PetscReal> coords(3 * (size_t)nv);
  for (PetscInt e = 0; e < nc; ++e) {
    const auto &T    = d->mesh.tets[e];
    cells[4 * e]     = T[0];
    cells[4 * e + 1] = T[2];
    cells[4 * e + 2] = T[1];
    cells[4 * e + 3] = T[3];
  }
  for (PetscInt i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = d->mesh.nodes[i][k];
  PetscCall(DMPlexCreateFromCellListPetsc(d->comm, 3, nc, nv, 4, PETSC_FALSE, cells.data(), 3, coords.data(), &dm));
  PetscCall(PetscObjectSetName((PetscObject)dm, "deformable mesh"));
  cells.clear();
  cells.shrink_to_fit();
  coords.clear();
  coords.shrink_to_fit();
  // root data over the serial chart: original point number and body of each cell
  // and, when the set-up split the mesh, its boundary faces (the split finds them on the way)
  std::vector<PetscInt> orig, cellbody, cellsurf;
  PetscInt              have_surf = d->rank == 0 && !d->split_boundary.empty();
  PetscCallMPI(MPI_Bcast(&have_surf, 1, MPIU_INT, 0, d->comm));
  {
    PetscInt pStart, pEnd;
    PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
    orig.resize(pEnd - pStart);
    cellbody.assign(pEnd - pStart, 0);
    std::iota(orig.begin(), orig.end(), 0);
    for (PetscInt e = 0; e < nc; ++e) cellbody[e] = d->mesh.body[e];
    if (have_surf) {
      cellsurf.assign(pEnd - pStart, 0);
      for (PetscInt e = 0; e < nc; ++e) {
        const auto &T = d->mesh.tets[e];
        cellsurf[e]   = BoundaryByNodeIds({T[0], T[1], T[2], T[3]}, d->split_boundary[e]);
      }
    }
  }
  if (d->size > 1) {
    PetscPartitioner      partr;
    PetscSF               sf = nullptr;
    DM                    dmd = nullptr;
    std::vector<PetscInt> sizes(d->size, 0), points;
    if (d->rank == 0) {
      for (PetscInt e = 0; e < nc; ++e) sizes[part[e]]++;
      std::vector<PetscInt> start(d->size, 0);
      for (int r = 1; r < d->size; ++r) start[r] = start[r - 1] + sizes[r - 1];
      points.resize(nc);
      for (PetscInt e = 0; e < nc; ++e) points[start[part[e]]++] = e;
    }
    PetscCall(DMPlexGetPartitioner(dm, &partr));
    PetscCall(PetscPartitionerSetType(partr, PETSCPARTITIONERSHELL));
    PetscCall(PetscPartitionerShellSetPartition(partr, d->size, sizes.data(), points.data()));
    PetscCall(DMPlexDistribute(dm, 0, &sf, &dmd));
    if (dmd) {
      PetscInt pStart, pEnd;
      PetscCall(DMPlexGetChart(dmd, &pStart, &pEnd));
      std::vector<PetscInt> lo(pEnd - pStart, -1), lb(pEnd - pStart, 0);
      PetscCall(PetscSFBcastBegin(sf, MPIU_INT, orig.data(), lo.data(), MPI_REPLACE));
      PetscCall(PetscSFBcastEnd(sf, MPIU_INT, orig.data(), lo.data(), MPI_REPLACE));
      PetscCall(PetscSFBcastBegin(sf, MPIU_INT, cellbody.data(), lb.data(), MPI_REPLACE));
      PetscCall(PetscSFBcastEnd(sf, MPIU_INT, cellbody.data(), lb.data(), MPI_REPLACE));
      orig.swap(lo);
      cellbody.swap(lb);
      if (have_surf) {
        std::vector<PetscInt> ls(pEnd - pStart, 0);
        PetscCall(PetscSFBcastBegin(sf, MPIU_INT, cellsurf.data(), ls.data(), MPI_REPLACE));
        PetscCall(PetscSFBcastEnd(sf, MPIU_INT, cellsurf.data(), ls.data(), MPI_REPLACE));
        cellsurf.swap(ls);
      }
      PetscCall(DMDestroy(&dm));
      dm = dmd;
    }
    PetscCall(PetscSFDestroy(&sf));
  }
  d->dm = dm;
  if (d->rank == 0) d->mesh = fdem::kernels::TetMesh(); // the distributed DM holds it now
  d->has_mesh = false;
  PetscCall(BuildLocal(d, orig, cellbody, cellsurf, dims[0]));
  PetscCall(SetUpJoints(d));
  d->split_parent.clear();
  d->split_tet.clear();
  d->split_boundary.clear();
  d->setup = true;
  if (d->view) {
    PetscReal w = 0;
    for (const auto &el : d->ed.elems) w += Weight(d, el.material);
    PetscCall(PetscSynchronizedPrintf(d->comm, "[%d] FDEMDeformable: %zu cells (weight %g), %" PetscInt_FMT " local nodes, %" PetscInt_FMT " owned\n", d->rank, d->ed.size(), (double)w, d->nlocal, d->nown));
    PetscCall(PetscSynchronizedFlush(d->comm, PETSC_STDOUT));
    PetscCall(PetscPrintf(d->comm, "FDEMDeformable: %" PetscInt_FMT " cells, %" PetscInt_FMT " nodes, %zu bodies, partition %s\n", d->ncells_global, d->nnodes_global, d->body_names.size(), PartitionTypes[d->partition]));
  }
  PetscFunctionReturn(0);
}

