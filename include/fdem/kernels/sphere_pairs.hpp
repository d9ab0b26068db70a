// The serial pair loop of sphere-sphere granular contact (doc/spheres.md):
// one cell search (CellSearch) over the spheres a rank holds, redone only when
// a sphere has moved more than half the skin since the last search, the
// distance test, the granular force law and the tangential history of every
// contact, kept between calls and keyed by the two spheres' global ids. The parallel
// layer feeds it owned and ghost spheres; no PETSc, no MPI.
#pragma once
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fdem/kernels/granular.hpp"
#include "fdem/kernels/nbs.hpp"

namespace fdem::kernels {

// Sphere data as arrays of n entries (3n for vectors). id: unique global ids
// (>= 0, < 2^32). material: index into the pair table.
struct SphereArrays {
  int n = 0;
  const double *x = nullptr, *v = nullptr, *w = nullptr;
  const double *radius = nullptr, *mass = nullptr;
  const int *material = nullptr;
  const std::int64_t *id = nullptr;
};

class SpherePairLoop {
public:
  // table[a * nmat + b]: the pair parameters of materials a and b (symmetric).
  void SetPairTable(std::vector<GranularPair> table, int nmat);
  // Candidate pairs are the spheres closer than r_i + r_j + skin; the search
  // is redone when the number of spheres changes, when a sphere has moved more
  // than skin / 2 since the last search, or after Invalidate() (call it when
  // the set of spheres or their order changes). skin = 0: search every call.
  void SetSkin(double skin);
  void Invalidate() { valid_ = false; }

  // Adds the contact forces and torques on every sphere to f and t (3n each;
  // not cleared) for a step of length dt, advancing the tangential histories.
  // A contact between two spheres that are not both in the set is forgotten.
  // Throws InputError on a material index outside the table, a non-positive
  // radius or mass, or a duplicated id in a touching pair.
  void AddForces(const SphereArrays &s, double dt, double *f, double *t);

  int NumContacts() const { return static_cast<int>(touching_.size()); }
  int NumSearches() const { return searches_; }
  // The touching pairs of the last call (indices into its arrays), e.g. for
  // the coordination number.
  const std::vector<std::pair<int, int>> &Contacts() const { return touching_; }

private:
  CellSearch search_;
  std::vector<GranularPair> table_;
  int nmat_ = 0;
  double skin_ = 0;
  bool valid_ = false;
  int searches_ = 0;
  std::vector<double> xref_, radius_; // positions at the last search; search radii
  // Candidate pairs (oriented so that id i < id j) and their tangential springs.
  std::vector<std::pair<int, int>> pairs_, touching_;
  std::vector<Vec3> shear_;
  std::vector<unsigned char> touch_;
  std::vector<std::int64_t> prev_id_;             // ids of each candidate pair
  std::unordered_map<std::uint64_t, Vec3> carry_; // springs carried over a search
};

} // namespace fdem::kernels
