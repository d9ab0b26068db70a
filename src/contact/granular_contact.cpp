// Contacts with spheres inside the contact engine (doc/spheres.md): sphere-sphere and
// sphere-surface pairs, the granular force laws (kernels/granular.hpp) and the tangential
// springs kept in the slots of the sphere whose owner computes the contact.
#include "engine.hpp"
#include "../util/guard.hpp"
#include <fdem/kernels/granular_sweep.hpp>
#include <fdem/kernels/sphere_surface.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace fdem::contact {
using fdem::kernels::GranularContact;
using fdem::kernels::GranularLaw;
using fdem::kernels::GranularPair;
using fdem::kernels::GranularResult;
using fdem::kernels::TriFeature;

namespace {
std::uint64_t Mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  h *= 0xBF58476D1CE4E5B9ull;
  return h ^ (h >> 31);
}
// A contact's key in its holder's slots: the engine's tag in the top two bits, never 0.
std::int64_t SlotKey(int tag, std::uint64_t h) { return (std::int64_t)(((std::uint64_t)tag << 62) | (h & ((1ull << 62) - 1)) | 1ull); }
int          SlotTag(std::int64_t key) { return (int)((std::uint64_t)key >> 62); }

// The effective mass of a contact; a mass of 0 is an immovable body.
double EffectiveMass(double ma, double mb) { return ma > 0 && mb > 0 ? ma * mb / (ma + mb) : std::max(ma, mb); }

// The law of one contact: a Hooke pair given a restitution instead of a damping rate gets the
// rate that makes it, for this contact's effective mass.
const GranularPair &ForContact(const GranularPair &p, double mstar, GranularPair &tmp) {
  if (p.law != GranularLaw::Hooke || p.gamma_n > 0 || !(p.restitution < 1) || !(mstar > 0)) return p;
  tmp         = p;
  tmp.gamma_n = fdem::kernels::HookeDampingForRestitution(p.restitution, p.kn, mstar);
  return tmp;
}

// Whether the box of tetrahedron v's face opposite vertex o comes within reach of x along every
// axis, the reach padded far beyond round-off: a face that does not has no point nearer than reach.
bool FaceWithin(const Tet4 &v, int o, const Vec3 &x, double reach) {
  const Vec3 &a = v[(o + 1) % 4], &b = v[(o + 2) % 4], &c = v[(o + 3) % 4];
  for (int d = 0; d < 3; ++d) {
    const double pad = reach + 1e-9 * (reach + std::fabs(x[d]));
    if (std::max({a[d], b[d], c[d]}) < x[d] - pad || std::min({a[d], b[d], c[d]}) > x[d] + pad) return false;
  }
  return true;
}

// Barycentric weights of p (a point of the triangle a, b, c); equal thirds for a degenerate triangle.
void Weights(const Vec3 &p, const Vec3 &a, const Vec3 &b, const Vec3 &c, double w[3]) {
  const Vec3   e0 = b - a, e1 = c - a, e2 = p - a;
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(e2, e0), d21 = dot(e2, e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 1e-30 * (d00 * d11))) {
    w[0] = w[1] = w[2] = 1.0 / 3.0;
    return;
  }
  w[1] = (d11 * d20 - d01 * d21) / den;
  w[2] = (d00 * d21 - d01 * d20) / den;
  w[0] = 1 - w[1] - w[2];
}
} // namespace

void Engine::WriteSprings() {
  for (size_t j = 0; j < sp_.size(); ++j) {
    if (sp_[j].slot < 0) continue;
    const int        i = sph_[sp_[j].a];
    const Primitive &p = P(i);
    HistorySlot     *h = adapters_[p.kind]->History(i - first_[p.kind]);
    if (h)
      for (int k = 0; k < 3; ++k) h[sp_[j].slot].s[k] = sps_[j][k];
  }
}

