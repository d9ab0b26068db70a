// Internal: what other layers (src/scene) use of the deformable model, for a
// combined state assembled elsewhere. Behaviour is that of
// FDEMDeformableSetUpTS's RHS. The object itself is in deformable_object.hpp.
#pragma once
#include <fdem/deformable.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

namespace fdem::model {
// dv/dt of the owned nodes (3 per owned node) from owned positions xo and
// velocities vo (vo feeds the viscous term and the external-force hook; may be
// null): (f_int + f_ext)/m + g, 0 at fixed nodes. The one implementation of
// this rule; FDEMDeformableSetUpTS's RHS calls it too. Collective.
PetscErrorCode DeformableAcceleration(FDEMDeformable d, PetscReal t, const PetscScalar *xo, const PetscScalar *vo, PetscScalar *ao);
// The external-force hooks alone at U (a state from FDEMDeformableSetUpTS; NULL: the stored
// state), as FDEMDeformableComputeForces evaluates them but without the internal and joint
// forces, their forces dropped: what a diagnostic needs of them, a contact object's energy,
// at the cost of the hooks. Collective.
PetscErrorCode DeformableEvaluateHooks(FDEMDeformable d, PetscReal t, Vec U = nullptr);
// This rank's cells as local node indices (the indexing of the hook's
// xloc/vloc/floc, 3 entries per local node), the global vertex number of
// every local node, and the number of local nodes.
PetscErrorCode DeformableGetLocalCells(FDEMDeformable d, std::vector<std::array<int, 4>> &cells, std::vector<PetscInt> &node_global, PetscInt *nlocal);
// Per owned node: 1 if fixed (FDEMDeformableFixNodes*).
PetscErrorCode DeformableGetFixed(FDEMDeformable d, const std::vector<char> **fixed);
// The TS of the last FDEMDeformableSetUpTS (NULL if none; not referenced).
PetscErrorCode DeformableGetTS(FDEMDeformable d, TS *ts);

// Broken joints and fragments (deformable_fragments.cpp, doc/fracture.md). A joint is
// broken when all three of its points are. The topology of the fractured mesh:
struct FractureTopology {
  PetscInt                             nbroken    = 0; // broken joints (all ranks)
  PetscInt                             ndamaged   = 0; // joints with a point beyond its peak (D > 0; broken ones included; all ranks)
  std::vector<PetscInt>                cell_fragment;  // per local cell (FDEMDeformableGetLocalCells order): its fragment's id, the smallest cell id in the connected component over shared nodes and intact joints (the same on any number of ranks)
  std::vector<char>                    fracturable;    // per body: 1 if fracturable (every rank)
  // per local cell of a fracturable body (0 elsewhere): bit o set when the face opposite
  // node o is free (on the body's outer surface or on a broken joint; for an unsplit cell,
  // bit 6 set, in a body with fracture zones: when it is not glued by an intact joint,
  // which includes the faces it shares with unsplit cells, so the surface is these bits
  // and the mesh's boundary faces); bit 4 set when a vertex lies on the free surface of a
  // split cell (its key is that of a node of such a face); bit 5 set when a face of the
  // cell is a damaged joint (a point beyond its peak, or broken); bit 7 set when a face of
  // the cell is a joint (intact or not) of a body whose joints are inserted during the run
  std::vector<unsigned char>           cell_free;
  // 4 per local cell: the key of each node, the smallest split-mesh id among the copies of
  // its input node glued to it through intact joints (its own id outside fracturable bodies)
  std::vector<PetscInt>                cell_key;
  std::vector<std::array<PetscInt, 2>> broken_pairs; // the two cell ids of every broken joint with a cell on this rank, smaller first, sorted
  // Each answer's number (1, 2, ... in a model), and, when the answer before this one differs
  // from it only where joints softened and none broke (bit 5 of cell_free), that answer's
  // number (else 0) and the local cells whose bit 5 changed, ascending: a reader that has
  // taken answer changed_from may update only those cells
  PetscInt                             version = 0, changed_from = 0;
  std::vector<PetscInt>                changed;
};
// Collective (each rank works on its own cells and joints, and exchanges labels with the
// ranks it shares joints or nodes with; deformable_fragments.cpp). Nothing per fragment of
// the whole mesh is held anywhere.
PetscErrorCode DeformableFractureTopology(FDEMDeformable d, FractureTopology &t);
// The same, kept by the model (valid until the next call or the model's destruction): not copied.
PetscErrorCode DeformableFractureTopology(FDEMDeformable d, const FractureTopology **t);
// The weight of a sphere's contact with one copy of a vertex or an edge of a fracturable
// body (doc/fracture.md, "Spheres on a fracturing body"): 10 per local cell, its 4 vertices and
// then its 6 edges in the order of fdem::kernels::kTetEdges. A copy of an input vertex (edge)
// is a node (pair of nodes) of the split mesh; the weight of each is 1 over the number of
// distinct copies of its input vertex (edge) that lie on the surface, so that a sphere
// touching the copies of one vertex where they coincide feels one contact in all, however
// the joints around it have broken, and each copy pushes back by its own overlap. surface:
// per local cell, bit o set when the face opposite vertex o is on the surface (the contact's
// faces). 1 outside fracturable bodies. Collective (a gather to the input nodes' ranks and a
// scatter back, over an SF built at the first call).
PetscErrorCode DeformableFeatureShares(FDEMDeformable d, const FractureTopology &t, const std::vector<unsigned char> &surface, std::vector<float> &share);
// The number of broken joints and of damaged joints (a point beyond its peak, broken ones
// included), all ranks, in one reduction; collective when the mesh has joints, 0 at once (no
// communication) when it has none. Both only grow.
PetscErrorCode DeformableJointCounts(FDEMDeformable d, PetscInt *nbroken, PetscInt *ndamaged);
// The local nodes this rank shares with others (1 per local node), through the DM's ghost
// nodes. Collective.
PetscErrorCode DeformableSharedNodes(FDEMDeformable d, std::vector<char> &shared);
// DMGlobalToLocal (INSERT_VALUES) and DMLocalToGlobal (INSERT_VALUES or ADD_VALUES) of the
// model's DM; on one rank whose local vectors are the global ones, a copy (a sum for
// ADD_VALUES): no section SF is made. Collective on more ranks.
PetscErrorCode DeformableGlobalToLocal(FDEMDeformable d, Vec g, Vec l);
PetscErrorCode DeformableLocalToGlobal(FDEMDeformable d, Vec l, InsertMode mode, Vec g);
// Whether the mesh has fracture joints (the same on every rank).
PetscErrorCode DeformableHasJoints(FDEMDeformable d, PetscBool *has);

// Union-find over a rank's nodes or cells whose root carries a label, the smallest global id
// known to be in its class, and a flag (or-ed over the class).
struct LabelClasses {
  std::vector<PetscInt> p, label;
  std::vector<char>     flag;

