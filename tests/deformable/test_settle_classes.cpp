// The classes that reach other ranks, completed by the ranks together (SettleClasses,
// src/model/deformable_fragments.cpp; doc/fracture.md, "Broken joints"): the labels of a graph
// spread over the ranks, each class ending with the smallest label of its component and the or
// of its flags. The graph is a long chain of N elements, each on a random rank, with ids in a
// random order (case "shuffled"), in decreasing order along the chain (case "reversed", the
// longest way for the smallest label to travel), and the shuffled chain cut into pieces at
// random (case "cut"); every 50th element (at random) carries a flag. On each rank the
// elements of one rank that are neighbours on the chain are one class (a union-find), and a
// link joins a class to the label of the class of its neighbour on another rank, as the
// fracture topology's exchange of labels gives them. Asserted against a union-find over the
// whole chain on every rank: every element's label and flag, and that the rounds stay
// logarithmic (at most 2 log2(classes) + 4; a chain of 1e4 classes takes 12 to 14, and rounds
// that each moved a label by one class, as the rounds of exchange before the gather on rank 0
// did, would take thousands).
#include "../common/check.hpp"
#include "../../src/model/deformable_impl.hpp"

#include <fdem.h>

#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

using fdem::model::LabelClasses;

static PetscErrorCode Chain(const char *name, PetscInt N, int mode, unsigned seed) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  std::mt19937_64       g(seed); // the same draws on every rank
  std::vector<PetscInt> id(N);
  std::iota(id.begin(), id.end(), (PetscInt)0);
  if (mode == 1) std::reverse(id.begin(), id.end());
  else std::shuffle(id.begin(), id.end(), g);
  std::vector<int> owner(N), cut(N, 0), flag(N, 0);
  for (PetscInt i = 0; i < N; ++i) owner[i] = (int)(g() % size), cut[i] = mode == 2 && g() % 7 == 0, flag[i] = g() % 50 == 0;
  LabelClasses whole(id); // element i of the chain has id[i]; cut[i]: no link between i and i + 1
  for (PetscInt i = 0; i < N; ++i) whole.flag[i] = (char)flag[i];
  for (PetscInt i = 0; i + 1 < N; ++i)
    if (!cut[i]) whole.Unite(i, i + 1);
  // this rank's elements and their classes
  std::vector<PetscInt> ids, at, boundary;
  for (PetscInt i = 0; i < N; ++i)
    if (owner[i] == rank) ids.push_back(id[i]), at.push_back(i);
  LabelClasses                           c(ids);
  std::unordered_map<PetscInt, PetscInt> local; // chain position -> element here
  for (std::size_t k = 0; k < at.size(); ++k) local[at[k]] = (PetscInt)k, c.flag[k] = (char)flag[at[k]], boundary.push_back((PetscInt)k);
  for (std::size_t k = 0; k < at.size(); ++k)
    if (at[k] + 1 < N && !cut[at[k]] && owner[at[k] + 1] == rank) c.Unite((PetscInt)k, local[at[k] + 1]);
  // the label of every element's class on its rank, as the exchange with the neighbours gives it
  std::vector<PetscInt> mine(N, PETSC_MAX_INT), lab(N);
  for (std::size_t k = 0; k < at.size(); ++k) mine[at[k]] = c.Label((PetscInt)k);
  PetscCallMPI(MPI_Allreduce(mine.data(), lab.data(), (int)N, MPIU_INT, MPI_MIN, PETSC_COMM_WORLD));
  std::vector<std::array<PetscInt, 2>> edges;
  for (std::size_t k = 0; k < at.size(); ++k)
    for (PetscInt j : {at[k] - 1, at[k] + 1})
      if (j >= 0 && j < N && !cut[std::min(at[k], j)] && owner[j] != rank) edges.push_back({c.Label((PetscInt)k), lab[j]});
  PetscInt nclasses, rounds, wrong = 0, gwrong;
  PetscCall(fdem::model::SettleClasses(PETSC_COMM_WORLD, c, boundary, edges, &nclasses, &rounds));
  for (std::size_t k = 0; k < at.size(); ++k) {
    const PetscInt e = (PetscInt)k, i = at[k];
    wrong += c.Label(e) != whole.Label(i) || c.flag[c.Find(e)] != whole.flag[whole.Find(i)];
  }
  PetscCallMPI(MPI_Allreduce(&wrong, &gwrong, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  const double bound = 2 * std::log2(std::max<double>(2, (double)nclasses)) + 4;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-9s chain of %" PetscInt_FMT " on %d ranks: %" PetscInt_FMT " classes in the graph, %" PetscInt_FMT " rounds (bound %.0f), %" PetscInt_FMT " elements wrong\n", name, N, size, nclasses, rounds, bound, gwrong));
  CHECK(gwrong == 0, "%s: %" PetscInt_FMT " elements without their component's smallest label or flag", name, gwrong);
  CHECK(size == 1 || rounds <= bound, "%s: %" PetscInt_FMT " rounds for %" PetscInt_FMT " classes (at most %.0f)", name, rounds, nclasses, bound);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscInt N = 20000;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-n", &N, nullptr));
  PetscCall(Chain("shuffled", N, 0, 1));
  PetscCall(Chain("reversed", N, 1, 2));
  PetscCall(Chain("cut", N, 2, 3));
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