PetscErrorCode Engine::FlushSprings() {
  PetscFunctionBegin;
  if (sp_.empty()) PetscFunctionReturn(0);
  for (auto *a : adapters_) PetscCall(a->HistoryBegin());
  WriteSprings();
  for (auto *a : adapters_) PetscCall(a->HistoryEnd());
  PetscFunctionReturn(0);
}

const GranularPair *Engine::Law(const Primitive &a, const Primitive &b) const {
  // a body without a granular material meets a sphere with the other side's material
  const int ma = a.mat >= 0 ? a.mat : b.mat, mb = b.mat >= 0 ? b.mat : a.mat;
  if (ma < 0 || ma >= gnmat_ || mb >= gnmat_) {
    const Primitive &m = a.mat < 0 || a.mat >= gnmat_ ? a : b, &o = &m == &a ? b : a;
    throw std::runtime_error(adapters_[m.kind]->BodyName(m) + " touches " + adapters_[o.kind]->BodyName(o) + " but has no granular material (a sphere's contacts need one on both sides: give the body a material; see doc/spheres.md)");
  }
  const GranularPair &p = gtable_[(size_t)ma * gnmat_ + mb];
  if (!(p.kn > 0) && !(p.estar > 0)) throw std::runtime_error(adapters_[a.kind]->BodyName(a) + " and " + adapters_[b.kind]->BodyName(b) + ": their materials give no granular law (see the set-up's message)");
  return &p;
}

