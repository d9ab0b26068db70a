// Tumbling rigid bodies: many irregular bodies built from tetrahedral meshes
// (convex hulls of random points, ellipsoids, boxes) with random spins and
// velocities fly through a box split into slabs, one per rank; bodies migrate
// between ranks as they cross the slab boundaries. Optional gravity. Writes
// the bodies' skins to DIR/tumbling.h5 + .xmf (FDEMRigidWriteHDF5;
// -fdem_output DIR, default out/tumbling) every -fdem_output_every steps, which
// is also the migration interval (-fdem_plain_bodies adds bodies given by
// principal data only, drawn as octahedra) and checks its own result:
//
//   no gravity (and no torque):  total linear momentum P and angular momentum
//     L (about the origin) conserved to 1e-12 relative (-fdem_expect_momentum),
//     kinetic energy E to -fdem_expect_energy (default 1e-12, the bound for
//     -fdem_rigid_rotation exact; the run.sh / CTest cases with munjiza and
//     nosquish pass their measured bounds);
//   -fdem_gravity:  P(t) = P(0) + M g t to 1e-12 relative to |P| + M|g|t, and
//     E - M g . x_cm conserved to -fdem_expect_energy.
//
// Run: mpiexec -n 2 ./tumbling -fdem_bodies 60 -ts_max_time 2 -fdem_output out/tumbling
// then open out/tumbling/tumbling.xmf in ParaView; check_output.py verifies the
// files. doc/examples.md lists the options.
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/rotation.hpp>

#include "../common/options.hpp"

#include <cmath>
#include <random>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {

struct Ctx {
  std::string output; // DIR/tumbling, or empty: no output
  PetscReal P0[3], L0[3], E0, X0[3]; // initial invariants and M x_cm
  PetscReal Mtot = 0, g[3] = {0, 0, 0};
  PetscInt  nglobal = 0;
  double    errP = 0, errL = 0, errE = 0;
  PetscInt  writes = 0;
  PetscMPIInt rank = 0;
};

