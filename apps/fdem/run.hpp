// The run loop of the driver: time stepping in segments between outputs
// (rigid migration between segments), progress line, balance.csv, HDF5 +
// XDMF output and the end summary; and `fdem check`.
#pragma once
#include "scene.hpp"

#include <fdem/kernels/tetmesh.hpp>
#include <petscsys.h>

#include <vector>

namespace fdem::driver {

struct RunOptions {
  char      output[PETSC_MAX_PATH_LEN] = ""; // -fdem_output: overrides output.dir; "none": no files
  PetscBool progress                   = PETSC_TRUE;
  char      restart[PETSC_MAX_PATH_LEN] = ""; // -restart: continue from this checkpoint
  PetscInt  kill_in_checkpoint          = 0; // test hook: SIGKILL between writing the k-th checkpoint and renaming it
  PetscBool check_only                 = PETSC_FALSE; // fdem check
  PetscReal gain_limit                 = 0.5; // -fdem_balance_gain_limit: stop when the scene gained this fraction of its energy
  PetscInt  insert_every               = 10;  // -fdem_insert_every: steps between the searches for tetrahedra that get joints (insert_at)
  PetscReal insert_heap                = 1.5; // -fdem_insert_heap: room kept for the rebuilds of a run that inserts joints, times the memory in use after the set-up
};

// Reads the driver's options (-fdem_output, -fdem_progress) in a PetscOptions block (shown by -help).
PetscErrorCode RunOptionsFromCommandLine(MPI_Comm comm, RunOptions &o);
// Builds the scene's models and runs it (or, with check_only, prints the summary of `fdem check`).
PetscErrorCode RunScene(MPI_Comm comm, const Scene &sc, std::vector<kernels::TetMesh> meshes, const RunOptions &o);

} // namespace fdem::driver
