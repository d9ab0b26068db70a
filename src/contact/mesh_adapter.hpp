// Internal: a deformable mesh (FDEMDeformable) as a body kind of the contact engine.
// It lends its cells at the boundary (the nodes' current positions and velocities)
// and adds the nodal forces to its force vector.
#pragma once
#include "engine.hpp"
#include "../model/deformable_impl.hpp"
#include <fdem/deformable.h>

#include <tuple>

namespace fdem::contact {
class MeshAdapter : public Adapter {
public:
  // Which cells take part: those with a boundary face (the surface tetrahedra), or
  // those with a vertex on the boundary (a rigid corner may enter through an edge).
  enum class Cells { BoundaryFace, BoundaryVertex };
  // Which pairs the engine forms with the mesh: its cells with each other (a body against
  // itself or another mesh body), or only with other kinds (rigid bodies, spheres). Only the
  // first needs the cells at damaged joints (a crack's sides, MeshAdapter::Select).
  enum class Pairs { WithItself, OtherKindsOnly };
  // Which weights a cell's vertices and edges carry for spheres (MeshAdapter::Shares): those of
  // their copies on a crack's sides, or none (the engine pairs the mesh with no sphere).
  enum class Spheres { Weighted, None };
  // Collective: finds the cells (after FDEMDeformableSetUp).
  static PetscErrorCode Create(FDEMDeformable d, Cells which, Pairs pairs, Spheres spheres, MeshAdapter **out);
  // Before each evaluation: local (ghosted) positions xl, velocities vl (may be null) and
  // forces fl (added to), in the node numbering of the mesh's local vectors.
  void Bind(const PetscScalar *xl, const PetscScalar *vl, PetscScalar *fl) {
    xl_ = xl;
    vl_ = vl;
    fl_ = fl;
  }
  // Without velocities: stop with an error (true) or take them as zero (false).
  void RequireVelocities(bool r) { require_v_ = r; }
  PetscErrorCode List(std::vector<Primitive> &prims) override;
  size_t         ListSize() const override { return prims_.size(); }
  PetscErrorCode Gather(const std::vector<int> *which, Vertices *x, Vertices *v) override;
  PetscErrorCode Scatter(const std::vector<int> &which, const Vertices *x, const Vertices *f) override;
  PetscErrorCode MoveRatio(PetscReal *ratio) override;
  PetscErrorCode Searched() override;
  PetscErrorCode Margins(PetscReal half, PetscInt evaluations, PetscReal *m) override;
  const char    *KindName() const override { return "mesh"; }
  bool           CanSelfContact() const override { return true; }
  // Fracturable bodies (doc/fracture.md): their fragments are one body, so pairs within it
  // are always computed, except between tetrahedra that share a node key (a node glued to
  // its copies by intact joints), unless the two are the sides of a broken joint.
  bool           AlwaysSelfContact(PetscInt body) const override { return fractured_ && fracturable_[body]; }
  bool           SelfPair(const Primitive &a, const Primitive &b) const override;
  // The number of broken joints changed: the cells are selected again (collective).
  PetscErrorCode Changed(PetscBool *changed) override;
  PetscErrorCode Pending(PetscBool *pending) override;
  bool           SurfacePending() const override { return surface_pending_; }
  bool           Relists() const override { return fractured_; }
  // After a Changed() that kept the cells (stable listings: the cells at joints are listed idle):
  // the records that changed, in place.
  bool           RefreshInPlace(Primitive *mine, size_t n, std::vector<int> &changed) override;
  // (The rule by shared node keys begins once a joint has softened or broken. A joint that
  // breaks frees a face of each of its two tetrahedra, a face of the split mesh's boundary, so
  // both records change: the pair of a broken joint is asked again without a new rule.)
  std::int64_t   PairRule() const override { return fractured_ && (nbroken_ > 0 || (damaged_cells_ && ndamaged_ > 0)) ? 1 : 0; }
  void           OnsetEnergy(PetscReal e) override;
  PetscErrorCode Frequency2(PetscReal penalty, PetscReal *w2) override;
  std::string    BodyName(const Primitive &p) const override;
  std::string    ElementName(const Primitive &p) const override;
  PetscErrorCode BufferProposal(PetscReal *sum, PetscInt *count) override;
  // Total contact force on each body at the last evaluation, this rank's cells (3 per body).
  const std::vector<PetscReal> &BodyForce() const { return body_force_; }
  PetscInt                      NumBodies() const { return nbodies_; }
  PetscInt                      NumCells() const { return (PetscInt)conn_.size(); }
  FDEMDeformable                Mesh() const { return d_; }
  // The granular material of each body (-1: none), for contacts with spheres.
  void                          SetGranularMaterials(std::vector<std::int32_t> m) {
    gmat_ = std::move(m);
    for (auto &p : prims_) p.mat = p.body < (PetscInt)gmat_.size() ? gmat_[p.body] : -1;
  }

private:
  // SelfPair without its groups and broken joints: the rule by the nodes (node keys) two tetrahedra share
  bool NeighbourPair(const Primitive &a, const Primitive &b) const;
  // Selects the cells taking part (conn_, prims_, faces_) from all_; t: the fracture
  // topology (null when the mesh has no joints).
  void Select(const fdem::model::FractureTopology *t);
  // Select's decision for local cell e: its surface, whether it takes part, or is listed idle
  void Take(PetscInt e, const fdem::model::FractureTopology *t, bool stable, char *surface, bool *taken, bool *idle) const;
  // Select where only joints softened since the listing (FractureTopology::changed): false
  // when that cannot be done in place (Select then looks at every cell)
  bool SelectChanged(const fdem::model::FractureTopology &t);
  // What the fracture topology decides in a listed cell's record (Select)
  struct CellState {
    PetscInt     node[4];
    std::int64_t group;
    std::int32_t surface, flags, idle;
    bool         operator==(const CellState &o) const {
      return node[0] == o.node[0] && node[1] == o.node[1] && node[2] == o.node[2] && node[3] == o.node[3] && group == o.group && surface == o.surface && flags == o.flags && idle == o.idle;
    }
    void Apply(Primitive &p) const {
      for (int k = 0; k < 4; ++k) p.node[k] = node[k];
      p.group   = group;
      p.surface = surface;
      p.flags   = flags;
      p.idle    = idle;
    }
  };
  CellState State(PetscInt e, char surf, bool idle, const fdem::model::FractureTopology *t) const;
  PetscErrorCode Shares(const fdem::model::FractureTopology &t); // share_ from t
  struct AllCells { // every local cell, kept when the mesh has joints (the selection changes)
    std::vector<PetscInt> conn, body, gid, ngid;
    std::vector<char>     surf, bnode;
  } all_;
  Cells                                which_     = Cells::BoundaryFace;
  bool                                 fractured_ = false; // the mesh has joints
  std::vector<char>                    fracturable_;       // per body
  PetscInt                             nbroken_ = 0;       // broken joints at the last selection
  PetscInt                             ndamaged_ = 0;      // damaged joints (a point beyond its peak) at the last selection
  int                                  pending_ = -1;      // Pending's answer, kept for the Changed that follows it at the same evaluation (-1: none)
  bool                                 surface_pending_ = false; // Pending's: joints broke (the surface changes)
  bool                                 damaged_cells_ = true; // -fdem_joint_damaged_contact: the cells of damaged joints take part
  std::vector<std::array<PetscInt, 2>> broken_;            // their cells' ids, smaller first, sorted
  bool                                 weights_ = false;   // Spheres::Weighted: share_ is kept
  bool                                 stable_ = false;    // the listing takes idle cells (Select): joints, and no spheres (whose engine searches at every listing)
  std::vector<float>                   share_;             // per local cell, 10: the weights of its vertices' and edges' copies (DeformableFeatureShares), as of nbroken_ (empty: all 1)
  FDEMDeformable                       d_ = nullptr;
  PetscInt                             nbodies_ = 0;
  std::vector<std::array<PetscInt, 4>> conn_;  // local node indices
  std::vector<Primitive>               prims_; // body, global element id, node global ids
  std::vector<char>                    faces_; // bit o: the face opposite node o is on the boundary
  std::vector<PetscInt>                cell_;  // with joints: the local cell of each listed one (all_'s index)
  std::vector<PetscReal>               diam_;  // with joints: each local cell's longest edge at the reference positions once asked for, else -1 (BufferProposal)
  std::vector<PetscScalar>             xref_;  // with joints: the local reference positions (BufferProposal)
  bool                                 diam_made_ = false; // xref_ and diam_ are made
  std::vector<std::tuple<PetscInt, char, bool>> taken_; // Select's scratch: the cells taken, their surfaces, idle
  std::vector<CellState>               state_;     // with joints: per listed cell, what the topology decided in its record
  bool                                 in_place_ = false; // the last Select kept the cells and changed the records refreshed_ in place
  std::vector<int>                     refreshed_;
  std::vector<PetscInt>                slot_;        // stable listings: per local cell, its index in the listing (-1: not listed)
  PetscInt                             version_ = 0; // the topology answer (FractureTopology::version) the listing is made from
  std::vector<PetscReal>               body_force_;
  std::vector<PetscInt>                ref_node_; // the local nodes of the listed cells, each once, in order
  std::vector<PetscReal>               ref_x_;    // their positions at the last search (3 a node)
  PetscReal                            half_ = 0; // the margin of every cell (Margins)
  const PetscScalar                   *xl_ = nullptr, *vl_ = nullptr;
  PetscScalar                         *fl_ = nullptr;
  bool                                 require_v_ = true;
  std::vector<std::int32_t>            gmat_; // per body: granular material
};
} // namespace fdem::contact