  explicit LabelClasses(const std::vector<PetscInt> &ids) : p(ids.size()), label(ids), flag(ids.size(), 0) { std::iota(p.begin(), p.end(), (PetscInt)0); }
  PetscInt Find(PetscInt i) {
    while (p[i] != i) i = p[i] = p[p[i]];
    return i;
  }
  void Unite(PetscInt a, PetscInt b) {
    a = Find(a);
    b = Find(b);
    if (a == b) return;
    if (label[b] < label[a]) std::swap(a, b);
    p[b]    = a;
    flag[a] = flag[a] | flag[b];
  }
  // what a class elsewhere that touches i says: its label L and flag f
  void Lower(PetscInt i, PetscInt L, char f) {
    const PetscInt r = Find(i);
    if (L < label[r]) label[r] = L;
    if (f) flag[r] = 1;
  }
  PetscInt Label(PetscInt i) { return label[Find(i)]; }
};

// What DeformableFractureTopology needs that the joints' states do not change, made at its
// first call on a model (the mesh and its split are fixed after set-up): the nodes shared
// across ranks, the split cells, the classes of the cells that share nodes (every path
// compressed, so that a copy finds its roots in one step), and the faces of tetrahedra b that
// joints glue, with the joint-face SF's root buffer kept between calls.
struct TopologyCache {
  std::vector<char>     shared, split;   // per local node; per local cell
  LabelClasses          cells{std::vector<PetscInt>{}};
  std::vector<PetscInt> glued;           // 12 e + 3 o for each face o of local cell e with a joint's leaves
  std::vector<PetscInt> froot;           // the SF's roots, 12 per cell (kept: only the glued are reset)
};

// Completes classes that reach other ranks (deformable_fragments.cpp, where the method is
// described): c's classes at this rank's boundaries (those of the elements in `boundary`) and
// the links `edges` (a class's label here, the label of a class elsewhere that touches it; sorted
// and made unique in place) end with the smallest label of their component over all ranks and
// the or of its flags. *nclasses: the labels in the graph, all ranks; *rounds: the rounds it
// took. Collective.
PetscErrorCode SettleClasses(MPI_Comm comm, LabelClasses &c, const std::vector<PetscInt> &boundary, std::vector<std::array<PetscInt, 2>> &edges, PetscInt *nclasses, PetscInt *rounds);
// A contact object tells the mesh that its contact energy changed by `e` (J, summed over ranks,
// the same on every rank) when it listed the mesh's primitives anew at a fixed state (faces that
// fracture exposed): the energy the contact took over from the removed joints, which the joints'
// dissipated energy then loses (FDEMDeformableGetJointEnergy; doc/fracture.md, "The handover
// to contact"). Not collective.
void DeformableAddOnset(FDEMDeformable d, PetscReal e);

// The criterion of joints inserted during a run (deformable_insertion.cpp): a material's
// strength, the ratio of a Cauchy stress (xx yy zz xy yz xz, tension positive) to it, and a
// test that needs no eigenvalues and is true only when the ratio is below r.
struct Strength {
  double ft = 0, ccos = 0, sin = 0; // f_t, c cos(phi), sin(phi)
  Strength() = default;
  Strength(double tensile_strength, double cohesion, double friction_angle_degrees);
};
double StrengthRatio(const PetscReal *T, const Strength &m);
bool   SurelyBelow(const PetscReal *T, const Strength &m, double r);
} // namespace fdem::model
