// A test problem shared by the tests, examples and benchmarks: the
// Fermi-Pasta-Ulam-beta chain. N particles on a line with fixed ends, unequal
// masses m_i, joined by anharmonic springs V(r) = k r^2/2 + beta r^4/4.
// Momentum form, laid out exactly as a -ts_type basicsymplectic program:
//   U = [x | p] per rank (each rank owns a block of particles and keeps its
//   positions then its momenta), "position" and "momentum" splits by IS,
//   dq/dt = p/m, dp/dt = f(x) = V'(x_{i+1}-x_i) - V'(x_i-x_{i-1}).
// Distributed with a 1D DMDA for the neighbour exchange.
#pragma once
#include <petscdmda.h>
#include <petscts.h>
#include <cmath>
#include <vector>

namespace fpu {

struct Chain {
  MPI_Comm  comm;
  PetscInt  N = 0, n = 0, start = 0;
  PetscReal k = 1, beta = 1;
  DM        da = nullptr;
  Vec       minv = nullptr, m = nullptr, xloc = nullptr, wloc = nullptr;
  IS        isq = nullptr, isp = nullptr;
  PetscInt  nforce = 0;
};

inline PetscReal Mass(PetscInt i) { return 1.0 + 0.5 * std::sin(1.3 * (double)i) * std::sin(1.3 * (double)i) + 0.25 * (i % 3); }

inline PetscErrorCode Create(MPI_Comm comm, PetscInt N, PetscReal beta, Chain *c) {
  PetscFunctionBeginUser;
  c->comm = comm;
  c->N    = N;
  c->beta = beta;
  PetscCall(DMDACreate1d(comm, DM_BOUNDARY_GHOSTED, N, 1, 1, nullptr, &c->da));
  PetscCall(DMSetUp(c->da));
  PetscCall(DMDAGetCorners(c->da, &c->start, nullptr, nullptr, &c->n, nullptr, nullptr));
  PetscCall(DMCreateGlobalVector(c->da, &c->minv));
  PetscCall(VecDuplicate(c->minv, &c->m));
  PetscCall(DMCreateLocalVector(c->da, &c->xloc));
  PetscCall(VecDuplicate(c->xloc, &c->wloc));
  PetscScalar *a, *b;
  PetscCall(VecGetArray(c->minv, &a));
  PetscCall(VecGetArray(c->m, &b));
  for (PetscInt i = 0; i < c->n; ++i) {
    b[i] = Mass(c->start + i);
    a[i] = 1.0 / b[i];
  }
  PetscCall(VecRestoreArray(c->minv, &a));
  PetscCall(VecRestoreArray(c->m, &b));
  // U holds, on each rank, its n positions then its n momenta
  PetscCall(ISCreateStride(comm, c->n, 2 * c->start, 1, &c->isq));
  PetscCall(ISCreateStride(comm, c->n, 2 * c->start + c->n, 1, &c->isp));
  PetscFunctionReturn(0);
}

inline PetscErrorCode Destroy(Chain *c) {
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&c->minv));
  PetscCall(VecDestroy(&c->m));
  PetscCall(VecDestroy(&c->xloc));
  PetscCall(VecDestroy(&c->wloc));
  PetscCall(ISDestroy(&c->isq));
  PetscCall(ISDestroy(&c->isp));
  PetscCall(DMDestroy(&c->da));
  PetscFunctionReturn(0);
}

inline PetscErrorCode CreateState(Chain *c, Vec *U) {
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(c->comm, 2 * c->n, 2 * c->N, U));
  PetscFunctionReturn(0);
}

