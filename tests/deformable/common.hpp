// Helpers shared by the deformable-body tests.
#pragma once
#include "../common/check.hpp"

#include <fdem.h>
#include <fdem/deformable.h>
#include <fdem/kernels/tetmesh.hpp>

#include <cmath>
#include <vector>

// A kernel mesh handed to FDEMDeformableSetMesh (rank 0's copy is used).
inline PetscErrorCode SetKernelMesh(FDEMDeformable d, const fdem::kernels::TetMesh &M) {
  std::vector<PetscReal>   X;
  std::vector<PetscInt>    T, B;
  std::vector<const char *> names;
  PetscFunctionBeginUser;
  for (const auto &p : M.nodes) X.insert(X.end(), {p.x, p.y, p.z});
  for (size_t e = 0; e < M.tets.size(); ++e) {
    for (int k = 0; k < 4; ++k) T.push_back(M.tets[e][k]);
    B.push_back(M.body.empty() ? 0 : M.body[e]);
  }
  for (const auto &s : M.body_names) names.push_back(s.c_str());
  PetscCall(FDEMDeformableSetMesh(d, (PetscInt)M.nodes.size(), X.data(), (PetscInt)M.tets.size(), T.data(), B.data(), (PetscInt)names.size(), names.data()));
  PetscFunctionReturn(0);
}
