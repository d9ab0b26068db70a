// Internal: the one contact engine of fdem (see doc/contact_engine.md).
//
// The engine knows contact primitives only: tetrahedra, each with four vertex
// positions and velocities and a static record saying which body kind lent it,
// which body and element it is. A body kind plugs in through an Adapter that
// lists its primitives, lends their current vertices at every evaluation and
// takes the nodal forces back (a rigid body sums them into force and torque, a
// mesh adds them to its nodes). Everything else exists here once: the cell
// search with its buffer and re-search rule, the ghost exchange of primitives
// between ranks, the pair loop (potential force, damping, friction), the deep
// initial overlap check, the time-step check, the statistics and the options.
#pragma once
#include <fdem/contact.h>
#include <fdem/kernels/contact.hpp>
#include <fdem/kernels/granular_sweep.hpp>
#include <petscsf.h>
#include <petscts.h>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fdem::contact {
using fdem::kernels::Tet4;
using fdem::kernels::Vec3;

// The shapes of primitives: a tetrahedron (four vertices) or a sphere (a centre and a radius).
enum : std::int32_t { kTetrahedron = 0, kSphere = 1 };

// The static record of a primitive; a ghost copy carries it to the ranks that need it.
struct Primitive {
  std::int32_t kind  = 0;  // the adapter's slot in the engine (set by the engine)
  std::int32_t fixed = 0;  // 1: a fixed body (pairs of two fixed primitives are skipped)
  PetscInt     body  = 0;  // the body within its kind (rigid body id, mesh body number)
  PetscInt     elem  = 0;  // the element within its kind (skin tetrahedron, global mesh element id)
  std::int64_t key   = 0;  // unique within the kind; a pair is computed by the owner of the smaller (kind, key)
  PetscInt     node[4] = {-1, -1, -1, -1}; // global node ids (self-contact skips neighbours); -1: none
  double       margin  = 0; // set at each search: how far it may move before the next (>= buffer/2)
  std::int32_t shape   = kTetrahedron;
  std::int32_t surface = 15; // tetrahedron: bit o set when its face opposite vertex o lies on the body's surface
  std::int32_t facet[4] = {-1, -1, -1, -1}; // a rigid skin's surface face opposite vertex o: its flat face (coplanar
                                             // surface faces joined by edges), numbered within the skin; -1: none.
                                             // A sphere's spring on a flat face is keyed by it (doc/spheres.md)
  std::int32_t push    = 15; // tetrahedron: bit o set when its face opposite vertex o must be pushed by another's
                             // potential (a rigid skin: its surface faces; the shared ones cancel, doc/contact.md)
  std::int32_t mat     = -1; // granular material (Engine::SetGranular) for contacts with spheres; -1: none
  std::int32_t flags   = 0;  // the adapter's own bits (the mesh adapter: 1 when the tetrahedron is at a damaged joint, 2 when
                             // it is a split cell of a fracturable body, its nodes its own;
                             // the rigid adapter: 1 for a sphere of a clump)
  double       radius  = 0;  // sphere: its radius
  double       mass    = 0;  // the body's mass, for the granular laws' effective mass; 0: immovable (fixed, a mesh)
  double       offset  = 0;  // a sphere of a clump: its centre's distance from the clump's centre of mass, and
  double       inertia = 0;  // the clump's least principal moment (the time-step check, GranularStableOmega)
  std::int32_t idle    = 0;  // 1: listed, but in no pair for now (its adapter lists it so that a listing that makes
                             // it take part keeps the search: the mesh adapter's cells at joints of a body whose
                             // joints are inserted during the run); searched and moved as any other
  std::int64_t group   = -1; // set by the adapter; the engine pairs no two primitives of one body with one group >= 0, without asking SelfPair (the mesh
                             // adapter: an unsplit tetrahedron of a body with fracture zones, its fragment's id)
  float        share[10] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1}; // tetrahedron: the weight of a sphere's contact with its
                             // vertex o ([o]) or its edge ([4 + m], fdem::kernels::kTetEdges order): in a split cell of a
                             // fracturable mesh (flags bit 2), 1 over the copies of the feature on the surface
                             // (doc/fracture.md, "Spheres on a fracturing body"); 1 elsewhere
};

