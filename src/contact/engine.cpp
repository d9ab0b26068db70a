// The contact engine: search, ghosts, pair loop, checks and statistics for every
// pair of body kinds (see engine.hpp and doc/contact_engine.md).
#include "engine.hpp"
#include "../util/guard.hpp"
#include "../util/halo.hpp"
#include "params.hpp"
#include <fdem/ts.h>
#include <fdem/kernels/nbs.hpp>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <functional>

namespace fdem::contact {
namespace {
PetscClassId  CLASSID = 0;
PetscLogEvent EV_LIST = 0, EV_GHOST = 0, EV_SEARCH = 0, EV_FORCE = 0;

// A rank's region: NGROUP groups of NBOX boxes each, from a k-d split of the bounding boxes of
// its primitives (group 0: those of moving bodies up to twice the median size; group 1: the
// larger ones, which would otherwise swell the small boxes; group 2: those of fixed bodies, such
// as a wall's); BW numbers per box: lo(3), -hi(3) (empty: +inf), the body and the kind of all its
// primitives (-1: several), the bit mask of the kinds in it and whether it holds a primitive of a
// body that moves.
constexpr int NBOX_DEPTH = 3, NBOX = 1 << NBOX_DEPTH, NGROUP = 3, BW = 10;

// Axis-aligned bounding box lo(3), hi(3) of a tetrahedron, grown by its margin: until the next
// search (no vertex moved more than its margin) the tetrahedron stays inside it.
void Box(const Tet4 &T, double half_buffer, double b[6]) {
  for (int k = 0; k < 3; ++k) {
    double lo = T[0][k], hi = T[0][k];
    for (int v = 1; v < 4; ++v) {
      lo = std::min(lo, T[v][k]);
      hi = std::max(hi, T[v][k]);
    }
    b[k]     = lo - half_buffer;
    b[3 + k] = hi + half_buffer;
  }
}

// The box of a primitive grown by its margin: a tetrahedron's vertices, a sphere's ball.
void PrimBox(const Primitive &p, const Tet4 &T, double margin, double b[6]) {
  if (p.shape == kSphere)
    for (int k = 0; k < 3; ++k) {
      b[k]     = T[0][k] - p.radius - margin;
      b[3 + k] = T[0][k] + p.radius + margin;
    }
  else Box(T, margin, b);
}

// The four face planes of a tetrahedron, outward unit normal n and offset d (n.x = d on the
// face): pl[4 k .. 4 k + 3] = (n, d) of the face opposite vertex k. A zero-area face gives NaN,
// which no test below passes.
void FacePlanes(const Tet4 &T, double pl[16]) {
  for (int k = 0; k < 4; ++k) {
    const Vec3 &p = T[(k + 1) % 4], &q = T[(k + 2) % 4], &r = T[(k + 3) % 4];
    Vec3        n = cross(q - p, r - p);
    n             = (1.0 / norm(n)) * n;
    if (dot(n, T[k] - p) > 0) n = -1.0 * n;
    for (int d = 0; d < 3; ++d) pl[4 * k + d] = n[d];
    pl[4 * k + 3] = dot(n, p);
  }
}

// Is every vertex of b farther than gap beyond one face plane of a? Then a and b stay apart as
// long as a's vertices move less than m_a and b's less than m_b with m_a + m_b <= gap: a stays
// within m_a of the plane's inner side, b beyond gap - m_b.
bool BeyondAFace(const double pa[16], const Tet4 &b, double gap) {
  for (int k = 0; k < 4; ++k) {
    const double *n = pa + 4 * k;
    bool          all = true;
    for (int v = 0; v < 4 && all; ++v) all = n[0] * b[v][0] + n[1] * b[v][1] + n[2] * b[v][2] - n[3] > gap;
    if (all) return true;
  }
  return false;
}

// The current box of a tetrahedron: lo(3), hi(3).
void CurrentBox(const Tet4 &a, std::array<double, 6> &b) {
  for (int k = 0; k < 3; ++k) {
    b[k]     = std::min(std::min(a[0][k], a[1][k]), std::min(a[2][k], a[3][k]));
    b[3 + k] = std::max(std::max(a[0][k], a[1][k]), std::max(a[2][k], a[3][k]));
  }
}

// Do the current boxes of two tetrahedra meet? (If not, they do not overlap: no contact force.)
bool BoxesMeet(const std::array<double, 6> &a, const std::array<double, 6> &b) {
  return !(a[0] > b[3] || b[0] > a[3] || a[1] > b[4] || b[1] > a[4] || a[2] > b[5] || b[2] > a[5]);
}

bool Before(const Primitive &a, const Primitive &b) { return a.kind != b.kind ? a.kind < b.kind : a.key < b.key; }

// A pair with a sphere is computed by the owner of its holder, the sphere that keeps the
// contact's tangential spring: of two spheres the moving one, else the first (a before b);
// a sphere and a tetrahedron: the sphere. (Returns true for a.)
bool HolderIsFirst(const Primitive &a, const Primitive &b) {
  if (a.shape == kSphere && b.shape == kSphere) return a.fixed == b.fixed ? true : !a.fixed;
  return a.shape == kSphere;
}

// Which of two primitives' owners computes their pair (a before b): with one fixed, the owner of
// the other (a wall needs no pebble as a ghost); otherwise one chosen by a hash of the two keys,
// so that the pairs shared by two ranks are split evenly between them (the smaller key would give
// every pair of the first bodies to one rank). Both ranks holding the pair decide alike.
bool FirstComputes(const Primitive &a, const Primitive &b) {
  if (a.shape == kSphere || b.shape == kSphere) return HolderIsFirst(a, b);
  if (a.fixed != b.fixed) return !a.fixed;
  std::uint64_t h = (std::uint64_t)a.key * 0x9E3779B97F4A7C15ull + (std::uint64_t)a.kind;
  h ^= ((std::uint64_t)b.key + ((std::uint64_t)b.kind << 48)) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 29;
  return (h >> 7 & 1u) == 0;
}

double Volume6(const Tet4 &a) { return std::fabs(dot(a[1] - a[0], cross(a[2] - a[0], a[3] - a[0]))); }
} // namespace

Engine::Engine(MPI_Comm comm, const char *who) : comm_(comm), who_(who) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
  first_.push_back(0);
}

Engine::~Engine() {
  PetscSFDestroy(&sf_);
  for (MPI_Datatype *t : {&vunit_, &sunit_, &funit_})
    if (*t != MPI_DATATYPE_NULL) MPI_Type_free(t);
}

int Engine::AddAdapter(Adapter *a) {
  adapters_.push_back(a);
  first_.push_back(0);
  listed_ = false;
  return (int)adapters_.size() - 1;
}

