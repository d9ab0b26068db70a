// Tests of the linear-cost cell search (src/kernels/nbs.cpp) against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <cstdlib>

#include "fdem/kernels/error.hpp"
#include "fdem/kernels/nbs.hpp"

using namespace fdem::kernels;
using Pairs = std::vector<std::pair<int, int>>;

namespace {

Pairs BruteForce(const std::vector<double> &c, const std::vector<double> *r, double d) {
  const int n = static_cast<int>(c.size() / 3);
  Pairs out;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double s = r ? (*r)[i] + (*r)[j] : d;
      bool hit = true;
      for (int k = 0; k < 3; ++k) hit = hit && std::fabs(c[3 * i + k] - c[3 * j + k]) <= s;
      if (hit) out.emplace_back(i, j);
    }
  return out;
}

// Runs the search and compares with brute force: same set, each pair once, i < j.
void Check(const std::vector<double> &c, const std::vector<double> *r, double d, const char *what,
           std::size_t min_pairs = 1) {
  CellSearch cs;
  cs.Build(c.data(), r ? r->data() : nullptr, static_cast<int>(c.size() / 3), d);
  Pairs got;
  cs.FindPairs(got);
  for (const auto &p : got) ASSERT_LT(p.first, p.second) << what;
  Pairs sorted = got;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << what << ": a pair reported twice";
  Pairs ref = BruteForce(c, r, d);
  EXPECT_EQ(sorted, ref) << what << ": " << got.size() << " pairs vs " << ref.size() << " by brute force";
  EXPECT_GE(ref.size(), min_pairs) << what << ": test set has too few pairs to mean anything";
  // Reuse of the object gives the same answer.
  cs.Build(c.data(), r ? r->data() : nullptr, static_cast<int>(c.size() / 3), d);
  Pairs again;
  cs.FindPairs(again);
  std::sort(again.begin(), again.end());
  EXPECT_EQ(again, sorted) << what;
}

std::vector<double> Uniform(std::mt19937_64 &rng, int n, double L, double off = 0) {
  std::uniform_real_distribution<double> U(off, off + L);
  std::vector<double> c(3 * n);
  for (double &v : c) v = U(rng);
  return c;
}

} // namespace

TEST(CellSearch, DenseRandom) {
  std::mt19937_64 rng(1);
  Check(Uniform(rng, 3000, 10.0), nullptr, 1.0, "dense, no radii", 1000);
  std::uniform_real_distribution<double> R(0, 0.5);
  std::vector<double> r(3000);
  for (double &v : r) v = R(rng);
  Check(Uniform(rng, 3000, 10.0, -4.0), &r, 1.0, "dense, radii", 500);
}

TEST(CellSearch, SparseRandom) {
  std::mt19937_64 rng(2);
  Check(Uniform(rng, 2000, 200.0), nullptr, 1.0, "sparse");
}

TEST(CellSearch, Clustered) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N(0, 1);
  std::uniform_real_distribution<double> U(-1000, 1000);
  std::vector<double> c;
  for (int cl = 0; cl < 20; ++cl) {
    const double cx = U(rng), cy = U(rng), cz = U(rng);
    for (int i = 0; i < 150; ++i) {
      c.push_back(cx + 2 * N(rng));
      c.push_back(cy + 2 * N(rng));
      c.push_back(cz + 0.5 * N(rng));
    }
  }
  Check(c, nullptr, 0.7, "clustered", 1000);
}

TEST(CellSearch, AllInOneCell) {
  std::mt19937_64 rng(4);
  Check(Uniform(rng, 400, 0.3), nullptr, 1.0, "one cell", 400 * 399 / 2);
  std::vector<double> same(3 * 50, 2.5); // all at one point
  Check(same, nullptr, 1.0, "coincident", 50 * 49 / 2);
}

TEST(CellSearch, OnCellBoundaries) {
  // Points on an integer lattice with d = 1: neighbours at distance exactly d
  // (touching boxes) must be found, diagonal ones too.
  std::vector<double> c;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 5; ++k) {
        c.push_back(i - 3.0);
        c.push_back(j * 1.0);
        c.push_back(k + 1e6);
      }
  // Exact count of lattice pairs at Chebyshev distance 1: sum over the 26
  // offsets of the number of lattice points having that neighbour, halved.
  std::size_t expect = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (dx || dy || dz) expect += (7 - std::abs(dx)) * (6 - std::abs(dy)) * (5 - std::abs(dz));
  expect /= 2;
  Check(c, nullptr, 1.0, "lattice, spacing d", expect);
  EXPECT_EQ(BruteForce(c, nullptr, 1.0).size(), expect);
  // Spacing 0.5 and radii 0.25: boxes touch exactly.
  std::vector<double> c2, r2;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      c2.push_back(0.5 * i);
      c2.push_back(0.5 * j);
      c2.push_back(0.0);
      r2.push_back(0.25);
    }
  Check(c2, &r2, 0.5, "touching boxes, radii", 200);
}

TEST(CellSearch, HugeCoordinateRange) {
  std::mt19937_64 rng(5);
  // Two dense clusters 1e12 cells apart along x, a third far in z: the grid
  // would have ~1e36 cells.
  std::vector<double> c = Uniform(rng, 500, 5.0);
  std::vector<double> far = Uniform(rng, 500, 5.0, 1e12);
  for (int i = 0; i < 500; ++i) { far[3 * i + 1] -= 1e12; far[3 * i + 2] += 3e11; }
  c.insert(c.end(), far.begin(), far.end());
  std::vector<double> mid = Uniform(rng, 300, 5.0, -7e11);
  c.insert(c.end(), mid.begin(), mid.end());
  Check(c, nullptr, 1.0, "huge range (comparison-sort path)", 100);
  // Long in one axis only: 2^40 cells along x, still the radix path.
  std::vector<double> line;
  for (int i = 0; i < 2000; ++i) {
    line.push_back(std::ldexp(1.0, 40) * (i % 2) + 0.4 * (i / 2 % 50));
    line.push_back(0.3 * (i / 100));
    line.push_back(0.0);
  }
  Check(line, nullptr, 1.0, "long line", 100);
}