// The dynamic ghost record, sent to the ghosts at every evaluation: vertex positions,
// then (when damping or friction is on) vertex velocities, one Tet4 each. A sphere uses
// the first entries only: position [0] its centre; velocity [0] its velocity and [1] its
// angular velocity (space frame); force [0] the force on its centre and [1] the torque.
using Vertices = Tet4;

// The tangential spring of one granular contact, kept by the sphere whose owner computes
// the contact (doc/spheres.md): key 0 is a free slot.
struct HistorySlot {
  std::int64_t key  = 0;
  double       s[3] = {0, 0, 0};
};
constexpr int kHistorySlots = 12; // per sphere (a clump's spheres share their body's)

// Contact parameters, one set for every pair of body kinds (options -fdem_contact_*).
struct Params {
  PetscReal                         penalty = -1; // < 0: not set
  PetscReal                         buffer  = -1; // < 0: automatic (Adapter::BufferProposal)
  PetscBool                         self    = PETSC_FALSE;
  fdem::kernels::ContactDissipation diss;
  bool Dissipative() const { return diss.normal_damping > 0 || diss.friction > 0 || diss.tangential_viscosity > 0; }
};

// Statistics (include/fdem/contact.h): every count and sum is over all ranks.
using Stats = FDEMContactStats;

