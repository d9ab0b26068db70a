// Internal: the deformable-body object shared by src/model/deformable*.cpp,
// one file per job:
//   deformable.cpp             the object: create/destroy, materials, options, accessors, fixed nodes
//   deformable_mesh_input.cpp  mesh setters and the validation of mesh + materials (rank 0)
//   deformable_partition.cpp   METIS partition, DMPlex distribution, the local layout (FDEMDeformableSetUp)
//   deformable_assembly.cpp    internal + external forces, a = f/m + g, the TS right-hand sides
//   deformable_diagnostics.cpp stress, energy, momentum, node state, smallest det F
//   deformable_output.cpp      HDF5 + XDMF output
//   deformable_joints.cpp      fracture joints: split meshes, joint forces across ranks
//   deformable_fragments.cpp   broken joints and fragments (the topology contact and output use)
// Other layers use src/model/deformable_impl.hpp, never this file.
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
#pragma once
#include "deformable_impl.hpp"
#include "work_meter.hpp"
#include <fdem/deformable.h>
#include <fdem/kernels/cst.hpp>
#include <fdem/kernels/joint.hpp>
#include <fdem/kernels/joint_mesh.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace fdem::model::deformable {
enum PartitionType { kPartMetis = 0, kPartSimple = 1 };
extern const char *const PartitionTypes[]; // deformable_partition.cpp

struct OutputRecord {
  PetscInt  step;
  PetscReal t;
  PetscInt  nvert, ncell;
};

// What the mapping from one split to another (Origins in deformable_insertion.cpp) reads of a
// split with some tetrahedra inserted: each tetrahedron's nodes, each node's input node (their
// count is the split's), the joints. A model with insertion keeps its own (rank 0), so that the
// model built after it with more joints needs to split neither again.
struct SplitRecord {
  std::vector<PetscInt>                 inserted; // the inserted tetrahedra (sorted)
  std::vector<std::array<int, 4>>       tets;
  std::vector<int>                      parent;
  std::vector<fdem::kernels::JointFace> joints;
};

// A joint of a larger split (joints inserted during a run): the joint of a smaller split it
// comes from, and the point of that joint on the same edge as each of its points.
struct JointOrigin {
  PetscInt joint    = -1;          // -1: a new joint
  int      point[3] = {0, 1, 2};
};
// The separations that a joint inserted into a stressed body starts from, at its three nodes
// (PrestressNewJoints, EquilibrateNewJoints, doc/fracture.md): kept in a frame of its face that
// both sides agree on (OffsetFrame), so that they survive a rebuild that swaps triangles a and b.
struct JointOffset {
  double c[3][3] = {}; // m: at each node of the face (in the order of their input nodes), along the frame's e1, e2 and normal
  double energy  = 0;  // J: what the joint stored when it got the offset (counted from there)
  bool   any() const {
    for (const auto &r : c)
      if (r[0] != 0 || r[1] != 0 || r[2] != 0) return true;
    return false;
  }
};
} // namespace fdem::model::deformable

