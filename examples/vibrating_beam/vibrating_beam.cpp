// A vibrating cantilever: a beam [0,L]x[0,W]x[0,H] of constant-strain
// tetrahedra (FDEMDeformable on a distributed DMPlex) clamped at x = 0, set
// moving in its Euler-Bernoulli first mode shape (initial velocity only), and
// stepped by an fdem TS scheme (-ts_type cd by default). The tip deflection
// u_z(t) (mean over the nodes at x = L) is recorded; its zero crossings give
// the first natural frequency, printed against Euler-Bernoulli
//   f1 = (beta1^2 / 2 pi) sqrt(E I / (rho A L^4)),  beta1 = 1.8751, I = W H^3 / 12.
// nu = 0 by default, so beam theory's E is the material's (no Poisson stiffening at the clamp).
//
// Options (doc/examples.md): -fdem_length 1 -fdem_width 0.1 -fdem_thickness 0.1
//   -fdem_cells_thick 8 (cells across the thickness) -fdem_cells_wide 1 -fdem_aspect 1
//   -fdem_young 1 -fdem_density 1 -fdem_poisson 0 -fdem_material munjiza_cst|neo_hookean|small_strain_linear
//   -fdem_cfl 0.3 (default -ts_dt = cfl h / c_p) -ts_max_time (default 1.1 Euler-Bernoulli periods)
//   -fdem_amplitude 1e-4 (tip amplitude / L) -fdem_output DIR (default out/vibrating_beam: tip.csv,
//   beam.h5 + beam.xmf every -fdem_output_every 200 steps; none: no files)
//   -fdem_expect_freq_error 0.03 (fails if |f - f_EB| / f_EB is larger)
//   -fdem_convergence 2,3,4 (runs the meshes in turn and prints the table)
#include <fdem.h>
#include <fdem/deformable.h>

#include "../common/options.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {
const double kBeta = 1.8751040687119611, kSigma = 0.7340955137589676;
double Mode(double xi) { return std::cosh(kBeta * xi) - std::cos(kBeta * xi) - kSigma * (std::sinh(kBeta * xi) - std::sin(kBeta * xi)); }

struct Ctx {
  double                L, v0;
  std::vector<PetscInt> tip; // owned indices of tip nodes
  PetscInt              ntip_global = 0, nown = 0;
  std::vector<double>   t, u;
  FDEMDeformable        d = nullptr;
  std::string           h5;
  PetscInt              h5_every = 0;
};

PetscErrorCode Velocity(PetscInt, const PetscReal X[3], PetscReal v[3], void *ctx) {
  Ctx *c = (Ctx *)ctx;
  v[0] = v[1] = 0;
  v[2] = c->v0 * Mode(X[0] / c->L) / Mode(1.0);
  return 0;
}

PetscErrorCode Monitor(TS ts, PetscInt step, PetscReal t, Vec U, void *ctx) {
  Ctx               *c = (Ctx *)ctx;
  const PetscScalar *u;
  PetscReal          loc = 0, glob;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(U, &u));
  const PetscScalar *X;
  Vec                Xr;
  PetscCall(FDEMDeformableGetReferencePositions(c->d, &Xr));
  PetscCall(VecGetArrayRead(Xr, &X));
  for (PetscInt k : c->tip) loc += u[3 * k + 2] - X[3 * k + 2];
  PetscCall(VecRestoreArrayRead(Xr, &X));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(MPIU_Allreduce(&loc, &glob, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)ts)));
  c->t.push_back(t);
  c->u.push_back(glob / c->ntip_global);
  if (!c->h5.empty() && c->h5_every > 0 && step % c->h5_every == 0) PetscCall(FDEMDeformableWriteHDF5(c->d, U, c->h5.c_str(), step, t));
  PetscFunctionReturn(0);
}

struct Result {
  double f, f_eb, err, wall;
  PetscInt cells, steps;
};