// A body kind's side of the engine. All calls are local to the rank except
// those marked collective.
class Adapter {
public:
  virtual ~Adapter() = default;
  // This rank's primitives, appended to prims (kind is set by the engine). Called at the first
  // evaluation after Engine::Reset(). Collective.
  virtual PetscErrorCode List(std::vector<Primitive> &prims) = 0;
  // How many records the next List() appends, if known (0: not known): the engine makes room
  // for all adapters' records at once, not as each appends.
  virtual size_t ListSize() const { return 0; }
  // Current vertex positions x[i] and, when v is not null, velocities v[i] of the listed
  // primitives i in `which` (increasing; null: all). The engine asks for all positions at a
  // search and otherwise only for the primitives that take part in a pair or are ghosts.
  virtual PetscErrorCode Gather(const std::vector<int> *which, Vertices *x, Vertices *v) = 0;
  // Contact forces f[i] on the vertices x[i] (as gathered) of the primitives i in `which`
  // (increasing), summed over all pairs and ranks; the other primitives have no force.
  virtual PetscErrorCode Scatter(const std::vector<int> &which, const Vertices *x, const Vertices *f) = 0;
  // The largest ratio, over this rank's primitives, of a vertex's displacement since the last
  // Searched() (an upper bound will do) to the primitive's search margin (the last Margins());
  // the engine searches again when it exceeds 1 on some rank. Searched() takes the current
  // state as the reference.
  virtual PetscErrorCode MoveRatio(PetscReal *ratio) = 0;
  virtual PetscErrorCode Searched()                  = 0;
  // At each search, before Searched(): the margin m[i] >= half of every listed primitive, how far
  // it may move before the next search (its box is grown by it). `evaluations` since the last
  // search (0: the first). Half the buffer for all is always correct; a body seen moving fast
  // gets a larger one, so that it alone does not force a search at every evaluation.
  virtual PetscErrorCode Margins(PetscReal half, PetscInt evaluations, PetscReal *m) = 0;
  // The body kind, for messages ("rigid", "mesh").
  virtual const char *KindName() const = 0;
  // May two primitives of one body touch (self-contact, when switched on)?
  virtual bool CanSelfContact() const { return false; }
  // May two primitives of body `body` touch even with self-contact off? (the fragments of a
  // fracturable mesh body are one body)
  virtual bool AlwaysSelfContact(PetscInt body) const {
    (void)body;
    return false;
  }
  // Two primitives of one body that may self-contact: do they form a pair? Default: unless
  // they share a node (node ids >= 0 equal). Called at a search or a kept listing, on the rank
  // computing the pair, for two primitives not of one group (Primitive::group).
  virtual bool SelfPair(const Primitive &a, const Primitive &b) const {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (a.node[i] >= 0 && a.node[i] == b.node[j]) return false;
    return true;
  }
  // Have this adapter's primitives changed since its last List() (fracture: new contact
  // surfaces)? The engine then lists them again. Called at every evaluation; the answer must
  // be the same on every rank. Collective.
  virtual PetscErrorCode Changed(PetscBool *changed) {
    *changed = PETSC_FALSE;
    return 0;
  }
  // After Changed() reported a change: if the adapter lists the same primitives as before, in
  // the same order (n of them; only their records changed), writes the records that changed
  // into its part of the engine's listing, mine (kind and margin are the engine's: kept), and
  // says true; false: the engine lists every adapter again.
  // changed: the numbers (in mine) of the records written, increasing.
  virtual bool RefreshInPlace(Primitive *mine, size_t n, std::vector<int> &changed) {
    (void)mine, (void)n, (void)changed;
    return false;
  }
  // A number that changes whenever SelfPair may answer otherwise for two records that did not
  // change (a mesh's rule by shared nodes began): the engine then asks again for every pair its
  // search kept (PairsFromKept).
  virtual std::int64_t PairRule() const { return 0; }
  // May Changed() report a change during a run (a mesh with fracture joints)? The engine then
  // keeps what a listing with the same primitives needs to keep its search (KeepSearch).
  virtual bool Relists() const { return false; }
  // Will the next Changed() report a change? (no state changes; collective, the same answer
  // on every rank). The engine then first takes the contact energy of the current listing at
  // the current state, to book the energy the new listing adds (OnsetEnergy).
  virtual PetscErrorCode Pending(PetscBool *pending) {
    *pending = PETSC_FALSE;
    return 0;
  }
  // After Pending() said yes: will the change move the surfaces that spheres touch (faces
  // exposed, the weights of the copies of vertices and edges)? Then the engine also takes the
  // spheres' contact energy with the listing before (the same answer on every rank).
  virtual bool SurfacePending() const { return false; }
  // After a listing that this adapter's change caused: the tetrahedron pairs' contact energy
  // at that state rose by e (J, summed over ranks, the same on every rank) from the listing
  // before to the new one (pairs met already overlapped: the faces of broken joints).
  virtual void OnsetEnergy(PetscReal e) { (void)e; }
  // The largest contact frequency squared, omega^2, of this rank's bodies for the given
  // penalty (0: none). Collective.
  virtual PetscErrorCode Frequency2(PetscReal penalty, PetscReal *w2) = 0;
  // "rigid body 3" / "deformable body 'ball'" and "skin tetrahedron 5" / "element 17", for messages.
  virtual std::string BodyName(const Primitive &p) const = 0;
  virtual std::string ElementName(const Primitive &p) const = 0;
  // For the automatic buffer: the sum of this rank's proposals of a search buffer and their
  // number (the engine takes the mean over all kinds and ranks). Collective.
  virtual PetscErrorCode BufferProposal(PetscReal *sum, PetscInt *count) = 0;
  // At each search: n[i], the candidate pairs this rank computes that own primitive i takes
  // part in (a measure of the contact work of its body, for a partition). Default: ignored.
  virtual PetscErrorCode PairCounts(const PetscInt *n) {
    (void)n;
    return 0;
  }
  // Spheres: the kHistorySlots tangential springs of own sphere primitive i, readable and
  // writable between HistoryBegin() and HistoryEnd() (null: none kept).
  virtual PetscErrorCode HistoryBegin() { return 0; }
  virtual HistorySlot   *History(int i) {
    (void)i;
    return nullptr;
  }
  virtual PetscErrorCode HistoryEnd() { return 0; }
  // Spheres, without the vertex records: s[to[m]] = the state of own sphere primitive
  // which[m] (centre, velocity, angular velocity, radius), and its force and torque f[from[m]]
  // added to that sphere, for m < n. Only a kind that lists spheres is asked.
  virtual PetscErrorCode SphereStates(int n, const int *which, const int *to, fdem::kernels::SphereState *s) {
    (void)n, (void)which, (void)to, (void)s;
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "this body kind has no spheres");
  }
  virtual PetscErrorCode AddSphereForces(int n, const int *which, const int *from, const fdem::kernels::SphereSum *f) {
    (void)n, (void)which, (void)from, (void)f;
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SUP, "this body kind has no spheres");
  }
};

