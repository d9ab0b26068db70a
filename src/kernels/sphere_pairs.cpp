// Serial sphere-sphere pair loop (include/fdem/kernels/sphere_pairs.hpp).
#include "fdem/kernels/sphere_pairs.hpp"

#include <algorithm>
#include <string>

#include "fdem/kernels/error.hpp"

namespace fdem::kernels {

void SpherePairLoop::SetPairTable(std::vector<GranularPair> table, int nmat) {
  if (nmat <= 0 || static_cast<int>(table.size()) != nmat * nmat)
    throw InputError("SpherePairLoop: pair table size " + std::to_string(table.size()) + " is not " +
                     std::to_string(nmat) + "^2");
  table_ = std::move(table);
  nmat_ = nmat;
}

void SpherePairLoop::AddForces(const SphereArrays &s, double dt, double *f, double *t) {
  double rmax = 0;
  for (int i = 0; i < s.n; ++i) {
    if (!(s.radius[i] > 0) || !(s.mass[i] > 0))
      throw InputError("sphere " + std::to_string(s.id[i]) + ": radius and mass must be > 0");
    if (s.material[i] < 0 || s.material[i] >= nmat_)
      throw InputError("sphere " + std::to_string(s.id[i]) + ": material index " + std::to_string(s.material[i]) +
                       " is not in the pair table (" + std::to_string(nmat_) + " materials)");
    rmax = std::max(rmax, s.radius[i]);
  }
  next_.clear();
  touching_.clear();
  if (s.n > 1) {
    search_.Build(s.x, s.radius, s.n, 2 * rmax);
    search_.FindPairs(pairs_);
  } else {
    pairs_.clear();
  }
  for (auto [a, b] : pairs_) {
    // Orient the pair by global id so that the history has one sign.
    int i = a, j = b;
    if (s.id[i] > s.id[j]) std::swap(i, j);
    if (s.id[i] == s.id[j]) throw InputError("sphere " + std::to_string(s.id[i]) + " appears twice");
    const Vec3 xi{s.x[3 * i], s.x[3 * i + 1], s.x[3 * i + 2]}, xj{s.x[3 * j], s.x[3 * j + 1], s.x[3 * j + 2]};
    const Vec3 d = xi - xj;
    const double ri = s.radius[i], rj = s.radius[j], dist2 = dot(d, d), rs = ri + rj;
    if (dist2 >= rs * rs || dist2 == 0) continue;
    const double dist = std::sqrt(dist2);
    GranularContact c;
    c.n = (1.0 / dist) * d;
    c.overlap = rs - dist;
    const Vec3 vi{s.v[3 * i], s.v[3 * i + 1], s.v[3 * i + 2]}, vj{s.v[3 * j], s.v[3 * j + 1], s.v[3 * j + 2]};
    const Vec3 wi{s.w[3 * i], s.w[3 * i + 1], s.w[3 * i + 2]}, wj{s.w[3 * j], s.w[3 * j + 1], s.w[3 * j + 2]};
    c.vrel = vi - vj - cross(ri * wi + rj * wj, c.n);
    c.wrel = wi - wj;
    c.rstar = ri * rj / rs;
    c.mstar = s.mass[i] * s.mass[j] / (s.mass[i] + s.mass[j]);
    const std::uint64_t key = (static_cast<std::uint64_t>(s.id[i]) << 32) | static_cast<std::uint64_t>(s.id[j]);
    auto h = history_.find(key);
    Vec3 shear = h == history_.end() ? Vec3{} : h->second;
    const GranularResult r = GranularForce(table_[s.material[i] * nmat_ + s.material[j]], c, dt, shear);
    next_[key] = shear;
    touching_.emplace_back(i, j);
    const Vec3 fsum = r.fn + r.ft;
    const Vec3 ti = cross(-ri * c.n, r.ft) + r.mroll, tj = cross(rj * c.n, -r.ft) - r.mroll;
    for (int k = 0; k < 3; ++k) {
      f[3 * i + k] += fsum[k];
      f[3 * j + k] -= fsum[k];
      t[3 * i + k] += ti[k];
      t[3 * j + k] += tj[k];
    }
  }
  history_.swap(next_);
}

} // namespace fdem::kernels
