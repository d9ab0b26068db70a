// The same problem solved on all ranks of PETSC_COMM_WORLD (distributed Vecs)
// and on PETSC_COMM_SELF (the whole chain on each rank), for every scheme:
// the answers must agree to 1e-12 relative. Run under mpiexec -n 1 and -n 2.
#include <fdem.h>
#include "../../examples/common/fpu_chain.hpp"

#include <cmath>

static PetscErrorCode Solve(MPI_Comm comm, const char *type, PetscInt N, std::vector<double> &out) {
  fpu::Chain c;
  TS         ts;
  Vec        U;
  PetscFunctionBeginUser;
  PetscCall(fpu::Create(comm, N, 1.0, &c));
  PetscCall(fpu::CreateState(&c, &U));
  PetscCall(fpu::Initial(&c, 0.6, U));
  PetscCall(TSCreate(comm, &ts));
  PetscCall(fpu::SetUpTS(&c, ts));
  PetscCall(TSSetType(ts, type));
  PetscCall(TSSetTimeStep(ts, 0.07));
  PetscCall(TSSetMaxTime(ts, 3.0));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(TSSolve(ts, U));
  PetscCall(fpu::Gather(&c, U, out));
  PetscCall(TSDestroy(&ts));
  PetscCall(VecDestroy(&U));
  PetscCall(fpu::Destroy(&c));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  int         failures = 0;
  PetscMPIInt size;
  PetscInt    N = 37; // not divisible by 2: uneven ownership
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  const char *types[] = {"cd", "pv", "t112", "t16", "d112", "pc3", "pc4", "pc5", "chin", "omf30", "omf32", "fr", "pefrl"};
  for (const char *type : types) {
    std::vector<double> par, ser;
    PetscCall(Solve(PETSC_COMM_WORLD, type, N, par));
    PetscCall(Solve(PETSC_COMM_SELF, type, N, ser));
    double dmax = 0, smax = 0;
    for (size_t i = 0; i < par.size(); ++i) {
      dmax = std::fmax(dmax, std::fabs(par[i] - ser[i]));
      smax = std::fmax(smax, std::fabs(ser[i]));
    }
    double gmax;
    PetscCallMPI(MPI_Allreduce(&dmax, &gmax, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    const bool ok = gmax <= 1e-12 * smax;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-6s %d ranks vs 1: max |difference| %.3e (scale %.3f) %s\n", type, (int)size, gmax, smax, ok ? "ok" : "FAIL"));
    if (!ok) failures++;
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