// The log events FDEMContactList, FDEMContactDetect (search, ghosts and cell search),
// FDEMContactHalo (ghost updates) and FDEMContactForce (pair loop, forces back).
PetscErrorCode RegisterEvents();

class Engine {
public:
  // `who` starts every message ("Contact", "Deformable contact", ...).
  Engine(MPI_Comm comm, const char *who);
  ~Engine();
  Engine(const Engine &)            = delete;
  Engine &operator=(const Engine &) = delete;

  // Adapters are not owned; their slot numbers are their kinds. Pairs of kinds (a, b)
  // are computed only when allowed (default: none).
  int  AddAdapter(Adapter *a);
  void AllowPair(int ka, int kb) { allow_[ka][kb] = allow_[kb][ka] = true; }
  // Start over (collective, at the same point on every rank): at the next evaluation the
  // primitives are listed again (after migration, or when primitives appeared, e.g. by
  // fracture), searched again and the initial overlap is checked again.
  // The sphere-sphere springs kept with the pairs are dropped (the adapters' memory may have moved):
  // call FlushSprings() first (the rigid contact does at the end of each TS segment).
  void Reset() {
    listed_ = searched_ = false;
    sp_.clear();
  }
  // Writes the springs of the sphere-sphere pairs into their slots (the slots are what migrates and
  // is checkpointed; between two flushes the engine reads and writes the copy kept with each pair).
  PetscErrorCode FlushSprings();
  // The same between the adapters' HistoryBegin() and HistoryEnd().
  void           WriteSprings();
  // The next evaluation checks the initial overlap again (a new run from a new state).
  void RecheckInitialOverlap() {
    checked_initial_ = false;
    checked_ts_      = nullptr;
  }
  void ReplaceAdapter(int k, Adapter *a) {
    adapters_[k] = a;
    listed_      = false;
  }
  // The TS whose first evaluation checks the time step (not referenced; null: no automatic check).
  void SetTS(TS ts) { ts_ = ts; }
  // Periodic boundaries: period[k] > 0 makes axis k periodic with that period (0: not). A
  // primitive near one side then meets the others' images across it: images are ghosts, on this
  // rank or another, with the period added to their vertices (doc/contact_engine.md). The
  // adapters keep their bodies' positions within one period (the rigid model wraps them).
  // lo: the cell's lower corner; the adapters keep every primitive within a quarter period of
  // the cell (checked at each search).
  void SetPeriodic(const double lo[3], const double period[3]) {
    for (int k = 0; k < 3; ++k) period_[k] = period[k] > 0 ? period[k] : 0, plo_[k] = lo[k];
    periodic_ = period_[0] > 0 || period_[1] > 0 || period_[2] > 0;
    searched_ = false;
  }
  // One evaluation: gather, re-search when needed, pair loop, forces back. Collective.
  PetscErrorCode Evaluate();
  // One evaluation over zero time, the clock left as it was: no tangential spring advances by
  // a slip, and the run's next evaluation sees the same time step as without it. For the energy
  // of a state (the first balance row of a run whose bodies touch at the start). Collective.
  PetscErrorCode EvaluateStill();
  // The time of the next evaluation: a granular contact's tangential spring advances by
  // the slip rate times the time since the last evaluation.
  void SetTime(PetscReal t) { time_ = t; }
  // The granular laws of contacts with spheres: table[a * nmat + b] for the materials a, b
  // of the two primitives (Primitive::mat). Tag (0-3) tells this engine's springs from
  // another engine's in a sphere's slots.
  void SetGranular(std::vector<fdem::kernels::GranularPair> table, int nmat, int tag) {
    gtable_ = std::move(table);
    gnmat_  = nmat;
    gtag_   = tag;
  }
  // omega_c dt / K_crit for the fdem TS type `scheme` (warning above 0.5). Collective.
  PetscErrorCode CheckTimeStep(const char *scheme, PetscReal dt, PetscReal *ratio);

