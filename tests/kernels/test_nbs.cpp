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

// ---------------------------------------------------------------- box queries and mixed sizes
namespace {
bool Meet(const double *a, const double *b) {
  for (int d = 0; d < 3; ++d)
    if (a[d] > b[3 + d] || b[d] > a[3 + d]) return false;
  return true;
}

// n boxes: most small (size ~ s), some a few times larger, a handful huge (walls).
std::vector<double> MixedBoxes(std::mt19937_64 &rng, int n, double L, double s) {
  std::uniform_real_distribution<double> U(0, L), V(0.2, 1.0);
  std::vector<double> b(6 * std::size_t(n));
  for (int i = 0; i < n; ++i) {
    const double scale = i % 50 == 0 ? 40 : i % 7 == 0 ? 5 : 1; // huge, medium, small
    for (int d = 0; d < 3; ++d) {
      const double c = U(rng), h = 0.5 * s * scale * V(rng);
      b[6 * i + d]     = c - h;
      b[6 * i + 3 + d] = c + h;
    }
  }
  return b;
}
} // namespace

TEST(CellSearch, FindInBoxAgainstBruteForce) {
  std::mt19937_64 rng(11);
  const int n = 3000;
  std::vector<double> c = Uniform(rng, n, 10.0, -3.0), r(n);
  std::uniform_real_distribution<double> R(0.0, 0.25);
  for (double &x : r) x = R(rng);
  CellSearch cs;
  cs.Build(c.data(), r.data(), n, 0.5);
  std::uniform_real_distribution<double> Q(-5.0, 9.0), H(0.0, 3.0);
  int total = 0;
  for (int q = 0; q < 200; ++q) {
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = Q(rng);
      hi[d] = lo[d] + (q % 3 == 0 ? 0.0 : H(rng)); // some queries are points
    }
    std::vector<int> got, ref;
    cs.FindInBox(lo, hi, got);
    for (int i = 0; i < n; ++i) {
      bool in = true;
      for (int d = 0; d < 3; ++d) in = in && c[3 * i + d] + r[i] >= lo[d] && c[3 * i + d] - r[i] <= hi[d];
      if (in) ref.push_back(i);
    }
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, ref) << "query " << q;
    total += (int)ref.size();
  }
  EXPECT_GT(total, 300) << "the queries must find something to mean anything";
  // a box outside everything finds nothing; `out` is appended to, not cleared
  std::vector<int> out{-7};
  const double lo[3] = {100, 100, 100}, hi[3] = {101, 101, 101};
  cs.FindInBox(lo, hi, out);
  EXPECT_EQ(out, std::vector<int>{-7});
}

TEST(BoxSearch, MixedSizesAgainstBruteForce) {
  for (int seed : {1, 2, 3}) {
    std::mt19937_64 rng(seed);
    const int n = 2500;
    const std::vector<double> b = MixedBoxes(rng, n, 12.0, 0.4);
    BoxSearch bs;
    bs.Build(b.data(), n);
    EXPECT_GE(bs.NumLevels(), 3) << "small, medium and huge boxes make several levels";
    Pairs got, ref;
    bs.FindPairs(got);
    for (const auto &p : got) ASSERT_LT(p.first, p.second);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(std::adjacent_find(got.begin(), got.end()), got.end()) << "a pair reported twice";
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (Meet(&b[6 * i], &b[6 * j])) ref.emplace_back(i, j);
    EXPECT_EQ(got, ref) << "seed " << seed << ": " << got.size() << " pairs vs " << ref.size() << " by brute force";
    EXPECT_GT(ref.size(), 2000u);
  }
}

TEST(BoxSearch, ClassesThatMayMeet) {
  // classes 0..5 (the contact engine's kind and fixed flag); 0 meets 2, 3 and 5; 2 meets 2 and 3;
  // 5 meets 1; nothing else. The listed pairs are the unfiltered search's of those classes, in its order.
  std::mt19937_64 rng(7);
  const int                 n = 2000;
  const std::vector<double> b = MixedBoxes(rng, n, 10.0, 0.4);
  std::vector<std::uint8_t> cls(n);
  for (int i = 0; i < n; ++i) cls[i] = (std::uint8_t)(rng() % 6);
  std::uint64_t meet = 0;
  auto          both = [&](int x, int y) { meet |= std::uint64_t(1) << (8 * x + y), meet |= std::uint64_t(1) << (8 * y + x); };
  both(0, 2), both(0, 3), both(0, 5), both(2, 2), both(2, 3), both(5, 1);
  BoxSearch bs;
  bs.Build(b.data(), n);
  Pairs all, got, ref;
  bs.FindPairs(all);
  bs.FindPairs(got, cls.data(), meet);
  for (const auto &p : all)
    if (meet >> (8 * cls[p.first] + cls[p.second]) & 1u) ref.push_back(p);
  EXPECT_EQ(got, ref);
  EXPECT_GT(ref.size(), 500u);
  EXPECT_LT(ref.size(), all.size() / 2) << "most pairs are of classes that do not meet";
  bs.FindPairs(got, cls.data(), 0); // no class meets any
  EXPECT_TRUE(got.empty());
}

