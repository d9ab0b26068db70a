// Deformable discrete elements on a distributed DMPlex; see include/fdem/deformable.h
// and doc/deformable.md.
//
// Layout after FDEMDeformableSetUp, on each rank:
//  - dm: the distributed, uninterpolated DMPlex (cells and vertices), local
//    section 3 dofs per vertex. Local vectors hold every vertex of the rank's
//    cells ("local nodes", index l = local offset / 3), global vectors the
//    owned ones (index k = (global offset - rstart) / 3).
//  - ed: the kernel's ElementData over the local cells, node indices = local
//    nodes, cells sorted by material (long runs for the batched kernel).
//  - cell_gid / node_gid: global (input) ids of local cells and nodes, carried
//    through the distribution by broadcasting over the migration SF.
#include "../util/guard.hpp"
#include "../util/output.hpp"
#include <fdem/deformable.h>
#include <fdem/deformable_contact.h>
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <metis.h>
#include <petscsf.h>
#include <petscviewerhdf5.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Material;
using fdem::kernels::Vec3;

const char *const FDEMMaterialModels[] = {"munjiza_cst", "neo_hookean", "small_strain_linear", "FDEMMaterialModel", "FDEM_MATERIAL_", nullptr};

namespace {
enum PartitionType { kPartMetis = 0, kPartSimple = 1 };
const char *const PartitionTypes[] = {"metis", "simple", "PartitionType", "", nullptr};

struct OutputRecord {
  PetscInt  step;
  PetscReal t;
  PetscInt  nvert, ncell;
};
} // namespace

struct _n_FDEMDeformable {
  MPI_Comm    comm;
  PetscMPIInt rank = 0, size = 1;
  // input (mesh on rank 0 only)
  std::vector<Material>              materials;
  std::map<std::string, std::string> body_material;
  fdem::kernels::TetMesh             mesh;
  bool                               has_mesh = false;
  PetscReal                          g[3] = {0, 0, 0};
  std::vector<std::pair<FDEMDeformableForceFn, void *>> ext; // force terms, added in order
  PetscInt                           partition = kPartMetis;
  PetscBool                          view = PETSC_FALSE;
  // after set-up (all ranks)
  bool                       setup = false;
  std::vector<std::string>   body_names;
  std::vector<int>           material_of_body;
  DM                         dm = nullptr;
  PetscInt                   ncells_global = 0, nnodes_global = 0, nlocal = 0, nown = 0;
  fdem::kernels::ElementData ed;
  std::vector<PetscInt>      cell_gid, node_gid, owned_gid, owned_local, node_global; // node_global: global vertex number per local node
  std::unordered_map<PetscInt, PetscInt> owned_of_gid;
  std::vector<char>          fixed; // per owned node
  bool                       viscous = false;
  Vec                        x = nullptr, v = nullptr, X = nullptr, m = nullptr, minv = nullptr;
  Vec                        xloc = nullptr, vloc = nullptr, floc = nullptr, gwork = nullptr;
  TS                         ts = nullptr; // the TS of FDEMDeformableSetUpTS (not referenced)
  std::vector<OutputRecord>  outputs;
};

namespace {

using fdem::Guard;

// A message decided on rank 0 (empty: no error) becomes an error on every rank.
PetscErrorCode CollectiveError(FDEMDeformable d, const std::string &msg_rank0, PetscErrorCode code) {
  int len = d->rank == 0 ? (int)msg_rank0.size() : 0;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, 0, d->comm));
  if (len == 0) PetscFunctionReturn(0);
  std::string msg = d->rank == 0 ? msg_rank0 : std::string((size_t)len, ' ');
  PetscCallMPI(MPI_Bcast(&msg[0], len, MPI_CHAR, 0, d->comm));
  SETERRQ(d->comm, code, "%s", msg.c_str());
}

PetscErrorCode CheckSetUp(FDEMDeformable d, const char *fn) {
  PetscFunctionBegin;
  PetscCheck(d->setup, d->comm, PETSC_ERR_ARG_WRONGSTATE, "%s: call FDEMDeformableSetUp() first", fn);
  PetscFunctionReturn(0);
}

PetscErrorCode CheckNotSetUp(FDEMDeformable d, const char *fn) {
  PetscFunctionBegin;
  PetscCheck(!d->setup, d->comm, PETSC_ERR_ARG_WRONGSTATE, "%s: the mesh is already set up; call it before FDEMDeformableSetUp()", fn);
  PetscFunctionReturn(0);
}

double ElementJ(const fdem::kernels::TetElement &el, const double *x) {
  const Vec3 x0(x[3 * el.n[0]], x[3 * el.n[0] + 1], x[3 * el.n[0] + 2]);
  Vec3       e[3];
  for (int a = 1; a < 4; ++a) e[a - 1] = Vec3(x[3 * el.n[a]], x[3 * el.n[a] + 1], x[3 * el.n[a] + 2]) - x0;
  return det(Mat3::columns(e[0], e[1], e[2])) * el.inv6V0;
}

// Relative cost of an element's model in the internal-force kernel (bench/cst_kernel).
idx_t ModelWeight(int model) { return model == fdem::kernels::kSmallStrainLinear ? 1 : 2; }

