// Serial sphere-sphere pair loop (include/fdem/kernels/sphere_pairs.hpp).
#include "fdem/kernels/sphere_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

void SpherePairLoop::SetSkin(double skin) {
  if (!(skin >= 0) || !std::isfinite(skin)) throw InputError("SpherePairLoop: skin " + std::to_string(skin) + " must be >= 0");
  skin_ = skin;
  valid_ = false;
}

namespace {
inline std::uint64_t Key(std::int64_t a, std::int64_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
}
} // namespace

void SpherePairLoop::AddForces(const SphereArrays &s, double dt, double *f, double *t) {
  bool search = !valid_ || static_cast<int>(xref_.size()) != 3 * s.n;
  if (!search) {
    const double lim = 0.25 * skin_ * skin_;
    for (int i = 0; i < s.n && !search; ++i) {
      const double dx = s.x[3 * i] - xref_[3 * i], dy = s.x[3 * i + 1] - xref_[3 * i + 1], dz = s.x[3 * i + 2] - xref_[3 * i + 2];
      search = dx * dx + dy * dy + dz * dz > lim;
    }
  }
  if (search) {
    double rmax = 0;
    for (int i = 0; i < s.n; ++i) {
      if (!(s.radius[i] > 0) || !(s.mass[i] > 0))
        throw InputError("sphere " + std::to_string(s.id[i]) + ": radius and mass must be > 0");
      if (!(std::isfinite(4 * s.radius[i]) && std::isfinite(s.mass[i]) && std::isfinite(s.x[3 * i]) && std::isfinite(s.x[3 * i + 1]) && std::isfinite(s.x[3 * i + 2]))) {
        char msg[200];
        std::snprintf(msg, sizeof msg, ": radius %g, mass %g, position %g %g %g: out of the range of numbers (a size, density, position or velocity too large, or a step made it so)", s.radius[i],
                      s.mass[i], s.x[3 * i], s.x[3 * i + 1], s.x[3 * i + 2]);
        throw InputError("sphere " + std::to_string(s.id[i]) + msg);
      }
      if (s.material[i] < 0 || s.material[i] >= nmat_)
        throw InputError("sphere " + std::to_string(s.id[i]) + ": material index " + std::to_string(s.material[i]) +
                         " is not in the pair table (" + std::to_string(nmat_) + " materials)");
      rmax = std::max(rmax, s.radius[i]);
    }
    // Carry the springs of touching contacts over to the new candidate list.
    carry_.clear();
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (touch_[k]) carry_[Key(prev_id_[2 * k], prev_id_[2 * k + 1])] = shear_[k];
    radius_.resize(s.n);
    for (int i = 0; i < s.n; ++i) radius_[i] = s.radius[i] + 0.5 * skin_;
    if (s.n > 1) {
      search_.Build(s.x, radius_.data(), s.n, 2 * (rmax + 0.5 * skin_));
      search_.FindPairs(pairs_);
    } else {
      pairs_.clear();
    }
    shear_.assign(pairs_.size(), Vec3{});
    touch_.assign(pairs_.size(), 0);
    prev_id_.resize(2 * pairs_.size());
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      auto &[i, j] = pairs_[k];
      if (s.id[i] > s.id[j]) std::swap(i, j);
      if (s.id[i] == s.id[j]) throw InputError("sphere " + std::to_string(s.id[i]) + " appears twice");
      prev_id_[2 * k] = s.id[i];
      prev_id_[2 * k + 1] = s.id[j];
      auto h = carry_.find(Key(s.id[i], s.id[j]));
      if (h != carry_.end()) {
        shear_[k] = h->second;
        touch_[k] = 1;
      }
    }
    xref_.assign(s.x, s.x + 3 * s.n);
    valid_ = true;
    ++searches_;
  }
  touching_.clear();
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const int i = pairs_[k].first, j = pairs_[k].second;
    const Vec3 xi{s.x[3 * i], s.x[3 * i + 1], s.x[3 * i + 2]}, xj{s.x[3 * j], s.x[3 * j + 1], s.x[3 * j + 2]};
    const Vec3 d = xi - xj;
    const double ri = s.radius[i], rj = s.radius[j], dist2 = dot(d, d), rs = ri + rj;
    if (dist2 >= rs * rs || dist2 == 0) {
      touch_[k] = 0;
      shear_[k] = Vec3{};
      continue;
    }
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
    const GranularResult r = GranularForce(table_[s.material[i] * nmat_ + s.material[j]], c, dt, shear_[k]);
    touch_[k] = 1;
    touching_.emplace_back(i, j);
    const Vec3 fsum = r.fn + r.ft;
    const Vec3 ti = cross(-ri * c.n, r.ft) + r.mroll, tj = cross(rj * c.n, -r.ft) - r.mroll;
    for (int q = 0; q < 3; ++q) {
      f[3 * i + q] += fsum[q];
      f[3 * j + q] -= fsum[q];
      t[3 * i + q] += ti[q];
      t[3 * j + q] += tj[q];
    }
  }
}

} // namespace fdem::kernels
