// Many elements' Cauchy stresses at once (cst.hpp, CellStresses): the force kernel's batched
// loop (cst_batch.hpp) storing each block's stresses instead of its nodal forces. In a file of
// its own: see cst_batch.hpp.
#include <fdem/kernels/cst.hpp>

#include <algorithm>
#include <array>
#include <vector>

#include "cst_batch.hpp"
#include "materials/table.hpp"

namespace fdem::kernels {
namespace {
// per material model, in the order of MaterialModels(): with and without velocities
template <class Model>
std::array<BatchFn, 2> StressEntry() {
  return {&Batch<Model, true, true>, &Batch<Model, false, true>};
}
const std::vector<std::array<BatchFn, 2>> &StressBatches() {
#define FDEM_STRESS_ENTRY(M) StressEntry<M>(),
  static const std::vector<std::array<BatchFn, 2>> table = {FDEM_MATERIAL_TABLE(FDEM_STRESS_ENTRY)};
#undef FDEM_STRESS_ENTRY
  return table;
}
} // namespace

void CellStresses(const ElementData &data, const double *x, const double *v, double *T, std::size_t begin, std::size_t end) {
  end = std::min(end, data.elems.size());
  const auto       &batches = StressBatches();
  const TetElement *E       = data.elems.data();
  for (std::size_t i = begin; i < end;) { // runs of one material, as ComputeInternalForces
    const int   m    = E[i].material;
    std::size_t done = 0;
    batches[data.materials[m].model][v ? 0 : 1](E + i, i, end - i, data.coeffs[m], x, v, T + 6 * (i - begin), &done);
    i += done;
  }
}
} // namespace fdem::kernels