// The contacts of the spheres with the surfaces near them (sgroup_) at the current state:
// the candidate tetrahedra of one body near one sphere, their surface triangles as one surface
// (one contact per touched face, edge or vertex, or per copy of a vertex or an edge of split
// cells), each handed to fn with its law, its spring's key and its weight.
void Engine::SurfaceHits(const std::function<void(const SurfaceHit &)> &fn) {
  std::vector<Vec3>                          nodes;
  std::vector<PetscInt>                      ids, keys;
  std::vector<int>                           group; // per node: its vertex among the copies (keys)
  std::vector<std::array<int, 3>>            tris;
  std::vector<std::array<int, 4>>            src; // per triangle: its tetrahedron and the three vertices
  std::vector<int>                           cand;
  std::vector<fdem::kernels::SurfaceContact> contacts;
  for (const SurfaceGroup &grp : sgroup_) {
    const int        si = grp.sphere;
    const Primitive &S  = P(si);
    const Vec3       xs = X(si)[0];
    nodes.clear();
    ids.clear();
    keys.clear();
    tris.clear();
    bool split = false;
    src.clear();
    for (int f = grp.begin; f < grp.end; ++f) {
      const int        t = sface_[f][0], o = sface_[f][1];
      const Primitive &T = P(t);
      const Tet4      &v = X(t);
      if (!FaceWithin(v, o, xs, S.radius)) continue; // SphereSurfaceContacts looks only at faces touched
      std::array<int, 3> tri, vq;
      for (int m = 0; m < 3; ++m) {
        const int q = (o + 1 + m) % 4;
        // a split cell's nodes are its own: each a copy of the vertex its key names
        const PetscInt key = T.node[q] >= 0 ? T.node[q] : -1 - (PetscInt)(4 * t + q);
        const PetscInt id  = T.flags & 2 ? -2 - (4 * (PetscInt)T.elem + q) : key;
        int            li  = (int)(std::find(ids.begin(), ids.end(), id) - ids.begin());
        if (li == (int)ids.size()) {
          ids.push_back(id);
          keys.push_back(key);
          nodes.push_back(v[q]);
        }
        split = split || (T.flags & 2);
        tri[m] = li;
        vq[m]  = q;
      }
      tris.push_back(tri);
      src.push_back({t, vq[0], vq[1], vq[2]});
    }
    if (tris.empty()) continue; // most candidates of a search are apart at a given evaluation
    cand.resize(tris.size());
    for (size_t k = 0; k < tris.size(); ++k) cand[k] = (int)k;
    if (split) {
      group.resize(keys.size());
      for (size_t k = 0; k < keys.size(); ++k) group[k] = (int)(std::find(keys.begin(), keys.end(), keys[k]) - keys.begin());
    }
    fdem::kernels::SphereSurfaceContacts(xs, S.radius, nodes, tris, cand, contacts, split ? &group : nullptr);
    for (const auto &ct : contacts) {
      const auto      &s4  = src[ct.tri];
      const int        t   = s4[0];
      const Primitive &T   = P(t);
      GranularPair     tmp;
      double           w[3];
      Weights(ct.point, X(t)[s4[1]], X(t)[s4[2]], X(t)[s4[3]], w);
      const Vec3 vsurf = w[0] * V(t)[s4[1]] + w[1] * V(t)[s4[2]] + w[2] * V(t)[s4[3]];
      GranularContact c;
      c.n       = ct.n;
      c.overlap = ct.overlap;
      c.vrel    = V(si)[0] - S.radius * cross(V(si)[1], ct.n) - vsurf;
      c.wrel    = V(si)[1];
      c.rstar   = S.radius;
      c.mstar   = EffectiveMass(S.mass, T.mass);
      const GranularPair &law = ForContact(*Law(S, T), c.mstar, tmp);
      // the feature's key: on a flat face of a rigid skin (the triangle's face, or an edge or
      // vertex right below the centre, the normal the face's), the body and that flat face, so
      // that the spring carries over from one triangle of the face to the next; elsewhere the
      // body and the node ids of the face, edge or vertex touched
      const auto        &tri   = tris[ct.tri];
      const std::int32_t facet = T.facet[6 - s4[1] - s4[2] - s4[3]]; // the face opposite the fourth vertex
      bool               flat  = facet >= 0 && ct.feature == TriFeature::Face;
      if (facet >= 0 && !flat) {
        const Vec3   nt  = cross(X(t)[s4[2]] - X(t)[s4[1]], X(t)[s4[3]] - X(t)[s4[1]]);
        const double len = norm(nt);
        flat             = len > 0 && std::fabs(dot(ct.n, nt)) > (1 - 1e-12) * len; // the triangle's winding is either way
      }
      std::uint64_t h;
      if (flat) h = Mix(Mix(Mix(3, (std::uint64_t)T.kind), (std::uint64_t)T.body), (std::uint64_t)facet);
      else {
        PetscInt f[3];
        int      nf = 0;
        switch (ct.feature) {
        case TriFeature::Face: f[0] = ids[tri[0]], f[1] = ids[tri[1]], f[2] = ids[tri[2]], nf = 3; break;
        case TriFeature::EdgeAB: f[0] = ids[tri[0]], f[1] = ids[tri[1]], nf = 2; break;
        case TriFeature::EdgeBC: f[0] = ids[tri[1]], f[1] = ids[tri[2]], nf = 2; break;
        case TriFeature::EdgeCA: f[0] = ids[tri[2]], f[1] = ids[tri[0]], nf = 2; break;
        case TriFeature::VertexA: f[0] = ids[tri[0]], nf = 1; break;
        case TriFeature::VertexB: f[0] = ids[tri[1]], nf = 1; break;
        case TriFeature::VertexC: f[0] = ids[tri[2]], nf = 1; break;
        }
        std::sort(f, f + nf);
        h = Mix(Mix(Mix(2, (std::uint64_t)T.kind), (std::uint64_t)T.body), (std::uint64_t)nf);
        for (int m = 0; m < nf; ++m) h = Mix(h, (std::uint64_t)f[m]);
      }
      if (S.elem) h = Mix(h, (std::uint64_t)S.elem); // the sphere within its clump
      // a copy of a vertex or an edge of a fracturable body's split cells: its part of the
      // contact, 1 over the copies on the surface (doc/fracture.md, "Spheres on a fracturing
      // body"); it changes only at a listing, where joints broke
      double share = 1;
      switch (ct.feature) {
      case TriFeature::Face: break;
      case TriFeature::EdgeAB: share = T.share[4 + fdem::kernels::TetEdgeSlot(s4[1], s4[2])]; break;
      case TriFeature::EdgeBC: share = T.share[4 + fdem::kernels::TetEdgeSlot(s4[2], s4[3])]; break;
      case TriFeature::EdgeCA: share = T.share[4 + fdem::kernels::TetEdgeSlot(s4[3], s4[1])]; break;
      case TriFeature::VertexA: share = T.share[s4[1]]; break;
      case TriFeature::VertexB: share = T.share[s4[2]]; break;
      case TriFeature::VertexC: share = T.share[s4[3]]; break;
      }
      const SurfaceHit q = {si, t, {s4[1], s4[2], s4[3]}, {w[0], w[1], w[2]}, c, &law, SlotKey(gtag_, h), share};
      fn(q);
    }
  }
}

