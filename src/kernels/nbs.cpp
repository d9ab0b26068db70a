// Munjiza-NBS style cell search (book ch. 3, SPEC.md D.2), sort form.
// The book keeps z-, y- and x-lists in integer arrays indexed by cell
// coordinate (C[n_z], B[2][n_y], A[2][n_x]); here the same (z, y, x) order
// comes from an LSD radix sort of packed cell keys, so nothing is indexed by
// cell coordinate and a huge coordinate range costs no memory.
#include "fdem/kernels/nbs.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "fdem/kernels/error.hpp"

namespace fdem::kernels {
namespace {

int BitsFor(std::uint64_t v) {
  int b = 0;
  while (v) { ++b; v >>= 1; }
  return b;
}

} // namespace

void CellSearch::Build(const double *c, const double *radii, int n, double cell) {
  if (n < 0) throw InputError("CellSearch::Build: negative element count " + std::to_string(n));
  if (!(cell > 0) || !std::isfinite(cell))
    throw InputError("CellSearch::Build: cell size must be finite and > 0, got " + std::to_string(cell));
  n_ = n;
  cell_ = cell;
  have_radii_ = radii != nullptr;
  cell_start_.clear();
  cell_x_.clear();
  row_cell_.clear();
  row_z_.clear();
  row_y_.clear();
  if (n == 0) {
    row_cell_.push_back(0);
    cell_start_.push_back(0);
    return;
  }
  double lo[3] = {c[0], c[1], c[2]}, hi[3] = {c[0], c[1], c[2]};
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      const double v = c[3 * i + d];
      if (!std::isfinite(v))
        throw InputError("CellSearch::Build: element " + std::to_string(i) + " has a non-finite centre coordinate");
      lo[d] = std::min(lo[d], v);
      hi[d] = std::max(hi[d], v);
    }
  if (radii)
    for (int i = 0; i < n; ++i)
      if (!(radii[i] >= 0) || !(2 * radii[i] <= cell))
        throw InputError("CellSearch::Build: element " + std::to_string(i) + " has radius " +
                         std::to_string(radii[i]) + "; radii must be >= 0 with diameter <= cell size " +
                         std::to_string(cell));
  // Slightly larger cells than d, so that rounding in the cell index can never
  // put two elements at distance <= d two cells apart.
  const double ext = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double h = cell * (1 + 1e-12) + 1e-15 * ext;
  const double inv = 1.0 / h;
  if (ext * inv > 4.0e18)
    throw InputError("CellSearch::Build: coordinate range / cell size exceeds 4e18 cells");
  ix_.resize(n);
  iy_.resize(n);
  iz_.resize(n);
  std::uint64_t mx[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    ix_[i] = static_cast<std::uint64_t>((c[3 * i] - lo[0]) * inv);
    iy_[i] = static_cast<std::uint64_t>((c[3 * i + 1] - lo[1]) * inv);
    iz_[i] = static_cast<std::uint64_t>((c[3 * i + 2] - lo[2]) * inv);
    mx[0] = std::max(mx[0], ix_[i]);
    mx[1] = std::max(mx[1], iy_[i]);
    mx[2] = std::max(mx[2], iz_[i]);
  }
  const int bx = BitsFor(mx[0]), by = BitsFor(mx[1]), bz = BitsFor(mx[2]);
  const int total = bx + by + bz;
  order_.resize(n);
  if (total <= 64) {
    // Packed key z|y|x, LSD radix sort with digits sized to n.
    sort_a_.resize(n);
    sort_b_.resize(n);
    for (int i = 0; i < n; ++i) {
      std::uint64_t k = ix_[i];
      if (by) k |= iy_[i] << bx;
      if (bz) k |= iz_[i] << (bx + by);
      sort_a_[i] = {k, i};
    }
    if (total > 0) {
      int bmax = 4;
      while (bmax < 12 && (std::int64_t(1) << (bmax + 3)) <= n) ++bmax;
      const int passes = (total + bmax - 1) / bmax;
      const int b = (total + passes - 1) / passes;
      const std::uint64_t mask = (std::uint64_t(1) << b) - 1;
      count_.resize(std::size_t(1) << b);
      KeyIndex *src = sort_a_.data(), *dst = sort_b_.data();
      for (int p = 0; p < passes; ++p) {
        const int shift = p * b;
        std::fill(count_.begin(), count_.end(), 0u);
        for (int i = 0; i < n; ++i) ++count_[(src[i].key >> shift) & mask];
        std::uint32_t s = 0;
        for (auto &v : count_) { const std::uint32_t t = v; v = s; s += t; }
        for (int i = 0; i < n; ++i) dst[count_[(src[i].key >> shift) & mask]++] = src[i];
        std::swap(src, dst);
      }
      for (int i = 0; i < n; ++i) order_[i] = src[i].index;
    } else {
      for (int i = 0; i < n; ++i) order_[i] = i;
    }
  } else {
    // More than 2^64 cells in the bounding box: comparison sort on (z, y, x).
    for (int i = 0; i < n; ++i) order_[i] = i;
    std::sort(order_.begin(), order_.end(), [this](std::int64_t a, std::int64_t b) {
      return std::tie(iz_[a], iy_[a], ix_[a]) < std::tie(iz_[b], iy_[b], ix_[b]);
    });
  }
  // Element data in cell order, then runs of cells and rows.
  x_.resize(n);
  y_.resize(n);
  z_.resize(n);
  r_.resize(have_radii_ ? n : 0);
  id_.resize(n);
  for (int p = 0; p < n; ++p) {
    const std::int64_t i = order_[p];
    x_[p] = c[3 * i];
    y_[p] = c[3 * i + 1];
    z_[p] = c[3 * i + 2];
    if (have_radii_) r_[p] = radii[i];
    id_[p] = static_cast<int>(i);
    const std::uint64_t X = ix_[i], Y = iy_[i], Z = iz_[i];
    const bool new_row = p == 0 || Z != row_z_.back() || Y != row_y_.back();
    if (new_row) {
      row_cell_.push_back(static_cast<int>(cell_x_.size()));
      row_z_.push_back(Z);
      row_y_.push_back(Y);
    }
    if (new_row || X != cell_x_.back()) {
      cell_start_.push_back(p);
      cell_x_.push_back(X);
    }
  }
  cell_start_.push_back(n);
  row_cell_.push_back(static_cast<int>(cell_x_.size()));
  cell_x_.push_back(~std::uint64_t(0)); // sentinel, not a cell
}

