// Munjiza-NBS style cell search (book ch. 3, doc/book.md D), sort form.
// The book keeps z-, y- and x-lists in integer arrays indexed by cell
// coordinate (C[n_z], B[2][n_y], A[2][n_x]); here the same (z, y, x) order
// comes from an LSD radix sort of packed cell keys, so nothing is indexed by
// cell coordinate and a huge coordinate range costs no memory.
//
// Memory traffic (what keeps the time per element flat up to 1e6 elements):
//  * Build reads the centres twice in input order (bounds, then keys), sorts
//    8-byte records (key << 32 | index) when the key fits 32 bits, counting
//    every digit in the key pass, and gathers each centre once, prefetched,
//    into a 32-byte record in cell order; the cell coordinates come back out
//    of the sorted key, so no per-element array is read at random.
//  * FindPairs streams the records: a cell's candidates are five contiguous
//    runs of records (its own row and four neighbour rows, at most a layer
//    behind, so still in cache), listed as element indices in a small buffer
//    and scanned in one branch-free loop per element.
#include "fdem/kernels/nbs.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "fdem/kernels/error.hpp"

#if defined(__GNUC__)
#define FDEM_NOINLINE __attribute__((noinline))
#else
#define FDEM_NOINLINE
#endif

namespace fdem::kernels {
namespace {

constexpr int kWindow = 4; // cells read at once when merging rows (FindPairs)

int BitsFor(std::uint64_t v) {
  int b = 0;
  while (v) { ++b; v >>= 1; }
  return b;
}

// v >> s and the low-b-bit mask, defined for shifts of 64 too.
inline std::uint64_t Shr(std::uint64_t v, int s) { return s >= 64 ? 0 : v >> s; }
inline std::uint64_t LowMask(int b) { return b >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << b) - 1; }

// One LSD radix pass over records of W words (word 0 holds the digit).
template <int W>
void RadixPass(const std::uint64_t *src, std::uint64_t *dst, int n, int shift, std::uint64_t mask,
               std::uint32_t *count) {
  for (int i = 0; i < n; ++i) {
    const std::uint64_t *s = src + std::size_t(W) * i;
    std::uint64_t *d = dst + std::size_t(W) * count[(s[0] >> shift) & mask]++;
    d[0] = s[0];
    if (W == 2) d[1] = s[1];
  }
}

} // namespace