// The normal elastic energy of the sphere-surface contacts at the current state, their
// weights included (the springs left out), on this rank.
double Engine::SurfaceEnergy() {
  double e = 0;
  SurfaceHits([&](const SurfaceHit &q) { e += q.share * fdem::kernels::GranularElasticEnergy(*q.law, q.c.overlap, q.c.rstar, Vec3()); });
  return e;
}

PetscErrorCode Engine::GranularForces(PetscReal sums[3], std::array<double, 3> &deep) {
  PetscFunctionBegin;
  const double dt = has_time_ ? time_ - last_time_ : 0;
  last_time_      = time_;
  has_time_       = true;
  for (auto *a : adapters_) PetscCall(a->HistoryBegin());
  PetscInt overflow = 0;
  PetscCall(fdem::Guard(comm_, [&]() -> PetscErrorCode {
    // 1. the springs stay in their holder's slots: a contact's slot is found by its key (or a
    //    free one taken, from zero) and marked seen; after the pairs, this engine's slots that
    //    were not seen (contacts that opened) are freed, in the spheres that held any before
    seen_.assign(nl_, 0);
    hslots_.assign(nl_, nullptr); // each holder's slots, looked up once
    std::uint16_t *const seen = seen_.data();
    HistorySlot **const  hp   = hslots_.data();
    // the spheres of one clump (consecutive own primitives of one body) share their body's
    // slots: a slot's use is marked on the first of them
    auto first_of = [&](int i) {
      while (i > 0 && P(i - 1).shape == kSphere && P(i - 1).kind == P(i).kind && P(i - 1).body == P(i).body) --i;
      return i;
    };
    auto                       slots = [&](int i) { // own sphere i's slots
      if (!hp[i]) hp[i] = adapters_[P(i).kind]->History(i - first_[P(i).kind]);
      return hp[i];
    };
    Vec3                       spare;            // the spring of a contact without a slot (it restarts from zero)
    auto                       spring = [&](int i, std::int64_t key) -> double * {
      HistorySlot *h = slots(i);
      if (h) {
        for (int k = 0; k < kHistorySlots; ++k)
          if (h[k].key == key) {
            seen[first_of(i)] |= (std::uint16_t)(1u << k);
            return h[k].s;
          }
        for (int k = 0; k < kHistorySlots; ++k)
          if (!h[k].key) {
            h[k] = HistorySlot{key, {0, 0, 0}};
            seen[first_of(i)] |= (std::uint16_t)(1u << k);
            return h[k].s;
          }
        ++overflow;
      }
      spare = Vec3();
      return &spare[0];
    };
    auto take = [&](double *p) { return Vec3(p[0], p[1], p[2]); };
    auto keep = [&](double *p, const Vec3 &v) { p[0] = v[0], p[1] = v[1], p[2] = v[2]; };
    auto first = [&](double ratio, int a, int b) {
      if (!checked_initial_ && ratio > deep[0]) deep = {ratio, (double)a, (double)b};
    };

    // 2. sphere-sphere: a is the holder (own), n from b to a. After a search the pairs are
    //    made once (sp_): sorted by holder, the spheres numbered compactly, each pair's law,
    //    effective mass, Hooke damping and key, and the slot of its spring found by the key; a
    //    pair keeps its slot from then on, takes a free one when it starts touching and frees
    //    it when it stops. Its spring is kept with the pair (sps_, in the pairs' order) and
    //    written to the slot at a flush: before the next search's pairs are made, and when the
    //    state goes back to the swarm (FlushSprings, before a migration or a checkpoint). At
    //    each evaluation the centres, velocities and spins go to compact arrays (a sphere's
    //    Vertices record is 96 bytes), and one sweep over the pairs runs the law of the touching
    //    ones and sums the forces per sphere in the order of the pairs.
    if (sp_fresh_) {
      WriteSprings(); // the old pairs' springs to their slots first (the numbering is still theirs)
      std::vector<int> comp(nl_ + ng_, -1);
      sph_.clear();
      sr_.clear();
      auto number = [&](int i) {
        if (comp[i] < 0) {
          comp[i] = (int)sph_.size();
          sph_.push_back(i);
          sr_.push_back(P(i).radius);
        }
        return comp[i];
      };
      { // sorted by holder, then by the other sphere: a counting sort by holder (own: the owner
        // of the holder computes the pair), then each holder's few pairs in order
        std::vector<int> start(nl_ + 1, 0);
        for (const auto &p : ss_) {
          if (p[0] < 0 || p[0] >= nl_) throw std::logic_error("contact: a sphere pair whose holder is not on this rank");
          ++start[p[0] + 1];
        }
        for (int i = 0; i < nl_; ++i) start[i + 1] += start[i];
        std::vector<std::array<int, 2>> by(ss_.size());
        for (const auto &p : ss_) by[start[p[0]]++] = p;
        for (size_t b = 0, e; b < by.size(); b = e) {
          for (e = b + 1; e < by.size() && by[e][0] == by[b][0]; ++e) {}
          std::sort(by.begin() + (std::ptrdiff_t)b, by.begin() + (std::ptrdiff_t)e);
        }
        ss_.swap(by);
      }
      for (const auto &p : ss_) number(p[0]);
      sfirst_.resize(sph_.size()); // the holders are numbered first, and are all own
      for (size_t c = 0; c < sph_.size(); ++c) sfirst_[c] = first_of(sph_[c]);
      sp_.resize(ss_.size());
      spc_.resize(ss_.size());
      sps_.resize(ss_.size());
      for (size_t j = 0; j < ss_.size(); ++j) {
        const int        a = ss_[j][0], b = ss_[j][1];
        const Primitive &A = P(a), &B = P(b);
        const int        ma = A.mat >= 0 ? A.mat : B.mat, mb = B.mat >= 0 ? B.mat : A.mat;
        int              law = ma >= 0 && ma < gnmat_ && mb < gnmat_ ? ma * gnmat_ + mb : -1;
        if (law >= 0 && !(gtable_[law].kn > 0) && !(gtable_[law].estar > 0)) law = -1; // Law() says why, if they touch
        SpherePairConst &c = spc_[j];
        std::uint64_t    kh = Mix(Mix(1, (std::uint64_t)B.kind), (std::uint64_t)B.key);
        if (A.elem) kh = Mix(kh, (std::uint64_t)A.elem); // the holder's sphere within its clump (its body's slots are shared)
        c.key = SlotKey(gtag_, kh);
        c.mstar            = EffectiveMass(A.mass, B.mass);
        c.cn               = 0;
        if (law >= 0) {
          GranularPair tmp;
          c.cn = c.mstar * ForContact(gtable_[law], c.mstar, tmp).gamma_n;
        }
        int          k = -1;
        HistorySlot *h = slots(a);
        for (int m = 0; h && m < kHistorySlots && k < 0; ++m)
          if (h[m].key == c.key) k = m;
        sp_[j]  = SpherePair{number(a), number(b), k, law};
        sps_[j] = k >= 0 ? Vec3(h[k].s[0], h[k].s[1], h[k].s[2]) : Vec3();
      }
      // the own spheres by adapter: read and given their forces without the vertex records
      // (the ghosts, ghost_c_, from their records)
      own_sph_.assign(adapters_.size(), {});
      own_c_.assign(adapters_.size(), {});
      ghost_c_.clear();
      for (int c = 0; c < (int)sph_.size(); ++c)
        if (sph_[c] < nl_) {
          const int k = prim_[sph_[c]].kind;
          own_sph_[k].push_back(sph_[c] - first_[k]);
          own_c_[k].push_back(c);
        } else ghost_c_.push_back(c);
      // the sphere-surface groups (st_ is grouped by sphere, then by body) and the surface faces
      // of each that the sphere may reach before the next search: a face whose box is farther
      // from the sphere's centre than its radius and the two margins (padded far beyond
      // round-off) along an axis stays out of reach until then
      sgroup_.clear();
      sface_.clear();
      for (size_t g = 0; g < st_.size();) {
        const int        si = st_[g][0];
        const Primitive &S = P(si), &T0 = P(st_[g][1]);
        size_t           e = g;
        while (e < st_.size() && st_[e][0] == si && P(st_[e][1]).kind == T0.kind && P(st_[e][1]).body == T0.body) ++e;
        const Vec3 xs = X(si)[0];
        const int  begin = (int)sface_.size();
        for (size_t j = g; j < e; ++j) {
          const int        t = st_[j][1];
          const Primitive &T = P(t);
          const Tet4      &v = X(t);
          for (int o = 0; o < 4; ++o)
            if ((T.surface >> o & 1) && FaceWithin(v, o, xs, S.radius + S.margin + T.margin)) sface_.push_back({t, o});
        }
        if ((int)sface_.size() > begin) sgroup_.push_back({si, begin, (int)sface_.size()});
        g = e;
      }
      sp_fresh_ = false;
    }
    const int ns = (int)sph_.size();
    snow_.resize((size_t)ns);
    ssum_.assign((size_t)ns, SphereSum{});
    SphereNow *const sn = snow_.data();
    SphereSum *const su = ssum_.data();
    auto holder = [&](int c) { return slots(sph_[c]); }; // a holder is own; looked up when a contact starts or ends
    for (size_t k = 0; k < adapters_.size(); ++k)
      if (!own_c_[k].empty()) PetscCall(adapters_[k]->SphereStates((int)own_c_[k].size(), own_sph_[k].data(), own_c_[k].data(), sn));
    for (int c : ghost_c_) { // from the sphere exchange, or from their records
      const int i = sph_[c];
      sn[c]       = sphere_only_ ? gs_[i - nl_] : SphereNow{X(i)[0], V(i)[0], V(i)[1], sr_[c]};
    }
    // the pairs in one sweep (granular_sweep.hpp): each touching pair's law, its forces summed
    // per sphere in the pairs' order; then what the sweep listed: a pair with no law or with
    // both centres at one point is an error, a contact that opened frees its slot, one that
    // started takes a free slot (its spring, advanced from zero, is kept if it gets one)
    fdem::kernels::SphereContactSweep(gtable_.data(), dt, sn, sp_.data(), spc_.data(), sps_.data(), (int)sp_.size(), su, sweep_);
    for (int j : sweep_.bad) {
      const SpherePair &q = sp_[j];
      if (q.law < 0) Law(P(sph_[q.a]), P(sph_[q.b])); // throws: no law for these two
      throw std::runtime_error(adapters_[P(sph_[q.a]).kind]->BodyName(P(sph_[q.a])) + " and " + adapters_[P(sph_[q.b]).kind]->BodyName(P(sph_[q.b])) + " have the same centre");
    }
    for (int j : sweep_.opened) {
      SpherePair &q = sp_[j];
      holder(q.a)[q.slot] = HistorySlot{}, q.slot = -1;
    }
    for (int j : sweep_.started) {
      SpherePair  &q = sp_[j];
      HistorySlot *h = holder(q.a);
      for (int k = 0; h && k < kHistorySlots && q.slot < 0; ++k)
        if (!h[k].key) h[k] = HistorySlot{spc_[j].key, {0, 0, 0}}, q.slot = k;
      if (h && q.slot < 0) ++overflow; // its spring restarts from zero at every evaluation
    }
    const int nt = (int)sweep_.touching.size();
    sums[0] += sweep_.energy;
    if (!holders_valid_ || !holders_.empty()) // the slots in use, for the sweep of unseen slots below
      for (int j : sweep_.touching) {
        const SpherePair &q = sp_[j];
        if (q.slot >= 0) seen[sfirst_[q.a]] |= (std::uint16_t)(1u << q.slot);
      }
    if (!checked_initial_)
      for (int j : sweep_.touching) { // deep: an overlap of half the smaller radius
        const SpherePair &q = sp_[j];
        const SphereNow  &A = sn[q.a], &B = sn[q.b];
        first((A.r + B.r - norm(A.x - B.x)) / (0.5 * std::min(A.r, B.r)), sph_[q.a], sph_[q.b]);
      }
    sums[1] += nt;
    for (size_t k = 0; k < adapters_.size(); ++k)
      if (!own_c_[k].empty()) PetscCall(adapters_[k]->AddSphereForces((int)own_c_[k].size(), own_sph_[k].data(), own_c_[k].data(), su));
    if (sphere_only_) gfs_.assign(ng_, SphereSum{});
    for (int c : ghost_c_) { // the ghosts' forces go back to their owners
      if (sphere_only_) {
        gfs_[sph_[c] - nl_] = su[c];
        continue;
      }
      Force(sph_[c])[0] += su[c].f;
      Force(sph_[c])[1] += su[c].t;
    }

    // 3. sphere-surface (SurfaceHits)
    SurfaceHits([&](const SurfaceHit &q) {
      const Primitive     &S  = P(q.sphere);
      double              *sp = spring(q.sphere, q.key);
      Vec3                 s  = take(sp);
      const GranularResult r  = fdem::kernels::GranularForce(*q.law, q.c, dt, s);
      keep(sp, s);
      const Vec3 F = q.share * (r.fn + r.ft);
      Force(q.sphere)[0] += F;
      Force(q.sphere)[1] += cross(-S.radius * q.c.n, F) + q.share * r.mroll;
      for (int m = 0; m < 3; ++m) Force(q.tet)[q.vertex[m]] -= q.w[m] * F;
      sums[0] += q.share * fdem::kernels::GranularElasticEnergy(*q.law, q.c.overlap, q.c.rstar, s);
      sums[1] += 1;
      first(q.c.overlap / (0.5 * S.radius), q.sphere, q.tet);
    });
    // free this engine's slots that no contact saw. A sphere-sphere pair frees its own slot when
    // it opens; what else may leave a slot behind is a pair that is no longer a candidate (after
    // a search or a listing: every own sphere is swept then) or a sphere-surface contact (the
    // spheres of st_ are swept at every evaluation)
    auto sweep = [&](int i) {
      if (prim_[i].shape != kSphere || first_of(i) != i) return;
      HistorySlot *h = slots(i);
      if (!h) return;
      for (int k = 0; k < kHistorySlots; ++k)
        if (h[k].key && SlotTag(h[k].key) == gtag_ && !(seen[i] >> k & 1u)) h[k] = HistorySlot{};
    };
    if (!holders_valid_) {
      for (int i = 0; i < nl_; ++i) sweep(i);
      holders_.clear();
      for (const auto &p : st_)
        if (p[0] < nl_ && (holders_.empty() || holders_.back() != first_of(p[0]))) holders_.push_back(first_of(p[0])); // st_ is grouped by sphere
    } else
      for (int i : holders_) sweep(i);
    holders_valid_ = true;
    return 0;
  }));
  for (auto *a : adapters_) PetscCall(a->HistoryEnd());
  sums[2] += (PetscReal)overflow; // summed over the ranks with the energy (Evaluate)
  PetscFunctionReturn(0);
}
} // namespace fdem::contact
