// Spheres at scale through the library (FDEMRigidAddSphere, FDEMContact, the TS):
// an fcc bed of touching spheres (diameter 1, mass 1, the dense bed of in.bed and
// make_bed.py) with random velocities, the Hooke law of gran/hooke/history 2000 NULL 50
// NULL 0.5 1, dt 1e-4, search buffer 0.1. Prints the memory in use per sphere (all
// ranks, resident, after the run against before the spheres were added), the set-up
// time and particle-steps per second per core of the stepping.
//   mpiexec -n 2 bench_spheres -cells 63 -steps 20     (1 000 188 spheres)
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>

#include <cmath>
#include <random>

int main(int argc, char **argv) {
  PetscInt       cells = 20, steps = 100;
  PetscMPIInt    size;
  PetscLogDouble m0, m1, t0, t1, t2;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, "bench_spheres: spheres at scale (see the source)"));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "bench_spheres", "");
  PetscCall(PetscOptionsInt("-cells", "fcc unit cells per side (4 cells^3 spheres)", "", cells, &cells, nullptr));
  PetscCall(PetscOptionsInt("-steps", "time steps", "", steps, &steps, nullptr));
  PetscOptionsEnd();
  PetscCall(PetscMemoryGetCurrentUsage(&m0));
  PetscCall(PetscTime(&t0));
  FDEMRigid            rb;
  FDEMContact          c;
  FDEMGranularMaterial g;
  PetscInt             mat;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  const PetscReal a = std::sqrt(2.0), L = a * cells, lo[3] = {-1, -1, -1}, hi[3] = {L + 1, L + 1, L + 1};
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law      = FDEM_GRANULAR_HOOKE;
  g.law_set  = PETSC_TRUE;
  g.kn       = 2000;
  g.kt       = 2000 * 2.0 / 7.0;
  g.gamma_n  = 50;
  g.gamma_t  = 25;
  g.friction = 0.5;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "bead", &g, &mat));
  std::mt19937_64                  rng(4928459);
  std::normal_distribution<double> N(0.0, 0.1);
  const double                     basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (PetscInt i = 0; i < cells; ++i)
    for (PetscInt j = 0; j < cells; ++j)
      for (PetscInt k = 0; k < cells; ++k)
        for (const auto &b : basis) {
          const PetscReal x[3] = {a * (i + b[0]), a * (j + b[1]), a * (k + b[2])}, v[3] = {N(rng), N(rng), N(rng)};
          PetscCall(FDEMRigidAddSphere(rb, "s", 0.5, 6 / PETSC_PI, mat, x, v, nullptr, nullptr));
        }
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMContactSetBuffer(c, 0.1));
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(FDEMContactSetFromOptions(c));
  PetscCall(FDEMRigidMigrate(rb));
  PetscCall(PetscTime(&t1));
  PetscCall(FDEMRigidSolve(rb, 0, steps * 1e-4, 1e-4, steps, nullptr, nullptr));
  PetscCall(PetscTime(&t2));
  PetscCall(PetscMemoryGetCurrentUsage(&m1));
  PetscLogDouble dm = m1 - m0, dmg;
  PetscCallMPI(MPI_Allreduce(&dm, &dmg, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD));
  PetscInt         n;
  FDEMContactStats st;
  PetscCall(FDEMRigidGetNumBodies(rb, nullptr, &n));
  PetscCall(FDEMContactGetStats(c, &st));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " spheres on %d rank(s): memory %.0f bytes per sphere (%.2f GB in all), set-up %.1f s, %" PetscInt_FMT " steps in %.2f s: %.3g particle-steps/s/core; coordination %.3f\n", n, size, dmg / n, dmg / 1e9,
                        t1 - t0, steps, t2 - t1, (double)n * steps / (t2 - t1) / size, 2.0 * st.active_pairs / n));
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(PetscFinalize());
  return 0;
}
