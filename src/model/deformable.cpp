// Deformable discrete elements on a distributed DMPlex: the object (create,
// destroy, materials, options, accessors, fixed nodes). The other jobs have
// their own files, listed in deformable_object.hpp; see
// include/fdem/deformable.h and doc/deformable.md.
#include "../util/guard.hpp"
#include "../util/options.hpp"
#include "deformable_impl.hpp"
#include <algorithm>
#include <utility>
#include "deformable_object.hpp"

#include "../kernels/materials/table.hpp"

#include <cmath>
#include <new>
#include <string>
#include <vector>

using fdem::kernels::Material;
using namespace fdem::model::deformable;

// The option names of FDEMMaterialModel: the rows of the material table.
#define FDEM_MATERIAL_NAME(M) fdem::kernels::M::kName,
const char *const FDEMMaterialModels[] = {FDEM_MATERIAL_TABLE(FDEM_MATERIAL_NAME) "FDEMMaterialModel", "FDEM_MATERIAL_", nullptr};
#undef FDEM_MATERIAL_NAME

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
  PetscCall(DestroyJoints(d));
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
  PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
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
  PetscFunctionBegin;
  PetscOptionsBegin(d->comm, nullptr, "fdem deformable bodies", "FDEMDeformable");
  PetscCall(fdem::OptionsVector3(PetscOptionsObject, d->comm, "-fdem_deformable_gravity", "gx,gy,gz", "Gravity acceleration gx,gy,gz", "FDEMDeformableSetGravity", d->g));
  PetscCall(PetscOptionsEList("-fdem_deformable_partition", "Element partition: metis (METIS_PartMeshDual) or simple (contiguous blocks)", "FDEMDeformableSetUp", PartitionTypes, 2, PartitionTypes[d->partition], &d->partition, nullptr));
  PetscCall(PetscOptionsBool("-fdem_deformable_view", "Print sizes and the partition balance after set-up", "FDEMDeformableSetUp", d->view, &d->view, nullptr));
  PetscOptionsEnd();
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
    PetscCall(fn(d->owned_input[k], in, out, ctx)); // the input mesh's id
    if (velocity && d->fixed[k])
      for (int c = 0; c < 3; ++c) out[c] = d->vfix[3 * k + c];
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
      for (int c = 0; c < 3; ++c) va[3 * k + c] = d->vfix[3 * k + c];
      ++n;
    }
  PetscCall(VecRestoreArray(d->v, &va));
  if (nfixed) PetscCall(MPIU_Allreduce(&n, nfixed, 1, MPIU_INT, MPI_SUM, d->comm));
  PetscFunctionReturn(0);
}

// Fixes (vel = NULL) or moves (held velocity vel) the nodes listed on any rank (input ids); *nset: how many nodes that holds.
static PetscErrorCode HoldNodes(FDEMDeformable d, const char *fn, PetscInt n, const PetscInt ids[], const PetscReal vel[3], PetscInt *nset) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, fn));
  // every rank's list reaches every rank
  PetscMPIInt           ln = (PetscMPIInt)n;
  std::vector<int>      counts(d->size), displs(d->size, 0);
  PetscCallMPI(MPI_Allgather(&ln, 1, MPI_INT, counts.data(), 1, MPI_INT, d->comm));
  for (int r = 1; r < d->size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<PetscInt> all(displs[d->size - 1] + counts[d->size - 1]);
  PetscCallMPI(MPI_Allgatherv(ids, ln, MPIU_INT, all.data(), counts.data(), displs.data(), MPIU_INT, d->comm));
  // ids are the input mesh's: with fracturable bodies, an input node stands for all its copies
  PetscInt bad = -1, gbad, mine = 0;
  for (PetscInt id : all)
    if (id < 0 || id >= d->ninput_nodes) bad = PetscMax(bad, id < 0 ? PETSC_MAX_INT : id);
  std::sort(all.begin(), all.end());
  for (PetscInt k = 0; k < d->nown; ++k) {
    if (!std::binary_search(all.begin(), all.end(), d->owned_input[k])) continue;
    d->fixed[k] = 1;
    for (int c = 0; c < 3; ++c) d->vfix[3 * k + c] = vel ? vel[c] : 0;
    ++mine;
  }
  PetscCallMPI(MPI_Allreduce(&bad, &gbad, 1, MPIU_INT, MPI_MAX, d->comm));
  PetscCheck(gbad < 0, d->comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: node id %" PetscInt_FMT " is not in [0, %" PetscInt_FMT ")", fn, gbad == PETSC_MAX_INT ? -1 : gbad, d->ninput_nodes);
  if (vel && (vel[0] != 0 || vel[1] != 0 || vel[2] != 0)) d->moved = true;
  if (nset) PetscCallMPI(MPI_Allreduce(&mine, nset, 1, MPIU_INT, MPI_SUM, d->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableFixNodes(FDEMDeformable d, PetscInt n, const PetscInt ids[], PetscInt *nfixed) {
  PetscFunctionBegin;
  PetscCall(HoldNodes(d, "FDEMDeformableFixNodes", n, ids, nullptr, nullptr));
  PetscCall(FinishFix(d, nfixed));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableMoveNodes(FDEMDeformable d, PetscInt n, const PetscInt ids[], const PetscReal v[3], PetscInt *nmoved) {
  PetscFunctionBegin;
  PetscCall(HoldNodes(d, "FDEMDeformableMoveNodes", n, ids, v, nmoved));
  PetscCall(FinishFix(d, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetExternalWork(FDEMDeformable d, PetscReal *W) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetExternalWork"));
  PetscCall(MPIU_Allreduce(&d->meter.work, W, 1, MPIU_REAL, MPIU_SUM, d->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetExternalWork(FDEMDeformable d, PetscReal W) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableSetExternalWork"));
  d->meter.Reset(d->rank == 0 ? W : 0);
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
    if (!in) continue;
    d->fixed[k] = 1;
    for (int c = 0; c < 3; ++c) d->vfix[3 * k + c] = 0;
  }
  PetscCall(VecRestoreArrayRead(d->X, &Xa));
  PetscCall(FinishFix(d, nfixed));
  PetscFunctionReturn(0);
}

// ---------------------------------------------------------------- internal accessors
// Declared in src/model/deformable_impl.hpp, for the layers above (src/scene).
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

// ---------------------------------------------------------------- developer accessors
// Declared in the developer section of fdem/deformable.h: this rank's cells in
// local node numbering (the layout of the local vectors the external-force hook gets).
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
