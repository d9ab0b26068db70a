// Sorting records whose order starts with a small non-negative integer (a node id): counted
// into one bucket per value, then each bucket sorted. Linear where the values are dense.
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace fdem::kernels {
// Sorts v by less, where less orders first by key(x), an integer: the same order as
// std::sort(v, less) when less is a strict total order. Falls back to std::sort when the
// keys span more than four times the records (a sparse range would cost its buckets).
template <class T, class Key, class Less>
void BucketSort(std::vector<T> &v, Key key, Less less) {
  if (v.size() < 2) return;
  long long lo = key(v[0]), hi = lo;
  for (const T &x : v) lo = std::min<long long>(lo, key(x)), hi = std::max<long long>(hi, key(x));
  if (static_cast<double>(hi - lo) >= 4.0 * static_cast<double>(v.size()) + 1024) {
    std::sort(v.begin(), v.end(), less);
    return;
  }
  std::vector<std::size_t> start(static_cast<std::size_t>(hi - lo) + 2, 0);
  for (const T &x : v) ++start[static_cast<std::size_t>(key(x) - lo) + 1];
  for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  std::vector<T>           out(v.size());
  std::vector<std::size_t> at(start.begin(), start.end() - 1);
  for (const T &x : v) out[at[static_cast<std::size_t>(key(x) - lo)]++] = x;
  for (std::size_t b = 0; b + 1 < start.size(); ++b)
    if (start[b + 1] - start[b] > 1) std::sort(out.begin() + static_cast<std::ptrdiff_t>(start[b]), out.begin() + static_cast<std::ptrdiff_t>(start[b + 1]), less);
  v.swap(out);
}
} // namespace fdem::kernels