void CellSearch::Build(const double *c, const double *radii, int n, double cell) {
  if (n < 0) throw InputError("CellSearch::Build: negative element count " + std::to_string(n));
  if (!(cell > 0) || !std::isfinite(cell))
    throw InputError("CellSearch::Build: cell size must be finite and > 0, got " + std::to_string(cell));
  n_ = n;
  cell_ = cell;
  inv_ = 0;
  have_radii_ = radii != nullptr;
  cell_start_.clear();
  cell_x_.clear();
  row_cell_.clear();
  row_z_.clear();
  row_y_.clear();
  if (n == 0) {
    row_cell_.push_back(0);
    cell_start_.push_back(0);
    cell_x_.assign(kWindow, ~std::uint64_t(0));
    elem_.clear();
    id_.clear();
    return;
  }
  double lo[3] = {c[0], c[1], c[2]}, hi[3] = {c[0], c[1], c[2]};
  bool finite = true;
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      const double v = c[3 * i + d];
      finite &= std::isfinite(v);
      lo[d] = std::min(lo[d], v);
      hi[d] = std::max(hi[d], v);
    }
  if (!finite)
    for (int i = 0; i < 3 * n; ++i)
      if (!std::isfinite(c[i]))
        throw InputError("CellSearch::Build: element " + std::to_string(i / 3) +
                         " has a non-finite centre coordinate");
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
  // Cell index of coordinate v along axis d. It is monotone in v, so the
  // largest index is that of the upper bound. The value is in [0, 4e18], so
  // the signed conversion (one instruction) is exact.
  auto index = [&](double v, int d) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>((v - lo[d]) * inv));
  };
  for (int d = 0; d < 3; ++d) {
    origin_[d] = lo[d];
    max_index_[d] = index(hi[d], d);
  }
  inv_ = inv;
  const int bx = BitsFor(index(hi[0], 0)), by = BitsFor(index(hi[1], 1)), bz = BitsFor(index(hi[2], 2));
  const int total = bx + by + bz;
  const double half = 0.5 * cell;
  elem_.resize(4 * std::size_t(n));
  id_.resize(n);
  double *E = elem_.data();
  int *id = id_.data();

  // Element data in cell order, then runs of cells and rows. at(p) gives the
  // input index and the cell (x, y, z) of the p-th element in (z, y, x) order.
  auto gather = [&](auto at) {
    std::uint64_t px = 0, py = 0, pz = 0;
    for (int p = 0; p < n; ++p) {
      std::uint64_t X, Y, Z;
      const int i = at(p, X, Y, Z);
      double *ep = E + 4 * std::size_t(p);
      ep[0] = c[3 * i];
      ep[1] = c[3 * i + 1];
      ep[2] = c[3 * i + 2];
      ep[3] = radii ? radii[i] : half;
      id[p] = i;
      const bool new_row = p == 0 || Z != pz || Y != py;
      if (new_row) {
        row_cell_.push_back(static_cast<int>(cell_x_.size()));
        row_z_.push_back(Z);
        row_y_.push_back(Y);
      }
      if (new_row || X != px) {
        cell_start_.push_back(p);
        cell_x_.push_back(X);
      }
      px = X;
      py = Y;
      pz = Z;
    }
  };

  if (total <= 64) {
    // Packed key z|y|x. Records are key << 32 | index (one word) when the key
    // fits 32 bits, else (key, index) in two words. LSD radix sort with
    // digits sized to n; all digit counts are taken in the key pass.
    const int W = total <= 32 ? 1 : 2;
    const int kshift = W == 1 ? 32 : 0; // where the key sits in word 0
    int passes = 0, b = 0;
    if (total > 0) {
      int bmax = 4;
      while (bmax < 11 && (std::int64_t(1) << (bmax + 3)) <= n) ++bmax;
      passes = (total + bmax - 1) / bmax;
      b = (total + passes - 1) / passes;
    }
    const std::uint64_t mask = LowMask(b);
    const std::size_t nb = std::size_t(1) << b;
    count_.assign(std::size_t(passes) * nb, 0u);
    sort_a_.resize(std::size_t(W) * n);
    sort_b_.resize(std::size_t(W) * n);
    std::uint64_t *src = sort_a_.data(), *dst = sort_b_.data();
    std::uint32_t *cnt = count_.data();
    for (int i = 0; i < n; ++i) {
      const std::uint64_t X = index(c[3 * i], 0), Y = index(c[3 * i + 1], 1), Z = index(c[3 * i + 2], 2);
      std::uint64_t k = X;
      if (by) k |= Y << bx;
      if (bz) k |= Z << (bx + by);
      if (W == 1) {
        src[i] = k << 32 | std::uint32_t(i);
      } else {
        src[2 * i] = k;
        src[2 * i + 1] = std::uint64_t(i);
      }
      for (int p = 0; p < passes; ++p) ++cnt[p * nb + ((k >> (p * b)) & mask)];
    }
    for (int p = 0; p < passes; ++p) {
      std::uint32_t *cp = cnt + p * nb;
      // A digit shared by every key leaves the order as it is.
      if (cp[(src[0] >> (kshift + p * b)) & mask] == std::uint32_t(n)) continue;
      std::uint32_t s = 0;
      for (std::size_t v = 0; v < nb; ++v) { const std::uint32_t t = cp[v]; cp[v] = s; s += t; }
      if (W == 1) RadixPass<1>(src, dst, n, kshift + p * b, mask, cp);
      else RadixPass<2>(src, dst, n, kshift + p * b, mask, cp);
      std::swap(src, dst);
    }
    const int sy = bx, sz = bx + by;
    const std::uint64_t mx = LowMask(bx), my = LowMask(by);
    constexpr int kAhead = 16; // prefetch distance for the gather of centres
    gather([&](int p, std::uint64_t &X, std::uint64_t &Y, std::uint64_t &Z) {
      if (p + kAhead < n) {
        const std::uint64_t *f = src + std::size_t(W) * (p + kAhead);
        const std::size_t j = W == 1 ? std::uint32_t(f[0]) : f[1];
        __builtin_prefetch(c + 3 * j);
        __builtin_prefetch(c + 3 * j + 2); // a centre may straddle two lines
        if (radii) __builtin_prefetch(radii + j);
      }
      const std::uint64_t *r = src + std::size_t(W) * p;
      const std::uint64_t k = W == 1 ? r[0] >> 32 : r[0];
      X = k & mx;
      Y = Shr(k, sy) & my;
      Z = Shr(k, sz);
      return W == 1 ? int(std::uint32_t(r[0])) : int(r[1]);
    });
  } else {
    // More than 2^64 cells in the bounding box: comparison sort on (z, y, x).
    ix_.resize(n);
    iy_.resize(n);
    iz_.resize(n);
    order_.resize(n);
    for (int i = 0; i < n; ++i) {
      ix_[i] = index(c[3 * i], 0);
      iy_[i] = index(c[3 * i + 1], 1);
      iz_[i] = index(c[3 * i + 2], 2);
      order_[i] = i;
    }
    std::sort(order_.begin(), order_.end(), [this](int a, int b) {
      return std::tie(iz_[a], iy_[a], ix_[a]) < std::tie(iz_[b], iy_[b], ix_[b]);
    });
    gather([&](int p, std::uint64_t &X, std::uint64_t &Y, std::uint64_t &Z) {
      const int i = order_[p];
      X = ix_[i];
      Y = iy_[i];
      Z = iz_[i];
      return i;
    });
  }
  cell_start_.push_back(n);
  row_cell_.push_back(static_cast<int>(cell_x_.size()));
  cell_x_.resize(cell_x_.size() + kWindow, ~std::uint64_t(0)); // sentinels, not cells
}