// Initial state: a smooth displacement and velocity pattern of amplitude amp.
inline PetscErrorCode Initial(Chain *c, PetscReal amp, Vec U) {
  PetscScalar *u;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(U, &u));
  for (PetscInt i = 0; i < c->n; ++i) {
    const PetscReal s = (c->start + i + 1.0) / (c->N + 1.0);
    u[i]        = amp * std::sin(M_PI * s) + 0.3 * amp * std::sin(3 * M_PI * s);
    u[c->n + i] = Mass(c->start + i) * amp * 0.5 * std::sin(2 * M_PI * s);
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

inline PetscReal Vp(const Chain *c, PetscReal r) { return c->k * r + c->beta * r * r * r; }
inline PetscReal Vpp(const Chain *c, PetscReal r) { return c->k + 3 * c->beta * r * r; }

// dq/dt = p / m
inline PetscErrorCode RHSPosition(TS, PetscReal, Vec p, Vec dq, void *ctx) {
  Chain *c = (Chain *)ctx;
  PetscFunctionBeginUser;
  PetscCall(VecPointwiseMult(dq, p, c->minv));
  PetscFunctionReturn(0);
}

// dp/dt = f(x)
inline PetscErrorCode RHSMomentum(TS, PetscReal, Vec x, Vec f, void *ctx) {
  Chain             *c = (Chain *)ctx;
  const PetscScalar *xl;
  PetscScalar       *fa;
  PetscFunctionBeginUser;
  PetscCall(VecSet(c->xloc, 0)); // fixed ends: ghost points outside the chain stay 0
  PetscCall(DMGlobalToLocalBegin(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(DMGlobalToLocalEnd(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(VecGetArrayRead(c->xloc, &xl));
  PetscCall(VecGetArray(f, &fa));
  for (PetscInt i = 0; i < c->n; ++i) {
    const PetscReal xm = xl[i], x0 = xl[i + 1], xp = xl[i + 2];
    fa[i] = Vp(c, xp - x0) - Vp(c, x0 - xm);
  }
  PetscCall(VecRestoreArray(f, &fa));
  PetscCall(VecRestoreArrayRead(c->xloc, &xl));
  c->nforce++;
  PetscFunctionReturn(0);
}

// JW = (df/dx) W
inline PetscErrorCode JacobianProduct(TS, PetscReal, Vec x, Vec W, Vec JW, void *ctx) {
  Chain             *c = (Chain *)ctx;
  const PetscScalar *xl, *wl;
  PetscScalar       *ja;
  PetscFunctionBeginUser;
  PetscCall(VecSet(c->xloc, 0));
  PetscCall(VecSet(c->wloc, 0));
  PetscCall(DMGlobalToLocalBegin(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(DMGlobalToLocalEnd(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(DMGlobalToLocalBegin(c->da, W, INSERT_VALUES, c->wloc));
  PetscCall(DMGlobalToLocalEnd(c->da, W, INSERT_VALUES, c->wloc));
  PetscCall(VecGetArrayRead(c->xloc, &xl));
  PetscCall(VecGetArrayRead(c->wloc, &wl));
  PetscCall(VecGetArray(JW, &ja));
  for (PetscInt i = 0; i < c->n; ++i) ja[i] = Vpp(c, xl[i + 2] - xl[i + 1]) * (wl[i + 2] - wl[i + 1]) - Vpp(c, xl[i + 1] - xl[i]) * (wl[i + 1] - wl[i]);
  PetscCall(VecRestoreArray(JW, &ja));
  PetscCall(VecRestoreArrayRead(c->wloc, &wl));
  PetscCall(VecRestoreArrayRead(c->xloc, &xl));
  PetscFunctionReturn(0);
}

// The splits exactly as for -ts_type basicsymplectic.
inline PetscErrorCode SetUpTS(Chain *c, TS ts) {
  PetscFunctionBeginUser;
  PetscCall(TSSetProblemType(ts, TS_NONLINEAR));
  PetscCall(TSRHSSplitSetIS(ts, "position", c->isq));
  PetscCall(TSRHSSplitSetIS(ts, "momentum", c->isp));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "position", nullptr, RHSPosition, c));
  PetscCall(TSRHSSplitSetRHSFunction(ts, "momentum", nullptr, RHSMomentum, c));
  PetscFunctionReturn(0);
}

// Total energy sum p^2/2m + sum V over the N+1 springs.
inline PetscErrorCode Energy(Chain *c, Vec U, PetscReal *E) {
  const PetscScalar *u, *xl;
  Vec                x;
  PetscReal          e = 0;
  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(U, c->isq, &x));
  PetscCall(VecSet(c->xloc, 0));
  PetscCall(DMGlobalToLocalBegin(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(DMGlobalToLocalEnd(c->da, x, INSERT_VALUES, c->xloc));
  PetscCall(VecRestoreSubVector(U, c->isq, &x));
  PetscCall(VecGetArrayRead(U, &u));
  PetscCall(VecGetArrayRead(c->xloc, &xl));
  for (PetscInt i = 0; i < c->n; ++i) {
    const PetscReal p = u[c->n + i], r = xl[i + 1] - xl[i];
    e += 0.5 * p * p / Mass(c->start + i) + 0.5 * c->k * r * r + 0.25 * c->beta * r * r * r * r;
    if (c->start + i == c->N - 1) {
      const PetscReal rl = -xl[i + 1];
      e += 0.5 * c->k * rl * rl + 0.25 * c->beta * rl * rl * rl * rl;
    }
  }
  PetscCall(VecRestoreArrayRead(c->xloc, &xl));
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCall(MPIU_Allreduce(&e, E, 1, MPIU_REAL, MPIU_SUM, c->comm));
  PetscFunctionReturn(0);
}

// The whole state in natural order (x_0..x_{N-1}, p_0..p_{N-1}) on every rank.
inline PetscErrorCode Gather(Chain *c, Vec U, std::vector<double> &all) {
  PetscMPIInt        size;
  const PetscScalar *u;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(c->comm, &size));
  std::vector<double> mine(2 * c->n);
  PetscCall(VecGetArrayRead(U, &u));
  for (PetscInt i = 0; i < 2 * c->n; ++i) mine[i] = PetscRealPart(u[i]);
  PetscCall(VecRestoreArrayRead(U, &u));
  std::vector<int> counts(size), displs(size);
  int              nl = (int)(2 * c->n);
  PetscCallMPI(MPI_Allgather(&nl, 1, MPI_INT, counts.data(), 1, MPI_INT, c->comm));
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> raw(2 * c->N);
  PetscCallMPI(MPI_Allgatherv(mine.data(), nl, MPI_DOUBLE, raw.data(), counts.data(), displs.data(), MPI_DOUBLE, c->comm));
  all.assign(2 * c->N, 0);
  PetscInt off = 0;
  for (int r = 0; r < size; ++r) {
    const PetscInt nr = counts[r] / 2, st = off / 2;
    for (PetscInt i = 0; i < nr; ++i) {
      all[st + i]        = raw[off + i];
      all[c->N + st + i] = raw[off + nr + i];
    }
    off += counts[r];
  }
  PetscFunctionReturn(0);
}

} // namespace fpu