// ------------------------------------------------------------------ parameters
PetscErrorCode Engine::SetPenalty(PetscReal penalty, const char *option) {
  PetscFunctionBegin;
  PetscCall(CheckPenalty(comm_, who_.c_str(), penalty, option));
  par_.penalty = penalty;
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::SetDissipation(PetscReal damping, PetscReal friction, PetscReal tangential_viscosity, const char *const *options) {
  PetscFunctionBegin;
  PetscCall(fdem::contact::SetDissipation(comm_, who_.c_str(), damping, friction, tangential_viscosity, par_.diss, options));
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::SetBuffer(PetscReal buffer, const char *option) {
  PetscFunctionBegin;
  PetscCall(CheckBuffer(comm_, who_.c_str(), buffer, option));
  par_.buffer   = buffer;
  stats_.buffer = buffer;
  searched_     = false;
  PetscFunctionReturn(0);
}

void Engine::SetAutomaticBuffer() {
  par_.buffer = -1;
  listed_     = false; // the automatic buffer is computed when listing
}

PetscErrorCode Engine::SetSelfContact(PetscBool self) {
  PetscFunctionBegin;
  par_.self = self;
  searched_ = false;
  PetscFunctionReturn(0);
}

// At every evaluation between tetrahedra: the penalty is set, and a friction coefficient has
// the tangential viscosity it needs (checked here, not when set, so that the two may be set
// in either order).
PetscErrorCode Engine::CheckPenaltySet() const {
  PetscFunctionBegin;
  PetscCheck(par_.penalty > 0, comm_, PETSC_ERR_ARG_WRONGSTATE, "%s: the penalty is not set; give -fdem_contact_penalty <Pa> (a positive modulus)", who_.c_str());
  PetscCheck(!(par_.diss.friction > 0) || par_.diss.tangential_viscosity > 0, comm_, PETSC_ERR_ARG_WRONGSTATE,
             "%s: a friction coefficient (%g: contact.friction, -fdem_contact_friction) needs a tangential viscosity > 0 (contact.tangential_viscosity, -fdem_contact_tangential_viscosity): the friction is regularised, F_t = -min(mu |F_n|, c_t A |v_t|) along v_t (doc/contact.md), so with c_t = 0 there is none",
             who_.c_str(), (double)par_.diss.friction);
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::SetFromOptions() {
  PetscReal pen = par_.penalty, damp = par_.diss.normal_damping, mu = par_.diss.friction, ct = par_.diss.tangential_viscosity, buf = par_.buffer;
  PetscBool fp, fd, fm, fc, fb, self = par_.self, so = surface_only_ ? PETSC_TRUE : PETSC_FALSE, ks = keep_search_ ? PETSC_TRUE : PETSC_FALSE, ic = initial_check_ ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionBegin;
  PetscOptionsBegin(comm_, nullptr, "fdem contact (every pair of body kinds)", "FDEMContact");
  PetscCall(PetscOptionsReal("-fdem_contact_penalty", "Penalty (Pa): a face pushed a depth d into a tetrahedron of height H feels ~ penalty d/H", "FDEMContactSetPenalty", pen, &pen, &fp));
  PetscCall(PetscOptionsReal("-fdem_contact_damping", "Normal contact damping (Pa s/m)", "FDEMContactSetDissipation", damp, &damp, &fd));
  PetscCall(PetscOptionsReal("-fdem_contact_friction", "Coulomb friction coefficient", "FDEMContactSetDissipation", mu, &mu, &fm));
  PetscCall(PetscOptionsReal("-fdem_contact_tangential_viscosity", "Tangential viscosity regularising stick (Pa s/m)", "FDEMContactSetDissipation", ct, &ct, &fc));
  PetscCall(PetscOptionsReal("-fdem_contact_buffer", "Search buffer (length; < 0: automatic, see doc/contact_engine.md; 0: a search at every evaluation); re-search after a vertex moved half of it", "FDEMContactSetBuffer", buf, &buf, &fb));
  PetscCall(PetscOptionsBool("-fdem_contact_self", "Self-contact between surface tetrahedra of one deformable body that share no node", "FDEMDeformableContactSetSelfContact", self, &self, nullptr));
  PetscCall(PetscOptionsBool("-fdem_contact_surface_only", "Push only the surface faces of a rigid body's skin tetrahedra (the shared faces' forces cancel; a pair's damping and friction then see the surface faces only)", "", so, &so, nullptr));
  PetscCall(PetscOptionsBool("-fdem_contact_keep_search", "Where fracture lists the contact again with the same contact tetrahedra, keep the last search and write the changed records in place; false: list and search again (a check: the same answers to round-off, doc/contact_engine.md)", "", ks, &ks, nullptr));
  PetscCall(PetscOptionsBool("-fdem_contact_initial_overlap_check", "Stop at the first evaluation when two bodies start interpenetrating deeply (a set-up error); false: a warning (the fdem driver's default when it restarts from a checkpoint, whose overlaps the run made)", "", ic, &ic, nullptr));
  PetscOptionsEnd();
  surface_only_  = so;
  keep_search_   = ks;
  initial_check_ = ic;
  // (the options that gave a value are named in an error: a scene's petsc: line is found by them)
  const char *given[3] = {fd ? "-fdem_contact_damping" : nullptr, fm ? "-fdem_contact_friction" : nullptr, fc ? "-fdem_contact_tangential_viscosity" : nullptr};
  if (fp) PetscCall(SetPenalty(pen, "-fdem_contact_penalty"));
  PetscCall(SetDissipation(damp, mu, ct, given));
  if (fb && buf < 0) SetAutomaticBuffer();
  else if (fb) PetscCall(SetBuffer(buf, "-fdem_contact_buffer"));
  if (self != par_.self) PetscCall(SetSelfContact(self));
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ primitives and ghosts
PetscErrorCode RegisterEvents() {
  PetscFunctionBegin;
  if (!CLASSID) {
    PetscCall(PetscClassIdRegister("FDEM Contact", &CLASSID));
    PetscCall(PetscLogEventRegister("FDEMContactList", CLASSID, &EV_LIST));
    PetscCall(PetscLogEventRegister("FDEMContactHalo", CLASSID, &EV_GHOST));
    PetscCall(PetscLogEventRegister("FDEMContactDetect", CLASSID, &EV_SEARCH));
    PetscCall(PetscLogEventRegister("FDEMContactForce", CLASSID, &EV_FORCE));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::ListAll() {
  PetscFunctionBegin;
  PetscCall(RegisterEvents());
  // the springs kept with the sphere pairs go to their slots while the numbering is still theirs
  // (Reset, after a migration, has dropped them: the rigid contact flushed them before)
  PetscCall(FlushSprings());
  sp_.clear();
  PetscCall(PetscLogEventBegin(EV_LIST, 0, 0, 0, 0));
  for (auto *a : adapters_) { // their selections brought up to date (a restart lists before its first evaluation)
    PetscBool changed;
    PetscCall(a->Changed(&changed));
  }
  prim_.clear();
  size_t room = 0; // (room for all, as the adapters know or the last listing needed: one allocation)
  for (auto *a : adapters_) room += a->ListSize();
  prim_.reserve(std::max(room + room / 8, (size_t)nl_ + nl_ / 2));
  for (size_t k = 0; k < adapters_.size(); ++k) {
    PetscCall(adapters_[k]->List(prim_)); // (a mesh lists thousands of records: copied once, into the kept array)
    for (size_t i = first_[k]; i < prim_.size(); ++i) prim_[i].kind = (std::int32_t)k;
    first_[k + 1] = (int)prim_.size();
  }
  nl_ = (int)prim_.size();
  x_.resize(nl_);
  f_.resize(nl_);
  {
    PetscBool mine[2] = {PETSC_FALSE, PETSC_FALSE}, any[2]; // a sphere, another shape
    for (const auto &q : prim_) mine[q.shape == kSphere ? 0 : 1] = PETSC_TRUE;
    PetscCallMPI(MPI_Allreduce(mine, any, 2, MPIU_BOOL, MPI_LOR, comm_));
    spheres_     = any[0];
    sphere_only_ = any[0] && !any[1];
  }
  PetscCall(Tally());
  listed_   = true;
  holders_valid_ = false; // the primitives are numbered anew: sweep every sphere's slots at the next evaluation
  searched_ = false;
  PetscCall(PetscLogEventEnd(EV_LIST, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Of a listing: the primitives in contact (the idle ones are not) and the automatic buffer, the
// mean of the adapters' proposals (summed in the adapters' order). Collective.
PetscErrorCode Engine::Tally() {
  PetscInt np = 0;
  PetscFunctionBegin;
  for (const auto &q : prim_) np += q.idle ? 0 : 1;
  PetscCallMPI(MPI_Allreduce(&np, &stats_.primitives, 1, MPIU_INT, MPI_SUM, comm_));
  if (par_.buffer < 0) { // automatic
    PetscReal sum = 0, g;
    PetscInt  count = 0, gn;
    for (auto *a : adapters_) {
      PetscReal s = 0;
      PetscInt  n = 0;
      PetscCall(a->BufferProposal(&s, &n));
      sum += s;
      count += n;
    }
    PetscCallMPI(MPI_Allreduce(&sum, &g, 1, MPIU_REAL, MPI_SUM, comm_));
    PetscCallMPI(MPI_Allreduce(&count, &gn, 1, MPIU_INT, MPI_SUM, comm_));
    stats_.buffer = gn > 0 ? g / (PetscReal)gn : 0;
  } else stats_.buffer = par_.buffer;
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::UpdateGhosts(bool x, bool v) {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_GHOST, 0, 0, 0, 0));
  // both exchanges in flight at once
  if (x) gx_.resize(ng_);
  if (v) gv_.resize(ng_);
  if (x) PetscCall(PetscSFBcastBegin(sf_, vunit_, x_.data(), gx_.data(), MPI_REPLACE));
  if (v) PetscCall(PetscSFBcastBegin(sf_, vunit_, v_.data(), gv_.data(), MPI_REPLACE));
  if (x) {
    PetscCall(PetscSFBcastEnd(sf_, vunit_, x_.data(), gx_.data(), MPI_REPLACE));
    if (shifted_) // periodic images: their vertices a period away
      for (int g = 0; g < ng_; ++g)
        for (auto &p : gx_[g])
          for (int k = 0; k < 3; ++k) p[k] += gshift_[g][k];
  }
  if (v) PetscCall(PetscSFBcastEnd(sf_, vunit_, v_.data(), gv_.data(), MPI_REPLACE));
  PetscCall(PetscLogEventEnd(EV_GHOST, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Sphere-only: the states of the own spheres that are ghosts somewhere, straight from their
// adapters, to the ghosts (gs_; periodic images shifted); no vertex records.
PetscErrorCode Engine::UpdateSphereGhosts() {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_GHOST, 0, 0, 0, 0));
  rs_.resize(nl_);
  gs_.resize(ng_);
  for (size_t k = 0; k < adapters_.size(); ++k)
    if (!exp_i_[k].empty()) PetscCall(adapters_[k]->SphereStates((int)exp_i_[k].size(), exp_sph_[k].data(), exp_i_[k].data(), rs_.data()));
  PetscCall(PetscSFBcastBegin(sf_, sunit_, rs_.data(), gs_.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf_, sunit_, rs_.data(), gs_.data(), MPI_REPLACE));
  if (shifted_)
    for (int g = 0; g < ng_; ++g)
      for (int k = 0; k < 3; ++k) gs_[g].x[k] += gshift_[g][k];
  PetscCall(PetscLogEventEnd(EV_GHOST, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// The halo and the candidate pairs. Each rank's region is NGROUP x NBOX boxes around the bounding
// boxes of its primitives; a primitive whose box meets another rank's box is sent there as a ghost
// when a pair can form there that the other rank computes (FirstComputes). The candidate pairs
// are the pairs of primitives whose boxes (grown by half the buffer) overlap, found level by level
// (kernels::BoxSearch), each computed by one rank; forces on ghosts go back through the same SF.
PetscErrorCode Engine::Search() {
  const PetscReal half = 0.5 * stats_.buffer;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_SEARCH, 0, 0, 0, 0));
  const int           nl = nl_;
  std::vector<double> boxes(6 * (size_t)nl), margin(nl);
  for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->Margins(half, searched_ ? since_search_ : 0, margin.data() + first_[k]));
  for (int i = 0; i < nl; ++i) {
    prim_[i].margin = std::max(margin[i], (double)half);
    PrimBox(prim_[i], x_[i], prim_[i].margin, &boxes[6 * (size_t)i]);
  }
  { // a primitive out of the range of doubles (a position, velocity or size overflowed): name its body, not a box of the search
    int bad = -1;
    for (int i = 0; i < nl && bad < 0; ++i)
      for (int k = 0; k < 3 && bad < 0; ++k)
        if (!std::isfinite(boxes[6 * (size_t)i + 3 + k] - boxes[6 * (size_t)i + k])) bad = i; // (corners finite and their distance too)
    int mine = bad < 0 ? size_ : rank_, first;
    PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm_));
    if (first < size_) {
      char msg[512] = "";
      if (rank_ == first) {
        const Primitive &p = prim_[bad];
        const double    *b = &boxes[6 * (size_t)bad];
        PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s (%s) left the range of numbers: its box is [%g, %g, %g] to [%g, %g, %g] at the contact search; a position, velocity, size or load of the scene is too large (or the step made it so)", adapters_[p.kind]->BodyName(p).c_str(),
                                adapters_[p.kind]->ElementName(p).c_str(), b[0], b[1], b[2], b[3], b[4], b[5]));
      }
      PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, first, comm_));
      SETERRQ(comm_, PETSC_ERR_USER_INPUT, "%s: %s", who_.c_str(), msg);
    }
  }
  if (periodic_) { // a pair must not meet both directly and through an image, and one period of shift must reach every image
    std::string bad;
    for (int i = 0; i < nl && bad.empty(); ++i)
      for (int k = 0; k < 3 && bad.empty(); ++k) {
        if (!(period_[k] > 0)) continue;
        const Primitive &p = prim_[i];
        const double     lo = boxes[6 * (size_t)i + k], hi = boxes[6 * (size_t)i + 3 + k], c = 0.5 * (lo + hi);
        char             msg[256];
        if (!(hi - lo < 0.5 * period_[k])) PetscCall(PetscSNPrintf(msg, sizeof(msg), "spans %g along the periodic axis %c with its search margin, more than half the period %g; make the periodic cell larger than twice the largest body", hi - lo, "xyz"[k], period_[k]));
        else if (!(c >= plo_[k] - 0.25 * period_[k] && c <= plo_[k] + 1.25 * period_[k])) PetscCall(PetscSNPrintf(msg, sizeof(msg), "is at %g along the periodic axis %c, more than a quarter period outside the cell [%g, %g]; it moved too far between two migrations (migrate more often)", c, "xyz"[k], plo_[k], plo_[k] + period_[k]));
        else continue;
        bad = adapters_[p.kind]->BodyName(p) + " (" + adapters_[p.kind]->ElementName(p) + ") " + msg;
      }
    int mine = bad.empty() ? size_ : rank_, first;
    PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm_));
    if (first < size_) {
      char msg[512] = "";
      if (rank_ == first) PetscCall(PetscStrncpy(msg, bad.c_str(), sizeof(msg)));
      PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, first, comm_));
      SETERRQ(comm_, PETSC_ERR_USER_INPUT, "%s: %s", who_.c_str(), msg);
    }
  }
  std::vector<double> box(BW * NGROUP * NBOX, INFINITY);
  if (size_ > 1 || periodic_) { // one rank without periodic images: no one to send to
    std::vector<double> size(nl), med;
    for (int i = 0; i < nl; ++i)
      for (int k = 0; k < 3; ++k) size[i] = std::max(size[i], boxes[6 * i + 3 + k] - boxes[6 * i + k]);
    med = size;
    if (nl) std::nth_element(med.begin(), med.begin() + nl / 2, med.end());
    const double     large = nl ? 2 * med[nl / 2] : 0;
    std::vector<int> idx[NGROUP];
    for (int i = 0; i < nl; ++i) idx[prim_[i].fixed ? 2 : size[i] > large ? 1 : 0].push_back(i);
    auto mid = [&](int i, int k) { return boxes[6 * i + k] + boxes[6 * i + 3 + k]; };
    for (int g = 0; g < NGROUP; ++g) {
      std::function<void(int, int, int, int)> split = [&](int b, int e, int depth, int slot) {
        if (b >= e) return;
        if (depth == 0) {
          double *bx = &box[BW * (g * NBOX + slot)];
          bx[6]      = (double)prim_[idx[g][b]].body;
          bx[7]      = (double)prim_[idx[g][b]].kind;
          unsigned mask = 0, moves = 0;
          for (int j = b; j < e; ++j) {
            const int i = idx[g][j];
            for (int k = 0; k < 3; ++k) {
              bx[k]     = std::min(bx[k], boxes[6 * i + k]);
              bx[3 + k] = std::min(bx[3 + k], -boxes[6 * i + 3 + k]);
            }
            if ((double)prim_[i].body != bx[6] || (double)prim_[i].kind != bx[7]) bx[6] = -1;
            if ((double)prim_[i].kind != bx[7]) bx[7] = -1;
            mask |= 1u << prim_[i].kind;
            moves |= prim_[i].fixed && prim_[i].shape != kSphere ? 0u : 1u; // a fixed sphere may compute a pair with a moving body
          }
          bx[8] = mask;
          bx[9] = moves;
          return;
        }
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int j = b; j < e; ++j)
          for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], mid(idx[g][j], k));
            hi[k] = std::max(hi[k], mid(idx[g][j], k));
          }
        int ax = 0;
        for (int k = 1; k < 3; ++k)
          if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
        const int m = b + (e - b) / 2;
        std::nth_element(idx[g].begin() + b, idx[g].begin() + m, idx[g].begin() + e, [&](int u, int v) { return mid(u, ax) < mid(v, ax); });
        split(b, m, depth - 1, 2 * slot);
        split(m, e, depth - 1, 2 * slot + 1);
      };
      split(0, (int)idx[g].size(), NBOX_DEPTH, 0);
    }
  }
  const int           nbox = NGROUP * NBOX;
  std::vector<double> all(BW * nbox * (size_t)size_);
  PetscCallMPI(MPI_Allgather(box.data(), BW * nbox, MPI_DOUBLE, all.data(), BW * nbox, MPI_DOUBLE, comm_));
  // 1. who needs which of my primitives: a rank with a primitive near it that can pair with it,
  //    unless I compute every such pair (mine moves, theirs in that box are all fixed). With
  //    periodic boundaries also as an image, shifted by a period along periodic axes, to any
  //    rank (this one too): shift code c = 9 (s_x + 1) + 3 (s_y + 1) + (s_z + 1), s_k in
  //    {-1, 0, 1}, sent as 27 i + c.
  std::vector<int> codes{13};
  if (periodic_)
    for (int c = 0; c < 27; ++c) {
      const int sh[3] = {c / 9 - 1, c / 3 % 3 - 1, c % 3 - 1};
      if (c != 13 && (sh[0] == 0 || period_[0] > 0) && (sh[1] == 0 || period_[1] > 0) && (sh[2] == 0 || period_[2] > 0)) codes.push_back(c);
    }
  std::vector<std::vector<PetscInt>> send(size_);
  for (int s = 0; s < size_; ++s) {
    double ulo[3] = {INFINITY, INFINITY, INFINITY}, uhi[3] = {-INFINITY, -INFINITY, -INFINITY}; // rank s's region: the union of its boxes
    for (int q = 0; q < nbox; ++q)
      for (int k = 0; k < 3; ++k) {
        ulo[k] = std::min(ulo[k], all[BW * ((size_t)s * nbox + q) + k]);
        uhi[k] = std::max(uhi[k], -all[BW * ((size_t)s * nbox + q) + 3 + k]);
      }
    for (int c : codes) {
      if (s == rank_ && c == 13) continue;
      const double sh[3] = {(c / 9 - 1) * period_[0], (c / 3 % 3 - 1) * period_[1], (c % 3 - 1) * period_[2]};
      for (int i = 0; i < nl; ++i) {
        const Primitive &p    = prim_[i];
        const double    *pb   = &boxes[6 * (size_t)i];
        bool             near = true;
        for (int k = 0; k < 3 && near; ++k) near = pb[3 + k] + sh[k] >= ulo[k] && pb[k] + sh[k] <= uhi[k];
        if (!near) continue;
        const bool self = (par_.self && adapters_[p.kind]->CanSelfContact()) || adapters_[p.kind]->AlwaysSelfContact(p.body);
        for (int q = 0; q < nbox; ++q) {
          const double  *b    = &all[BW * ((size_t)s * nbox + q)];
          if (!(b[0] < INFINITY)) continue; // empty
          const unsigned mask = (unsigned)b[8];
          bool           in   = false;
          for (int k = 0; k < (int)adapters_.size() && !in; ++k) in = (mask >> k & 1u) && allow_[p.kind][k];
          // no pairs within one body without self-contact
          in = in && (self || b[6] != (double)p.body || b[7] != (double)p.kind);
          // theirs all fixed: mine fixed too (no pair) or mine moves (I compute them all)
          in = in && b[9] != 0;
          for (int k = 0; k < 3 && in; ++k) in = pb[3 + k] + sh[k] >= b[k] && pb[k] + sh[k] <= -b[3 + k];
          if (in) {
            send[s].push_back(periodic_ ? 27 * (PetscInt)i + c : i);
            break;
          }
        }
      }
    }
  }
  std::vector<PetscSFNode> ghosts;
  PetscCall(fdem::HaloExchange(comm_, send, ghosts, periodic_));
  gshift_.assign(ghosts.size(), {0, 0, 0});
  shifted_ = false;
  if (periodic_) {
    for (size_t g = 0; g < ghosts.size(); ++g) {
      const int c     = (int)(ghosts[g].index % 27);
      ghosts[g].index = ghosts[g].index / 27;
      gshift_[g]      = {(c / 9 - 1) * period_[0], (c / 3 % 3 - 1) * period_[1], (c % 3 - 1) * period_[2]};
      shifted_        = shifted_ || c != 13;
    }
    for (auto &l : send)
      for (PetscInt &i : l) i /= 27;
  }
  // the own primitives that are ghosts somewhere, by adapter (the sphere-only exchange fills their states)
  {
    std::vector<char> out(nl, 0);
    for (const auto &l : send)
      for (PetscInt i : l) out[i] = 1;
    exp_sph_.assign(adapters_.size(), {});
    exp_i_.assign(adapters_.size(), {});
    for (int i = 0; i < nl; ++i)
      if (out[i]) exp_sph_[prim_[i].kind].push_back(i - first_[prim_[i].kind]), exp_i_[prim_[i].kind].push_back(i);
  }
  // 2. the SF (one Vertices record per primitive) and the ghosts' static records (a one-off SF)
  ng_ = (int)ghosts.size();
  if (vunit_ == MPI_DATATYPE_NULL) PetscCall(fdem::HaloUnit((PetscInt)(sizeof(Vertices) / sizeof(PetscReal)), MPIU_REAL, &vunit_));
  if (sunit_ == MPI_DATATYPE_NULL) PetscCall(fdem::HaloUnit((PetscInt)(sizeof(SphereNow) / sizeof(PetscReal)), MPIU_REAL, &sunit_));
  if (funit_ == MPI_DATATYPE_NULL) PetscCall(fdem::HaloUnit((PetscInt)(sizeof(SphereSum) / sizeof(PetscReal)), MPIU_REAL, &funit_));
  PetscCall(fdem::HaloSF(comm_, nl, ghosts, &sf_));
  gprim_.resize(ng_);
  PetscCall(SendRecords());
  PetscCall(UpdateGhosts(true, false));
  // 3. the candidate pairs among own and ghost primitives: boxes that overlap
  const int N = nl + ng_;
  boxes.resize(6 * (size_t)N);
  for (int i = nl; i < N; ++i) PrimBox(gprim_[i - nl], gx_[i - nl], gprim_[i - nl].margin, &boxes[6 * (size_t)i]);
  pairs_.clear();
  kept_.clear();
  kept_made_ = false;
  kept_off_.clear();
  ss_.clear();
  st_.clear();
  sp_fresh_      = true;
  holders_valid_ = false;
  {
    PetscCall(fdem::Guard(comm_, [&]() -> PetscErrorCode { // collective: every rank enters, ranks without primitives do nothing
      if (nl == 0) return 0;
      fdem::kernels::BoxSearch         bs;
      std::vector<std::pair<int, int>> tp;
      // each box's class (kind, fixed): only pairs of classes that may meet are listed (a
      // fixed body meets moving ones only; a kind the engine pairs with others only, such as
      // the mesh of the contact with rigid bodies, has its own pairs left out of the search,
      // and its cells far from every rigid body out of the search's levels)
      std::vector<std::uint8_t> cls(N);
      std::uint64_t             meet = 0;
      for (int i = 0; i < N; ++i) cls[i] = (std::uint8_t)(2 * P(i).kind + (P(i).fixed ? 1 : 0));
      for (int ca = 0; ca < 8; ++ca)
        for (int cb = 0; cb < 8; ++cb)
          if (allow_[ca / 2][cb / 2] && !(ca % 2 && cb % 2)) meet |= std::uint64_t(1) << (8 * ca + cb);
      bs.Build(boxes.data(), N, cls.data(), meet);
      bs.FindPairs(tp, cls.data(), meet);
      // face planes, made when a pair first needs them
      std::vector<double> planes(16 * (size_t)N);
      std::vector<char>   have(N, 0);
      auto                plane = [&](int i) {
        if (!have[i]) FacePlanes(X(i), &planes[16 * (size_t)i]), have[i] = 1;
        return &planes[16 * (size_t)i];
      };
      const bool keep = Keepable();
      for (const auto &pr : tp) {
        int              a = pr.first, b = pr.second;
        const Primitive &A = P(a), &B = P(b); // (kinds allowed together, not both fixed: the box classes above)
        const int spheres = (A.shape == kSphere) + (B.shape == kSphere);
        int       itself  = 0; // a pair within one body: 1, and 2 where its adapter does not pair it now
        if (A.kind == B.kind && A.body == B.body) { // one body: only with self-contact, and never neighbours (a sphere is one primitive)
          const Adapter *ad = adapters_[A.kind];
          if (spheres || !((par_.self && ad->CanSelfContact()) || ad->AlwaysSelfContact(A.body))) continue;
          itself = Paired(A, B) ? 1 : 2;
          if (itself == 2 && !keep) continue;
        }
        const bool idle = A.idle || B.idle; // not paired now, as itself == 2
        if (idle && !keep) continue;
        // apart for as long as neither moves more than its margin: not a candidate (not tested
        // for a pair not paired now: kept for a listing that pairs it, it is a candidate then)
        const double gap = A.margin + B.margin;
        if (itself == 2 || idle) { // (no gap test: see above)
        } else if (spheres == 2) {
          if (norm(X(a)[0] - X(b)[0]) > A.radius + B.radius + gap) continue;
        } else if (spheres == 1) { // the centre beyond a face plane of the tetrahedron by more than the radius
          const int     s = A.shape == kSphere ? a : b;
          const double *pl = plane(A.shape == kSphere ? b : a);
          bool          out = false;
          for (int k = 0; k < 4 && !out; ++k) out = pl[4 * k] * X(s)[0][0] + pl[4 * k + 1] * X(s)[0][1] + pl[4 * k + 2] * X(s)[0][2] - pl[4 * k + 3] > P(s).radius + gap;
          if (out) continue;
        } else if (BeyondAFace(plane(a), X(b), gap) || BeyondAFace(plane(b), X(a), gap)) continue;
        if (Before(B, A)) std::swap(a, b); // a: the smaller (kind, key), first in the force call
        if (a >= nl && b >= nl) continue;   // two ghosts: their owners compute it
        if ((a >= nl || b >= nl) && (FirstComputes(P(a), P(b)) != (a < nl))) continue; // the other rank computes it
        if (keep) kept_.push_back({a, b, itself});
        if (itself == 2 || idle) continue;
        if (spheres == 0) pairs_.push_back({a, b});
        else if (spheres == 2) ss_.push_back(HolderIsFirst(P(a), P(b)) ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a}); // the holder first
        else st_.push_back(P(a).shape == kSphere ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a});                      // the sphere first
      }
      // a sphere's surface candidates grouped by body, in the order of the keys (as on any number of ranks)
      std::sort(st_.begin(), st_.end(), [&](const std::array<int, 2> &u, const std::array<int, 2> &w) {
        const Primitive &su = P(u[0]), &sw = P(w[0]), &tu = P(u[1]), &tw = P(w[1]);
        if (su.kind != sw.kind || su.key != sw.key) return Before(su, sw);
        if (tu.kind != tw.kind) return tu.kind < tw.kind;
        if (tu.body != tw.body) return tu.body < tw.body;
        return tu.key < tw.key;
      });
      return 0;
    }));
  }
  sep_.assign(pairs_.size(), 0);
  PetscCall(PairsListed());
  for (auto *a : adapters_) PetscCall(a->Searched());
  gf_.resize(ng_);
  searched_     = true;
  since_search_ = 0;
  stats_.searches++;
  PetscInt loc[2] = {(PetscInt)(pairs_.size() + ss_.size() + st_.size()), (PetscInt)ng_}, glob[2];
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPIU_INT, MPI_SUM, comm_));
  stats_.candidate_pairs = glob[0];
  stats_.ghosts          = glob[1];
  PetscCall(PetscLogEventEnd(EV_SEARCH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// The own primitives' records to their ghosts (gprim_, sized), over the search's SF.
PetscErrorCode Engine::SendRecords() {
  MPI_Datatype punit;
  PetscFunctionBegin;
  PetscCall(fdem::HaloUnit((PetscInt)sizeof(Primitive), MPI_BYTE, &punit));
  PetscCall(PetscSFBcastBegin(sf_, punit, prim_.data(), gprim_.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf_, punit, prim_.data(), gprim_.data(), MPI_REPLACE));
  PetscCallMPI(MPI_Type_free(&punit));
  PetscFunctionReturn(0);
}

// 4. of a search: the primitives that may get a force here (in a pair, or a ghost elsewhere)
// and how many pairs each takes part in, for its adapter.
PetscErrorCode Engine::PairsListed() {
  const int nl = nl_;
  PetscFunctionBegin;
  std::vector<char>     t(nl, 0);
  std::vector<PetscInt> count(nl, 0);
  for (const auto *list : {&pairs_, &ss_, &st_})
    for (const auto &p : *list)
      for (int i : p)
        if (i < nl) t[i] |= list != &ss_, ++count[i]; // an own sphere of a sphere-sphere pair is read and given its force without records
  for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->PairCounts(count.data() + first_[k]));
  for (const auto &l : exp_i_)
    for (int i : l) t[i] = 1;
  touch_.assign(adapters_.size(), {});
  for (size_t k = 0; k < adapters_.size(); ++k)
    for (int i = first_[k]; i < first_[k + 1]; ++i)
      if (t[i]) touch_[k].push_back(i - first_[k]);
  PetscFunctionReturn(0);
}

// A listing that fracture caused keeps the search when the primitives are the ones listed before,
// in the same order (only their records changed: free faces, node keys, the flags of damaged
// cells, whether one is idle), on every rank: the candidates that the search found by their
// boxes (kept_) are still all the pairs that can touch before the next search, and only whether
// a body's adapter pairs two of its own primitives (SelfPair) and which are idle may have
// changed. The pairs are taken again from kept_, each keeping the axis that last found it
// apart; the ghosts get their records again. Only where
// an adapter may list again (fracture), and not with spheres (their springs and surface groups
// are made at a search) or periodic images.
bool Engine::Keepable() const {
  bool relists = false;
  for (const auto *a : adapters_) relists = relists || a->Relists();
  return keep_search_ && relists && !spheres_ && !periodic_;
}

PetscErrorCode Engine::KeepSearch(const std::vector<Primitive> &before, bool *kept) {
  PetscFunctionBegin;
  *kept = false;
  int same = Keepable() && before.size() == prim_.size();
  for (size_t i = 0; same && i < before.size(); ++i) {
    const Primitive &u = before[i], &w = prim_[i];
    same = u.kind == w.kind && u.key == w.key && u.body == w.body && u.fixed == w.fixed && u.shape == w.shape;
  }
  int all;
  PetscCallMPI(MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_LAND, comm_));
  if (!all) PetscFunctionReturn(0);
  for (size_t i = 0; i < before.size(); ++i) prim_[i].margin = before[i].margin;
  PetscCall(PairsFromKept());
  *kept = true;
  PetscFunctionReturn(0);
}