namespace {

struct SearchView {
  int nrows;
  const int *row_cell, *cell_start, *id;
  const std::uint64_t *row_z, *row_y, *cell_x;
  const double *elem; // x, y, z, r per element
  double d;
};

// Tests each of the `own` elements b, b+1, ... (listed first in L) against
// the entries of L after it; writes every candidate at out[cnt] and advances
// cnt on a hit, so there is no branch on the outcome. A separate function, so
// that the count stays in a register.
template <bool kRadii>
FDEM_NOINLINE std::size_t ScanCell(const double *E, const int *id, const int *L, int b, int own, int m, double d,
                     std::pair<int, int> *out, std::size_t cnt) {
  for (int a = 0; a < own; ++a) {
    const double *ei = E + 4 * std::size_t(b + a);
    const double xi = ei[0], yi = ei[1], zi = ei[2], ri = ei[3];
    const int ii = id[b + a];
    for (int t = a + 1; t < m; ++t) {
      const int j = L[t];
      const double *ej = E + 4 * std::size_t(j);
      const double s = kRadii ? ri + ej[3] : d;
      const bool hit = (std::fabs(xi - ej[0]) <= s) & (std::fabs(yi - ej[1]) <= s) & (std::fabs(zi - ej[2]) <= s);
      // Smaller index first, without a branch (ids are in random order).
      const int jj = id[j];
      const int lo = jj ^ ((ii ^ jj) & -int(ii < jj));
      out[cnt] = {lo, ii ^ jj ^ lo};
      cnt += hit;
    }
  }
  return cnt;
}

// The half mask (3.73) mirrored in x: the same row contributes the cell itself
// and cell x+1, rows (z, y-1), (z-1, y-1), (z-1, y), (z-1, y+1) cells x-1..x+1.
// (Every offset o != 0 has exactly one of o, -o in this set.) Cells of a row
// are consecutive in element order, so the candidates of a cell are five
// contiguous runs of elements. Their indices are listed in `buf`, the cell's
// own elements first, and every own element is tested against the entries
// after it in one branch-free loop.
template <bool kRadii>
std::size_t Search(const SearchView &v, std::vector<std::pair<int, int>> &pairs) {
  constexpr int kDz[4] = {0, -1, -1, -1};
  constexpr int kDy[4] = {-1, -1, 0, 1};
  constexpr int kChunk = 8; // runs are listed kChunk indices at a time
  constexpr int kWin = kWindow;
  int ptr[4] = {0, 0, 0, 0};
  int nb[4], q[4]; // neighbour row of each offset (-1: none) and its cell cursor
  std::vector<int> buf(256);
  std::size_t cnt = 0;
  const int *cs = v.cell_start, *id = v.id;
  const std::uint64_t *cx_of = v.cell_x;
  const double *E = v.elem;
  const double d = v.d;
  for (int r = 0; r < v.nrows; ++r) {
    const int c0 = v.row_cell[r], c1 = v.row_cell[r + 1];
    const std::uint64_t rz = v.row_z[r], ry = v.row_y[r];
    int nnb = 0;
    for (int k = 0; k < 4; ++k) {
      if ((kDz[k] < 0 && rz == 0) || (kDy[k] < 0 && ry == 0)) continue;
      const std::uint64_t tz = rz + kDz[k], ty = ry + kDy[k];
      int &p = ptr[k];
      while (p < v.nrows && (v.row_z[p] < tz || (v.row_z[p] == tz && v.row_y[p] < ty))) ++p;
      if (p < v.nrows && v.row_z[p] == tz && v.row_y[p] == ty) {
        nb[nnb] = p;
        q[nnb++] = v.row_cell[p];
      }
    }
    for (int c = c0; c < c1; ++c) {
      const std::uint64_t cx = cx_of[c];
      const int b = cs[c], e = cs[c + 1];
      int m = 0;
      auto list = [&](int s, int t) {
        const int len = t - s;
        if (m + len + kChunk > static_cast<int>(buf.size())) buf.resize(2 * (m + len + kChunk));
        int *o = buf.data() + m;
        for (int u = 0; u < kChunk; ++u) o[u] = s + u;
        for (int u = kChunk; u < len; ++u) o[u] = s + u;
        m += len;
      };
      // Own cell, then cell x+1 of the same row if there is one (cx_of ends
      // with a sentinel, so reading cx_of[c + 1] is in bounds).
      const int next = (c + 1 < c1) & (cx_of[c + 1] == cx + 1);
      list(b, cs[c + 1 + next]);
      for (int k = 0; k < nnb; ++k) {
        const int n1 = v.row_cell[nb[k] + 1];
        // The cursor u moves to the first cell at x >= cx - 1 and w past the
        // last at x <= cx + 1. Both counts are taken over a window of kWin
        // cells read at once (independent loads, no branch); cell_x ends with
        // kWin sentinels, so the window stays in bounds.
        const int u0 = q[k];
        int adv = 0, le = 0;
        for (int t = 0; t < kWin; ++t) {
          const std::uint64_t xt = cx_of[u0 + t];
          const int in = u0 + t < n1;
          adv += in & (xt + 1 < cx);
          le += in & (xt <= cx + 1);
        }
        int u = u0 + adv, w = u0 + le;
        if (le == kWin) { // the window was too short: walk on
          while (u < n1 && cx_of[u] + 1 < cx) ++u;
          w = u;
          while (w < n1 && cx_of[w] <= cx + 1) ++w;
        }
        q[k] = u;
        list(cs[u], cs[w]);
      }
      const std::size_t most = std::size_t(e - b) * m;
      if (cnt + most > pairs.size()) pairs.resize(cnt + most + 4096 + pairs.size() / 4);
      cnt = ScanCell<kRadii>(E, id, buf.data(), b, e - b, m, d, pairs.data(), cnt);
    }
  }
  return cnt;
}

} // namespace

