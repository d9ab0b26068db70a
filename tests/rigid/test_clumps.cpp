// Clumps (FDEMRigidAddClump, doc/spheres.md "Clumps") through the library API:
//  1. A clump of one sphere is that sphere: the same oblique, spinning Hertz impact with
//     friction in gross slip (restitution 0.8, mu 0.05), once between two spheres and once
//     with one of them a clump of one sphere, in one run: the two pairs end equal to 1e-9 m/s
//     and 1e-8 rad/s (measured 1.2e-11 and 4e-10 of 0.35 m/s and 11 rad/s: the clump's R turns
//     and its spin comes from R, I and H, the sphere's from H / I). With mu 0.4 the contact
//     passes from slip to stick, a comparison that round-off can move by a step, and they
//     part by 3e-8 of the spin.
//  2. An off-centre impact: a dumbbell (two spheres 2d apart along y) moving along -x strikes
//     a fixed sphere with its +y sphere, centre to centre (Hooke, undamped, stiff enough that
//     the dumbbell barely turns during the contact). Rigid-body impact theory: the impulse
//     J = 2 m_eff v with 1 / m_eff = 1 / m + d^2 / I_z, so afterwards v_x = -v + J / m and
//     omega_z = -J d / I_z; both within 2% (measured 5e-7), and the kinetic energy kept to 1%. A wrong lever
//     arm (the torque of the force about the sphere instead of the body) would leave the
//     dumbbell unturned and rebounding at +v.
//  3. Bad input: no spheres, a radius that is not positive, a density of 0, a material that
//     does not exist, a position that is not finite: errors naming the clump and the sphere.
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>

#include <algorithm>
#include <cmath>

#include "../common/check.hpp"

namespace {
const PetscReal R0 = 0.01, RHO = 2500;

PetscErrorCode Material(FDEMRigid rb, FDEMGranularLaw law, PetscReal e, PetscReal mu, PetscReal kn, PetscInt *m) {
  FDEMGranularMaterial g;
  PetscFunctionBeginUser;
  PetscCall(FDEMGranularMaterialInitialize(&g));
  g.law     = law;
  g.law_set = PETSC_TRUE;
  g.young   = 5e9;
  g.poisson = 0.25;
  g.kn      = kn;
  g.kt      = kn * 2.0 / 7.0;
  if (e > 0) g.restitution = e;
  g.friction = mu;
  PetscCall(FDEMRigidAddGranularMaterial(rb, "glass", &g, m));
  PetscFunctionReturn(0);
}

PetscErrorCode OneSphereClump() {
  FDEMRigid   rb;
  FDEMContact c;
  PetscInt    m, a, b, a2, b2;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(Material(rb, FDEM_GRANULAR_HERTZ, 0.8, 0.05, 2e5, &m)); // friction in gross slip throughout (a law continuous in the state)
  const PetscReal va[3] = {0.5, 0.1, 0}, vb[3] = {-0.5, 0, 0}, wa[3] = {0, 0, 30};
  const PetscReal xa[3] = {-R0 - 1e-5, 0.4 * R0, 0}, xb[3] = {R0 + 1e-5, 0, 0};
  const PetscReal ya[3] = {-R0 - 1e-5, 0.4 * R0 + 1, 0}, yb[3] = {R0 + 1e-5, 1, 0};
  const PetscReal ball[4] = {0.2, -0.1, 0.3, R0}; // off the clump's own origin: it is placed by its centre of mass
  PetscCall(FDEMRigidAddSphere(rb, "a", R0, RHO, m, xa, va, wa, &a));
  PetscCall(FDEMRigidAddSphere(rb, "b", R0, RHO, m, xb, vb, nullptr, &b));
  PetscCall(FDEMRigidAddClump(rb, "a as a clump", 1, ball, RHO, m, ya, nullptr, va, wa, &a2));
  PetscCall(FDEMRigidAddSphere(rb, "b2", R0, RHO, m, yb, vb, nullptr, &b2));
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMRigidSolve(rb, 0, 1e-3, 2e-7, 100, nullptr, nullptr)); // the gap (4e-4 m at 1 m/s) closes at 4e-4 s
  FDEMRigidBodyState A, B, A2, B2;
  PetscCall(FDEMRigidGetBodyState(rb, a, &A));
  PetscCall(FDEMRigidGetBodyState(rb, b, &B));
  PetscCall(FDEMRigidGetBodyState(rb, a2, &A2));
  PetscCall(FDEMRigidGetBodyState(rb, b2, &B2));
  PetscReal dv = 0, dw = 0, turned = 0;
  for (int k = 0; k < 3; ++k) {
    dv     = std::max({dv, std::fabs(A.v[k] - A2.v[k]), std::fabs(B.v[k] - B2.v[k])});
    dw     = std::max({dw, std::fabs(A.omega_space[k] - A2.omega_space[k]), std::fabs(B.omega_space[k] - B2.omega_space[k])});
    turned = std::max(turned, std::fabs(B.omega_space[k]));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "one-sphere clump against the sphere: max |dv| %.3e m/s, |domega| %.3e rad/s (b's spin after %.3f rad/s; a's speed %.4f -> %.4f m/s)\n", (double)dv, (double)dw, (double)turned, 0.5, (double)A.v[0]));
  CHECK(turned > 1, "one-sphere clump: the impact gave b no spin (%g rad/s): not oblique with friction?", (double)turned);
  CHECK(dv < 1e-9 && dw < 1e-8, "one-sphere clump: it differs from the sphere by %g m/s, %g rad/s", (double)dv, (double)dw);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

