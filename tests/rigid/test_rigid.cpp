// Rigid bodies in a DMSwarm stepped by fdem's TS types (issue: rigid bodies).
//  1. the book's axisymmetric example (Fig 5.6-5.9, inertia diag(I, I, 2I))
//  2. observed orders with an orientation-dependent torque, per drift variant x scheme
//  3. zero torque: |H| and energy, orthonormality
//  4. constant torque about a principal axis (spin-up) and a torque impulse
//  5. bad input: clear errors naming the body
#include <fdem.h>
#include <fdem/rigid.h>
#include <fdem/kernels/rotation.hpp>
#include <fdem/kernels/massprops.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

#include "../common/check.hpp"

// torque from a constant space force F0 applied at the body point c (body frame): M = (R c) x F0
struct TorqueCtx {
  PetscReal c[3] = {0.3, -0.2, 0.5}, F0[3] = {0, 0, -4.0};
  PetscReal M[3] = {0, 0, 0}; // plus a constant torque
  PetscReal until = 1e300;    // constant torque acts for t < until
};
static PetscErrorCode Torque(PetscInt, PetscReal t, const PetscReal *, const PetscReal R[9], const PetscReal *, const PetscReal *, PetscReal F[3], PetscReal M[3], void *ctx) {
  TorqueCtx *tc = (TorqueCtx *)ctx;
  PetscFunctionBeginUser;
  Vec3 rc;
  for (int r = 0; r < 3; ++r) rc[r] = R[3 * r] * tc->c[0] + R[3 * r + 1] * tc->c[1] + R[3 * r + 2] * tc->c[2];
  const Vec3 m = fdem::kernels::cross(rc, Vec3(tc->F0[0], tc->F0[1], tc->F0[2]));
  for (int k = 0; k < 3; ++k) M[k] += m[k] + (t < tc->until ? tc->M[k] : 0);
  PetscFunctionReturn(0);
}

struct Track {
  std::vector<double> t, w[3]; // body-frame omega of body 0 after each step
  PetscReal           I[3];
};
static PetscErrorCode TrackOmega(TS ts, PetscInt, PetscReal t, Vec U, void *ctx) {
  Track             *tr = (Track *)ctx;
  const PetscScalar *u;
  PetscInt           n;
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(U, &n));
  if (n == 0) PetscFunctionReturn(0);
  n /= 18;
  PetscCall(VecGetArrayRead(U, &u));
  Mat3 R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R.m[r][c] = u[3 * n + 3 * r + c];
  const Vec3 H(u[15 * n], u[15 * n + 1], u[15 * n + 2]);
  const Vec3 wb = fdem::kernels::transpose(R) * fdem::kernels::BodyOmega(R, Vec3(tr->I[0], tr->I[1], tr->I[2]), H);
  tr->t.push_back(t);
  for (int k = 0; k < 3; ++k) tr->w[k].push_back(wb[k]);
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscFunctionReturn(0);
}

// One body, run with a scheme and a rotation variant to time T with step h; returns the final state.
static PetscErrorCode RunOne(const char *scheme, FDEMRotationType rot, const PetscReal I[3], const PetscReal omega_body[3], TorqueCtx *tc, PetscReal h, PetscReal T, Track *track, FDEMRigidBodyState *st) {
  FDEMRigid rb;
  TS        ts;
  Vec       U;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
  PetscCall(FDEMRigidSetRotationType(rb, rot));
  if (tc) PetscCall(FDEMRigidSetForceFunction(rb, Torque, tc));
  const PetscReal x[3] = {0, 0, 0}, v[3] = {0, 0, 0};
  // R = identity: body and space frames coincide at t = 0
  PetscCall(FDEMRigidAddBody(rb, "top", 1.0, I, x, nullptr, v, omega_body, nullptr));
  PetscCall(TSCreate(PETSC_COMM_SELF, &ts));
  PetscCall(TSSetType(ts, scheme));
  PetscCall(FDEMRigidSetUpTS(rb, ts, &U));
  PetscCall(TSSetTimeStep(ts, h));
  PetscCall(TSSetMaxTime(ts, T));
  PetscCall(TSSetMaxSteps(ts, 100000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  if (track) {
    for (int k = 0; k < 3; ++k) track->I[k] = I[k];
    PetscCall(TSMonitorSet(ts, TrackOmega, track, nullptr));
  }
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMRigidRestoreState(rb, U));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMRigidGetBodyState(rb, 0, st));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscFunctionReturn(0);
}