void CellSearch::FindInBox(const double lo[3], const double hi[3], std::vector<int> &out) const {
  if (n_ == 0) return;
  // An element's centre lies within r <= cell/2 of the box when their boxes meet.
  std::uint64_t i0[3], i1[3];
  const double half = 0.5 * cell_;
  for (int d = 0; d < 3; ++d) {
    const double a = (lo[d] - half - origin_[d]) * inv_, b = (hi[d] + half - origin_[d]) * inv_;
    if (!(b >= 0) || !(a <= static_cast<double>(max_index_[d]) + 1)) return; // also NaN
    i0[d] = a <= 0 ? 0 : static_cast<std::uint64_t>(a);
    i1[d] = b >= static_cast<double>(max_index_[d]) ? max_index_[d] : static_cast<std::uint64_t>(b);
  }
  const int nrows = NumRows();
  const std::uint64_t *rz = row_z_.data(), *ry = row_y_.data();
  const double *E = elem_.data();
  auto meets = [&](int p) {
    const double *e = E + 4 * std::size_t(p);
    return (e[0] + e[3] >= lo[0]) & (e[0] - e[3] <= hi[0]) & (e[1] + e[3] >= lo[1]) & (e[1] - e[3] <= hi[1]) &
           (e[2] + e[3] >= lo[2]) & (e[2] - e[3] <= hi[2]);
  };
  // rows are in (z, y) order: one binary search per z layer, then a walk along y
  int r = 0;
  for (std::uint64_t z = i0[2]; z <= i1[2]; ++z) {
    r = static_cast<int>(std::lower_bound(rz + r, rz + nrows, z) - rz);
    if (r == nrows) break;
    if (rz[r] != z) { // jump to the next non-empty layer
      if (rz[r] > i1[2]) break;
      z = rz[r];
    }
    int q = static_cast<int>(std::lower_bound(ry + r, ry + (std::upper_bound(rz + r, rz + nrows, z) - rz), i0[1]) - ry);
    for (; q < nrows && rz[q] == z && ry[q] <= i1[1]; ++q) {
      const std::uint64_t *cx = cell_x_.data();
      int c = static_cast<int>(std::lower_bound(cx + row_cell_[q], cx + row_cell_[q + 1], i0[0]) - cx);
      for (; c < row_cell_[q + 1] && cx[c] <= i1[0]; ++c)
        for (int p = cell_start_[c]; p < cell_start_[c + 1]; ++p)
          if (meets(p)) out.push_back(id_[p]);
    }
    r = q;
  }
}

