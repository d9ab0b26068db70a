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
}

inline void CellSearch::CheckCell(int a, std::vector<std::pair<int, int>> &pairs) const {
  const int e = cell_start_[a + 1];
  for (int i = cell_start_[a]; i < e; ++i)
    for (int j = i + 1; j < e; ++j) {
      const double s = have_radii_ ? r_[i] + r_[j] : cell_;
      if (std::fabs(x_[i] - x_[j]) <= s && std::fabs(y_[i] - y_[j]) <= s && std::fabs(z_[i] - z_[j]) <= s)
        pairs.emplace_back(std::min(id_[i], id_[j]), std::max(id_[i], id_[j]));
    }
}

inline void CellSearch::CheckCells(int a, int b, std::vector<std::pair<int, int>> &pairs) const {
  const int ea = cell_start_[a + 1], eb = cell_start_[b + 1], sb = cell_start_[b];
  for (int i = cell_start_[a]; i < ea; ++i) {
    const double xi = x_[i], yi = y_[i], zi = z_[i];
    const double ri = have_radii_ ? r_[i] : 0.0;
    for (int j = sb; j < eb; ++j) {
      const double s = have_radii_ ? ri + r_[j] : cell_;
      if (std::fabs(xi - x_[j]) <= s && std::fabs(yi - y_[j]) <= s && std::fabs(zi - z_[j]) <= s)
        pairs.emplace_back(std::min(id_[i], id_[j]), std::max(id_[i], id_[j]));
    }
  }
}

void CellSearch::FindPairs(std::vector<std::pair<int, int>> &pairs) const {
  pairs.clear();
  const int nrows = NumRows();
  if (nrows <= 0) return;
  // The book's half mask (3.73) as row offsets (dz, dy); each with x-1..x+1.
  // The same row contributes the cell itself and (x-1).
  constexpr int kDz[4] = {0, -1, -1, -1};
  constexpr int kDy[4] = {-1, -1, 0, 1};
  int ptr[4] = {0, 0, 0, 0};
  for (int r = 0; r < nrows; ++r) {
    const int c0 = row_cell_[r], c1 = row_cell_[r + 1];
    for (int c = c0; c < c1; ++c) {
      CheckCell(c, pairs);
      if (c > c0 && cell_x_[c - 1] + 1 == cell_x_[c]) CheckCells(c, c - 1, pairs);
    }
    const std::uint64_t Z = row_z_[r], Y = row_y_[r];
    for (int k = 0; k < 4; ++k) {
      if ((kDz[k] < 0 && Z == 0) || (kDy[k] < 0 && Y == 0)) continue;
      const std::uint64_t tz = Z + kDz[k], ty = Y + kDy[k]; // wraps only for +1 at 2^64-1, impossible here
      int &p = ptr[k];
      while (p < nrows && (row_z_[p] < tz || (row_z_[p] == tz && row_y_[p] < ty))) ++p;
      if (p == nrows || row_z_[p] != tz || row_y_[p] != ty) continue;
      // Merge the two rows' cells, both sorted by x.
      const int n0 = row_cell_[p], n1 = row_cell_[p + 1];
      int q = n0;
      for (int c = c0; c < c1; ++c) {
        const std::uint64_t X = cell_x_[c];
        while (q < n1 && cell_x_[q] + 1 < X) ++q;
        for (int m = q; m < n1 && cell_x_[m] <= X + 1; ++m) CheckCells(c, m, pairs);
      }
    }
  }
}

} // namespace fdem::kernels