  // Parameters; the setters check the values. SetFromOptions reads -fdem_contact_*.
  // (option: the option that gave the value, named in an error; options likewise, one per value)
  PetscErrorCode SetPenalty(PetscReal penalty, const char *option = nullptr);
  PetscErrorCode SetDissipation(PetscReal damping, PetscReal friction, PetscReal tangential_viscosity, const char *const *options = nullptr);
  PetscErrorCode SetBuffer(PetscReal buffer, const char *option = nullptr); // >= 0
  void           SetAutomaticBuffer();        // the default (Adapter::BufferProposal)
  PetscErrorCode SetSelfContact(PetscBool self);
  // Push only the faces in Primitive::push (a rigid skin's surface faces) or every face of every
  // tetrahedron (default). The bodies' forces, torques and the energy are the same to round-off;
  // a pair's damping and friction are not: they then see only the surface faces (doc/performance.md).
  void           SetSurfaceOnly(bool on) { surface_only_ = on; }
  PetscErrorCode SetFromOptions();
  PetscErrorCode CheckPenaltySet() const;
  const Params  &GetParams() const { return par_; }
  const Stats   &GetStats() const { return stats_; }
  MPI_Comm       Comm() const { return comm_; }

private:
  PetscErrorCode ListAll();
  // Is a search due (some primitive moved beyond its margin since the last, or none yet)? Collective.
  PetscErrorCode SearchDue(bool *due);
  // Evaluate's loop over the tetrahedron pairs: forces, sums[0] += energy, sums[1] += touching
  // pairs; deep: the initial-overlap check's worst pair. With onset: the energy of the touching
  // pairs that are not in old_pairs_ (fresh_ where the listing kept the search) is added to it.
  PetscErrorCode PairLoop(PetscReal sums[2], std::array<double, 3> &deep, PetscReal *onset);
  // A pair's identity across listings: its primitives' (key, kind), smaller first.
  std::array<std::int64_t, 2> PairId(int i, int j) const {
    const std::int64_t u = P(i).key * 4 + P(i).kind, v = P(j).key * 4 + P(j).kind;
    return {std::min(u, v), std::max(u, v)};
  }
  PetscErrorCode CheckInitialOverlap(const std::array<double, 3> &deep);
  PetscErrorCode Search();
  PetscErrorCode SendRecords();
  PetscErrorCode PairsListed();
  bool           Keepable() const;
  // Two primitives of one body that may self-contact: a pair unless they are of one group
  // (Primitive::group, the engine's rule) or their adapter's SelfPair refuses them.
  bool Paired(const Primitive &a, const Primitive &b) const {
    return !(a.group >= 0 && a.group == b.group) && adapters_[a.kind]->SelfPair(a, b);
  }
  PetscErrorCode KeepSearch(const std::vector<Primitive> &before, bool *kept);
  PetscErrorCode PairsFromKept(const std::vector<int> *changed = nullptr);
  bool           KeptPaired(const std::array<int, 3> &c) const;
  PetscErrorCode RefreshListing();
  PetscErrorCode Tally();
  PetscErrorCode UpdateGhosts(bool x, bool v);
  PetscErrorCode UpdateSphereGhosts();
  // The pairs with a sphere (granular laws): sphere-sphere and sphere-surface.
  // sums: energy, touching pairs, contacts without a free spring slot (added to)
  PetscErrorCode GranularForces(PetscReal sums[3], std::array<double, 3> &deep);
  // One contact of a sphere with a surface (granular_contact.cpp): the sphere, the
  // tetrahedron and its three vertices of the touched triangle, the contact point's weights
  // on them, the contact, its law, its spring's key and its weight (Primitive::share).
  struct SurfaceHit {
    int                                 sphere, tet;
    std::array<int, 3>                  vertex;
    std::array<double, 3>               w;
    fdem::kernels::GranularContact      c;
    const fdem::kernels::GranularPair  *law;
    std::int64_t                        key;
    double                              share;
  };
  void   SurfaceHits(const std::function<void(const SurfaceHit &)> &fn);
  double SurfaceEnergy();
  double surface_before_ = 0; // SurfaceEnergy at a new listing's state, with the listing before it (the handover)
  const fdem::kernels::GranularPair *Law(const Primitive &a, const Primitive &b) const;
  Vertices      &Force(int i) { return i < nl_ ? f_[i] : gf_[i - nl_]; }
  const Tet4    &X(int i) const { return i < nl_ ? x_[i] : gx_[i - nl_]; }
  const Tet4    &V(int i) const { return i < nl_ ? v_[i] : gv_[i - nl_]; }
  const Primitive &P(int i) const { return i < nl_ ? prim_[i] : gprim_[i - nl_]; }