void CellSearch::FindPairs(std::vector<std::pair<int, int>> &pairs) const {
  const int nrows = NumRows();
  if (nrows <= 0) {
    pairs.clear();
    return;
  }
  const SearchView v{nrows,         row_cell_.data(), cell_start_.data(), id_.data(), row_z_.data(),
                     row_y_.data(), cell_x_.data(),   elem_.data(),      cell_};
  const std::size_t cnt = have_radii_ ? Search<true>(v, pairs) : Search<false>(v, pairs);
  pairs.resize(cnt);
}

namespace {
inline bool BoxesMeet(const double *a, const double *b) {
  return (a[0] <= b[3]) & (b[0] <= a[3]) & (a[1] <= b[4]) & (b[1] <= a[4]) & (a[2] <= b[5]) & (b[2] <= a[5]);
}
} // namespace

void BoxSearch::Build(const double *boxes, int n, const std::uint8_t *cls, std::uint64_t meet) {
  if (n < 0) throw InputError("BoxSearch::Build: negative box count " + std::to_string(n));
  for (int i = 0; i < n; ++i) // (every box checked, those left out too)
    for (int d = 0; d < 3; ++d) {
      const double *b = boxes + 6 * std::size_t(i);
      if (!std::isfinite(b[d]) || !std::isfinite(b[3 + d]) || !(b[d] <= b[3 + d]))
        throw InputError("BoxSearch::Build: box " + std::to_string(i) + " is not finite or has lo > hi");
    }
  // the box around each class's boxes; a box meeting none of the classes its own may meet is out
  double around[8][6];
  for (auto &a : around) a[0] = a[1] = a[2] = INFINITY, a[3] = a[4] = a[5] = -INFINITY;
  for (int i = 0; i < n; ++i) {
    const double *b = boxes + 6 * std::size_t(i);
    double       *a = around[cls[i] & 7];
    for (int d = 0; d < 3; ++d) a[d] = std::min(a[d], b[d]), a[3 + d] = std::max(a[3 + d], b[3 + d]);
  }
  std::vector<int> kept;
  kept.reserve(n);
  for (int i = 0; i < n; ++i) {
    bool in = false;
    for (int c = 0; c < 8 && !in; ++c)
      in = (meet >> (8 * (cls[i] & 7) + c) & 1u) && BoxesMeet(boxes + 6 * std::size_t(i), around[c]);
    if (in) kept.push_back(i);
  }
  if (4 * (n - static_cast<std::int64_t>(kept.size())) < n) { // too few out to pay for the copy
    Build(boxes, n);
    return;
  }
  std::vector<double> sub(6 * kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) std::copy(boxes + 6 * std::size_t(kept[k]), boxes + 6 * std::size_t(kept[k]) + 6, sub.begin() + 6 * std::ptrdiff_t(k));
  Build(sub.data(), static_cast<int>(kept.size()));
  kept_ = std::move(kept);
}