namespace fdem::model::deformable {
// What the set-up of a body with joints inserted during the run derives from its input mesh
// alone (rank 0): the same for every model that a run's insertions build.
struct InsertionInput {
  fdem::kernels::TetMesh                        mesh;        // the mesh before the split
  std::vector<double>                           key;         // per body: fracturable, inserting, density, fracture properties; then the zones' tetrahedra
  std::unique_ptr<fdem::kernels::JointSplitter> splitter;    // its splits (the faces sorted once), of `mesh` here
  double                                        joint_omega = 0; // the joints' largest frequency with every tetrahedron that may split split
};
// This rank's cells' centroids (reference positions) and their Hilbert keys, in the order its
// DM numbers its cells, with the box the keys were scaled to: a model built again after an
// insertion (FDEMDeformableReuseSetUp) takes the key of each cell whose centroid and box are
// the same to the bit instead of computing it (BuildLocal).
struct CellKeys {
  fdem::kernels::Vec3                lo, hi;
  std::vector<fdem::kernels::Vec3>   centroid;
  std::vector<std::uint64_t>         key;
};
// Whether two meshes have the same bodies, tetrahedra and node positions.
inline bool SameMesh(const fdem::kernels::TetMesh &M, const fdem::kernels::TetMesh &mesh) {
  return M.tets == mesh.tets && M.body == mesh.body && M.nodes.size() == mesh.nodes.size() &&
         std::equal(M.nodes.begin(), M.nodes.end(), mesh.nodes.begin(), [](const fdem::kernels::Vec3 &a, const fdem::kernels::Vec3 &b) { return a.x == b.x && a.y == b.y && a.z == b.z; });
}
// Whether r was made from this key and mesh.
inline bool SameInput(const InsertionInput &r, const std::vector<double> &key, const fdem::kernels::TetMesh &mesh) { return r.key == key && SameMesh(r.mesh, mesh); }
} // namespace fdem::model::deformable

