// The input files fdem reads, and the paths each goes through: shared by the
// fuzz driver (fdem_fuzz.cpp) and the bad-input tests (tests/bad_input).
//
// An input kind has a name, the file extensions it takes and its paths (fdem
// entry points). A path is collective on comm and turns bad input into a PETSc
// error whose message names the file (and line) and what is wrong; it frees
// what it created on every exit. A new kind (e.g. YAML scene files, once a
// reader exists) is one more entry in Kinds().
#pragma once
#include <fdem.h>
#include <fdem/kernels/tetmesh.hpp>

#include <exception>
#include <string>
#include <vector>

namespace fdem_inputs {

using PathFn = PetscErrorCode (*)(MPI_Comm comm, const char *file);
struct Path {
  const char *name;
  PathFn      run;
};
struct Kind {
  const char              *name;
  std::vector<std::string> extensions;  // with the dot
  std::vector<Path>        paths;
};

// Every rank reads the file with the kernel reader; if any rank fails, all
// return the error of the lowest failing rank. Warnings are printed once.
inline PetscErrorCode ReadMesh(MPI_Comm comm, const char *file, fdem::kernels::TetMesh &mesh) {
  std::string err;
  PetscMPIInt rank, size, first;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  try {
    mesh = fdem::kernels::ReadGmsh(file);
  } catch (const std::exception &e) {
    err = e.what();
  }
  const PetscMPIInt mine = err.empty() ? size : rank;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first < size) {
    int len = (int)err.size();
    PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, comm));
    err.resize((size_t)len);
    PetscCallMPI(MPI_Bcast(&err[0], len, MPI_CHAR, first, comm));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "%s", err.c_str());
  }
  for (const auto &w : mesh.warnings) PetscCall(PetscPrintf(comm, "Warning: %s\n", w.c_str()));
  PetscFunctionReturn(0);
}

// Each body of the mesh becomes a rigid body (density 1, at its place),
// named "file:line: body 'name'" with the line of its first tetrahedron.
inline PetscErrorCode AddRigidBodies(FDEMRigid rb, const char *file, const fdem::kernels::TetMesh &M) {
  PetscFunctionBeginUser;
  for (int b = 0; b < M.NumBodies(); ++b) {
    std::vector<PetscInt>  local(M.nodes.size(), -1), tets;
    std::vector<PetscReal> nodes;
    long                   line = -1;
    for (size_t e = 0; e < M.tets.size(); ++e) {
      if (M.body[e] != b) continue;
      if (line < 0) line = M.tet_line[e];
      for (int n : M.tets[e]) {
        if (local[n] < 0) {
          local[n] = (PetscInt)(nodes.size() / 3);
          nodes.insert(nodes.end(), {M.nodes[n].x, M.nodes[n].y, M.nodes[n].z});
        }
        tets.push_back(local[n]);
      }
    }
    const std::string name = std::string(file) + ":" + std::to_string(line) + ": body '" + M.body_names[b] + "'";
    PetscReal         x[3] = {0, 0, 0};
    for (size_t i = 0; i < nodes.size(); ++i) x[i % 3] += nodes[i] / (PetscReal)(nodes.size() / 3);
    PetscCall(FDEMRigidAddBodyFromMesh(rb, name.c_str(), (PetscInt)(nodes.size() / 3), nodes.data(), (PetscInt)(tets.size() / 4), tets.data(), 1.0, x, nullptr, nullptr, nullptr, nullptr));
  }
  PetscFunctionReturn(0);
}

// Rigid path: the reader, then FDEMRigidAddBodyFromMesh for every body.
inline PetscErrorCode MeshRigid(MPI_Comm comm, const char *file) {
  fdem::kernels::TetMesh M;
  FDEMRigid              rb;
  PetscFunctionBeginUser;
  PetscCall(ReadMesh(comm, file, M));
  PetscCall(FDEMRigidCreate(comm, &rb));
  const PetscErrorCode ierr = AddRigidBodies(rb, file, M);
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

// Deformable path: FDEMDeformableSetMeshFromGmsh and FDEMDeformableSetUp (one
// material, E = 1, nu = 0.25, rho = 1, for every body).
inline PetscErrorCode SetUpDeformable(FDEMDeformable d, const char *file) {
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableAddMaterial(d, "fuzz", 1.0, 0.25, 1.0, 0.0, FDEM_MATERIAL_NEO_HOOKEAN));
  PetscCall(FDEMDeformableSetMeshFromGmsh(d, file));
  PetscCall(FDEMDeformableSetUp(d));
  PetscFunctionReturn(0);
}
inline PetscErrorCode MeshDeformable(MPI_Comm comm, const char *file) {
  FDEMDeformable d;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, &d));
  const PetscErrorCode ierr = SetUpDeformable(d, file);
  PetscCall(FDEMDeformableDestroy(&d));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

inline const std::vector<Kind> &Kinds() {
  static const std::vector<Kind> kinds = {
    {"msh", {".msh"}, {{"rigid", MeshRigid}, {"deformable", MeshDeformable}}},
  };
  return kinds;
}

// The kind named `name`, or (name empty) the one taking the file's extension.
inline const Kind *FindKind(const std::string &name, const std::string &file) {
  for (const auto &k : Kinds()) {
    if (!name.empty()) {
      if (name == k.name) return &k;
      continue;
    }
    for (const auto &ext : k.extensions)
      if (file.size() >= ext.size() && file.compare(file.size() - ext.size(), ext.size(), ext) == 0) return &k;
  }
  return nullptr;
}

// Runs file through one path with errors returned, not printed: *msg gets the
// error message ("" if accepted). Collective.
inline PetscErrorCode RunPath(MPI_Comm comm, const Path &p, const char *file, std::string *msg) {
  char *text = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  const PetscErrorCode ierr = p.run(comm, file);
  PetscCall(PetscPopErrorHandler());
  msg->clear();
  if (ierr) {
    PetscCall(PetscErrorMessage(ierr, nullptr, &text));
    *msg = text && *text ? text : "(error " + std::to_string((int)ierr) + " without a message)";
  }
  PetscFunctionReturn(0);
}

} // namespace fdem_inputs