void BoxSearch::Build(const double *boxes, int n) {
  if (n < 0) throw InputError("BoxSearch::Build: negative box count " + std::to_string(n));
  boxes_.assign(boxes, boxes + 6 * std::size_t(n));
  kept_.clear();
  levels_.clear();
  std::vector<double> size(n);
  for (int i = 0; i < n; ++i) {
    const double *b = boxes + 6 * std::size_t(i);
    double s = 0;
    for (int d = 0; d < 3; ++d) {
      if (!std::isfinite(b[d]) || !std::isfinite(b[3 + d]) || !(b[d] <= b[3 + d]))
        throw InputError("BoxSearch::Build: box " + std::to_string(i) + " is not finite or has lo > hi");
      s = std::max(s, b[3 + d] - b[d]);
    }
    size[i] = s;
  }
  if (n == 0) return;
  std::vector<double> sorted(size);
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const double base = 2 * sorted[n / 2];
  std::vector<int> level(n, 0);
  int nlev = 1;
  for (int i = 0; i < n; ++i) {
    int k = 0;
    for (double t = base; size[i] > t && k < 60; t *= 4) ++k;
    level[i] = k;
    nlev = std::max(nlev, k + 1);
  }
  std::vector<Level> lv(nlev);
  for (int i = 0; i < n; ++i) lv[level[i]].ids.push_back(i);
  std::vector<double> c, r;
  for (Level &L : lv) {
    if (L.ids.empty()) continue;
    const int m = static_cast<int>(L.ids.size());
    c.resize(3 * std::size_t(m));
    r.resize(m);
    double dmax = 0;
    for (int j = 0; j < m; ++j) {
      const double *b = boxes + 6 * std::size_t(L.ids[j]);
      double h = 0;
      for (int d = 0; d < 3; ++d) {
        c[3 * j + d] = 0.5 * (b[d] + b[3 + d]);
        h = std::max(h, 0.5 * (b[3 + d] - b[d]));
      }
      r[j] = h;
      dmax = std::max(dmax, 2 * h);
    }
    // cells no smaller than the largest box (a level of points gets a tiny positive cell)
    const double cell = dmax > 0 ? dmax * (1 + 1e-12) : 1e-300;
    L.cs.Build(c.data(), r.data(), m, std::max(cell, 1e-300));
    levels_.push_back(std::move(L));
  }
}

void BoxSearch::FindPairs(std::vector<std::pair<int, int>> &pairs, const std::uint8_t *cls, std::uint64_t meet) const {
  pairs.clear();
  const double *B = boxes_.data();
  std::vector<std::pair<int, int>> tp;
  std::vector<int> hits;
  const int *id = kept_.empty() ? nullptr : kept_.data(); // the caller's id of a box here
  auto may = [&](int a, int b) { return !cls || (id ? meet >> (8 * cls[id[a]] + cls[id[b]]) & 1u : meet >> (8 * cls[a] + cls[b]) & 1u); };
  auto add = [&](int a, int b) {
    if (id) a = id[a], b = id[b];
    pairs.push_back({std::min(a, b), std::max(a, b)});
  };
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    const Level &L = levels_[l];
    L.cs.FindPairs(tp); // cubes around the boxes: test the boxes themselves
    for (const auto &p : tp) {
      const int a = L.ids[p.first], b = L.ids[p.second];
      if (may(a, b) && BoxesMeet(B + 6 * std::size_t(a), B + 6 * std::size_t(b))) add(a, b);
    }
    for (std::size_t k = 0; k < l; ++k) // the smaller levels, one query per box of this level
      for (int a : L.ids) {
        const double *ba = B + 6 * std::size_t(a);
        hits.clear();
        levels_[k].cs.FindInBox(ba, ba + 3, hits);
        for (int j : hits) {
          const int b = levels_[k].ids[j];
          if (may(a, b) && BoxesMeet(ba, B + 6 * std::size_t(b))) add(a, b);
        }
      }
  }
}

} // namespace fdem::kernels
