// Internal: rigid bodies as a body kind of the contact engine. Each local body lends
// the tetrahedra of its contact skin, placed in the world (x + R p) with the vertex
// velocities v + omega x (p - x); the nodal forces come back summed into the body's
// force and torque about its centre of mass.
#pragma once
#include "engine.hpp"
#include "../model/rigid_impl.hpp"

namespace fdem::contact {
class RigidAdapter : public Adapter {
public:
  explicit RigidAdapter(FDEMRigid rb) : rb_(rb) {}
  FDEMRigid Model() const { return rb_; }
  // A skin's surface faces: per tetrahedron, bit o set when its face opposite vertex o is on the
  // surface (Primitive::surface), and the flat face it belongs to (Primitive::facet; -1 inside).
  struct SkinFaces {
    std::vector<std::int32_t>                surface;
    std::vector<std::array<std::int32_t, 4>> facet;
  };
  // Before each evaluation: positions q = [x | R] and state u = [x | R | v | H] (velocities;
  // may be null without damping and friction) of the rb->n local bodies (RigidLayout); the
  // forces and torques are added to FM = [F | M].
  void Bind(const PetscScalar *q, const PetscScalar *u, PetscScalar *FM) {
    q_  = q;
    u_  = u;
    fm_ = FM;
  }
  PetscErrorCode List(std::vector<Primitive> &prims) override;
  PetscErrorCode Gather(const std::vector<int> *which, Vertices *x, Vertices *v) override;
  PetscErrorCode Scatter(const std::vector<int> &which, const Vertices *x, const Vertices *f) override;
  PetscErrorCode MoveRatio(PetscReal *ratio) override;
  PetscErrorCode Searched() override;
  PetscErrorCode Margins(PetscReal half, PetscInt evaluations, PetscReal *m) override;
  const char    *KindName() const override { return "rigid"; }
  PetscErrorCode Frequency2(PetscReal penalty, PetscReal *w2) override;
  std::string    BodyName(const Primitive &p) const override;
  std::string    ElementName(const Primitive &p) const override;
  PetscErrorCode BufferProposal(PetscReal *sum, PetscInt *count) override;
  PetscInt       NumBodies() const { return rb_->n; }
  PetscErrorCode HistoryBegin() override;
  HistorySlot   *History(int i) override { return hist_ ? reinterpret_cast<HistorySlot *>(hist_ + fdem::model::kHistoryBytes * (size_t)body_[prim_body_[i]]) : nullptr; }
  PetscErrorCode HistoryEnd() override;
  PetscErrorCode SphereStates(int n, const int *which, const int *to, fdem::kernels::SphereState *s) override;
  PetscErrorCode AddSphereForces(int n, const int *which, const int *from, const fdem::kernels::SphereSum *f) override;
  // Keep each body's pair count in the weight of the rigid model's partition: the rigid bodies'
  // own contact in the swarm field "work" (kept in checkpoints), a combined scene's rigid-mesh
  // contact (mesh = true) in the model's mesh_work (until the next migration); both count.
  void           RecordWork(bool on, bool mesh = false) { record_work_ = on, mesh_work_ = mesh; }
  PetscErrorCode PairCounts(const PetscInt *n) override;

private:
  FDEMRigid             rb_;
  bool                  record_work_ = false, mesh_work_ = false;
  const PetscScalar    *q_ = nullptr, *u_ = nullptr;
  PetscScalar          *fm_ = nullptr;
  std::vector<PetscInt>  body_, skin_;  // per listed body (with a skin): local index, skin
  std::vector<PetscReal> radius_;       // per listed body: a sphere's radius, a clump's farthest sphere centre, else the bounding radius (the lever of Move)
  std::vector<PetscReal> refx_, refR_;  // per listed body: x (3) and R (9) at the last search
  std::vector<PetscReal> inv_inertia_;  // per listed body: a sphere's 1 / I (0 for other bodies)
  std::vector<PetscReal> margin_;       // per listed body: its search margin (Margins)
  PetscReal              Move(size_t j) const;
  std::vector<int>       prim_body_;    // per primitive: its listed body
  std::vector<int>       prim_tet_;     // per primitive: its skin tetrahedron (-1 for a sphere; a clump's: ball_)
  std::vector<std::array<PetscReal, 4>> ball_; // per primitive: a clump's sphere (centre in the body frame, radius), read
                                               // at every evaluation without going through the body's skin
  std::vector<Vec3>      world_;        // scratch: a body's skin nodes in the world
  std::vector<char>      sphere_;       // per listed body: a sphere
  std::vector<char>      clump_;        // per listed body: a clump (its primitives are spheres, ball_ theirs)
  std::vector<SkinFaces> surface_; // per skin: each tetrahedron's surface faces and their flat faces
  char                  *hist_ = nullptr; // the swarm's "history" field between HistoryBegin and HistoryEnd
};

// The granular pair table of rb's materials (every pair mixed; a pair that cannot be mixed is
// left empty, and an error names it if its bodies meet) set on engine with tag (made once, kept
// in rb). Collective.
PetscErrorCode SetGranularTable(FDEMRigid rb, Engine &engine, int tag);
} // namespace fdem::contact