// M x_cm (sum of m x over all bodies), through the public API
PetscErrorCode MassMoment(FDEMRigid rb, PetscInt nglobal, PetscReal mx[3], PetscReal *M) {
  PetscFunctionBeginUser;
  mx[0] = mx[1] = mx[2] = 0;
  *M                    = 0;
  for (PetscInt id = 0; id < nglobal; ++id) {
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(rb, id, &st));
    for (int k = 0; k < 3; ++k) mx[k] += st.mass * st.x[k];
    *M += st.mass;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode Monitor(FDEMRigid rb, PetscInt step, PetscReal t, void *ptr) {
  Ctx      *c = (Ctx *)ptr;
  PetscReal P[3], L[3], E, X[3], M;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetInvariants(rb, P, L, &E));
  PetscCall(MassMoment(rb, c->nglobal, X, &M));
  // expected: P = P0 + M g t; L about the origin gains sum x x m g = (M x_cm) x g (torque of gravity)
  // -- L is only checked without gravity; E_kin - M g.x_cm is conserved
  double dP = 0, sP = 0, dL = 0, sL = 0;
  const double gn = std::sqrt(c->g[0] * c->g[0] + c->g[1] * c->g[1] + c->g[2] * c->g[2]);
  for (int k = 0; k < 3; ++k) {
    dP += std::pow(P[k] - (c->P0[k] + c->Mtot * c->g[k] * t), 2);
    sP += std::pow(c->P0[k], 2);
    dL += std::pow(L[k] - c->L0[k], 2);
    sL += std::pow(c->L0[k], 2);
  }
  const double eP = std::sqrt(dP) / (std::sqrt(sP) + c->Mtot * gn * t);
  const double eL = std::sqrt(dL) / std::sqrt(sL);
  const double V = -(c->g[0] * X[0] + c->g[1] * X[1] + c->g[2] * X[2]), V0 = -(c->g[0] * c->X0[0] + c->g[1] * c->X0[1] + c->g[2] * c->X0[2]);
  const double eE = std::fabs((E + V) - (c->E0 + V0)) / c->E0;
  c->errP = std::fmax(c->errP, eP);
  if (gn == 0) c->errL = std::fmax(c->errL, eL);
  c->errE = std::fmax(c->errE, eE);
  PetscInt nloc;
  PetscCall(FDEMRigidGetNumBodies(rb, &nloc, nullptr));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "step %5" PetscInt_FMT " t %8.4f  |dP|/|P| %9.2e  |dL|/|L| %9.2e  dE/E %9.2e  bodies per rank:", step, (double)t, eP, gn == 0 ? eL : NAN, eE));
  PetscCall(PetscSynchronizedPrintf(PETSC_COMM_WORLD, " %" PetscInt_FMT, nloc));
  PetscCall(PetscSynchronizedFlush(PETSC_COMM_WORLD, PETSC_STDOUT));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\n"));
  // FDEMRigidSolve calls the monitor at step 0, every migration (= output) interval and at the end
  if (!c->output.empty()) {
    PetscCall(FDEMRigidWriteHDF5(rb, c->output.c_str(), step, t));
    c->writes++;
  }
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RunExample(int *status) {
  PetscFunctionBeginUser;
  namespace ex = fdem::examples;
  Ctx        c;
  PetscInt   n = 60, seed = 7, nplain = 0;
  PetscReal  vmax = 3.0, wmax = 6.0;
  PetscReal  expect_momentum = 1e-12, expect_energy = 1e-12;
  PetscBool  gravity = PETSC_FALSE;
  ex::Output out{"out/tumbling", 10};
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &c.rank));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Tumbling rigid bodies; time steps: -ts_dt (0.005), -ts_max_time (1), -ts_type (cd)", "");
  PetscCall(PetscOptionsInt("-fdem_bodies", "number of mesh bodies (hulls, ellipsoids, boxes)", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-fdem_plain_bodies", "further bodies from principal data only (no mesh; drawn as octahedra)", "", nplain, &nplain, nullptr));
  PetscCall(PetscOptionsInt("-fdem_seed", "random seed", "", seed, &seed, nullptr));
  PetscCall(PetscOptionsReal("-fdem_vmax", "largest initial speed component", "", vmax, &vmax, nullptr));
  PetscCall(PetscOptionsReal("-fdem_wmax", "largest initial angular speed", "", wmax, &wmax, nullptr));
  PetscCall(PetscOptionsBool("-fdem_gravity", "gravity (0, 0, -9.81)", "", gravity, &gravity, nullptr));
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (HDF5 + XDMF) and migrations");
  PetscCall(PetscOptionsReal("-fdem_expect_momentum", "bound on the relative change of P and L", "", expect_momentum, &expect_momentum, nullptr));
  PetscCall(PetscOptionsReal("-fdem_expect_energy", "bound on the relative change of the energy", "", expect_energy, &expect_energy, nullptr));
  PetscOptionsEnd();
  PetscCall(ex::CheckInt("-fdem_bodies", n, 0, 100000));
  PetscCall(ex::CheckInt("-fdem_plain_bodies", nplain, 0, 100000));
  PetscCheck(n + nplain > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "Options -fdem_bodies %" PetscInt_FMT " and -fdem_plain_bodies %" PetscInt_FMT ": need at least one body", n, nplain);
  PetscCall(ex::CheckInt("-fdem_seed", seed, 0, PETSC_MAX_INT));
  PetscCall(ex::CheckNonNegative("-fdem_vmax", vmax));
  PetscCall(ex::CheckNonNegative("-fdem_wmax", wmax));
  PetscCall(ex::CheckPositive("-fdem_expect_momentum", expect_momentum));
  PetscCall(ex::CheckPositive("-fdem_expect_energy", expect_energy));
  PetscCall(ex::SetUpOutput(out));
  c.output = out.path("tumbling");

  FDEMRigid rb;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  const PetscReal L = 20.0, lo[3] = {0, 0, 0}, hi[3] = {L, 4, 4};
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  if (gravity) {
    c.g[2] = -9.81;
    PetscCall(FDEMRigidSetGravity(rb, c.g));
  }
  PetscCall(FDEMRigidSetFromOptions(rb)); // -fdem_rigid_rotation, -fdem_rigid_gravity
  {
    // read back a gravity given with -fdem_rigid_gravity (checks use it)
    PetscInt  three = 3;
    PetscBool flg;
    PetscCall(PetscOptionsGetRealArray(nullptr, nullptr, "-fdem_rigid_gravity", c.g, &three, &flg));
  }

  // every rank builds the same scene (same seed); each keeps the bodies in its slab
  std::mt19937_64                        rng((unsigned long)seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const char                            *kinds[3] = {"hull", "ellipsoid", "box"};
  for (PetscInt b = 0; b < n; ++b) {
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> Tt;
    const int                       kind = (int)(b % 3);
    const Vec3                      size(0.25 + 0.15 * (U(rng) + 1), 0.2 + 0.1 * (U(rng) + 1), 0.12 + 0.08 * (U(rng) + 1));
    if (kind == 0) {
      std::vector<Vec3> pts;
      for (int i = 0; i < 14; ++i) pts.push_back(Vec3(size[0] * U(rng), size[1] * U(rng), size[2] * U(rng)));
      fdem::kernels::MakeConvexPolyhedronTets(pts, X, Tt);
    } else if (kind == 1) {
      fdem::kernels::MakeEllipsoidTets(size, 1, X, Tt);
    } else {
      fdem::kernels::MakeBoxTets(-1.0 * size, size, 1, 1, 1, X, Tt);
    }
    std::vector<PetscReal> nodes;
    std::vector<PetscInt>  tets;
    for (const Vec3 &p : X) nodes.insert(nodes.end(), {p.x, p.y, p.z});
    for (const auto &t : Tt) tets.insert(tets.end(), {t[0], t[1], t[2], t[3]});
    // a lattice of sites 1 apart inside the box, random orientation, spin and velocity
    const PetscReal x[3] = {1.0 + (PetscReal)(b % 18), 1.0 + (PetscReal)((b / 18) % 3), 1.0 + (PetscReal)((b / 54) % 3)};
    const Mat3      Q    = fdem::kernels::RotationMatrix(Vec3(3 * U(rng), 3 * U(rng), 3 * U(rng)));
    PetscReal       Qr[9], v[3], w[3];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) Qr[3 * r + k] = Q.m[r][k];
    for (int k = 0; k < 3; ++k) {
      v[k] = vmax * U(rng);
      w[k] = wmax / std::sqrt(3.0) * U(rng);
    }
    char name[64];
    PetscCall(PetscSNPrintf(name, sizeof(name), "%s%" PetscInt_FMT, kinds[kind], b));
    PetscCall(FDEMRigidAddBodyFromMesh(rb, name, (PetscInt)X.size(), nodes.data(), (PetscInt)Tt.size(), tets.data(), 1000.0, x, Qr, v, w, nullptr));
  }
  for (PetscInt b = 0; b < nplain; ++b) {
    const PetscReal I[3] = {2.0 + 0.4 * U(rng), 3.0 + 0.4 * U(rng), 3.8 + 0.3 * U(rng)} /* I1 + I2 >= 4.2 > 4.1 >= I3 */, x[3] = {1.0 + 17.0 * (0.5 + 0.5 * U(rng)), 2.0 + U(rng), 2.0 + U(rng)};
    const PetscReal v[3] = {vmax * U(rng), vmax * U(rng), vmax * U(rng)}, w[3] = {wmax * U(rng) / 2, wmax * U(rng) / 2, wmax * U(rng) / 2};
    PetscCall(FDEMRigidAddBody(rb, "plain", 100.0, I, x, nullptr, v, w, nullptr));
  }
  PetscInt nloc;
  PetscCall(FDEMRigidGetNumBodies(rb, &nloc, &c.nglobal));
  PetscCall(FDEMRigidGetInvariants(rb, c.P0, c.L0, &c.E0));
  PetscCall(MassMoment(rb, c.nglobal, c.X0, &c.Mtot));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " bodies (hulls, ellipsoids, boxes), total mass %g, gravity (%g, %g, %g)\n", c.nglobal, (double)c.Mtot, (double)c.g[0], (double)c.g[1], (double)c.g[2]));
  PetscCall(FDEMRigidSolve(rb, 0.0, 1.0, 0.005, out.every, Monitor, &c)); // -ts_max_time, -ts_dt override 1.0, 0.005
  PetscReal tf;
  PetscInt  steps;
  PetscCall(FDEMRigidGetTime(rb, &tf, &steps));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " steps to t = %g\n", steps, (double)tf));

  int failures = 0;
  const bool torque_free = c.g[0] == 0 && c.g[1] == 0 && c.g[2] == 0;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "max relative change: P %.3e, L %s%.3e, energy %.3e (bounds %.1e, %.1e)\n", c.errP, torque_free ? "" : "(not checked) ", c.errL, c.errE, (double)expect_momentum,
                        (double)expect_energy));
  if (!(c.errP <= expect_momentum)) {
    failures++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: linear momentum changed by %.3e > %.1e\n", c.errP, (double)expect_momentum));
  }
  if (torque_free && !(c.errL <= expect_momentum)) {
    failures++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: angular momentum changed by %.3e > %.1e\n", c.errL, (double)expect_momentum));
  }
  if (!(c.errE <= expect_energy)) {
    failures++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: energy changed by %.3e > %.1e\n", c.errE, (double)expect_energy));
  }
  if (!c.output.empty()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "wrote %" PetscInt_FMT " steps to %s.h5 and %s.xmf\n", c.writes, c.output.c_str(), c.output.c_str()));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  *status = failures ? 1 : 0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