struct _n_FDEMDeformable {
  MPI_Comm    comm;
  PetscMPIInt rank = 0, size = 1;
  // input (mesh on rank 0 only)
  std::vector<fdem::kernels::Material> materials;
  std::map<std::string, std::string>   body_material;
  fdem::kernels::TetMesh               mesh;
  bool                                 has_mesh = false;
  PetscReal                            g[3] = {0, 0, 0};
  std::vector<std::pair<FDEMDeformableForceFn, void *>> ext; // force terms, added in order (a chain: none replaces another)
  PetscInt                             partition = fdem::model::deformable::kPartMetis;
  PetscBool                            view = PETSC_FALSE;
  // after set-up (all ranks)
  bool                       setup = false;
  std::vector<std::string>   body_names;
  std::vector<int>           material_of_body;
  DM                         dm = nullptr;
  PetscInt                   ncells_global = 0, nnodes_global = 0, nlocal = 0, nown = 0;
  fdem::kernels::ElementData ed;
  std::vector<PetscInt>      cell_gid, node_gid, owned_gid, owned_local, node_global; // node_global: global vertex number per local node
  std::unordered_map<PetscInt, PetscInt> owned_of_gid;
  std::vector<char>          fixed; // per owned node (fixed or moved: no acceleration)
  std::vector<PetscReal>     vfix;  // per owned node, 3 each: the held velocity (0 for fixed nodes)
  bool                       moved = false; // some node has a nonzero held velocity
  fdem::model::WorkMeter     meter; // work of the reactions on moved nodes
  bool                       viscous = false;
  // one rank whose local nodes are its owned nodes in the same order: the
  // local vectors are then the global ones, and the force evaluation works
  // on the state and the result in place (no scatter, no assembly pass)
  bool                       local_is_owned = false;
  Vec                        x = nullptr, v = nullptr, X = nullptr, m = nullptr, minv = nullptr;
  Vec                        xloc = nullptr, vloc = nullptr, floc = nullptr, gwork = nullptr;
  TS                         ts = nullptr; // the TS of FDEMDeformableSetUpTS (not referenced)
  std::vector<fdem::model::deformable::OutputRecord> outputs;
  // fracture joints (deformable_joints.cpp)
  std::map<std::string, fdem::kernels::JointMaterial> fracture; // by material name: its bodies are fracturable
  std::map<std::string, std::vector<std::array<double, 6>>> fracture_zones; // by body name: boxes (lo, hi) that limit its split
  // joints inserted during a run (deformable_insertion.cpp)
  std::map<std::string, PetscReal>        insertion;      // by body name: the stress ratio at which its tetrahedra get joints
  std::vector<PetscInt>                   inserted;       // sorted input tetrahedra split by insertion (all ranks)
  std::vector<PetscReal>                  body_insertion; // per body: its ratio, 0 without insertion (all ranks, after set-up)
  std::vector<char>                       cell_inserted;  // per local cell: 1 when it is in `inserted` (FDEMDeformableFindCellsToSplit)
  std::vector<double>                     stress_scratch; // FDEMDeformableFindCellsToSplit's stresses (kept: a search every few steps)
  std::shared_ptr<const fdem::model::deformable::InsertionInput> insertion_input; // rank 0, with insertion (FDEMDeformableReuseSetUp shares it between the models of one run)
  std::shared_ptr<const fdem::model::deformable::InsertionInput> reuse;           // rank 0: the one FDEMDeformableReuseSetUp gave, for SetUp
  std::shared_ptr<const fdem::model::deformable::CellKeys> cell_keys;             // this rank's cells' Hilbert keys (BuildLocal)
  std::shared_ptr<const fdem::model::deformable::CellKeys> reuse_keys;            // those of the model FDEMDeformableReuseSetUp gave, for SetUp
  std::vector<char>                       split_body, box_split; // rank 0, with insertion: fracturable bodies; tetrahedra split by their zones (or whole bodies)
  std::vector<char>                       tet_split;      // rank 0, with insertion: the tetrahedra split now
  std::vector<PetscInt>                   origin_of;      // rank 0: the inserted cells of the split that node_origin and joint_origin map from
  std::vector<PetscInt>                   node_origin;    // rank 0: per node, its node in that split (NodeOrigins)
  std::vector<fdem::model::deformable::JointOrigin> joint_origin; // rank 0: per joint, its joint there (JointOrigins)
  PetscInt                                origin_nodes = -1, origin_joints = -1; // that split's counts (-1: not made)
  std::shared_ptr<const fdem::model::deformable::SplitRecord> own_split;   // rank 0, with insertion: this model's split
  std::shared_ptr<const fdem::model::deformable::SplitRecord> origin_split; // rank 0: the split of a model continued from (FDEMDeformableContinue*), if Origins maps from it
  std::vector<int>                        split_parent;   // rank 0, set-up: input node of each split node (partition)
  std::vector<char>                       split_tet;      // rank 0, set-up: 1 for a tetrahedron with nodes of its own (partition weights)
  std::vector<char>                       split_boundary; // rank 0, set-up: per tetrahedron, the split mesh's boundary faces (SplitMesh::boundary), for boundary_faces
  std::vector<fdem::kernels::JointFace>   joints_input;   // rank 0, set-up: every joint, split node / tet ids
  std::vector<fdem::kernels::JointLaw>    laws_input;     // rank 0, set-up: the law of each joint
  std::vector<PetscInt>                   owned_input;    // the input node of each owned node (FixNodes/MoveNodes/field ids; owned_gid unless split)
  std::vector<PetscInt>                   local_input;    // the input node of each local node (empty when nothing was split)
  std::vector<char>                       boundary_faces; // per local cell, bit o: its face o is on the mesh's boundary (contact::BoundaryFaces, made once for every contact that lists the mesh)
  bool                                    boundary_made = false; // boundary_faces is made (on every rank)
  PetscSF                                 share_sf = nullptr; // 10 leaves per cell of a fracturable body -> its input vertices and edges (DeformableFeatureShares)
  PetscInt                                ninput_nodes = 0; // nodes of the input mesh
  PetscInt                                njoints_global = 0;
  PetscReal                               joint_omega = 0;    // the joints' largest frequency (estimate), 1/s
  TS                                      joint_checked = nullptr; // the TS whose time step was checked against it
  std::vector<std::array<int, 3>>         jnode_a;        // this rank's joints: local nodes of triangle a
  std::vector<fdem::kernels::JointLaw>    jlaw;           // their laws
  std::vector<std::array<fdem::kernels::JointState, 3>> jstate; // their point histories
  std::vector<PetscInt>                   jgid;           // their ids in the split's joint order (checkpoints)
  std::vector<PetscReal>                  jdiss;          // the energy each has dissipated so far, J (with the compression it took when it was removed)
  PetscReal                               onset = 0;      // the contact energy that pairs listed anew had when their listing changed (fracture), J, summed over ranks and contact objects; the same on every rank
  std::vector<PetscInt>                   jbody;          // their bodies
  std::vector<char>                       jgone;          // broken at all three points (and reported in jbreaks)
  std::vector<FDEMJointBreak>             jbreaks;        // this rank's breaks since FDEMDeformableGetJointBreaks last took them
  PetscSF                                 jsf = nullptr;  // 9 leaves per joint <- triangle b's node coordinates (roots: local vectors)
  std::vector<std::array<int, 3>>         jnode_b;        // local nodes of triangle b where it is on this rank, else -1
  PetscSF                                 jsf_remote = nullptr; // jsf's leaves of the joints whose triangle b is on another rank only
  std::vector<PetscScalar>                jxb, jfb;       // leaf buffers: b's coordinates, b's forces
  std::vector<PetscInt>                   jcell_a;        // their tetrahedra a: local cells
  std::vector<fdem::model::deformable::JointOffset> jofs; // their offsets (empty when none has one)
  std::vector<char>                       jfresh;         // inserted by the last load of a joint state: their offsets are still to make
  std::vector<char>                       jequil;         // given the mean traction by PrestressNewJoints, to be balanced node by node (EquilibrateNewJoints)
  bool                                    equilibrate_pending = false; // the same on every rank
  bool                                    prestress = true; // -fdem_insert_prestress: joints inserted under load start with their faces' forces
  bool                                    prestress_pending = false; // some joint is fresh (the same on every rank)
  PetscReal                               insert_ahead = 0.25; // -fdem_insert_ahead: FindCellsToSplit also takes the cells at (1 - this) of the ratio linked to one at it
  std::vector<std::array<PetscInt, 4>>    jtet_b;         // their tetrahedra b: id, rank, local cell there, the node opposite the joint's face
  PetscSF                                 jfsf = nullptr; // 3 leaves per joint -> 3 roots per face of tetrahedron b (12 per local cell)
  fdem::model::FractureTopology           topology;       // the last DeformableFractureTopology, for its counts of broken and damaged joints (each set only grows while the joints step)
  bool                                    topology_made = false;
  std::unique_ptr<fdem::model::TopologyCache> topology_cache; // (DeformableFractureTopology's parts that the joints' states do not change)
  bool                                    zoned = false;  // a fracture zone split part of a body (cells of fracturable bodies may share nodes)
};