// csv, h5: file names, or empty for none
PetscErrorCode Run(PetscInt n, PetscInt ny, PetscReal aspect, double L, double W, double H, double E, double rho, double nu, FDEMMaterialModel model, double cfl, double amp, const std::string &csv, const std::string &h5, PetscInt h5_every, Result *res) {
  FDEMDeformable d;
  Ctx            c;
  TS             ts;
  Vec            U;
  PetscFunctionBeginUser;
  const double A = W * H, I = W * H * H * H / 12;
  const double omega = kBeta * kBeta * std::sqrt(E * I / (rho * A)) / (L * L);
  res->f_eb = omega / (2 * M_PI);
  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "beam", E, nu, rho, 0.0, model));
  if (ny > 0) { // n layers through the thickness, ny across the width, elements aspect times longer along x
    const PetscReal lo[3] = {0, 0, 0}, hi[3] = {L, W, H};
    const PetscInt  nx    = (PetscInt)std::lround(L / (aspect * H / n));
    PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, nx, ny, n));
  } else PetscCall(FDEMDeformableSetMeshBeam(d, L, W, H, n));
  PetscCall(FDEMDeformableSetFromOptions(d));
  PetscCall(FDEMDeformableSetUp(d));
  const PetscReal lo[3] = {-1, -1, -1}, hi[3] = {1e-9 * L, 2 * W + 1, 2 * H + 1};
  PetscInt        nfixed;
  PetscCall(FDEMDeformableFixNodesInBox(d, lo, hi, &nfixed));
  c.L  = L;
  c.v0 = amp * L * omega;
  c.d  = d;
  PetscCall(FDEMDeformableSetVelocityField(d, Velocity, &c));
  {
    Vec                Xr;
    const PetscScalar *X;
    PetscCall(FDEMDeformableGetReferencePositions(d, &Xr));
    PetscCall(FDEMDeformableGetSizes(d, nullptr, &res->cells, &c.nown, nullptr));
    PetscCall(VecGetArrayRead(Xr, &X));
    for (PetscInt k = 0; k < c.nown; ++k)
      if (X[3 * k] > L * (1 - 1e-9)) c.tip.push_back(k);
    PetscCall(VecRestoreArrayRead(Xr, &X));
    PetscInt nt = (PetscInt)c.tip.size();
    PetscCall(MPIU_Allreduce(&nt, &c.ntip_global, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD));
  }
  c.h5       = h5;
  c.h5_every = h5_every;
  // time step from the P-wave speed and the element size
  const double cp = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho));
  PetscReal dt = cfl * (H / n) / cp, tf = 1.1 / res->f_eb;
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(fdem::examples::SetTimeDefaults(ts, TSFDEMCD, dt, tf));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSMonitorSet(ts, Monitor, &c, nullptr));
  PetscCall(TSSetFromOptions(ts));
  PetscCall(fdem::examples::GetTimeSettings(ts, &dt, &tf, nullptr));
  PetscLogDouble t0, t1;
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, U));
  PetscCall(PetscTime(&t1));
  PetscCall(TSGetStepNumber(ts, &res->steps));
  res->wall = t1 - t0;
  // zero crossings: u = A sin(omega t) crosses zero at t_k = k T / 2 (k = 1, 2, ...)
  std::vector<double> tc;
  for (size_t i = 1; i < c.u.size(); ++i)
    if ((c.u[i - 1] > 0) != (c.u[i] > 0) && c.t[i - 1] > 0) tc.push_back(c.t[i - 1] + (c.t[i] - c.t[i - 1]) * c.u[i - 1] / (c.u[i - 1] - c.u[i]));
  double num = 0, den = 0;
  for (size_t k = 0; k < tc.size(); ++k) {
    num += (k + 1) * tc[k];
    den += (k + 1) * (k + 1);
  }
  PetscCheck(!tc.empty(), PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "vibrating_beam: the tip never crossed zero in %g periods (t = %g); run longer (-ts_max_time)", (double)(tf * res->f_eb), (double)tf);
  const double T = 2 * num / den;
  res->f         = 1 / T;
  res->err       = (res->f - res->f_eb) / res->f_eb;
  if (!csv.empty()) {
    FILE *fp = nullptr;
    if (!c.u.empty()) {
      PetscCall(PetscFOpen(PETSC_COMM_WORLD, csv.c_str(), "w", &fp));
      PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "t,tip_uz\n"));
      for (size_t i = 0; i < c.u.size(); ++i) PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "%.10g,%.10g\n", c.t[i], c.u[i]));
      PetscCall(PetscFClose(PETSC_COMM_WORLD, fp));
    }
  }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode RunExample(int *status) {
  PetscFunctionBeginUser;
  namespace ex = fdem::examples;
  PetscReal         L = 1, W = 0.1, H = 0.1, E = 1, rho = 1, nu = 0, cfl = 0.3, amp = 1e-4, expect = -1;
  PetscReal         aspect = 1;
  PetscInt          ny = 1, n = 8, conv[8], nconv = 8;
  PetscBool         has_conv, has_expect;
  ex::Output        out{"out/vibrating_beam", 200};
  FDEMMaterialModel model = FDEM_MATERIAL_MUNJIZA_CST;
  PetscCall(FDEMInitializePackage());
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Vibrating cantilever; time steps: -ts_dt (cfl h / c_p), -ts_max_time (1.1 periods), -ts_type (cd)", "");
  PetscCall(PetscOptionsReal("-fdem_length", "length L (x)", "", L, &L, nullptr));
  PetscCall(PetscOptionsReal("-fdem_width", "width W (y)", "", W, &W, nullptr));
  PetscCall(PetscOptionsReal("-fdem_thickness", "thickness H (z, bending direction)", "", H, &H, nullptr));
  PetscCall(PetscOptionsInt("-fdem_cells_thick", "cells across the thickness", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-fdem_cells_wide", "cells across the width (0: the beam mesh of cubes, as many as across the thickness)", "", ny, &ny, nullptr));
  PetscCall(PetscOptionsReal("-fdem_aspect", "element length along x / thickness size (with -fdem_cells_wide > 0)", "", aspect, &aspect, nullptr));
  PetscCall(PetscOptionsReal("-fdem_young", "Young's modulus E", "", E, &E, nullptr));
  PetscCall(PetscOptionsReal("-fdem_density", "density rho", "", rho, &rho, nullptr));
  PetscCall(PetscOptionsReal("-fdem_poisson", "Poisson's ratio nu", "", nu, &nu, nullptr));
  PetscCall(PetscOptionsEnum("-fdem_material", "material model", "", FDEMMaterialModels, (PetscEnum)model, (PetscEnum *)&model, nullptr));
  PetscCall(PetscOptionsReal("-fdem_cfl", "default time step = cfl h / c_p (-ts_dt overrides)", "", cfl, &cfl, nullptr));
  PetscCall(PetscOptionsReal("-fdem_amplitude", "tip amplitude / L", "", amp, &amp, nullptr));
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (HDF5 + XDMF of the mesh)");
  PetscCall(PetscOptionsReal("-fdem_expect_freq_error", "fail if |f - f_EB| / f_EB exceeds this", "", expect, &expect, &has_expect));
  PetscCall(PetscOptionsIntArray("-fdem_convergence", "run these -fdem_cells_thick in turn", "", conv, &nconv, &has_conv));
  PetscOptionsEnd();
  PetscCall(ex::CheckPositive("-fdem_length", L));
  PetscCall(ex::CheckPositive("-fdem_width", W));
  PetscCall(ex::CheckPositive("-fdem_thickness", H));
  PetscCall(ex::CheckInt("-fdem_cells_thick", n, 1, 1000));
  PetscCall(ex::CheckInt("-fdem_cells_wide", ny, 0, 1000));
  PetscCall(ex::CheckPositive("-fdem_aspect", aspect));
  PetscCall(ex::CheckPositive("-fdem_young", E));
  PetscCall(ex::CheckPositive("-fdem_density", rho));
  PetscCall(ex::CheckReal("-fdem_poisson", nu, 0, false, 0.5, true));
  PetscCall(ex::CheckReal("-fdem_cfl", cfl, 0, true, 1, false));
  PetscCall(ex::CheckPositive("-fdem_amplitude", amp));
  if (has_expect) PetscCall(ex::CheckPositive("-fdem_expect_freq_error", expect));
  if (has_conv) {
    PetscCheck(nconv > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "Option -fdem_convergence: give at least one number of cells");
    for (PetscInt i = 0; i < nconv; ++i) PetscCall(ex::CheckInt("-fdem_convergence", conv[i], 1, 1000));
  }
  PetscCall(ex::SetUpOutput(out));
  if (!has_conv) {
    conv[0] = n;
    nconv   = 1;
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Cantilever %gx%gx%g, E %g, rho %g, nu %g, %s; clamped at x = 0, first-mode initial velocity\n", (double)L, (double)W, (double)H, (double)E, (double)rho, (double)nu, FDEMMaterialModels[model]));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%4s %9s %8s %12s %12s %9s %8s\n", "n", "cells", "steps", "f measured", "f EB", "error", "wall s"));
  Result r{};
  double prev_err = 1e300;
  for (PetscInt i = 0; i < nconv; ++i) {
    const bool last = i == nconv - 1;
    PetscCall(Run(conv[i], ny, aspect, L, W, H, E, rho, nu, model, cfl, amp, last ? out.path("tip.csv") : "", last ? out.path("beam") : "", out.every, &r));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%4d %9d %8d %12.6g %12.6g %+8.2f%% %8.2f\n", (int)conv[i], (int)r.cells, (int)r.steps, r.f, r.f_eb, 100 * r.err, r.wall));
    PetscCheck(i == 0 || std::fabs(r.err) < std::fabs(prev_err), PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "vibrating_beam: no convergence: error %.2f%% after %.2f%%", 100 * r.err, 100 * prev_err);
    prev_err = r.err;
  }
  if (out.on()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "tip history: %s/tip.csv; mesh: %s/beam.h5 + beam.xmf (ParaView: open the .xmf)\n", out.dir, out.dir));
  if (nconv > 1) { // convergence: the error fell with every refinement (checked in the loop)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: the error falls with every refinement\n"));
  }
  if (has_expect) {
    PetscCheck(std::fabs(r.err) <= expect, PETSC_COMM_WORLD, PETSC_ERR_NOT_CONVERGED, "vibrating_beam: first frequency %g differs from Euler-Bernoulli %g by %.2f%% > %.2f%%", r.f, r.f_eb, 100 * std::fabs(r.err), 100 * (double)expect);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ok: |f - f_EB| / f_EB = %.2f%% <= %.2f%%\n", 100 * std::fabs(r.err), 100 * (double)expect));
  }
  *status = 0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