// The pairs of the kept search (kept_) for the records of the listing now: the ghosts get their
// records again, and each candidate is paired unless a primitive is idle or its adapter does
// not pair the two. changed: where only those own records changed since the last call (a
// listing in place), and no adapter's PairRule, only the candidates of those and of the ghosts
// whose records changed are asked again, and the pairs before are kept in the same order.
// Collective.
PetscErrorCode Engine::PairsFromKept(const std::vector<int> *changed) {
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_SEARCH, 0, 0, 0, 0));
  std::vector<std::int64_t> rule(adapters_.size());
  for (size_t k = 0; k < adapters_.size(); ++k) rule[k] = adapters_[k]->PairRule();
  const bool few = changed && kept_made_ && rule == kept_rule_;
  if (few) gprim_before_.assign(gprim_.begin(), gprim_.end());
  PetscCall(SendRecords());
  const int N = nl_ + ng_;
  if (few) {
    // the primitives whose records changed: own ones (changed) and ghosts (their records compared)
    flips_.clear();
    refreshed_.assign(changed->begin(), changed->end());
    for (int g = 0; g < ng_; ++g)
      if (std::memcmp(&gprim_before_[g], &gprim_[g], sizeof(Primitive))) refreshed_.push_back(nl_ + g);
    if (kept_off_.empty()) { // each primitive's entries in kept_, once per search
      kept_off_.assign(N + 1, 0);
      for (const auto &c : kept_) ++kept_off_[c[0] + 1], ++kept_off_[c[1] + 1];
      for (int i = 0; i < N; ++i) kept_off_[i + 1] += kept_off_[i];
      kept_at_.resize(kept_off_[N]);
      std::vector<int> fill(kept_off_.begin(), kept_off_.end() - 1);
      for (size_t q = 0; q < kept_.size(); ++q) kept_at_[fill[kept_[q][0]]++] = (int)q, kept_at_[fill[kept_[q][1]]++] = (int)q;
    }
    for (int i : refreshed_) held_[i] = P(i).idle ? kIdle : P(i).group;
    for (int i : refreshed_)
      for (int m = kept_off_[i]; m < kept_off_[i + 1]; ++m)
        if (const int q = kept_at_[m]; (char)KeptPaired(kept_[q]) != kept_on_[q]) flips_.push_back(q);
    std::sort(flips_.begin(), flips_.end());
    flips_.erase(std::unique(flips_.begin(), flips_.end()), flips_.end());
    fresh_.assign(pairs_.size(), 0);
    if (!flips_.empty()) { // the pairs before and the flipped candidates, merged in kept_'s order
      auto &pairs = pairs_next_;
      auto &sep   = sep_next_;
      auto &at    = pair_kept_next_;
      pairs.clear(), sep.clear(), fresh_.clear(), at.clear();
      size_t i = 0, f = 0;
      while (i < pairs_.size() || f < flips_.size()) {
        const int qi = i < pairs_.size() ? pair_kept_[i] : INT32_MAX, qf = f < flips_.size() ? flips_[f] : INT32_MAX;
        if (qi < qf) pairs.push_back(pairs_[i]), sep.push_back(sep_[i]), fresh_.push_back(0), at.push_back(qi), ++i;
        else if (qf < qi) pairs.push_back({kept_[qf][0], kept_[qf][1]}), sep.push_back(0), fresh_.push_back(1), at.push_back(qf), ++f; // paired now
        else ++i, ++f; // paired no more
      }
      for (int q : flips_) kept_on_[q] ^= 1;
      pairs_.swap(pairs);
      sep_.swap(sep);
      pair_kept_.swap(at);
      PetscCall(PairsListed());
    }
    stats_.in_place_few++;
  } else {
    auto  &pairs = pairs_next_; // (swapped with pairs_ and sep_ below: the arrays are kept)
    auto  &sep   = sep_next_;
    size_t j     = 0; // the pairs before are kept_'s paired entries, in its order
    pairs.clear();
    sep.clear();
    fresh_.clear();
    pair_kept_.clear();
    kept_on_.assign(kept_.size(), 0);
    // what decides most candidates, per primitive in one compact array (the records are large, and
    // kept_ holds every pair of neighbours within a fracturable body): idle, and the group (two
    // primitives of one body with one group >= 0 are not paired, Primitive::group)
    held_.resize(N);
    for (int i = 0; i < N; ++i) held_[i] = P(i).idle ? kIdle : P(i).group;
    for (size_t q = 0; q < kept_.size(); ++q) {
      const auto        &c   = kept_[q];
      const bool         was = j < pairs_.size() && pairs_[j][0] == c[0] && pairs_[j][1] == c[1];
      const std::int8_t  s   = was ? sep_[j] : 0;
      if (was) ++j;
      if (!KeptPaired(c)) continue;
      pairs.push_back({c[0], c[1]});
      sep.push_back(s);
      fresh_.push_back(was ? 0 : 1);
      pair_kept_.push_back((int)q);
      kept_on_[q] = 1;
    }
    pairs_.swap(pairs);
    sep_.swap(sep);
    kept_rule_ = rule;
    kept_made_ = true;
    PetscCall(PairsListed());
  }
  fresh_valid_ = true;
  searched_ = true;
  PetscInt loc = (PetscInt)pairs_.size(), glob;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPIU_INT, MPI_SUM, comm_));
  stats_.candidate_pairs = glob;
  stats_.kept++;
  PetscCall(PetscLogEventEnd(EV_SEARCH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Is kept candidate c paired, by held_ and its adapter (PairsFromKept)?
bool Engine::KeptPaired(const std::array<int, 3> &c) const {
  const std::int64_t ga = held_[c[0]], gb = held_[c[1]];
  if (ga == kIdle || gb == kIdle) return false;
  return !(c[2] != 0 && ((ga >= 0 && ga == gb) || !adapters_[P(c[0]).kind]->SelfPair(P(c[0]), P(c[1])))); // (Paired, the group from held_)
}

// A listing that fracture caused, without listing: where every adapter that changed kept its
// primitives (Adapter::RefreshInPlace) on every rank, their changed records are written into
// the listing as they are, and the search is kept (PairsFromKept). Otherwise (listed_ stays
// false) a full listing follows, and KeepSearch compares it with the one before (a record written here
// changes neither its identity nor its margin). Collective.
PetscErrorCode Engine::RefreshListing() {
  int mine = 1, all;
  PetscFunctionBegin;
  PetscCall(PetscLogEventBegin(EV_LIST, 0, 0, 0, 0));
  std::vector<int> changed, part;
  for (size_t k = 0; k < adapters_.size() && mine; ++k)
    if (changed_[k]) {
      part.clear();
      mine = adapters_[k]->RefreshInPlace(prim_.data() + first_[k], (size_t)(first_[k + 1] - first_[k]), part) ? 1 : 0;
      for (int i : part) changed.push_back(first_[k] + i);
    }
  PetscCallMPI(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_LAND, comm_));
  if (all) PetscCall(Tally());
  PetscCall(PetscLogEventEnd(EV_LIST, 0, 0, 0, 0));
  if (!all) PetscFunctionReturn(0);
  listed_ = true;
  stats_.in_place++;
  PetscCall(PairsFromKept(&changed));
  PetscFunctionReturn(0);
}

// ------------------------------------------------------------------ evaluation
PetscErrorCode Engine::SearchDue(bool *due) {
  PetscReal ratio = searched_ ? 0 : PETSC_MAX_REAL, gratio;
  PetscFunctionBegin;
  if (searched_)
    for (auto *a : adapters_) {
      PetscReal r;
      PetscCall(a->MoveRatio(&r));
      ratio = std::max(ratio, r);
    }
  PetscCallMPI(MPI_Allreduce(&ratio, &gratio, 1, MPIU_REAL, MPI_MAX, comm_));
  *due = gratio > 1 || !(stats_.buffer > 0);
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::PairLoop(PetscReal sums[2], std::array<double, 3> &deep, PetscReal *onset) {
  const PetscReal pen = par_.penalty;
  PetscFunctionBegin;
  PetscCall(fdem::Guard(comm_, [&]() -> PetscErrorCode {
    fdem::kernels::TetPairContact pc, full;
    std::array<Vec3, 4>           fa, fb, da, db;
    // each tetrahedron's frame and current box once per evaluation, made when a pair first needs
    // it (the arrays kept from one evaluation to the next: no allocation per evaluation)
    if (!pairs_.empty()) {
      frames_.resize(nl_ + ng_);
      made_.assign(nl_ + ng_, 0);
      cboxes_.resize(nl_ + ng_);
      cmade_.assign(nl_ + ng_, 0);
    }
    auto frame = [&](int i, const char *name) -> const fdem::kernels::TetFrame & {
      if (!made_[i]) {
        fdem::kernels::MakeTetFrame(X(i), name, frames_[i]);
        made_[i] = 1;
      }
      return frames_[i];
    };
    PetscCheck(pen > 0 || pairs_.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "%s: the penalty is not set; give -fdem_contact_penalty <Pa> (a positive modulus)", who_.c_str());
    auto cbox = [&](int i) -> const std::array<double, 6> & { // a tetrahedron is in many pairs
      if (!cmade_[i]) {
        CurrentBox(X(i), cboxes_[i]);
        cmade_[i] = 1;
      }
      return cboxes_[i];
    };
    for (size_t q = 0; q < pairs_.size(); ++q) {
      const auto &p = pairs_[q];
      const Tet4 &a = X(p[0]), &b = X(p[1]);
      if (!BoxesMeet(cbox(p[0]), cbox(p[1]))) continue;
      const fdem::kernels::TetFrame &ta = frame(p[0], "a"), &tb = frame(p[1], "b");
      // apart along the axis that separated the pair last time: no force, and no need to clip
      if (sep_[q] && fdem::kernels::SeparatedAlong(sep_[q], a, ta, b, tb)) continue;
      const int  pa = surface_only_ ? P(p[0]).push : 15, pb = surface_only_ ? P(p[1]).push : 15;
      const bool hit = fdem::kernels::PotentialContactForce(a, ta, b, tb, pen, pen, pa, pb, pc);
      sep_[q]        = hit ? 0 : (std::int8_t)fdem::kernels::SeparatingAxis(a, ta, b, tb);
      if (!checked_initial_) {
        // the deep-overlap check: overlap energy above that of 10% of the smaller tetrahedron at mid
        // potential (with some faces only, pc.energy is a share: the pair's own, every face, once here)
        const fdem::kernels::TetPairContact *chk  = &pc;
        bool                                 chit = hit;
        if ((pa & pb & 15) != 15) chit = fdem::kernels::PotentialContactForce(a, ta, b, tb, pen, pen, full), chk = &full;
        const double ratio = chit ? chk->energy / (0.1 * std::min(Volume6(a), Volume6(b)) / 6 * pen / 8) : 0;
        if (ratio > deep[0]) deep = {ratio, (double)p[0], (double)p[1]};
      }
      if (!hit) continue;
      sums[0] += pc.energy;
      sums[1] += 1;
      if (onset && (fresh_valid_ ? fresh_[q] != 0 : !std::binary_search(old_pairs_.begin(), old_pairs_.end(), PairId(p[0], p[1])))) *onset += pc.energy;
      fa = pc.fa;
      fb = pc.fb;
      if (with_v_) {
        fdem::kernels::ContactDampingFriction(ta, tb, V(p[0]), V(p[1]), pc, par_.diss, da, db);
        for (int k = 0; k < 4; ++k) {
          fa[k] += da[k];
          fb[k] += db[k];
        }
      }
      Vertices &oa = p[0] < nl_ ? f_[p[0]] : gf_[p[0] - nl_], &ob = p[1] < nl_ ? f_[p[1]] : gf_[p[1] - nl_];
      for (int k = 0; k < 4; ++k) {
        oa[k] += fa[k];
        ob[k] += fb[k];
      }
    }
    return 0;
  }));
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::EvaluateStill() {
  const PetscReal t = time_, last = last_time_;
  const bool      had = has_time_;
  PetscFunctionBegin;
  if (had) time_ = last_time_;
  PetscCall(Evaluate());
  time_ = t, last_time_ = last, has_time_ = had;
  PetscFunctionReturn(0);
}

PetscErrorCode Engine::Evaluate() {
  bool     pending = false, surface = false;
  Adapter *changer = nullptr;
  PetscFunctionBegin;
  // Primitives that appeared (fracture) are listed again, and the overlap energy the new listing
  // adds at this state is booked (Adapter::OnsetEnergy): the listing so far, searched again
  // first if a search is due, holds every pair that touches now, and a new listing keeps them
  // (fracture only adds primitives and pairs: damage never heals), so what it adds is the energy
  // of its touching pairs that the listing before did not have, found by their keys.
  fresh_valid_ = false; // (set by a listing that keeps the search, for this evaluation's onset)
  if (listed_)
    for (auto *a : adapters_) {
      PetscBool p;
      PetscCall(a->Pending(&p));
      pending = pending || p == PETSC_TRUE;
      surface = surface || (p == PETSC_TRUE && a->SurfacePending());
    }
  surface = surface && spheres_ && pending && !sphere_only_;
  if (pending && !sphere_only_) {
    bool due;
    PetscCall(SearchDue(&due));
    if (due) {
      for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->Gather(nullptr, x_.data() + first_[k], nullptr));
      PetscCall(Search());
    }
    old_pairs_.resize(pairs_.size()); // sorted below unless the listing keeps the search
    for (size_t q = 0; q < pairs_.size(); ++q) old_pairs_[q] = PairId(pairs_[q][0], pairs_[q][1]);
    // the spheres' contacts with the surfaces as listed so far, at this state: where joints
    // broke, a new listing changes the surface (faces exposed, the weights of the copies of a
    // vertex or an edge), and what that adds is booked with the pairs' (doc/fracture.md)
    if (surface) {
      v_.resize(nl_);
      for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->Gather(nullptr, x_.data() + first_[k], v_.data() + first_[k]));
      PetscCall(UpdateGhosts(true, true));
      PetscCall(fdem::Guard(comm_, [&]() -> PetscErrorCode {
        surface_before_ = SurfaceEnergy();
        return 0;
      }));
    }
  }
  const bool was_listed = listed_;
  changed_.assign(adapters_.size(), 0);
  for (size_t k = 0; k < adapters_.size(); ++k) {
    PetscBool changed;
    PetscCall(adapters_[k]->Changed(&changed));
    if (changed && !changer) changer = adapters_[k];
    if (changed) listed_ = false, changed_[k] = 1;
  }
  pending = pending && changer != nullptr; // (the same on every rank)
  if (!listed_ && was_listed && searched_ && Keepable()) PetscCall(RefreshListing()); // (listed_ if it could)
  if (!listed_) {
    const bool searched = searched_;
    // the listing before, for KeepSearch (the two arrays swap: neither is copied nor allocated again)
    if (searched && Keepable()) prim_before_.swap(prim_);
    else prim_before_.clear();
    PetscCall(ListAll());
    bool kept = false;
    if (searched) PetscCall(KeepSearch(prim_before_, &kept));
    if (pending && !kept) std::sort(old_pairs_.begin(), old_pairs_.end()); // a search follows: its pairs are found among the old ones by their keys
  }
  if (!spheres_) PetscCall(CheckPenaltySet()); // with spheres: only when two tetrahedra meet
  if (ts_ && ts_ != checked_ts_) { // once per TS, at its first evaluation: the contact frequency against K_crit
    TSType         type;
    PetscReal      dt;
    PetscBool      found;
    FDEMSchemeInfo info;
    checked_ts_ = ts_;
    PetscCall(TSGetType(ts_, &type));
    PetscCall(TSGetTimeStep(ts_, &dt));
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    if (found && dt > 0) PetscCall(CheckTimeStep(type, dt, &stats_.dt_ratio));
  }
  with_v_ = par_.Dissipative() || spheres_;
  if (with_v_) v_.resize(nl_);
  // the re-search rule: some vertex moved more than its margin (at least half the buffer) since
  // the last search (all ranks)
  bool search;
  PetscCall(SearchDue(&search));
  ++since_search_;
  if (search) {
    if (fresh_valid_) { // the kept search's pairs give way to a new search's (a buffer of 0): found by their keys
      fresh_valid_ = false;
      std::sort(old_pairs_.begin(), old_pairs_.end());
    }
    for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->Gather(nullptr, x_.data() + first_[k], nullptr));
    PetscCall(Search());
  }
  if (sphere_only_) PetscCall(UpdateSphereGhosts()); // no vertex records: the spheres' states go to their ghosts
  else {
    for (size_t k = 0; k < adapters_.size(); ++k)
      if (!search || with_v_) PetscCall(adapters_[k]->Gather(&touch_[k], x_.data() + first_[k], with_v_ ? v_.data() + first_[k] : nullptr));
    PetscCall(UpdateGhosts(!search, with_v_));
  }

  // the pair loop: potential force both ways, damping and friction; forces per vertex
  PetscCall(PetscLogEventBegin(EV_FORCE, 0, 0, 0, 0));
  const Vertices zero{};
  if (!sphere_only_) {
    for (size_t k = 0; k < adapters_.size(); ++k)
      for (int i : touch_[k]) f_[first_[k] + i] = zero;
    std::fill(gf_.begin(), gf_.end(), zero);
  }
  PetscReal             sums[4] = {0, 0, 0, 0}; // energy, active pairs, sphere contacts without a spring slot, onset
  std::array<double, 3> deep{0, -1, -1};     // worst initial overlap ratio, the pair
  PetscCall(PairLoop(sums, deep, pending ? &sums[3] : nullptr));
  if (spheres_) PetscCall(GranularForces(sums, deep));
  if (surface && pending) // the same with the new listing, at the same state
    PetscCall(fdem::Guard(comm_, [&]() -> PetscErrorCode {
      sums[3] += SurfaceEnergy() - surface_before_;
      return 0;
    }));
  if (!checked_initial_) PetscCall(CheckInitialOverlap(deep));
  // forces on ghosts go back to their owners and are summed there
  if (sphere_only_) {
    fs_.resize(nl_); // the reduction adds into the exported spheres' entries only: zero those
    for (const auto &l : exp_i_)
      for (int i : l) fs_[i] = SphereSum{};
    PetscCall(PetscSFReduceBegin(sf_, funit_, gfs_.data(), fs_.data(), MPI_SUM));
    PetscCall(PetscSFReduceEnd(sf_, funit_, gfs_.data(), fs_.data(), MPI_SUM));
    for (size_t k = 0; k < adapters_.size(); ++k)
      if (!exp_i_[k].empty()) PetscCall(adapters_[k]->AddSphereForces((int)exp_i_[k].size(), exp_sph_[k].data(), exp_i_[k].data(), fs_.data()));
  } else {
    PetscCall(PetscSFReduceBegin(sf_, vunit_, gf_.data(), f_.data(), MPI_SUM));
    PetscCall(PetscSFReduceEnd(sf_, vunit_, gf_.data(), f_.data(), MPI_SUM));
    for (size_t k = 0; k < adapters_.size(); ++k) PetscCall(adapters_[k]->Scatter(touch_[k], x_.data() + first_[k], f_.data() + first_[k]));
  }
  PetscReal gsums[4];
  PetscCallMPI(MPI_Allreduce(sums, gsums, 4, MPIU_REAL, MPI_SUM, comm_));
  if (pending) {
    stats_.onset += gsums[3];
    changer->OnsetEnergy(gsums[3]);
  }
  const PetscInt gover = (PetscInt)gsums[2];
  if (gover > 0 && hist_overflow_ == 0)
    PetscCall(PetscPrintf(comm_, "WARNING %s: %" PetscInt_FMT " granular contacts found no free slot for their tangential spring (%d per sphere); they restart from zero at every step\n", who_.c_str(), gover, kHistorySlots));
  hist_overflow_ += gover;
  stats_.energy       = gsums[0];
  stats_.active_pairs = (PetscInt)gsums[1];
  stats_.evaluations++;
  PetscCall(PetscLogEventEnd(EV_FORCE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

// Collective: every rank stops with the same message, composed by the rank holding the worst pair.
PetscErrorCode Engine::CheckInitialOverlap(const std::array<double, 3> &deep) {
  double worst;
  PetscFunctionBegin;
  PetscCallMPI(MPI_Allreduce(&deep[0], &worst, 1, MPI_DOUBLE, MPI_MAX, comm_));
  checked_initial_ = true;
  if (!(worst > 1)) PetscFunctionReturn(0);
  PetscMPIInt mine = deep[0] == worst ? rank_ : size_, from;
  PetscCallMPI(MPI_Allreduce(&mine, &from, 1, MPI_INT, MPI_MIN, comm_));
  char msg[512] = "";
  if (rank_ == from) {
    const Primitive &A = P((int)deep[1]), &B = P((int)deep[2]);
    const Adapter   *a = adapters_[A.kind], *b = adapters_[B.kind];
    PetscCall(PetscSNPrintf(msg, sizeof(msg), "%s and %s start interpenetrating deeply (their %s and %s overlap %.1f times more than allowed); separate them", a->BodyName(A).c_str(), b->BodyName(B).c_str(),
                            a->ElementName(A).c_str(), b->ElementName(B).c_str(), worst));
  }
  PetscCallMPI(MPI_Bcast(msg, sizeof(msg), MPI_CHAR, from, comm_));
  if (!initial_check_) {
    PetscCall(PetscPrintf(comm_, "WARNING %s: %s (continuing: -fdem_contact_initial_overlap_check is off)\n", who_.c_str(), msg));
    PetscFunctionReturn(0);
  }
  SETERRQ(comm_, PETSC_ERR_USER_INPUT, "%s: %s", who_.c_str(), msg);
}

// ------------------------------------------------------------------ the time-step check
PetscErrorCode Engine::CheckTimeStep(const char *scheme, PetscReal dt, PetscReal *ratio) {
  FDEMSchemeInfo info;
  PetscBool      found;
  struct {
    double val;
    int    kind;
  } loc{0, -1}, glob;
  PetscFunctionBegin;
  if (!listed_) PetscCall(ListAll());
  if (!spheres_) PetscCall(CheckPenaltySet());
  PetscCheck(dt > 0 && std::isfinite(dt), comm_, PETSC_ERR_ARG_OUTOFRANGE, "%s: the time step must be positive, got %g", who_.c_str(), (double)dt);
  PetscCall(FDEMSchemeInfoFind(scheme, &found, &info));
  PetscCheck(found, comm_, PETSC_ERR_ARG_UNKNOWN_TYPE, "%s: %s is not an fdem TS type", who_.c_str(), scheme);
  for (size_t k = 0; k < adapters_.size(); ++k) {
    PetscReal a;
    PetscCall(adapters_[k]->Frequency2(std::max<PetscReal>(par_.penalty, 0), &a)); // collective
    if (a > loc.val) loc = {a, (int)k};
  }
  // a sphere against one like it, normal and tangential springs with their damping (GranularStableOmega)
  for (int i = 0; i < nl_; ++i) {
    const Primitive &p = prim_[i];
    if (p.shape != kSphere || p.fixed || p.mat < 0 || p.mat >= gnmat_ || !(p.mass > 0)) continue;
    const double w = fdem::kernels::GranularStableOmega(gtable_[(size_t)p.mat * gnmat_ + p.mat], p.mass, p.radius, p.offset, p.inertia);
    if (w * w > loc.val) loc = {w * w, (int)adapters_.size()};
  }
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm_));
  const PetscReal omega = std::sqrt(glob.val);
  const PetscReal r     = info.kcrit > 0 ? omega * dt / info.kcrit : PETSC_MAX_REAL;
  if (ratio) *ratio = r;
  if (r > 0.5)
    PetscCall(PetscPrintf(comm_,
                          "WARNING fdem contact: the contact frequency omega_c = %g (%s side; see doc/contact_engine.md) makes omega_c dt = %g, %.3g%% of the stability limit K_crit = %.4f of -ts_type %s; reduce dt below %g "
                          "or the penalty\n",
                          (double)omega, glob.kind >= (int)adapters_.size() ? "granular" : glob.kind >= 0 ? adapters_[glob.kind]->KindName() : "no", (double)(omega * dt), (double)(100 * r), (double)info.kcrit, scheme, (double)(0.5 * info.kcrit / omega)));
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