namespace fdem::model::deformable {

// "fn: call FDEMDeformableSetUp() first" / "fn: the mesh is already set up".
inline PetscErrorCode CheckSetUp(FDEMDeformable d, const char *fn) {
  PetscFunctionBegin;
  PetscCheck(d->setup, d->comm, PETSC_ERR_ARG_WRONGSTATE, "%s: call FDEMDeformableSetUp() first", fn);
  PetscFunctionReturn(0);
}
inline PetscErrorCode CheckNotSetUp(FDEMDeformable d, const char *fn) {
  PetscFunctionBegin;
  PetscCheck(!d->setup, d->comm, PETSC_ERR_ARG_WRONGSTATE, "%s: the mesh is already set up; call it before FDEMDeformableSetUp()", fn);
  PetscFunctionReturn(0);
}

// Rank 0, before the partition: resolves the material of every body and checks
// the mesh (node indices, positive volumes). Throws InputError with what is
// wrong (deformable_mesh_input.cpp).
void ValidateInput(FDEMDeformable d, std::vector<int> &material_of_body);

// Assembled nodal force f (owned layout) from owned positions xo and
// velocities vo (may be null): internal forces of the local cells plus the
// external-force hook; collective inversion check (deformable_assembly.cpp).
PetscErrorCode AssembleForces(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *fo);

// Fracture joints (deformable_joints.cpp). Rank 0, after ValidateInput: splits
// the bodies of fracturable materials (d->mesh becomes the split mesh) and makes
// each joint's law; throws InputError naming the material. Collective, after
// BuildLocal: hands each joint to the rank of its tetrahedron a and builds the
// SF that brings triangle b's nodes to it.
void SplitFracturable(FDEMDeformable d, const std::vector<int> &material_of_body);
PetscErrorCode SetUpJoints(FDEMDeformable d);
// Joints inserted during a run (deformable_insertion.cpp).
PetscErrorCode ReadInsertedCells(MPI_Comm comm, PetscViewer viewer, std::vector<PetscInt> &cells, bool *has);
PetscErrorCode ViewInsertedCells(FDEMDeformable d, PetscViewer viewer);
// Where a load takes the state it continues from: a checkpoint's viewer, or (no viewer) the
// model `from` that a rebuild continues, with the same fields by name. Has: whether the state
// has the field `name` (a checkpoint written by an earlier fdem may not; a viewer other than
// HDF5 is taken to have it, as VecLoad reads it in order).
struct SavedState {
  PetscViewer    viewer = nullptr;
  FDEMDeformable from   = nullptr;
  PetscErrorCode Has(const char *name, bool *has) const;
};
PetscErrorCode SavedSplitDiffers(FDEMDeformable d, const SavedState &saved, std::vector<PetscInt> &old, bool *differs);
void           NodeOrigins(FDEMDeformable d, const std::vector<PetscInt> &old, std::vector<PetscInt> &from, PetscInt *nold);
void           JointOrigins(FDEMDeformable d, const std::vector<PetscInt> &old, std::vector<JointOrigin> &from, PetscInt *nold);
PetscErrorCode MapFromSplit(FDEMDeformable d, Vec old, Vec nat, PetscInt nold, PetscInt per, const std::function<void(const PetscScalar *, PetscScalar *)> &fill);
PetscErrorCode LoadJointState(FDEMDeformable d, const SavedState &saved);
// Adds the joint forces at local positions xl into the local forces fl and records the
// joints that break (time t, jbreaks); at the first evaluation of a TS, warns when its time step is near the joints' limit (collective).
PetscErrorCode AddJointForces(FDEMDeformable d, PetscReal t, const PetscScalar *xl, PetscScalar *fl);
// After the hooks of the first evaluation after an insertion: shifts the forces of the new joints
// node by node so that every copy of a node accelerates as the node it came from did, and adds
// the change to the local forces d->floc (deformable_joints.cpp). Collective.
PetscErrorCode EquilibrateNewJoints(FDEMDeformable d);
PetscErrorCode DestroyJoints(FDEMDeformable d);

// Owned positions xo (and velocities vo, may be null) into the local vectors xloc
// (vloc), ghosts included (deformable_diagnostics.cpp).
PetscErrorCode LocalPositions(FDEMDeformable d, const PetscScalar *xo, const PetscScalar *vo);

// det F of element el at local positions x.
inline double ElementJ(const fdem::kernels::TetElement &el, const double *x) {
  using fdem::kernels::Mat3;
  using fdem::kernels::Vec3;
  const Vec3 x0(x[3 * el.n[0]], x[3 * el.n[0] + 1], x[3 * el.n[0] + 2]);
  Vec3       e[3];
  for (int a = 1; a < 4; ++a) e[a - 1] = Vec3(x[3 * el.n[a]], x[3 * el.n[a] + 1], x[3 * el.n[a] + 2]) - x0;
  return det(Mat3::columns(e[0], e[1], e[2])) * el.inv6V0;
}

// Owned x and v arrays of a state U [x | v] from FDEMDeformableSetUpTS (or of
// the stored vectors when U is null).
struct StateView {
  FDEMDeformable     d = nullptr;
  Vec                U = nullptr;
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

} // namespace fdem::model::deformable
