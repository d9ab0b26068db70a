// A wave in a long bar: a bar [0,L]x[0,W]x[0,W] of constant-strain tetrahedra
// (FDEMDeformable, distributed DMPlex) at rest and unstrained gets a Gaussian
// pulse of axial velocity v_x = v0 exp(-((x - x0)/s)^2); it splits into two
// halves, and the right-going one passes two stations x1 < x2. The times of the
// velocity peak at the stations (mean v_x over the nodes of each cross-section,
// parabola through the largest sample) give the measured speed
// c = (x2 - x1) / (t2 - t1), printed against the bar velocity sqrt(E / rho)
// (exact for nu = 0, where it equals the P-wave speed; the long-wave limit for nu > 0).
//
// Options (doc/examples.md): -fdem_length 1 -fdem_cells_along 200 -fdem_cells_across 2
//   -fdem_young 1 -fdem_density 1 -fdem_poisson 0 -fdem_material munjiza_cst|...
//   -fdem_cfl 0.3 (default -ts_dt = cfl h / c_p; -ts_max_time: until the pulse passed x2)
//   -fdem_pulse_centre 0.15 -fdem_pulse_width 0.03 -fdem_station1 0.4 -fdem_station2 0.8 (fractions of L)
//   -fdem_amplitude 1e-4 (v0 / c) -fdem_output DIR (default out/bar_wave: stations.csv, a row
//   every -fdem_output_every steps) -fdem_expect_speed_error 0.02
#include <fdem.h>
#include <fdem/deformable.h>

#include "../common/options.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

namespace {
struct Ctx {
  double                x0, s, v0;
  std::vector<PetscInt> st[2];
  PetscInt              nst[2] = {0, 0};
  std::vector<PetscInt> step;
  std::vector<double>   t, v[2];
};

PetscErrorCode Pulse(PetscInt, const PetscReal X[3], PetscReal v[3], void *ctx) {
  Ctx *c = (Ctx *)ctx;
  const double z = (X[0] - c->x0) / c->s;
  v[0] = c->v0 * std::exp(-z * z);
  v[1] = v[2] = 0;
  return 0;
}

PetscErrorCode Monitor(TS ts, PetscInt step, PetscReal t, Vec U, void *ctx) {
  Ctx               *c = (Ctx *)ctx;
  const PetscScalar *u;
  PetscInt           n;
  PetscReal          loc[2] = {0, 0}, glob[2];
  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(U, &n));
  PetscCall(VecGetArrayRead(U, &u));
  for (int j = 0; j < 2; ++j)
    for (PetscInt k : c->st[j]) loc[j] += u[n / 2 + 3 * k];
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)ts)));
  c->step.push_back(step);
  c->t.push_back(t);
  for (int j = 0; j < 2; ++j) c->v[j].push_back(glob[j] / c->nst[j]);
  PetscFunctionReturn(0);
}

// time of the first peak above half of `level`, by a parabola through the top three samples
double PeakTime(const std::vector<double> &t, const std::vector<double> &v, double level) {
  for (size_t i = 1; i + 1 < v.size(); ++i)
    if (v[i] > 0.5 * level && v[i] >= v[i - 1] && v[i] >= v[i + 1]) {
      const double a = v[i - 1], b = v[i], c = v[i + 1], den = a - 2 * b + c;
      const double off = den != 0 ? 0.5 * (a - c) / den : 0;
      return t[i] + off * (t[i + 1] - t[i]);
    }
  return NAN;
}
} // namespace