TEST(BoxSearch, BoxesThatMeetNoClassTheyMayMeetAreLeftOut) {
  // a mesh of 20^3 unit boxes (class 0, which meets class 2 only) and 30 small boxes (class 2,
  // meets 0) near one corner of it: built with the classes, the mesh's boxes away from the
  // corner are out of the levels, and the pairs are those of the plain search, in another order
  std::mt19937_64                        rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double>                    b;
  std::vector<std::uint8_t>              cls;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 20; ++k) {
        const double c[3] = {i + 0.05 * u(rng), j + 0.05 * u(rng), k + 0.05 * u(rng)};
        for (int d = 0; d < 3; ++d) b.push_back(c[d] - 0.55);
        for (int d = 0; d < 3; ++d) b.push_back(c[d] + 0.55);
        cls.push_back(0);
      }
  for (int q = 0; q < 30; ++q) {
    const double c[3] = {3 * u(rng) - 1, 3 * u(rng) - 1, 3 * u(rng) - 1}, h = 0.05 + 0.2 * u(rng);
    for (int d = 0; d < 3; ++d) b.push_back(c[d] - h);
    for (int d = 0; d < 3; ++d) b.push_back(c[d] + h);
    cls.push_back(2);
  }
  const int     n    = (int)cls.size();
  std::uint64_t meet = std::uint64_t(1) << (8 * 0 + 2) | std::uint64_t(1) << (8 * 2 + 0);
  BoxSearch     plain, culled;
  plain.Build(b.data(), n);
  culled.Build(b.data(), n, cls.data(), meet);
  EXPECT_EQ(plain.NumSearched(), n);
  EXPECT_LT(culled.NumSearched(), 200) << "the mesh's boxes far from the small ones are out";
  EXPECT_GT(culled.NumSearched(), 30);
  Pairs ref, got;
  plain.FindPairs(ref, cls.data(), meet);
  culled.FindPairs(got, cls.data(), meet);
  for (const auto &p : got) ASSERT_LT(p.first, p.second);
  std::sort(ref.begin(), ref.end());
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, ref);
  EXPECT_GT(ref.size(), 40u);
  // with every class meeting every other, nothing is out and the search is the plain one, in its order
  BoxSearch all;
  all.Build(b.data(), n, cls.data(), ~std::uint64_t(0));
  EXPECT_EQ(all.NumSearched(), n);
  Pairs a, p;
  all.FindPairs(a);
  plain.FindPairs(p);
  EXPECT_EQ(a, p);
  // a bad box is named by its own index, left out or not
  b[6 * 5000 + 1] = NAN;
  EXPECT_THROW(culled.Build(b.data(), n, cls.data(), meet), fdem::kernels::InputError);
}

TEST(BoxSearch, EqualSizesTouchingAndDegenerate) {
  // a lattice of unit boxes touching face to face, and flat boxes (zero thickness)
  std::vector<double> b;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) b.insert(b.end(), {double(i), double(j), double(k), i + 1.0, j + 1.0, k + 1.0});
  b.insert(b.end(), {0.5, 0.5, 2.0, 3.5, 3.5, 2.0}); // a flat plate on the plane z = 2
  b.insert(b.end(), {9, 9, 9, 9, 9, 9});             // a point, far away
  const int n = (int)(b.size() / 6);
  BoxSearch bs;
  bs.Build(b.data(), n);
  Pairs got, ref;
  bs.FindPairs(got);
  std::sort(got.begin(), got.end());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (Meet(&b[6 * i], &b[6 * j])) ref.emplace_back(i, j);
  EXPECT_EQ(got, ref);
  // 64 cubes: 3*3*3*... neighbours incl. edges and corners; the plate meets the 2 layers it touches
  EXPECT_GT(ref.size(), 64u * 3);
}

TEST(BoxSearch, RejectsBadBoxes) {
  BoxSearch bs;
  const double inverted[6] = {0, 0, 1, 1, 1, 0};
  EXPECT_THROW(bs.Build(inverted, 1), InputError);
  const double nan[6] = {0, 0, 0, 1, NAN, 1};
  EXPECT_THROW(bs.Build(nan, 1), InputError);
  EXPECT_THROW(bs.Build(nullptr, -1), InputError);
  bs.Build(nullptr, 0);
  Pairs p{{1, 2}};
  bs.FindPairs(p);
  EXPECT_TRUE(p.empty());
}