void CellSearch::FindPairs(std::vector<std::pair<int, int>> &pairs) const {
  const int nrows = NumRows();
  if (nrows <= 0) {
    pairs.clear();
    return;
  }
  // The book's half mask (3.73) as row offsets (dz, dy), each with cells
  // x-1..x+1; the same row contributes the cell itself and cell x-1. Cells of a
  // row are consecutive in element order, so each mask row is one contiguous
  // range of elements, scanned with a branch-free test and append.
  constexpr int kDz[4] = {0, -1, -1, -1};
  constexpr int kDy[4] = {-1, -1, 0, 1};
  int ptr[4] = {0, 0, 0, 0};
  int nb[4], q[4]; // neighbour row of each offset (-1: none) and its cell cursor
  std::size_t cnt = 0;
  if (pairs.size() < std::size_t(n_)) pairs.resize(std::size_t(n_));
  const double *X = x_.data(), *Y = y_.data(), *Z = z_.data(), *R = r_.data();
  const int *id = id_.data();
  const double d = cell_;
  for (int r = 0; r < nrows; ++r) {
    const int c0 = row_cell_[r], c1 = row_cell_[r + 1];
    const std::uint64_t rz = row_z_[r], ry = row_y_[r];
    for (int k = 0; k < 4; ++k) {
      nb[k] = -1;
      if ((kDz[k] < 0 && rz == 0) || (kDy[k] < 0 && ry == 0)) continue;
      const std::uint64_t tz = rz + kDz[k], ty = ry + kDy[k];
      int &p = ptr[k];
      while (p < nrows && (row_z_[p] < tz || (row_z_[p] == tz && row_y_[p] < ty))) ++p;
      if (p < nrows && row_z_[p] == tz && row_y_[p] == ty) {
        nb[k] = p;
        q[k] = row_cell_[p];
      }
    }
    for (int c = c0; c < c1; ++c) {
      const std::uint64_t cx = cell_x_[c];
      int rb[5], re[5], nr = 0;
      if (c > c0 && cell_x_[c - 1] + 1 == cx) {
        rb[nr] = cell_start_[c - 1];
        re[nr++] = cell_start_[c];
      }
      for (int k = 0; k < 4; ++k) {
        if (nb[k] < 0) continue;
        const int n1 = row_cell_[nb[k] + 1];
        int &m = q[k];
        while (m < n1 && cell_x_[m] + 1 < cx) ++m;
        // At most three cells (distinct x) fall in x-1..x+1: branch-free count.
        // cell_x_ ends with a sentinel, so reading at e == n1 is in bounds.
        int e = m;
        e += (e < n1) & (cell_x_[e] <= cx + 1);
        e += (e < n1) & (cell_x_[e] <= cx + 1);
        e += (e < n1) & (cell_x_[e] <= cx + 1);
        if (e > m) {
          rb[nr] = cell_start_[m];
          re[nr++] = cell_start_[e];
        }
      }
      const int b = cell_start_[c], e = cell_start_[c + 1];
      std::size_t most = std::size_t(e - b) * (e - b);
      for (int k = 0; k < nr; ++k) most += std::size_t(e - b) * (re[k] - rb[k]);
      if (cnt + most > pairs.size()) pairs.resize(2 * (cnt + most));
      std::pair<int, int> *out = pairs.data();
      for (int i = b; i < e; ++i) {
        const double xi = X[i], yi = Y[i], zi = Z[i];
        const double ri = have_radii_ ? R[i] : 0.0;
        const int ii = id[i];
        auto scan = [&](int j0, int j1) {
          for (int j = j0; j < j1; ++j) {
            const double s = have_radii_ ? ri + R[j] : d;
            const bool hit = (std::fabs(xi - X[j]) <= s) & (std::fabs(yi - Y[j]) <= s) & (std::fabs(zi - Z[j]) <= s);
            const int jj = id[j];
            out[cnt] = {ii < jj ? ii : jj, ii < jj ? jj : ii};
            cnt += hit;
          }
        };
        scan(i + 1, e);
        for (int k = 0; k < nr; ++k) scan(rb[k], re[k]);
      }
    }
  }
  pairs.resize(cnt);
}

} // namespace fdem::kernels