PetscErrorCode OffCentre() {
  FDEMRigid   rb;
  FDEMContact c;
  PetscInt    m, bell, target;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(Material(rb, FDEM_GRANULAR_HOOKE, -1, 0, 1e7, &m));
  const PetscReal d = 2 * R0, v = 0.05;
  const PetscReal balls[8] = {0, -d, 0, R0, 0, d, 0, R0};
  const PetscReal x[3] = {2 * R0 + 1e-5, 0, 0}, vel[3] = {-v, 0, 0}, xt[3] = {0, d, 0};
  PetscCall(FDEMRigidAddClump(rb, "dumbbell", 2, balls, RHO, m, x, nullptr, vel, nullptr, &bell));
  PetscCall(FDEMRigidAddSphere(rb, "target", R0, RHO, m, xt, nullptr, nullptr, &target));
  PetscCall(FDEMRigidFixBody(rb, target));
  PetscCall(FDEMContactCreate(rb, &c));
  const PetscReal ms = 4.0 / 3.0 * PETSC_PI * R0 * R0 * R0 * RHO, mass = 2 * ms, Iz = 2 * (0.4 * ms * R0 * R0 + ms * d * d);
  const PetscReal meff = 1 / (1 / mass + d * d / Iz), tc = PETSC_PI * PetscSqrtReal(meff / 1e7), J = 2 * meff * v;
  PetscCall(FDEMRigidSolve(rb, 0, 1e-5 / v + 2 * tc, tc / 200, 100000, nullptr, nullptr));
  FDEMRigidBodyState S;
  PetscCall(FDEMRigidGetBodyState(rb, bell, &S));
  const PetscReal vx = -v + J / mass, wz = -J * d / Iz;
  const PetscReal ke0 = 0.5 * mass * v * v, ke1 = 0.5 * mass * (S.v[0] * S.v[0] + S.v[1] * S.v[1] + S.v[2] * S.v[2]) + 0.5 * Iz * S.omega_space[2] * S.omega_space[2];
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "dumbbell struck off its centre: v_x %.6e m/s (theory %.6e), omega_z %.6e rad/s (theory %.6e); kinetic energy %.6e -> %.6e J\n", (double)S.v[0], (double)vx, (double)S.omega_space[2], (double)wz, (double)ke0, (double)ke1));
  CHECK(std::fabs(S.v[0] - vx) < 0.02 * v, "dumbbell: v_x %g, theory %g", (double)S.v[0], (double)vx);
  CHECK(std::fabs(S.omega_space[2] - wz) < 0.02 * std::fabs(wz), "dumbbell: omega_z %g, theory %g", (double)S.omega_space[2], (double)wz);
  CHECK(std::fabs(ke1 - ke0) < 0.01 * ke0, "dumbbell: kinetic energy %g -> %g (elastic)", (double)ke0, (double)ke1);
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

PetscErrorCode BadInput() {
  FDEMRigid       rb;
  PetscInt        m;
  const PetscReal x[3] = {0, 0, 0}, nanx[3] = {0, NAN, 0};
  const PetscReal two[8] = {0, 0, 0, R0, R0, 0, 0, -R0};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(Material(rb, FDEM_GRANULAR_HERTZ, 0.5, 0.3, 2e5, &m));
  PetscCall(ExpectError("clump without spheres", {"Clump c", "at least one sphere"}, [&] { return FDEMRigidAddClump(rb, "c", 0, two, RHO, m, x, nullptr, nullptr, nullptr, nullptr); }));
  PetscCall(ExpectError("clump with a negative radius", {"Clump c", "sphere 1: radius"}, [&] { return FDEMRigidAddClump(rb, "c", 2, two, RHO, m, x, nullptr, nullptr, nullptr, nullptr); }));
  PetscCall(ExpectError("clump of density 0", {"Clump c", "density"}, [&] { return FDEMRigidAddClump(rb, "c", 1, two, 0, m, x, nullptr, nullptr, nullptr, nullptr); }));
  PetscCall(ExpectError("clump of an unknown material", {"Clump c", "no granular material 7"}, [&] { return FDEMRigidAddClump(rb, "c", 1, two, RHO, 7, x, nullptr, nullptr, nullptr, nullptr); }));
  PetscCall(ExpectError("clump at a position not finite", {"Clump c", "not finite"}, [&] { return FDEMRigidAddClump(rb, "c", 1, two, RHO, m, nanx, nullptr, nullptr, nullptr, nullptr); }));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(OneSphereClump());
  PetscCall(OffCentre());
  PetscCall(BadInput());
  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