  MPI_Comm                      comm_;
  PetscMPIInt                   rank_ = 0, size_ = 1;
  std::string                   who_;
  std::vector<Adapter *>        adapters_;
  std::vector<int>              first_;  // adapter k's primitives are own [first_[k], first_[k+1])
  bool                          allow_[4][4] = {};
  Params                        par_;
  TS                            ts_ = nullptr, checked_ts_ = nullptr;
  // own primitives [0, nl_) then ghosts [nl_, nl_ + ng_)
  int                           nl_ = 0, ng_ = 0;
  std::vector<Primitive>        prim_, gprim_;
  std::vector<char>             changed_;     // per adapter: changed at this evaluation (Evaluate)
  static constexpr std::int64_t kIdle = -2;   // held_: an idle primitive
  std::vector<std::int64_t>     held_;        // PairsFromKept's: per own and ghost primitive, kIdle or its group
  std::vector<Primitive>        prim_before_; // the listing before a listing that may keep the search (Evaluate, KeepSearch)
  std::vector<std::array<int, 2>> pairs_next_; // KeepSearch's pairs and axes, swapped with pairs_ and sep_
  std::vector<std::int8_t>        sep_next_;
  std::vector<Vertices>         x_, v_, gx_, gv_, f_, gf_;
  std::vector<std::vector<int>> touch_; // per adapter: its primitives with vertex records at an evaluation (increasing): in a pair here or ghosts elsewhere, but for own spheres met only by spheres (read and given their forces directly)
  PetscSF                       sf_ = nullptr; // one item per primitive: its Vertices record (vunit_) or its Primitive
  MPI_Datatype                  vunit_ = MPI_DATATYPE_NULL; // a Vertices record as one MPI unit
  MPI_Datatype                  sunit_ = MPI_DATATYPE_NULL, funit_ = MPI_DATATYPE_NULL; // a SphereNow, a SphereSum
  // Every primitive on every rank a sphere: no vertex records at an evaluation. The own spheres
  // that are ghosts somewhere (exp_: adapter's numbers, primitive numbers) send their states
  // (rs_, per own primitive) to their ghosts (gs_), which send their forces (gfs_) back (fs_).
  bool                          sphere_only_ = false;
  std::vector<std::vector<int>> exp_sph_, exp_i_;
  std::vector<fdem::kernels::SphereState> rs_, gs_;
  std::vector<fdem::kernels::SphereSum>   fs_, gfs_;
  std::vector<fdem::kernels::TetFrame> frames_; // per own and ghost primitive, at this evaluation
  std::vector<char>             made_;           // frames_[i] made at this evaluation
  std::vector<std::array<double, 6>> cboxes_;    // per own and ghost primitive: its current box, at this evaluation
  std::vector<char>             cmade_;          // cboxes_[i] made at this evaluation
  std::vector<std::uint16_t>    seen_;           // per own sphere: the spring slots a contact used at this evaluation
  std::vector<HistorySlot *>    hslots_;         // per own sphere: its spring slots, looked up once per evaluation
  std::vector<std::array<int, 2>> pairs_;      // (a, b), a before b, computed here (at least one own)
  std::vector<std::array<std::int64_t, 2>> old_pairs_; // at a listing caused by fracture: the listing before's pairs (PairId, sorted where a search follows)
  std::vector<char>               fresh_;      // at a listing caused by fracture that kept the search: per pair, not a pair before it
  bool                            fresh_valid_ = false; // fresh_ is this evaluation's (else old_pairs_ is sorted and searched)
  std::vector<std::int8_t>        sep_;        // per pair: the axis that last found it apart (SeparatingAxis; 0: none)
  // PairsFromKept's decision per entry of kept_ (paired or not) and, per pair, its entry in
  // kept_, as of the adapters' PairRule in kept_rule_ (kept_made_: made since the last search);
  // per own and ghost primitive, its entries in kept_ (kept_off_, kept_at_: made at the first
  // relisting of a search that changes only some records)
  std::vector<char>               kept_on_;
  std::vector<int>                pair_kept_, pair_kept_next_, kept_off_, kept_at_, refreshed_, flips_;
  std::vector<std::int64_t>       kept_rule_;
  std::vector<Primitive>          gprim_before_;
  bool                            kept_made_ = false;
  std::vector<std::array<int, 3>> kept_;       // where a search may be kept (KeepSearch): the candidate tetrahedron pairs (a, b, c) in the order of pairs_, c = 0 between two bodies, 1 within a body, 2 within a body and not paired by its adapter at the search (a pair with an idle primitive is kept too, and paired once neither is idle)
  std::vector<std::array<int, 2>> ss_, st_;    // sphere-sphere (holder first), sphere-tetrahedron (sphere first, grouped by body)
  // The sphere-sphere pairs ready for the pair loop, made from ss_ after each search: the two
  // spheres as numbers in the compact arrays below (a the holder), the slot of the pair's spring
  // in a's slots (-1: none yet) and the pair's law (an index into gtable_; -1: none); and what
  // stays fixed while the pair lasts.
  using SpherePair      = fdem::kernels::SpherePair;
  using SpherePairConst = fdem::kernels::SpherePairConst;
  std::vector<SpherePair>       sp_;
  std::vector<SpherePairConst>  spc_;
  std::vector<Vec3>             sps_;          // per pair: its spring while it has a slot (the slot's value since the last flush)
  std::vector<int>              sph_;          // per compact sphere: its primitive
  std::vector<std::vector<int>> own_sph_, own_c_; // per adapter: its own spheres of sp_ (adapter's numbers) and their compact numbers
  std::vector<int>              ghost_c_;       // the compact numbers of the ghost spheres
  std::vector<double>           sr_;           // per compact sphere: its radius
  std::vector<int>              sfirst_;       // per holder (numbered first): the first sphere of its clump (its slots' use is marked there)
  bool                          sp_fresh_ = false; // ss_ changed: make sp_ again
  struct SurfaceGroup {
    int sphere, begin, end; // a sphere of st_ and its near faces sface_[begin, end) of one body
  };
  std::vector<SurfaceGroup>       sgroup_; // made with sp_: the groups of st_ with a face the sphere may reach before the next search
  std::vector<std::array<int, 2>> sface_;  // per group, its faces {tetrahedron, face opposite vertex o}, in st_'s order
  using SphereNow = fdem::kernels::SphereState; // a compact sphere at an evaluation
  using SphereSum = fdem::kernels::SphereSum;   // the forces on a compact sphere at an evaluation
  std::vector<SphereNow>        snow_;
  std::vector<SphereSum>        ssum_;
  fdem::kernels::SphereSweep    sweep_;        // at an evaluation: what the sweep over sp_ found
  std::vector<fdem::kernels::GranularPair> gtable_;
  int                           gnmat_ = 0, gtag_ = 0;
  PetscReal                     time_ = 0, last_time_ = 0;
  bool                          has_time_ = false;
  PetscInt                      hist_overflow_ = 0; // contacts without a free history slot (warned once)
  bool                          spheres_ = false;   // some rank lists a sphere
  bool                          periodic_ = false;
  double                        period_[3] = {0, 0, 0}, plo_[3] = {0, 0, 0};
  std::vector<std::array<double, 3>> gshift_;       // per ghost: what is added to its vertices (periodic images; 0 otherwise)
  bool                          shifted_ = false;   // some ghost here is an image
  std::vector<int>              holders_;           // own spheres of st_ (their slots are swept at every evaluation)
  bool                          holders_valid_ = false; // false after a listing or a search: every own sphere is swept
  bool                          listed_ = false, searched_ = false, checked_initial_ = false, with_v_ = false;
  bool                          surface_only_ = false;
  bool                          keep_search_  = true;  // false (-fdem_contact_keep_search 0): fracture's listings list and search again
  bool                          initial_check_ = true; // false: a deep initial overlap is a warning (a restart's state)
  PetscInt                      since_search_ = 0; // evaluations since the last search
  Stats                         stats_{};
};
} // namespace fdem::contact