// ---------------------------------------------------------------- set-up pieces
// Rank 0: resolve materials, validate, partition. Returns an error message or "".
std::string ValidateAndPartition(FDEMDeformable d, std::vector<PetscInt> &part, std::vector<int> &mat_of_body) {
  const auto &M = d->mesh;
  if (M.tets.empty()) return "FDEMDeformableSetUp: the mesh has no tetrahedra";
  if (d->materials.empty()) return "FDEMDeformableSetUp: no materials; add them with FDEMDeformableAddMaterial()";
  auto find = [&](const std::string &name) {
    for (size_t i = 0; i < d->materials.size(); ++i)
      if (d->materials[i].name == name) return (int)i;
    return -1;
  };
  std::string have;
  for (const auto &m : d->materials) have += (have.empty() ? "" : ", ") + m.name;
  mat_of_body.assign(M.NumBodies(), -1);
  for (int b = 0; b < M.NumBodies(); ++b) {
    const std::string &bn = M.body_names[b];
    auto               it = d->body_material.find(bn);
    std::string        want;
    if (it != d->body_material.end()) want = it->second;
    else if (find(bn) >= 0 || d->materials.size() > 1) want = bn;
    else want = d->materials[0].name;
    mat_of_body[b] = find(want);
    if (mat_of_body[b] < 0) return "FDEMDeformableSetUp: body '" + bn + "' needs material '" + want + "', which is not in the material table (have: " + have + "); add it with FDEMDeformableAddMaterial() or map the body with FDEMDeformableSetBodyMaterial()";
  }
  for (const auto &kv : d->body_material) {
    bool found = false;
    for (const auto &bn : M.body_names) found = found || bn == kv.first;
    if (!found) return "FDEMDeformableSetUp: FDEMDeformableSetBodyMaterial names body '" + kv.first + "', which is not in the mesh";
  }
  const int nn = (int)M.nodes.size();
  for (size_t t = 0; t < M.tets.size(); ++t) {
    const auto &T = M.tets[t];
    const int   b = M.body[t];
    for (int a = 0; a < 4; ++a)
      if (T[a] < 0 || T[a] >= nn) return "FDEMDeformableSetUp: element " + std::to_string(t) + " of body '" + M.body_names[b] + "': node " + std::to_string(T[a]) + " out of range [0, " + std::to_string(nn) + ")";
    const Vec3 &a0 = M.nodes[T[0]], &a1 = M.nodes[T[1]], &a2 = M.nodes[T[2]], &a3 = M.nodes[T[3]];
    const double six = 6 * fdem::kernels::TetSignedVolume(a0, a1, a2, a3);
    double       h   = 0;
    for (int a = 0; a < 4; ++a)
      for (int c = a + 1; c < 4; ++c) h = std::max(h, norm(M.nodes[T[a]] - M.nodes[T[c]]));
    if (!(six > 1e-12 * h * h * h)) {
      std::ostringstream o;
      o << "FDEMDeformableSetUp: element " << t << " of body '" << M.body_names[b] << "' (nodes " << T[0] << " " << T[1] << " " << T[2] << " " << T[3] << "): reference volume " << six / 6
        << (six < 0 ? " is negative (inverted: need det[x1-x0, x2-x0, x3-x0] > 0)" : " is zero (degenerate tetrahedron)");
      return o.str();
    }
  }
  const idx_t ne = (idx_t)M.tets.size();
  part.assign(ne, 0);
  if (d->size == 1) return "";
  if (d->partition == kPartSimple) {
    for (idx_t e = 0; e < ne; ++e) part[e] = (PetscInt)((long long)e * d->size / ne);
    return "";
  }
  std::vector<idx_t> eptr(ne + 1), eind(4 * (size_t)ne), vwgt(ne), epart(ne), npart(nn);
  for (idx_t e = 0; e < ne; ++e) {
    eptr[e] = 4 * e;
    for (int a = 0; a < 4; ++a) eind[4 * (size_t)e + a] = M.tets[e][a];
    vwgt[e] = ModelWeight(d->materials[mat_of_body[M.body[e]]].model);
  }
  eptr[ne] = 4 * ne;
  idx_t ne_ = ne, nnodes = nn, ncommon = 3, nparts = d->size, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  const int st = METIS_PartMeshDual(&ne_, &nnodes, eptr.data(), eind.data(), vwgt.data(), nullptr, &ncommon, &nparts, nullptr, options, &objval, epart.data(), npart.data());
  if (st != METIS_OK) return "FDEMDeformableSetUp: METIS_PartMeshDual failed (status " + std::to_string(st) + ")";
  for (idx_t e = 0; e < ne; ++e) part[e] = epart[e];
  return "";
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

PetscErrorCode BuildLocal(FDEMDeformable d, const std::vector<PetscInt> &orig, const std::vector<PetscInt> &cellbody, PetscInt nc_orig) {
  DM           dm = d->dm;
  PetscInt     pStart, pEnd, cStart, cEnd, vStart, vEnd, rstart;
  PetscSection s, gs, cs;
  Vec          coords;
  const PetscScalar *ca;
  PetscFunctionBegin;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(PetscSectionCreate(d->comm, &s));
  PetscCall(PetscSectionSetChart(s, pStart, pEnd));
  for (PetscInt p = vStart; p < vEnd; ++p) PetscCall(PetscSectionSetDof(s, p, 3));
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
  PetscCall(DMGetCoordinateSection(dm, &cs));
  PetscCall(DMGetCoordinatesLocal(dm, &coords));
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
  // local cells, sorted by material then global id
  const PetscInt                  nc = cEnd - cStart;
  std::vector<PetscInt>           order(nc);
  std::vector<std::array<int, 4>> tets(nc);
  std::vector<int>                tmat(nc), tbody(nc);
  std::iota(order.begin(), order.end(), 0);
  auto matof = [&](PetscInt c) { return d->material_of_body[cellbody[cStart + c]]; };
  std::sort(order.begin(), order.end(), [&](PetscInt a, PetscInt b) {
    const int ma = matof(a), mb = matof(b);
    return ma != mb ? ma < mb : orig[cStart + a] < orig[cStart + b];
  });
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
  PetscCall(Guard(d->comm, [&]() -> PetscErrorCode {
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
  PetscCall(DMLocalToGlobal(dm, d->xloc, INSERT_VALUES, d->X));
  PetscCall(VecSet(d->m, 0));
  PetscCall(DMLocalToGlobal(dm, d->floc, ADD_VALUES, d->m));
  PetscCall(VecCopy(d->X, d->x));
  PetscCall(VecSet(d->v, 0));
  PetscCall(VecCopy(d->m, d->minv));
  PetscCall(VecReciprocal(d->minv));
  d->fixed.assign(d->nown, 0);
  PetscFunctionReturn(0);
}

// Assembled nodal force f (owned layout) from owned positions xo and velocities vo (may be null).
PetscErrorCode AssembleForces(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *fo) {
  PetscScalar *xl, *vl = nullptr, *fl;
  PetscFunctionBegin;
  PetscCall(VecPlaceArray(d->gwork, xo));
  PetscCall(DMGlobalToLocalBegin(d->dm, d->gwork, INSERT_VALUES, d->xloc));
  PetscCall(DMGlobalToLocalEnd(d->dm, d->gwork, INSERT_VALUES, d->xloc));
  PetscCall(VecResetArray(d->gwork));
  const bool use_v = vo && d->viscous;
  if (vo) {
    PetscCall(VecPlaceArray(d->gwork, vo));
    PetscCall(DMGlobalToLocalBegin(d->dm, d->gwork, INSERT_VALUES, d->vloc));
    PetscCall(DMGlobalToLocalEnd(d->dm, d->gwork, INSERT_VALUES, d->vloc));
    PetscCall(VecResetArray(d->gwork));
  }
  PetscCall(VecSet(d->floc, 0));
  PetscCall(VecGetArray(d->xloc, &xl));
  if (use_v) PetscCall(VecGetArray(d->vloc, &vl));
  PetscCall(VecGetArray(d->floc, &fl));
  const std::int64_t bad = fdem::kernels::ComputeInternalForces(d->ed, xl, vl, fl);
  // collective inversion check: the smallest global id of an inverted element
  PetscInt   gid = bad >= 0 ? d->cell_gid[bad] : PETSC_MAX_INT, gmin;
  PetscCallMPI(MPI_Allreduce(&gid, &gmin, 1, MPIU_INT, MPI_MIN, d->comm));
  if (gmin != PETSC_MAX_INT) {
    PetscReal info[2] = {0, 0}, ginfo[2];
    if (gid == gmin) {
      info[0] = d->ed.body[bad];
      info[1] = ElementJ(d->ed.elems[bad], xl);
    }
    PetscCallMPI(MPI_Allreduce(info, ginfo, 2, MPIU_REAL, MPIU_SUM, d->comm));
    PetscCall(VecRestoreArray(d->floc, &fl));
    if (use_v) PetscCall(VecRestoreArray(d->vloc, &vl));
    PetscCall(VecRestoreArray(d->xloc, &xl));
    const int b = (int)ginfo[0];
    SETERRQ(d->comm, PETSC_ERR_NOT_CONVERGED, "FDEMDeformable: element %" PetscInt_FMT " of body '%s' inverted (det F = %g <= 0) at t = %g; reduce the time step or check the loading", gmin, d->body_names[b].c_str(),
            (double)ginfo[1], (double)t);
  }
  PetscCall(VecRestoreArray(d->floc, &fl));
  if (use_v) PetscCall(VecRestoreArray(d->vloc, &vl));
  PetscCall(VecRestoreArray(d->xloc, &xl));
  for (const auto &e : d->ext) PetscCall(e.first(d, t, d->xloc, vo ? d->vloc : nullptr, d->floc, e.second));
  PetscCall(VecPlaceArray(d->gwork, fo));
  PetscCall(VecSet(d->gwork, 0));
  PetscCall(DMLocalToGlobalBegin(d->dm, d->floc, ADD_VALUES, d->gwork));
  PetscCall(DMLocalToGlobalEnd(d->dm, d->floc, ADD_VALUES, d->gwork));
  PetscCall(VecResetArray(d->gwork));
  PetscFunctionReturn(0);
}

// dx/dt = v
PetscErrorCode RHSPosition(TS, PetscReal, Vec V, Vec dX, void *) {
  PetscFunctionBegin;
  PetscCall(VecCopy(V, dX));
  PetscFunctionReturn(0);
}

// dv/dt = (f_int + f_ext)/m + g, 0 at fixed nodes
PetscErrorCode RHSMomentum(TS, PetscReal t, Vec Xq, Vec A, void *ctx) {
  FDEMDeformable     d = (FDEMDeformable)ctx;
  const PetscScalar *xq, *u = nullptr, *mi;
  PetscScalar       *a;
  Vec                U = nullptr;
  PetscFunctionBegin;
  const bool need_v = d->viscous || !d->ext.empty();
  if (need_v && d->ts) {
    PetscCall(TSGetSolution(d->ts, &U));
    PetscCall(VecGetArrayRead(U, &u));
  }
  PetscCall(VecGetArrayRead(Xq, &xq));
  PetscCall(VecGetArray(A, &a));
  PetscCall(AssembleForces(d, t, xq, u ? u + 3 * d->nown : nullptr, a));
  PetscCall(VecGetArrayRead(d->minv, &mi));
  for (PetscInt k = 0; k < d->nown; ++k) {
    if (d->fixed[k]) {
      a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = 0;
      continue;
    }
    for (int c = 0; c < 3; ++c) a[3 * k + c] = a[3 * k + c] * mi[3 * k + c] + d->g[c];
  }
  PetscCall(VecRestoreArrayRead(d->minv, &mi));
  PetscCall(VecRestoreArray(A, &a));
  PetscCall(VecRestoreArrayRead(Xq, &xq));
  if (u) PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

// Owned x and v arrays of a state U (or the stored vectors).
struct StateView {
  FDEMDeformable     d;
  Vec                U;
  const PetscScalar *u = nullptr, *xa = nullptr, *va = nullptr;
  PetscErrorCode Get(FDEMDeformable dd, Vec UU) {
    d = dd;
    U = UU;
    PetscFunctionBegin;
    if (U) {
      PetscInt n;
      PetscCall(VecGetLocalSize(U, &n));
      PetscCheck(n == 6 * d->nown, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "FDEMDeformable: the state vector has %" PetscInt_FMT " local entries, expected 6 x %" PetscInt_FMT " owned nodes (a vector from FDEMDeformableSetUpTS)", n, d->nown);
      PetscCall(VecGetArrayRead(U, &u));
      xa = u;
      va = u + 3 * d->nown;
    } else {
      PetscCall(VecGetArrayRead(d->x, &xa));
      PetscCall(VecGetArrayRead(d->v, &va));
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode Restore() {
    PetscFunctionBegin;
    if (U) PetscCall(VecRestoreArrayRead(U, &u));
    else {
      PetscCall(VecRestoreArrayRead(d->x, &xa));
      PetscCall(VecRestoreArrayRead(d->v, &va));
    }
    PetscFunctionReturn(0);
  }
};

// positions of all local nodes at a state
PetscErrorCode LocalPositions(FDEMDeformable d, const PetscScalar *xo, const PetscScalar *vo) {
  PetscFunctionBegin;
  PetscCall(VecPlaceArray(d->gwork, xo));
  PetscCall(DMGlobalToLocal(d->dm, d->gwork, INSERT_VALUES, d->xloc));
  PetscCall(VecResetArray(d->gwork));
  if (vo) {
    PetscCall(VecPlaceArray(d->gwork, vo));
    PetscCall(DMGlobalToLocal(d->dm, d->gwork, INSERT_VALUES, d->vloc));
    PetscCall(VecResetArray(d->gwork));
  }
  PetscFunctionReturn(0);
}

// strain energy density per reference volume
double StrainEnergyDensity(const fdem::kernels::MaterialCoeffs &c, int model, const Mat3 &F) {
  const double J = det(F);
  if (model == fdem::kernels::kSmallStrainLinear) {
    double e[3][3], tr = 0, ee = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) e[i][j] = 0.5 * (F(i, j) + F(j, i)) - (i == j ? 1 : 0);
    for (int i = 0; i < 3; ++i) tr += e[i][i];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ee += e[i][j] * e[i][j];
    return 0.5 * c.lambda * tr * tr + c.G * ee;
  }
  if (!(J > 0)) return NAN;
  double I1 = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) I1 += F(i, j) * F(i, j);
  return 0.5 * c.G * (I1 / std::cbrt(J * J) - 3) + 0.5 * c.K * (0.5 * (J * J - 1) - std::log(J));
}

PetscErrorCode ResetMesh(FDEMDeformable d) {
  PetscFunctionBegin;
  d->mesh     = fdem::kernels::TetMesh();
  d->has_mesh = false;
  PetscFunctionReturn(0);
}

PetscErrorCode FinishMesh(FDEMDeformable d) {
  PetscFunctionBegin;
  d->has_mesh = true;
  if (d->mesh.body.empty()) d->mesh.body.assign(d->mesh.tets.size(), 0);
  if (d->mesh.body_names.empty()) d->mesh.body_names.push_back("body_0");
  PetscFunctionReturn(0);
}

} // namespace

// ============================================================== public API
PetscErrorCode FDEMDeformableCreate(MPI_Comm comm, FDEMDeformable *out) {
  PetscFunctionBegin;
  FDEMDeformable d = new (std::nothrow) _n_FDEMDeformable();
  PetscCheck(d, comm, PETSC_ERR_MEM, "Out of memory");
  d->comm = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &d->rank));
  PetscCallMPI(MPI_Comm_size(comm, &d->size));
  *out = d;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableDestroy(FDEMDeformable *dp) {
  PetscFunctionBegin;
  if (!dp || !*dp) PetscFunctionReturn(0);
  FDEMDeformable d = *dp;
  for (Vec *w : {&d->x, &d->v, &d->X, &d->m, &d->minv, &d->xloc, &d->vloc, &d->floc, &d->gwork}) PetscCall(VecDestroy(w));
  PetscCall(DMDestroy(&d->dm));
  delete d;
  *dp = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableAddMaterial(FDEMDeformable d, const char *name, PetscReal E, PetscReal nu, PetscReal rho, PetscReal mu_visc, FDEMMaterialModel model) {
  PetscFunctionBegin;
  PetscCheck(name && name[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableAddMaterial: the material needs a name");
  for (const auto &m : d->materials) PetscCheck(m.name != name, d->comm, PETSC_ERR_ARG_WRONG, "FDEMDeformableAddMaterial: material '%s' is already in the table", name);
  PetscCall(CheckNotSetUp(d, "FDEMDeformableAddMaterial"));
  Material m;
  m.name    = name;
  m.E       = E;
  m.nu      = nu;
  m.rho     = rho;
  m.mu_visc = mu_visc;
  m.model   = (int)model;
  PetscCall(Guard(d->comm, [&]() -> PetscErrorCode {
    fdem::kernels::CheckMaterial(m);
    return 0;
  }));
  d->materials.push_back(m);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetBodyMaterial(FDEMDeformable d, const char *body, const char *material) {
  PetscFunctionBegin;
  PetscCheck(body && material, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableSetBodyMaterial: body and material names are needed");
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetBodyMaterial"));
  d->body_material[body] = material;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMesh(FDEMDeformable d, PetscInt nnodes, const PetscReal nodes[], PetscInt ntets, const PetscInt tets[], const PetscInt body[], PetscInt nbodies, const char *const names[]) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMesh"));
  PetscCall(ResetMesh(d));
  if (d->rank == 0) {
    auto &M = d->mesh;
    M.nodes.resize(nnodes);
    for (PetscInt i = 0; i < nnodes; ++i) M.nodes[i] = Vec3(nodes[3 * i], nodes[3 * i + 1], nodes[3 * i + 2]);
    M.tets.resize(ntets);
    M.body.assign(ntets, 0);
    PetscInt nb = PetscMax(nbodies, 1);
    for (PetscInt e = 0; e < ntets; ++e) {
      for (int k = 0; k < 4; ++k) M.tets[e][k] = (int)tets[4 * e + k];
      if (body) {
        PetscCheck(body[e] >= 0 && body[e] < nb, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMesh: element %" PetscInt_FMT " has body %" PetscInt_FMT ", not in [0, %" PetscInt_FMT ")", e, body[e], nb);
        M.body[e] = (int)body[e];
      }
    }
    for (PetscInt b = 0; b < nb; ++b) M.body_names.push_back(names && names[b] ? std::string(names[b]) : "body_" + std::to_string(b));
  }
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshBox(FDEMDeformable d, const PetscReal lo[3], const PetscReal hi[3], PetscInt nx, PetscInt ny, PetscInt nz) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshBox"));
  PetscCheck(nx > 0 && ny > 0 && nz > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshBox: cell counts must be positive");
  PetscCall(ResetMesh(d));
  if (d->rank == 0) PetscCall(Guard(PETSC_COMM_SELF, [&]() -> PetscErrorCode {
      d->mesh = fdem::kernels::MakeBoxMesh(Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2]), (int)nx, (int)ny, (int)nz);
      return 0;
    }));
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshBeam(FDEMDeformable d, PetscReal L, PetscReal W, PetscReal H, PetscInt n) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshBeam"));
  PetscCheck(L > 0 && W > 0 && H > 0 && n > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshBeam: sizes and n must be positive");
  PetscCall(ResetMesh(d));
  if (d->rank == 0) PetscCall(Guard(PETSC_COMM_SELF, [&]() -> PetscErrorCode {
      d->mesh = fdem::kernels::MakeBeamMesh(L, W, H, (int)n);
      return 0;
    }));
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshCylinder(FDEMDeformable d, PetscReal radius, PetscReal height, PetscInt n_radial, PetscInt n_axial) {
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshCylinder"));
  PetscCheck(radius > 0 && height > 0 && n_radial > 0 && n_axial > 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableSetMeshCylinder: sizes and counts must be positive");
  PetscCall(ResetMesh(d));
  if (d->rank == 0) PetscCall(Guard(PETSC_COMM_SELF, [&]() -> PetscErrorCode {
      d->mesh = fdem::kernels::MakeCylinderMesh(radius, height, (int)n_radial, (int)n_axial);
      return 0;
    }));
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMeshFromGmsh(FDEMDeformable d, const char *path) {
  std::string err;
  PetscFunctionBegin;
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMeshFromGmsh"));
  PetscCall(ResetMesh(d));
  if (d->rank == 0) {
    try {
      d->mesh = fdem::kernels::ReadGmsh(path ? path : "");
    } catch (const std::exception &e) {
      err = std::string("FDEMDeformableSetMeshFromGmsh: ") + e.what();
    }
  }
  PetscCall(CollectiveError(d, err, PETSC_ERR_FILE_UNEXPECTED));
  PetscCall(FinishMesh(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetGravity(FDEMDeformable d, const PetscReal g[3]) {
  PetscFunctionBegin;
  for (int k = 0; k < 3; ++k) d->g[k] = g[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableAddForce(FDEMDeformable d, FDEMDeformableForceFn fn, void *ctx) {
  PetscFunctionBegin;
  PetscCheck(fn, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableAddForce: the force function is NULL");
  d->ext.emplace_back(fn, ctx);
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableRemoveForce(FDEMDeformable d, FDEMDeformableForceFn fn, void *ctx) {
  PetscFunctionBegin;
  d->ext.erase(std::remove(d->ext.begin(), d->ext.end(), std::make_pair(fn, ctx)), d->ext.end());
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetExternalForce(FDEMDeformable d, FDEMDeformableForceFn fn, void *ctx) { return FDEMDeformableAddForce(d, fn, ctx); }

PetscErrorCode FDEMDeformableSetFromOptions(FDEMDeformable d) {
  PetscInt  three = 3;
  PetscBool flg;
  PetscFunctionBegin;
  PetscOptionsBegin(d->comm, nullptr, "fdem deformable bodies", "FDEMDeformable");
  PetscCall(PetscOptionsRealArray("-fdem_deformable_gravity", "Gravity acceleration gx,gy,gz", "FDEMDeformableSetGravity", d->g, &three, &flg));
  PetscCheck(!flg || three == 3, d->comm, PETSC_ERR_ARG_SIZ, "-fdem_deformable_gravity takes three numbers gx,gy,gz; got %" PetscInt_FMT, three);
  PetscCall(PetscOptionsEList("-fdem_deformable_partition", "Element partition: metis (METIS_PartMeshDual) or simple (contiguous blocks)", "FDEMDeformableSetUp", PartitionTypes, 2, PartitionTypes[d->partition], &d->partition, nullptr));
  PetscCall(PetscOptionsBool("-fdem_deformable_view", "Print sizes and the partition balance after set-up", "FDEMDeformableSetUp", d->view, &d->view, nullptr));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetUp(FDEMDeformable d) {
  std::vector<PetscInt> part;
  std::vector<int>      mob;
  std::string           err;
  PetscInt              dims[3] = {0, 0, 0}; // ncells, nnodes, nbodies
  PetscFunctionBegin;
  if (d->setup) PetscFunctionReturn(0);
  {
    int has = d->has_mesh ? 1 : 0, all;
    PetscCallMPI(MPI_Allreduce(&has, &all, 1, MPI_INT, MPI_MIN, d->comm));
    PetscCheck(all, d->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMDeformableSetUp: no mesh; give one with FDEMDeformableSetMesh/SetMeshBox/SetMeshBeam/SetMeshCylinder/SetMeshFromGmsh");
  }
  if (d->rank == 0) {
    try {
      err = ValidateAndPartition(d, part, mob);
    } catch (const std::exception &e) {
      err = std::string("FDEMDeformableSetUp: ") + e.what();
    }
    dims[0] = (PetscInt)d->mesh.tets.size();
    dims[1] = (PetscInt)d->mesh.nodes.size();
    dims[2] = (PetscInt)d->mesh.NumBodies();
  }
  PetscCall(CollectiveError(d, err, PETSC_ERR_USER_INPUT));
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
  std::vector<PetscInt> orig, cellbody;
  {
    PetscInt pStart, pEnd;
    PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
    orig.resize(pEnd - pStart);
    cellbody.assign(pEnd - pStart, 0);
    std::iota(orig.begin(), orig.end(), 0);
    for (PetscInt e = 0; e < nc; ++e) cellbody[e] = d->mesh.body[e];
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
      PetscCall(DMDestroy(&dm));
      dm = dmd;
    }
    PetscCall(PetscSFDestroy(&sf));
  }
  d->dm = dm;
  if (d->rank == 0) d->mesh = fdem::kernels::TetMesh(); // the distributed DM holds it now
  d->has_mesh = false;
  PetscCall(BuildLocal(d, orig, cellbody, dims[0]));
  d->setup = true;
  if (d->view) {
    PetscReal w = 0;
    for (const auto &el : d->ed.elems) w += ModelWeight(d->materials[el.material].model);
    PetscCall(PetscSynchronizedPrintf(d->comm, "[%d] FDEMDeformable: %zu cells (weight %g), %" PetscInt_FMT " local nodes, %" PetscInt_FMT " owned\n", d->rank, d->ed.size(), (double)w, d->nlocal, d->nown));
    PetscCall(PetscSynchronizedFlush(d->comm, PETSC_STDOUT));
    PetscCall(PetscPrintf(d->comm, "FDEMDeformable: %" PetscInt_FMT " cells, %" PetscInt_FMT " nodes, %zu bodies, partition %s\n", d->ncells_global, d->nnodes_global, d->body_names.size(), PartitionTypes[d->partition]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetDM(FDEMDeformable d, DM *dm) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetDM"));
  *dm = d->dm;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetSizes(FDEMDeformable d, PetscInt *cl, PetscInt *cg, PetscInt *no, PetscInt *ng) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetSizes"));
  if (cl) *cl = (PetscInt)d->ed.size();
  if (cg) *cg = d->ncells_global;
  if (no) *no = d->nown;
  if (ng) *ng = d->nnodes_global;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetNodeIds(FDEMDeformable d, PetscInt *n, const PetscInt *ids[]) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetNodeIds"));
  if (n) *n = d->nown;
  if (ids) *ids = d->owned_gid.data();
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetCellIds(FDEMDeformable d, PetscInt *n, const PetscInt *ids[]) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetCellIds"));
  if (n) *n = (PetscInt)d->cell_gid.size();
  if (ids) *ids = d->cell_gid.data();
  PetscFunctionReturn(0);
}

#define GETTER(name, field) \
  PetscErrorCode name(FDEMDeformable d, Vec *out) { \
    PetscFunctionBegin; \
    PetscCall(CheckSetUp(d, #name)); \
    *out = d->field; \
    PetscFunctionReturn(0); \
  }
GETTER(FDEMDeformableGetPositions, x)
GETTER(FDEMDeformableGetVelocities, v)
GETTER(FDEMDeformableGetReferencePositions, X)
GETTER(FDEMDeformableGetMasses, m)
#undef GETTER

static PetscErrorCode SetField(FDEMDeformable d, Vec target, FDEMDeformableFieldFn fn, void *ctx, bool velocity) {
  const PetscScalar *Xa;
  PetscScalar       *t;
  PetscFunctionBegin;
  PetscCall(VecGetArrayRead(d->X, &Xa));
  PetscCall(VecGetArray(target, &t));
  for (PetscInt k = 0; k < d->nown; ++k) {
    PetscReal in[3] = {Xa[3 * k], Xa[3 * k + 1], Xa[3 * k + 2]}, out[3] = {0, 0, 0};
    PetscCall(fn(d->owned_gid[k], in, out, ctx));
    if (velocity && d->fixed[k]) out[0] = out[1] = out[2] = 0;
    for (int c = 0; c < 3; ++c) t[3 * k + c] = out[c];
  }
  PetscCall(VecRestoreArray(target, &t));
  PetscCall(VecRestoreArrayRead(d->X, &Xa));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetPositionField(FDEMDeformable d, FDEMDeformableFieldFn fn, void *ctx) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableSetPositionField"));
  PetscCall(SetField(d, d->x, fn, ctx, false));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetVelocityField(FDEMDeformable d, FDEMDeformableFieldFn fn, void *ctx) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableSetVelocityField"));
  PetscCall(SetField(d, d->v, fn, ctx, true));
  PetscFunctionReturn(0);
}

static PetscErrorCode FinishFix(FDEMDeformable d, PetscInt *nfixed) {
  PetscScalar *va;
  PetscInt     n = 0;
  PetscFunctionBegin;
  PetscCall(VecGetArray(d->v, &va));
  for (PetscInt k = 0; k < d->nown; ++k)
    if (d->fixed[k]) {
      va[3 * k] = va[3 * k + 1] = va[3 * k + 2] = 0;
      ++n;
    }
  PetscCall(VecRestoreArray(d->v, &va));
  if (nfixed) PetscCall(MPIU_Allreduce(&n, nfixed, 1, MPIU_INT, MPI_SUM, d->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableFixNodes(FDEMDeformable d, PetscInt n, const PetscInt ids[], PetscInt *nfixed) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableFixNodes"));
  // every rank's list reaches every rank
  PetscMPIInt           ln = (PetscMPIInt)n;
  std::vector<int>      counts(d->size), displs(d->size, 0);
  PetscCallMPI(MPI_Allgather(&ln, 1, MPI_INT, counts.data(), 1, MPI_INT, d->comm));
  for (int r = 1; r < d->size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<PetscInt> all(displs[d->size - 1] + counts[d->size - 1]);
  PetscCallMPI(MPI_Allgatherv(ids, ln, MPIU_INT, all.data(), counts.data(), displs.data(), MPIU_INT, d->comm));
  PetscInt bad = -1, gbad;
  for (PetscInt id : all) {
    if (id < 0 || id >= d->nnodes_global) bad = PetscMax(bad, id < 0 ? PETSC_MAX_INT : id);
    auto it = d->owned_of_gid.find(id);
    if (it != d->owned_of_gid.end()) d->fixed[it->second] = 1;
  }
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_MAX, d->comm));
  PetscCheck(gbad < 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableFixNodes: node id %" PetscInt_FMT " is not in [0, %" PetscInt_FMT ")", gbad == PETSC_MAX_INT ? -1 : gbad, d->nnodes_global);
  PetscCall(FinishFix(d, nfixed));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableFixNodesInBox(FDEMDeformable d, const PetscReal lo[3], const PetscReal hi[3], PetscInt *nfixed) {
  const PetscScalar *Xa;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableFixNodesInBox"));
  PetscCall(VecGetArrayRead(d->X, &Xa));
  for (PetscInt k = 0; k < d->nown; ++k) {
    bool in = true;
    for (int c = 0; c < 3; ++c) in = in && Xa[3 * k + c] >= lo[c] && Xa[3 * k + c] <= hi[c];
    if (in) d->fixed[k] = 1;
  }
  PetscCall(VecRestoreArrayRead(d->X, &Xa));
  PetscCall(FinishFix(d, nfixed));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableComputeForces(FDEMDeformable d, PetscReal t, Vec U, Vec F) {
  StateView    sv;
  PetscScalar *f;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableComputeForces"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArray(F, &f));
  PetscCall(AssembleForces(d, t, sv.xa, sv.va, f));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(sv.Restore());
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableComputeCellStress(FDEMDeformable d, Vec U, Vec *S) {
  StateView    sv;
  PetscScalar *s, *xl, *vl = nullptr;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableComputeCellStress"));
  PetscCall(sv.Get(d, U));
  PetscCall(LocalPositions(d, sv.xa, d->viscous ? sv.va : nullptr));
  PetscCall(sv.Restore());
  PetscCall(VecCreateMPI(d->comm, 6 * (PetscInt)d->ed.size(), PETSC_DETERMINE, S));
  PetscCall(VecSetBlockSize(*S, 6));
  PetscCall(PetscObjectSetName((PetscObject)*S, "stress"));
  PetscCall(VecGetArray(*S, &s));
  PetscCall(VecGetArray(d->xloc, &xl));
  if (d->viscous) PetscCall(VecGetArray(d->vloc, &vl));
  for (size_t e = 0; e < d->ed.size(); ++e) {
    fdem::kernels::TetState st;
    const bool              ok = fdem::kernels::EvaluateTet(d->ed, e, xl, vl, st);
    const double            T[6] = {st.T(0, 0), st.T(1, 1), st.T(2, 2), st.T(0, 1), st.T(1, 2), st.T(0, 2)};
    for (int k = 0; k < 6; ++k) s[6 * e + k] = ok ? T[k] : NAN;
  }
  if (d->viscous) PetscCall(VecRestoreArray(d->vloc, &vl));
  PetscCall(VecRestoreArray(d->xloc, &xl));
  PetscCall(VecRestoreArray(*S, &s));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetUpTS(FDEMDeformable d, TS ts, Vec *U) {
  PetscInt     start;
  PetscScalar *u;
  const PetscScalar *xa, *va;
  IS           isq, isp;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableSetUpTS"));
  const PetscInt n = 3 * d->nown;
  PetscCall(VecCreateMPI(d->comm, 2 * n, PETSC_DETERMINE, U));
  PetscCall(PetscObjectSetName((PetscObject)*U, "deformable state"));
  PetscCall(VecGetOwnershipRange(*U, &start, nullptr));
  PetscCall(VecGetArray(*U, &u));
  PetscCall(VecGetArrayRead(d->x, &xa));
  PetscCall(VecGetArrayRead(d->v, &va));
  for (PetscInt i = 0; i < n; ++i) {
    u[i]     = xa[i];
    u[n + i] = d->fixed[i / 3] ? 0 : va[i];
  }
  PetscCall(VecRestoreArrayRead(d->v, &va));
  PetscCall(VecRestoreArrayRead(d->x, &xa));
  PetscCall(VecRestoreArray(*U, &u));
  PetscCall(ISCreateStride(d->comm, n, start, 1, &isq));
  PetscCall(ISCreateStride(d->comm, n, start + n, 1, &isp));
  PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
  PetscCall(TSRHSSplitSetIS(ts, "position", isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", isp));
  PetscCall(ISDestroy(&isq));
  PetscCall(ISDestroy(&isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, d));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, d));
  PetscCall(TSSetSolution(ts, *U));
  d->ts = ts;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableRestoreState(FDEMDeformable d, Vec U) {
  const PetscScalar *u;
  PetscScalar       *xa, *va;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableRestoreState"));
  const PetscInt n = 3 * d->nown;
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArray(d->x, &xa));
  PetscCall(VecGetArray(d->v, &va));
  for (PetscInt i = 0; i < n; ++i) {
    xa[i] = u[i];
    va[i] = u[n + i];
  }
  PetscCall(VecRestoreArray(d->v, &va));
  PetscCall(VecRestoreArray(d->x, &xa));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetEnergy(FDEMDeformable d, Vec U, PetscReal *kinetic, PetscReal *strain, PetscReal *gravity) {
  StateView          sv;
  const PetscScalar *ma, *xl;
  PetscReal          loc[3] = {0, 0, 0}, glob[3];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetEnergy"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->m, &ma));
  for (PetscInt i = 0; i < 3 * d->nown; ++i) {
    loc[0] += 0.5 * ma[i] * sv.va[i] * sv.va[i];
    loc[2] -= ma[i] * d->g[i % 3] * sv.xa[i];
  }
  PetscCall(VecRestoreArrayRead(d->m, &ma));
  PetscCall(LocalPositions(d, sv.xa, nullptr));
  PetscCall(sv.Restore());
  PetscCall(VecGetArrayRead(d->xloc, &xl));
  for (const auto &el : d->ed.elems) {
    const Vec3 x0(xl[3 * el.n[0]], xl[3 * el.n[0] + 1], xl[3 * el.n[0] + 2]);
    Vec3       e[3];
    for (int a = 1; a < 4; ++a) e[a - 1] = Vec3(xl[3 * el.n[a]], xl[3 * el.n[a] + 1], xl[3 * el.n[a] + 2]) - x0;
    Mat3 Xi;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) Xi.m[r][c] = el.Xinv[3 * r + c];
    const Mat3 F = Mat3::columns(e[0], e[1], e[2]) * Xi;
    loc[1] += el.V0 * StrainEnergyDensity(d->ed.coeffs[el.material], d->materials[el.material].model, F);
  }
  PetscCall(VecRestoreArrayRead(d->xloc, &xl));
  PetscCall(MPIU_Allreduce(loc, glob, 3, MPIU_REAL, MPIU_SUM, d->comm));
  if (kinetic) *kinetic = glob[0];
  if (strain) *strain = glob[1];
  if (gravity) *gravity = glob[2];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetMomentum(FDEMDeformable d, Vec U, PetscReal *mass, PetscReal com[3], PetscReal P[3], PetscReal L[3]) {
  StateView          sv;
  const PetscScalar *ma;
  PetscReal          loc[10] = {0}, glob[10];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetMomentum"));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->m, &ma));
  for (PetscInt k = 0; k < d->nown; ++k) {
    const double mk = ma[3 * k];
    const Vec3   x(sv.xa[3 * k], sv.xa[3 * k + 1], sv.xa[3 * k + 2]), v(sv.va[3 * k], sv.va[3 * k + 1], sv.va[3 * k + 2]);
    const Vec3   l = mk * cross(x, v);
    loc[0] += mk;
    for (int c = 0; c < 3; ++c) {
      loc[1 + c] += mk * x[c];
      loc[4 + c] += mk * v[c];
      loc[7 + c] += l[c];
    }
  }
  PetscCall(VecRestoreArrayRead(d->m, &ma));
  PetscCall(sv.Restore());
  PetscCall(MPIU_Allreduce(loc, glob, 10, MPIU_REAL, MPIU_SUM, d->comm));
  if (mass) *mass = glob[0];
  for (int c = 0; c < 3; ++c) {
    if (com) com[c] = glob[1 + c] / glob[0];
    if (P) P[c] = glob[4 + c];
    if (L) L[c] = glob[7 + c];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetNodeState(FDEMDeformable d, Vec U, PetscInt id, PetscReal x[3], PetscReal v[3]) {
  StateView sv;
  PetscReal loc[7] = {0}, glob[7];
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetNodeState"));
  PetscCall(sv.Get(d, U));
  auto it = d->owned_of_gid.find(id);
  if (it != d->owned_of_gid.end()) {
    const PetscInt k = it->second;
    loc[0]           = 1;
    for (int c = 0; c < 3; ++c) {
      loc[1 + c] = sv.xa[3 * k + c];
      loc[4 + c] = sv.va[3 * k + c];
    }
  }
  PetscCall(sv.Restore());
  PetscCall(MPIU_Allreduce(loc, glob, 7, MPIU_REAL, MPIU_SUM, d->comm));
  PetscCheck(glob[0] == 1, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableGetNodeState: no node with id %" PetscInt_FMT " (the mesh has %" PetscInt_FMT " nodes)", id, d->nnodes_global);
  for (int c = 0; c < 3; ++c) {
    if (x) x[c] = glob[1 + c];
    if (v) v[c] = glob[4 + c];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetMinJacobian(FDEMDeformable d, Vec U, PetscReal *Jmin, PetscInt *element) {
  StateView          sv;
  const PetscScalar *xl;
  struct {
    double v;
    int    r;
  } loc = {INFINITY, 0}, glob;
  PetscInt best = -1;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetMinJacobian"));
  PetscCall(sv.Get(d, U));
  PetscCall(LocalPositions(d, sv.xa, nullptr));
  PetscCall(sv.Restore());
  PetscCall(VecGetArrayRead(d->xloc, &xl));
  for (size_t e = 0; e < d->ed.size(); ++e) {
    const double J = ElementJ(d->ed.elems[e], xl);
    if (J < loc.v) {
      loc.v = J;
      best  = d->cell_gid[e];
    }
  }
  PetscCall(VecRestoreArrayRead(d->xloc, &xl));
  loc.r = d->rank;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MINLOC, d->comm));
  PetscCallMPI(MPI_Bcast(&best, 1, MPIU_INT, glob.r, d->comm));
  if (Jmin) *Jmin = glob.v;
  if (element) *element = best;
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- output
PetscErrorCode FDEMDeformableWriteHDF5(FDEMDeformable d, Vec U, const char *base, PetscInt step, PetscReal t) {
  StateView              sv;
  const PetscScalar     *Xa, *sa;
  Vec                    S;
  std::vector<PetscReal> xv, dv, vv, st, vm;
  std::vector<PetscInt>  cells, body, rank, nid;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableWriteHDF5"));
  PetscCheck(base && base[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableWriteHDF5: no file base name");
  PetscCheck(step >= 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "FDEMDeformableWriteHDF5: step %" PetscInt_FMT " must be non-negative", step);
  for (const auto &o : d->outputs) PetscCheck(o.step != step, d->comm, PETSC_ERR_ARG_WRONGSTATE, "FDEMDeformableWriteHDF5: step %" PetscInt_FMT " was already written to %s.h5", step, base);
  PetscCall(FDEMDeformableComputeCellStress(d, U, &S));
  PetscCall(sv.Get(d, U));
  PetscCall(VecGetArrayRead(d->X, &Xa));
  const PetscInt n = 3 * d->nown;
  xv.assign(sv.xa, sv.xa + n);
  vv.assign(sv.va, sv.va + n);
  dv.resize(n);
  for (PetscInt i = 0; i < n; ++i) dv[i] = sv.xa[i] - Xa[i];
  PetscCall(VecRestoreArrayRead(d->X, &Xa));
  PetscCall(sv.Restore());
  nid = d->owned_gid;
  PetscCall(VecGetArrayRead(S, &sa));
  const size_t nc = d->ed.size();
  for (size_t e = 0; e < nc; ++e) {
    const auto &el = d->ed.elems[e];
    for (int a = 0; a < 4; ++a) cells.push_back(d->node_global[el.n[a]]);
    body.push_back(d->ed.body[e]);
    rank.push_back(d->rank);
    const double *T = &sa[6 * e]; // xx yy zz xy yz xz -> XDMF Tensor6 xx xy xz yy yz zz
    st.insert(st.end(), {T[0], T[3], T[5], T[1], T[4], T[2]});
    const double s1 = T[0] - T[1], s2 = T[1] - T[2], s3 = T[2] - T[0];
    vm.push_back(std::sqrt(0.5 * (s1 * s1 + s2 * s2 + s3 * s3) + 3 * (T[3] * T[3] + T[4] * T[4] + T[5] * T[5])));
  }
  PetscCall(VecRestoreArrayRead(S, &sa));
  PetscCall(VecDestroy(&S));

  PetscViewer viewer;
  char        file[PETSC_MAX_PATH_LEN], group[64];
  PetscCall(PetscSNPrintf(file, sizeof(file), "%s.h5", base));
  PetscCall(PetscSNPrintf(group, sizeof(group), "/step_%06d", (int)step));
  PetscCall(PetscViewerHDF5Open(d->comm, file, d->outputs.empty() ? FILE_MODE_WRITE : FILE_MODE_APPEND, &viewer));
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "vertices", xv, 3));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "displacement", dv, 3));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "velocity", vv, 3));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "node_id", nid, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "cells", cells, 4));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "stress", st, 6));
  PetscCall(fdem::output::WriteReal(d->comm, viewer, "von_mises", vm, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "body", body, 1));
  PetscCall(fdem::output::WriteInt(d->comm, viewer, "rank", rank, 1));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "time", PETSC_REAL, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "step", PETSC_INT, &step));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  d->outputs.push_back({step, t, d->nnodes_global, d->ncells_global});
  {
    std::vector<fdem::output::XdmfStep> steps;
    for (const auto &o : d->outputs) steps.push_back({o.step, o.t, (long long)o.nvert, (long long)o.ncell});
    PetscCall(fdem::output::WriteXDMF(d->comm, "FDEMDeformableWriteHDF5", base, "deformable mesh", "Tetrahedron", 4, steps,
                                      {{"displacement", "Vector", "Node", 3, true},
                                       {"velocity", "Vector", "Node", 3, true},
                                       {"node_id", "Scalar", "Node", 1, false},
                                       {"stress", "Tensor6", "Cell", 6, true},
                                       {"von_mises", "Scalar", "Cell", 1, true},
                                       {"body", "Scalar", "Cell", 1, false},
                                       {"rank", "Scalar", "Cell", 1, false}}));
  }
  PetscFunctionReturn(0);
}

// Internal accessors for src/scene (src/model/deformable_impl.hpp).
#include "deformable_impl.hpp"

PetscErrorCode fdem::model::DeformableAcceleration(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *a) {
  const PetscScalar *mi;
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableAcceleration"));
  PetscCall(AssembleForces(d, t, xo, vo, a));
  PetscCall(VecGetArrayRead(d->minv, &mi));
  for (PetscInt k = 0; k < d->nown; ++k) {
    if (d->fixed[k]) {
      a[3 * k] = a[3 * k + 1] = a[3 * k + 2] = 0;
      continue;
    }
    for (int c = 0; c < 3; ++c) a[3 * k + c] = a[3 * k + c] * mi[3 * k + c] + d->g[c];
  }
  PetscCall(VecRestoreArrayRead(d->minv, &mi));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableGetFixed(FDEMDeformable d, const std::vector<char> **fixed) {
  PetscFunctionBegin;
  *fixed = &d->fixed;
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableGetTS(FDEMDeformable d, TS *ts) {
  PetscFunctionBegin;
  *ts = d->ts;
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::DeformableGetLocalCells(FDEMDeformable d, std::vector<std::array<int, 4>> &cells, std::vector<PetscInt> &node_global, PetscInt *nlocal) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "DeformableGetLocalCells"));
  cells.resize(d->ed.size());
  for (size_t e = 0; e < d->ed.size(); ++e) cells[e] = d->ed.elems[e].n;
  node_global = d->node_global;
  *nlocal     = d->nlocal;
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- developer accessors (contact)
// Declared in fdem/deformable_contact.h: this rank's cells in local node
// numbering (the layout of the local vectors the external-force hook gets).
PetscErrorCode FDEMDeformableGetLocalCells(FDEMDeformable d, PetscInt *ncells, PetscInt *nlocal, PetscInt conn[], PetscInt body[], PetscInt cell_gid[], PetscInt node_gid[]) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetLocalCells"));
  if (ncells) *ncells = (PetscInt)d->ed.size();
  if (nlocal) *nlocal = d->nlocal;
  for (size_t e = 0; e < d->ed.size(); ++e) {
    if (conn)
      for (int a = 0; a < 4; ++a) conn[4 * e + a] = d->ed.elems[e].n[a];
    if (body) body[e] = d->ed.body[e];
    if (cell_gid) cell_gid[e] = d->cell_gid[e];
  }
  if (node_gid)
    for (PetscInt l = 0; l < d->nlocal; ++l) node_gid[l] = d->node_gid[l];
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetBodyName(FDEMDeformable d, PetscInt b, PetscInt *nbodies, const char **name) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetBodyName"));
  if (nbodies) *nbodies = (PetscInt)d->body_names.size();
  if (name) *name = (b >= 0 && b < (PetscInt)d->body_names.size()) ? d->body_names[b].c_str() : "?";
  PetscFunctionReturn(0);
}