PetscErrorCode RunExample(int *status) {
  PetscFunctionBeginUser;
  namespace ex = fdem::examples;
  PetscReal         L = 1, E = 1, rho = 1, nu = 0, cfl = 0.3, x0 = 0.15, s = 0.03, x1 = 0.4, x2 = 0.8, amp = 1e-4, expect = -1;
  PetscInt          n = 200, ny = 2;
  PetscBool         has_expect;
  ex::Output        out{"out/bar_wave", 1};
  FDEMMaterialModel model = FDEM_MATERIAL_MUNJIZA_CST;
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Wave in a bar; time steps: -ts_dt (cfl h / c_p), -ts_max_time (until the pulse passed station 2), -ts_type (cd)", "");
  PetscCall(PetscOptionsReal("-fdem_length", "bar length L", "", L, &L, nullptr));
  PetscCall(PetscOptionsInt("-fdem_cells_along", "cells along the bar", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-fdem_cells_across", "cells across the bar (y and z)", "", ny, &ny, nullptr));
  PetscCall(PetscOptionsReal("-fdem_young", "Young's modulus E", "", E, &E, nullptr));
  PetscCall(PetscOptionsReal("-fdem_density", "density rho", "", rho, &rho, nullptr));
  PetscCall(PetscOptionsReal("-fdem_poisson", "Poisson's ratio nu", "", nu, &nu, nullptr));
  PetscCall(PetscOptionsEnum("-fdem_material", "material model", "", FDEMMaterialModels, (PetscEnum)model, (PetscEnum *)&model, nullptr));
  PetscCall(PetscOptionsReal("-fdem_cfl", "default time step = cfl h / c_p (-ts_dt overrides)", "", cfl, &cfl, nullptr));
  PetscCall(PetscOptionsReal("-fdem_pulse_centre", "pulse centre / L", "", x0, &x0, nullptr));
  PetscCall(PetscOptionsReal("-fdem_pulse_width", "pulse width / L", "", s, &s, nullptr));
  PetscCall(PetscOptionsReal("-fdem_station1", "first station / L", "", x1, &x1, nullptr));
  PetscCall(PetscOptionsReal("-fdem_station2", "second station / L", "", x2, &x2, nullptr));
  PetscCall(PetscOptionsReal("-fdem_amplitude", "pulse velocity / bar velocity", "", amp, &amp, nullptr));
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (rows of stations.csv)");
  PetscCall(PetscOptionsReal("-fdem_expect_speed_error", "fail if |c - c_theory| / c_theory exceeds this", "", expect, &expect, &has_expect));
  PetscOptionsEnd();
  PetscCall(ex::CheckPositive("-fdem_length", L));
  PetscCall(ex::CheckInt("-fdem_cells_along", n, 1, 100000));
  PetscCall(ex::CheckInt("-fdem_cells_across", ny, 1, 1000));
  PetscCall(ex::CheckPositive("-fdem_young", E));
  PetscCall(ex::CheckPositive("-fdem_density", rho));
  PetscCall(ex::CheckReal("-fdem_poisson", nu, 0, false, 0.5, true));
  PetscCall(ex::CheckReal("-fdem_cfl", cfl, 0, true, 1, false));
  PetscCall(ex::CheckReal("-fdem_pulse_centre", x0, 0, true, 1, true));
  PetscCall(ex::CheckReal("-fdem_pulse_width", s, 0, true, 1, true));
  PetscCall(ex::CheckReal("-fdem_station1", x1, x0, true, 1, false)); // right of the pulse: the right-going half passes it
  PetscCall(ex::CheckReal("-fdem_station2", x2, x1, true, 1, false));
  PetscCheck(std::round(x1 * n) < std::round(x2 * n), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "Options -fdem_station1 %g and -fdem_station2 %g fall on the same grid plane of the %" PetscInt_FMT " cells; move them apart", (double)x1, (double)x2, n);
  PetscCall(ex::CheckPositive("-fdem_amplitude", amp));
  if (has_expect) PetscCall(ex::CheckPositive("-fdem_expect_speed_error", expect));
  PetscCall(ex::SetUpOutput(out));

  const double h = L / n, W = ny * h, c_bar = std::sqrt(E / rho), cp = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho));
  FDEMDeformable d;
  Ctx            c;
  c.x0 = x0 * L;
  c.s  = s * L;
  c.v0 = amp * c_bar;
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "bar", E, nu, rho, 0.0, model));
  {
    const PetscReal lo[3] = {0, 0, 0}, hi[3] = {L, W, W};
    PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, n, ny, ny));
  }
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCall(FDEMDeformableSetUp(d));
  PetscCall(FDEMDeformableSetVelocityField(d, Pulse, &c));
  // stations on grid planes
  const double xs[2] = {std::round(x1 * n) * h, std::round(x2 * n) * h};
  {
    Vec                Xr;
    const PetscScalar *X;
    PetscInt           nown, cells;
    PetscCall(FDEMDeformableGetReferencePositions(d, &Xr));
    PetscCall(FDEMDeformableGetSizes(d, nullptr, &cells, &nown, nullptr));
    PetscCall(VecGetArrayRead(Xr, &X));
    for (PetscInt k = 0; k < nown; ++k)
      for (int j = 0; j < 2; ++j)
        if (std::fabs(X[3 * k] - xs[j]) < 1e-6 * h) c.st[j].push_back(k);
    PetscCall(VecRestoreArrayRead(Xr, &X));
    for (int j = 0; j < 2; ++j) {
      PetscInt m = (PetscInt)c.st[j].size();
      PetscCall(MPIU_Allreduce(&m, &c.nst[j], 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
    }
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Bar %gx%gx%g, %d cells (h = %g), E %g, rho %g, nu %g, %s; Gaussian velocity pulse at x = %g, width %g\n", (double)L, W, W, (int)cells, h, (double)E, (double)rho, (double)nu,
                          FDEMMaterialModels[model], c.x0, c.s));
  }
  TS  ts;
  Vec U;
  PetscReal dt = cfl * h / cp, tf = (xs[1] - c.x0) / c_bar + 4 * c.s / c_bar;
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(ex::SetTimeDefaults(ts, TSFDEMCD, dt, tf));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSMonitorSet(ts, Monitor, &c, nullptr));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(ex::GetTimeSettings(ts, &dt, &tf, nullptr));
  PetscLogDouble w0, w1;
  PetscInt       steps;
  PetscCall(PetscTime(&w0));
  PetscCall(TSSolve(ts, U));
  PetscCall(PetscTime(&w1));
  PetscCall(TSGetStepNumber(ts, &steps));
  // the right-going half carries v0/2
  const double t1 = PeakTime(c.t, c.v[0], 0.5 * c.v0), t2 = PeakTime(c.t, c.v[1], 0.5 * c.v0);
  TSType type;
  PetscCall(TSGetType(ts, &type));
  PetscCall(TSGetTime(ts, &tf));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d steps of %g (%s) to t = %g, %.2f s\n", (int)steps, (double)dt, type, (double)tf, w1 - w0));
  PetscCheck(std::isfinite(t1) && std::isfinite(t2) && t2 > t1, PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "bar_wave: the pulse peak was not seen at both stations by t = %g (peak times %g, %g): run longer (-ts_max_time, -ts_max_steps) or move the stations (-fdem_station1, -fdem_station2)", (double)tf, t1, t2);
  const double speed = (xs[1] - xs[0]) / (t2 - t1), err = (speed - c_bar) / c_bar;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "peak at x1 = %g: t = %.6g, at x2 = %g: t = %.6g\n", xs[0], t1, xs[1], t2));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "measured wave speed %.6g, sqrt(E/rho) = %.6g (P-wave speed %.6g): error %+.3f%%\n", speed, c_bar, cp, 100 * err));
  if (out.on()) {
    FILE             *fp;
    const std::string csv = out.path("stations.csv");
    PetscCall(PetscFOpen(PETSC_COMM_WORLD, csv.c_str(), "w", &fp));
    PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "t,v_x1,v_x2\n"));
    for (size_t i = 0; i < c.t.size(); ++i)
      if (c.step[i] % out.every == 0) PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "%.10g,%.10g,%.10g\n", c.t[i], c.v[0][i], c.v[1][i]));
    PetscCall(PetscFClose(PETSC_COMM_WORLD, fp));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "station histories: %s\n", csv.c_str()));
  }
  if (has_expect) {
    PetscCheck(std::isfinite(err) && std::fabs(err) <= expect, PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "bar_wave: wave speed %g differs from sqrt(E/rho) = %g by %.3f%% > %.3f%%", speed, c_bar, 100 * err, 100 * (double)expect);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: |c - sqrt(E/rho)| / sqrt(E/rho) = %.3f%% <= %.3f%%\n", 100 * std::fabs(err), 100 * (double)expect));
  }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  *status = 0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