static double StateDiff(const FDEMRigidBodyState &a, const FDEMRigidBodyState &b) {
  double d = 0;
  for (int k = 0; k < 9; ++k) d = std::fmax(d, std::fabs(a.R[k] - b.R[k]));
  for (int k = 0; k < 3; ++k) d = std::fmax(d, std::fabs(a.H[k] - b.H[k]) / (1 + std::fabs(b.H[k])));
  return d;
}


int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  const FDEMRotationType rots[3] = {FDEM_ROTATION_MUNJIZA, FDEM_ROTATION_NOSQUISH, FDEM_ROTATION_EXACT};

  // 1. the book's axisymmetric element: I = diag(I, I, 2I), omega0 = (0, 1, 100) in the body frame;
  //    exact: omega_x = -sin 100t, omega_y = cos 100t (doc/book.md B)
  {
    const PetscReal I[3] = {1, 1, 2}, w0[3] = {0, 1, 100};
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Book Fig 5.6-5.9, -ts_type cd, t in [0, 0.25]: max |omega_body - exact|\n%-9s %12s %12s %12s\n", "rotation", "h=0.0005", "h=0.001", "h=0.005"));
    for (FDEMRotationType rot : rots) {
      double err[3];
      int    k = 0;
      for (PetscReal h : {0.0005, 0.001, 0.005}) {
        Track              tr;
        FDEMRigidBodyState st;
        PetscCall(RunOne("cd", rot, I, w0, nullptr, h, 0.25, &tr, &st));
        double e = 0;
        for (size_t i = 0; i < tr.t.size(); ++i) e = std::fmax(e, std::fmax(std::fabs(tr.w[0][i] + std::sin(100 * tr.t[i])), std::fabs(tr.w[1][i] - std::cos(100 * tr.t[i]))));
        err[k++] = e;
      }
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-9s %12.4e %12.4e %12.4e\n", FDEMRotationTypes[rot], err[0], err[1], err[2]));
      if (rot == FDEM_ROTATION_EXACT) CHECK(err[2] < 1e-11, "exact rotation on the axisymmetric example: error %g", err[2]);
      else {
        // second order: halving h divides the error by ~4; the book's figures: 'almost indistinguishable' at 0.0005
        CHECK(err[0] < 2.5e-2 && std::fabs(std::log2(err[1] / err[0]) - 2) < 0.3, "%s: errors %g %g (order %.2f)", FDEMRotationTypes[rot], err[0], err[1], std::log2(err[1] / err[0]));
        CHECK(err[2] > 10 * err[1], "%s: h = 0.005 should lag visibly (book Fig 5.9): %g vs %g", FDEMRotationTypes[rot], err[2], err[1]);
      }
    }
  }

  // 2. orientation-dependent torque: observed orders per rotation variant and scheme
  {
    const PetscReal I[3] = {1.0, 2.0, 3.0}, w0[3] = {0.8, -0.4, 1.1};
    const PetscReal T = 2.0, h0 = 0.1;
    TorqueCtx       tc;
    struct Case {
      const char *scheme;
      double      expect[3]; // munjiza, nosquish, exact
    } cases[] = {{"cd", {2, 2, 2}}, {"pv", {2, 2, 2}}, {"omf30", {2, 2, 2}},
                 // Forest-Ruth is a triple-jump composition of a symmetric step: with the symmetric
                 // NO_SQUISH drift it stays 4th order; Munjiza's non-symmetric drift gives 3
                 {"fr", {3, 4, 4}}, {"pefrl", {2, 2, 4}}, {"chin", {2, 2, -1}}, {"omf32", {2, 2, -1}}};
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nTorque M = (R c) x F0, I = (1,2,3), T = %g: d(h) = max|state_h - state_h/2| and orders\n%-6s %-9s %11s %11s %11s %7s %7s %s\n", (double)T, "scheme", "rotation", "d(h0)", "d(h0/2)",
                          "d(h0/4)", "p1", "p2", "expect"));
    for (auto &cs : cases)
      for (int r = 0; r < 3; ++r) {
        FDEMRigidBodyState st[4];
        for (int k = 0; k < 4; ++k) PetscCall(RunOne(cs.scheme, rots[r], I, w0, &tc, h0 / (1 << k), T, nullptr, &st[k]));
        double d[3];
        for (int k = 0; k < 3; ++k) d[k] = StateDiff(st[k], st[k + 1]);
        const double p1 = std::log2(d[0] / d[1]), p2 = std::log2(d[1] / d[2]);
        const bool   ok = cs.expect[r] < 0 || std::fabs(p2 - cs.expect[r]) < 0.35;
        PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-6s %-9s %11.3e %11.3e %11.3e %7.3f %7.3f %s %s\n", cs.scheme, FDEMRotationTypes[rots[r]], d[0], d[1], d[2], p1, p2,
                              cs.expect[r] < 0 ? "(measured)" : (cs.expect[r] == 2 ? "2" : "4"), ok ? "ok" : "FAIL"));
        if (!ok) failures++;
      }
  }

  // 3. zero torque: |H| in the body frame and the energy, orthonormality of R over 1e4 steps
  {
    const PetscReal I[3] = {1.0, 2.0, 3.0}, w0[3] = {0.02, 1.0, 0.02}; // near the intermediate axis: flips
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nZero torque, start near the intermediate axis, 1e4 steps of h = 0.01 (cd)\n%-9s %14s %14s %14s %14s\n", "rotation", "|H| rel.err", "energy drift", "orthonorm.",
                          "omega err"));
    for (FDEMRotationType rot : rots) {
      Track              tr;
      FDEMRigidBodyState st;
      PetscCall(RunOne("cd", rot, I, w0, nullptr, 0.01, 100.0, &tr, &st));
      const Vec3   H0(I[0] * w0[0], I[1] * w0[1], I[2] * w0[2]);
      const double E0 = 0.5 * (I[0] * w0[0] * w0[0] + I[1] * w0[1] * w0[1] + I[2] * w0[2] * w0[2]);
      double       edrift = 0, herr = 0, werr = 0;
      for (size_t i = 0; i < tr.t.size(); ++i) {
        const Vec3 w(tr.w[0][i], tr.w[1][i], tr.w[2][i]);
        const Vec3 Hb(I[0] * w[0], I[1] * w[1], I[2] * w[2]);
        herr   = std::fmax(herr, std::fabs(norm(Hb) - norm(H0)) / norm(H0));
        edrift = std::fmax(edrift, std::fabs(0.5 * dot(Hb, w) - E0) / E0);
        Vec3 we;
        fdem::kernels::TorqueFreeOmegaBody(Vec3(I[0], I[1], I[2]), Vec3(w0[0], w0[1], w0[2]), tr.t[i], we);
        werr = std::fmax(werr, norm(w - we));
      }
      const double orth = fdem::kernels::OrthonormalityError(Mat3{{{{st.R[0], st.R[1], st.R[2]}, {st.R[3], st.R[4], st.R[5]}, {st.R[6], st.R[7], st.R[8]}}}});
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%-9s %14.3e %14.3e %14.3e %14.3e\n", FDEMRotationTypes[rot], herr, edrift, orth, werr));
      CHECK(herr < 1e-12, "%s: |H| not conserved: %g", FDEMRotationTypes[rot], herr);
      CHECK(orth < 1e-13, "%s: R not orthonormal: %g", FDEMRotationTypes[rot], orth);
      if (rot == FDEM_ROTATION_EXACT) CHECK(edrift < 1e-12 && werr < 1e-8, "exact: energy %g, omega error %g", edrift, werr);
      else CHECK(edrift < 5e-3, "%s: energy error %g above the stated bound 5e-3", FDEMRotationTypes[rot], edrift);
    }
  }

  // 4. constant torque about a principal axis: omega_3(t) = omega_0 + M t / I_3; impulse: stops at t = 0.5
  {
    const PetscReal I[3] = {2.0, 3.0, 4.0}, w0[3] = {0, 0, 0.5};
    for (const char *scheme : {"cd", "pefrl", "omf32"})
      for (FDEMRotationType rot : rots) {
        TorqueCtx tc;
        tc.c[0] = tc.c[1] = tc.c[2] = 0;
        tc.M[2]                     = 1.2;
        FDEMRigidBodyState st;
        PetscCall(RunOne(scheme, rot, I, w0, &tc, 0.01, 2.0, nullptr, &st));
        const double expect = 0.5 + 1.2 * 2.0 / 4.0;
        CHECK(std::fabs(st.omega_space[2] - expect) < 1e-12 && std::fabs(st.omega_space[0]) < 1e-14, "spin-up %s/%s: omega_z %.15g, expected %.15g", scheme, FDEMRotationTypes[rot], st.omega_space[2], expect);
        tc.until = 0.5; // the torque acts on [0, 0.5): an impulse of 0.6
        PetscCall(RunOne(scheme, rot, I, w0, &tc, 0.01, 2.0, nullptr, &st));
        CHECK(std::fabs(st.omega_space[2] - (0.5 + 0.6 / 4.0)) < 0.01 * 1.2 / 4.0 + 1e-12, "impulse %s/%s: omega_z %.15g, expected %.15g", scheme, FDEMRotationTypes[rot], st.omega_space[2], 0.5 + 0.6 / 4);
      }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nok: spin-up under a constant principal torque exact to 1e-12 (cd, pefrl, omf32 x 3 rotations); torque impulse within one step\n"));
  }

  // 5. bad input
  {
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> T;
    fdem::kernels::MakeBoxTets(Vec3(0, 0, 0), Vec3(1, 2, 3), 2, 2, 2, X, T);
    std::vector<PetscReal> nodes;
    std::vector<PetscInt>  tets;
    for (auto &p : X) nodes.insert(nodes.end(), {p.x, p.y, p.z});
    for (auto &t : T) tets.insert(tets.end(), {t[0], t[1], t[2], t[3]});
    const PetscReal x[3] = {0, 0, 0};
    auto            add = [&](const char *name, std::vector<PetscInt> tt, PetscReal rho) -> PetscErrorCode {
      FDEMRigid rb;
      PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
      PetscErrorCode ierr = FDEMRigidAddBodyFromMesh(rb, name, (PetscInt)X.size(), nodes.data(), (PetscInt)tt.size() / 4, tt.data(), rho, x, nullptr, nullptr, nullptr, nullptr);
      PetscCall(FDEMRigidDestroy(&rb));
      return ierr;
    };
    PetscCall(ExpectError("zero density", "pebble_a", [&]() { return add("pebble_a", tets, 0.0); }));
    // two tetrahedra meeting along one edge only: the skin is not a closed 2-manifold
    PetscCall(ExpectError("non-closed skin", "pebble_b", [&]() -> PetscErrorCode {
      FDEMRigid             rb;
      std::vector<PetscReal> nn = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1};
      std::vector<PetscInt>  tt = {0, 1, 2, 3, 0, 1, 4, 5};
      PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
      PetscErrorCode ierr = FDEMRigidAddBodyFromMesh(rb, "pebble_b", 6, nn.data(), 2, tt.data(), 1000.0, x, nullptr, nullptr, nullptr, nullptr);
      PetscCall(FDEMRigidDestroy(&rb));
      return ierr;
    }));
    std::vector<PetscInt> inv = tets;
    std::swap(inv[4 * 7 + 1], inv[4 * 7 + 2]); // invert tetrahedron 7
    PetscCall(ExpectError("inverted tetrahedron", "7", [&]() { return add("pebble_c", inv, 1000.0); }));
    PetscCall(ExpectError("degenerate inertia", "rod", [&]() -> PetscErrorCode {
      FDEMRigid       rb;
      const PetscReal I[3] = {0, 1, 1};
      PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
      PetscErrorCode ierr = FDEMRigidAddBody(rb, "rod", 1.0, I, x, nullptr, nullptr, nullptr, nullptr);
      PetscCall(FDEMRigidDestroy(&rb));
      return ierr;
    }));
    PetscCall(ExpectError("negative mass", "ghost", [&]() -> PetscErrorCode {
      FDEMRigid       rb;
      const PetscReal I[3] = {1, 1, 1};
      PetscCall(FDEMRigidCreate(PETSC_COMM_SELF, &rb));
      PetscErrorCode ierr = FDEMRigidAddBody(rb, "ghost", -1.0, I, x, nullptr, nullptr, nullptr, nullptr);
      PetscCall(FDEMRigidDestroy(&rb));
      return ierr;
    }));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
