// Linear-cost broad-phase contact detection in 3D: Munjiza-NBS (book ch. 3,
// doc/book.md D) in its sort form. Elements are binned into cubic cells of a
// common size d >= every element's diameter; the cell keys are ordered by z,
// then y, then x with a radix sort, and every non-empty cell is checked
// against itself and the 13 cells of a half mask (the book's, eq 3.73,
// mirrored in x), found by merging sorted rows. Every loop runs over elements, non-empty cells or
// non-empty rows -- never over empty cells -- so the cost is proportional to
// N, independent of packing density, and memory is O(N) whatever the
// coordinate range.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace fdem::kernels {

class CellSearch {
public:
  // centres: 3n doubles (x, y, z of each element). radii: n bounding radii or
  // nullptr (then every element's box is centre +- cell/2). cell: the cell
  // size d; it must be >= every diameter 2 r_i. The centres are copied.
  // Throws InputError on n < 0, cell <= 0 or non-finite, a negative radius, a
  // diameter larger than the cell, or a non-finite coordinate. Buffers are
  // reused between calls.
  void Build(const double *centres, const double *radii, int n, double cell);

  // All pairs (i, j), i < j, whose axis-aligned bounding boxes overlap or
  // touch: |c_i - c_j| <= r_i + r_j along each axis (<= d without radii).
  // Each pair once, in no particular order. `pairs` is cleared first.
  void FindPairs(std::vector<std::pair<int, int>> &pairs) const;

  // The elements whose bounding boxes (centre +- r, or +- cell/2 without
  // radii) meet or touch the box [lo, hi], appended to `out` (not cleared),
  // in cell order. The cost is the number of non-empty rows and cells the box
  // spans plus the elements in them.
  void FindInBox(const double lo[3], const double hi[3], std::vector<int> &out) const;

  int NumElements() const { return n_; }
  int NumCells() const { return static_cast<int>(cell_start_.size()) - 1; } // non-empty cells
  int NumRows() const { return static_cast<int>(row_cell_.size()) - 1; } // non-empty rows

private:
  int n_ = 0;
  double cell_ = 0;
  double origin_[3] = {0, 0, 0}, inv_ = 0; // cell index of v along d: (v - origin_[d]) * inv_
  std::uint64_t max_index_[3] = {0, 0, 0};
  bool have_radii_ = false;
  // Element data in cell order, four doubles each (x, y, z and the bounding
  // radius, cell / 2 when no radii are given) so that a run of cells is one
  // stream; and the caller's index of each element.
  std::vector<double> elem_;
  std::vector<int> id_;
  // Non-empty cells in (z, y, x) order: first element and x index.
  std::vector<int> cell_start_;
  std::vector<std::uint64_t> cell_x_;
  // Non-empty rows (z, y): first cell; row_cell_ has one extra entry.
  std::vector<int> row_cell_;
  std::vector<std::uint64_t> row_z_, row_y_;
  // Scratch: sort records (key << 32 | index when the key fits 32 bits,
  // otherwise key and index in two words), digit counts, and the cell
  // coordinates for the comparison-sort fallback.
  std::vector<std::uint64_t> sort_a_, sort_b_;
  std::vector<std::uint32_t> count_;
  std::vector<std::uint64_t> ix_, iy_, iz_;
  std::vector<int> order_;
};

// Broad phase for axis-aligned boxes of very different sizes -- a wall's or a
// mesh's large tetrahedra among the small ones of pebbles -- where one cell
// size (that of the largest box) would put hundreds of small boxes in every
// cell. The boxes are grouped in levels by size: level 0 holds the boxes up to
// twice the median size, level k those up to 4^k times that. Each level has its
// own CellSearch with cells as large as its largest box; pairs within a level
// come from its FindPairs, pairs across levels from a FindInBox of the larger
// box in the smaller level. Every candidate is then tested box against box,
// so the result is exactly the pairs of overlapping (or touching) boxes.
class BoxSearch {
public:
  // boxes: 6n doubles, lo(3) then hi(3) of each box. Copied. Throws InputError
  // on n < 0, a non-finite coordinate or lo > hi.
  void Build(const double *boxes, int n);
  // The same, for the pairs of classes that may meet only (cls and meet as in
  // FindPairs, which must then get the same two): a box that overlaps no box of
  // a class its own may meet is in no such pair. When such boxes are a quarter
  // of all or more (a few rigid bodies on a large mesh that pairs only with
  // them), they are left out of the levels, and the search costs what the
  // others cost; FindPairs then lists the same pairs in another order.
  void Build(const double *boxes, int n, const std::uint8_t *cls, std::uint64_t meet);
  // All pairs (i, j), i < j, of boxes that overlap or touch, each once, in an
  // order that depends only on the boxes. `pairs` is cleared first. With cls
  // (n numbers below 8, one a box), only the pairs whose classes may meet:
  // bit 8 ca + cb of `meet` set (and bit 8 cb + ca), in the same order.
  void FindPairs(std::vector<std::pair<int, int>> &pairs, const std::uint8_t *cls = nullptr, std::uint64_t meet = ~std::uint64_t(0)) const;
  int NumLevels() const { return static_cast<int>(levels_.size()); }
  int NumSearched() const { return static_cast<int>(boxes_.size() / 6); } // the boxes in the levels

private:
  struct Level {
    CellSearch cs;
    std::vector<int> ids; // the level's element j is box ids[j]
  };
  std::vector<double> boxes_;
  std::vector<int> kept_; // the id given to Build of each box in boxes_ (empty: the same)
  std::vector<Level> levels_;
};

} // namespace fdem::kernels