TEST(CellSearch, OneAndTwoWordSortRecords) {
  // The same dense cloud sorted with a key of <= 32 bits (one-word records)
  // and, with two far elements added, of > 32 bits (key and index in two
  // words): both must equal brute force, and the cloud's pairs must not change.
  std::mt19937_64 rng(7);
  std::vector<double> c = Uniform(rng, 2500, 12.0);
  Check(c, nullptr, 1.0, "32-bit key", 1000);
  const double far[6] = {1e5, 1e5, 0.5, 1e5 + 0.5, 1e5 - 0.5, 1.0}; // 17 + 17 + 4 bits
  c.insert(c.end(), far, far + 6);
  Check(c, nullptr, 1.0, "38-bit key", 1000);
  // Duplicated centres in both layouts: every copy pairs with every other.
  std::vector<double> dup;
  for (int k = 0; k < 3; ++k) dup.insert(dup.end(), c.begin(), c.begin() + 3 * 400);
  Check(dup, nullptr, 1.0, "duplicated centres", 3 * 400);
}

TEST(CellSearch, RowMergeLongJumps) {
  // Two adjacent rows of cells: row y = 0 has every cell x = 0..199, row
  // y = 1 only x = 0 and x = 150..199, and a layer below with runs and gaps of
  // every length. Finding the neighbour cells x-1..x+1 in the other rows must
  // jump over long gaps and long runs (past the row merge's fixed window).
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> J(0.05, 0.95);
  std::vector<double> c;
  auto put = [&](int x, int y, int z) {
    c.push_back(x + J(rng));
    c.push_back(y + J(rng));
    c.push_back(z + J(rng));
  };
  for (int x = 0; x < 200; ++x) put(x, 0, 1);
  put(0, 1, 1);
  for (int x = 150; x < 200; ++x) put(x, 1, 1);
  for (int x = 0, run = 1; x < 200; x += 2 * run, run = run % 9 + 1)
    for (int k = 0; k < run && x + k < 200; ++k) {
      put(x + k, 0, 0);
      put(x + k, 1, 0);
      put(x + k, 2, 0);
    }
  Check(c, nullptr, 1.0, "row merge", 200);
  // The same with radii (the radii branch of the scan).
  std::vector<double> r(c.size() / 3);
  std::uniform_real_distribution<double> R(0, 0.5);
  for (double &v : r) v = R(rng);
  Check(c, &r, 1.0, "row merge, radii", 50);
}

TEST(CellSearch, IdsInReverseCellOrder) {
  // Elements given in decreasing cell order, so that the caller's indices run
  // against the sorted order: every pair must still come out as (i < j).
  std::vector<double> c;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) {
        c.push_back(9.0 - i + 0.3 * ((i + j + k) % 3));
        c.push_back(9.0 - j);
        c.push_back(9.0 - k);
      }
  Check(c, nullptr, 1.0, "reverse order", 1000);
}

TEST(CellSearch, SmallAndEmpty) {
  CellSearch cs;
  Pairs p{{1, 2}};
  cs.Build(nullptr, nullptr, 0, 1.0);
  cs.FindPairs(p);
  EXPECT_TRUE(p.empty());
  EXPECT_EQ(cs.NumCells(), 0);
  EXPECT_EQ(cs.NumRows(), 0);
  const double one[3] = {1, 2, 3};
  cs.Build(one, nullptr, 1, 1.0);
  cs.FindPairs(p);
  EXPECT_TRUE(p.empty());
  const double two[6] = {0, 0, 0, 1, 1, 1};
  cs.Build(two, nullptr, 2, 1.0);
  cs.FindPairs(p);
  ASSERT_EQ(p.size(), 1u);
  cs.Build(two, nullptr, 2, 0.99);
  cs.FindPairs(p);
  EXPECT_TRUE(p.empty());
}

TEST(CellSearch, CostIsPerElement) {
  // Cells visited are the non-empty ones only: a sparse set has at most n
  // cells and rows, however large its bounding box.
  std::mt19937_64 rng(6);
  const auto c = Uniform(rng, 1000, 1e5);
  CellSearch cs;
  cs.Build(c.data(), nullptr, 1000, 1.0);
  EXPECT_LE(cs.NumCells(), 1000);
  EXPECT_LE(cs.NumRows(), cs.NumCells());
}

TEST(CellSearch, RejectsBadInput) {
  CellSearch cs;
  const double c[6] = {0, 0, 0, 1, 1, 1};
  const double r[2] = {0.3, 0.6};
  const double nan[6] = {0, 0, 0, 1, std::nan(""), 1};
  EXPECT_THROW(cs.Build(c, nullptr, 2, 0.0), InputError);
  EXPECT_THROW(cs.Build(c, nullptr, 2, -1.0), InputError);
  EXPECT_THROW(cs.Build(c, nullptr, -1, 1.0), InputError);
  EXPECT_THROW(cs.Build(c, r, 2, 1.0), InputError); // diameter 1.2 > cell 1
  EXPECT_THROW(cs.Build(nan, nullptr, 2, 1.0), InputError);
}
