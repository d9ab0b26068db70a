// A stack of blocks resting on a fixed floor under gravity, with contact
// damping and friction (rigid bodies + TS + halo + cell search + potential
// contact force):
//  1. the blocks are dropped from small gaps and settle; after settling the
//     drift of every block over a long interval is below -drift_bound (per
//     second, relative to the block's height; rotation measured at the block's
//     corners). What remains after settling is the creep of the viscously
//     regularised friction, v_t = F_t / (c_t A), under the small tangential
//     components of the potential force where the block meshes are offset:
//     measured 3.8e-5 block heights/s with c_t = 1e5 Pa s/m (bound 1e-4);
//     c_t = 1e4 creeps ~10x faster, and c_t = 1e6 (c_t A dt / m ~ 0.8 per
//     contact, explicit) makes the tangential viscosity chatter (2e-2/s);
//  2. no block sinks: the penetration at each contact (from the centre
//     distances) matches the penalty's static estimate
//        d = p / (penalty (1/H_a + 1/H_b)),   p = weight above / contact area,
//     H_a, H_b the heights of the skin tetrahedra over the contact faces,
//     within -pen_tol (relative; measured 0.95..1.10 of the estimate);
//  3. the blocks stay stacked: no sideways slip beyond the drift bound.
// The blocks alternate around x = 0, the boundary between the slabs of rank 0
// and rank 1, so on 2 ranks every contact between blocks crosses ranks.
#include "../common/check.hpp"

#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>

#include <cmath>
#include <vector>

using fdem::kernels::Vec3;

struct Mesh {
  std::vector<PetscReal> nodes;
  std::vector<PetscInt>  tets;
  PetscInt               nn() const { return (PetscInt)nodes.size() / 3; }
  PetscInt               nt() const { return (PetscInt)tets.size() / 4; }
};
static Mesh Box(Vec3 half, int nx, int ny, int nz) {
  std::vector<Vec3>               X;
  std::vector<std::array<int, 4>> T;
  fdem::kernels::MakeBoxTets(-1.0 * half, half, nx, ny, nz, X, T);
  Mesh m;
  for (auto &p : X) m.nodes.insert(m.nodes.end(), {p.x, p.y, p.z});
  for (auto &t : T) m.tets.insert(m.tets.end(), {t[0], t[1], t[2], t[3]});
  return m;
}

struct Snapshot {
  std::vector<Vec3>                     x;
  std::vector<std::array<PetscReal, 9>> R;
};

static PetscErrorCode Take(FDEMRigid rb, PetscInt first, PetscInt nblocks, Snapshot &s) {
  PetscFunctionBeginUser;
  s.x.resize(nblocks);
  s.R.resize(nblocks);
  for (PetscInt b = 0; b < nblocks; ++b) {
    FDEMRigidBodyState st;
    PetscCall(FDEMRigidGetBodyState(rb, first + b, &st));
    s.x[b] = Vec3(st.x[0], st.x[1], st.x[2]);
    for (int k = 0; k < 9; ++k) s.R[b][k] = st.R[k];
  }
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) {
  PetscMPIInt size;
  PetscInt    nblocks = 4;
  PetscReal   yoff = 0.0, penalty = 1e7, damping = 3e5, mu = 0.5, ct = 1e5, dt = 2e-4, t_settle = 0.3, t_drift = 1.0, drift_bound = 1e-4, pen_tol = 0.2, offset = 0.01;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Stack of blocks on a floor", "");
  PetscCall(PetscOptionsInt("-n_blocks", "number of blocks", "", nblocks, &nblocks, nullptr));
  PetscCall(PetscOptionsReal("-penalty", "contact penalty (Pa)", "", penalty, &penalty, nullptr));
  PetscCall(PetscOptionsReal("-damping", "normal contact damping (Pa s/m)", "", damping, &damping, nullptr));
  PetscCall(PetscOptionsReal("-friction", "Coulomb friction", "", mu, &mu, nullptr));
  PetscCall(PetscOptionsReal("-tangential_viscosity", "tangential viscosity (Pa s/m)", "", ct, &ct, nullptr));
  PetscCall(PetscOptionsReal("-dt", "time step", "", dt, &dt, nullptr));
  PetscCall(PetscOptionsReal("-t_settle", "settling time", "", t_settle, &t_settle, nullptr));
  PetscCall(PetscOptionsReal("-t_drift", "interval over which the drift is measured", "", t_drift, &t_drift, nullptr));
  PetscCall(PetscOptionsReal("-drift_bound", "bound on the drift per second relative to the block height", "", drift_bound, &drift_bound, nullptr));
  PetscCall(PetscOptionsReal("-pen_tol", "relative tolerance of the penetration against the static estimate", "", pen_tol, &pen_tol, nullptr));
  PetscCall(PetscOptionsReal("-offset", "sideways offset of the blocks, alternating +-", "", offset, &offset, nullptr));
  PetscCall(PetscOptionsReal("-yoffset", "offsets along y: -1, 0, 1 times this", "", yoff, &yoff, nullptr));
  PetscOptionsEnd();

  // blocks 0.4 x 0.3 x 0.2 (2 x 2 x 2 hexahedra: skin tetrahedra 0.1 high over the top
  // and bottom faces), floor 1.2 x 1.2 x 0.2 (3 x 3 x 1: 0.2 high)
  const Vec3      hb(0.2, 0.15, 0.1), hf(0.6, 0.6, 0.1);
  const PetscReal Hb = 2 * hb.z / 2, Hf = 2 * hf.z / 1, rho = 1000, g = 9.81, gap = 0.002;
  const Mesh      block = Box(hb, 2, 2, 2), floor = Box(hf, 3, 3, 1);
  const PetscReal lo[3] = {-1, -1, -0.3}, hi[3] = {1, 1, 0.3 + 2 * hb.z * nblocks};
  PetscCheck(hi[2] - lo[2] < hi[0] - lo[0], PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "too many blocks: the slabs must cut along x");
  FDEMRigid   rb;
  FDEMContact c;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  PetscCall(FDEMRigidSetDomain(rb, lo, hi));
  PetscCall(FDEMContactCreate(rb, &c));
  PetscCall(FDEMContactSetPenalty(c, penalty));
  PetscCall(FDEMContactSetDissipation(c, damping, mu, ct));
  PetscCall(FDEMContactSetFromOptions(c));
  PetscCall(FDEMRigidSetFromOptions(rb));
  const PetscReal gv[3] = {0, 0, -g}, xf[3] = {0, 0, -hf.z};
  PetscInt        fid;
  PetscCall(FDEMRigidSetGravity(rb, gv));
  PetscCall(FDEMRigidAddBodyFromMesh(rb, "floor", floor.nn(), floor.nodes.data(), floor.nt(), floor.tets.data(), rho, xf, nullptr, nullptr, nullptr, &fid));
  PetscCall(FDEMRigidFixBody(rb, fid));
  for (PetscInt b = 0; b < nblocks; ++b) {
    const PetscReal x[3] = {(b % 2 ? -offset : offset), yoff * (b % 3 - 1), hb.z + gap + b * (2 * hb.z + gap)};
    PetscCall(FDEMRigidAddBodyFromMesh(rb, "block", block.nn(), block.nodes.data(), block.nt(), block.tets.data(), rho, x, nullptr, nullptr, nullptr, nullptr));
  }
  const PetscReal m = rho * 8 * hb.x * hb.y * hb.z;
  PetscReal       ratio;
  PetscCall(FDEMContactCheckTimeStep(c, "cd", dt, &ratio));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d blocks (%.0f kg each) on a floor, %d ranks: penalty %g, damping %g, friction %g, dt %g, omega_c dt / K_crit = %.3f\n", (int)nblocks, (double)m, (int)size,
                        (double)penalty, (double)damping, (double)mu, (double)dt, (double)ratio));
  CHECK(ratio < 0.5, "time step too large for the contact: ratio %g", (double)ratio);

  Snapshot s0, s1;
  PetscCall(FDEMRigidSolve(rb, 0, t_settle, dt, 100, nullptr, nullptr));
  PetscCall(Take(rb, 1, nblocks, s0));
  PetscCall(FDEMRigidSolve(rb, t_settle, t_settle + t_drift, dt, 100, nullptr, nullptr));
  PetscCall(Take(rb, 1, nblocks, s1));
  PetscReal P[3], L[3], E;
  PetscCall(FDEMRigidGetInvariants(rb, P, L, &E));

  // 1. drift: centre displacement plus the largest corner displacement from the change of R
  const PetscReal hdiag = std::sqrt(hb.x * hb.x + hb.y * hb.y + hb.z * hb.z);
  PetscReal       worst = 0;
  for (PetscInt b = 0; b < nblocks; ++b) {
    PetscReal dR = 0;
    for (int k = 0; k < 9; ++k) dR += PetscSqr(s1.R[b][k] - s0.R[b][k]);
    const PetscReal dx = fdem::kernels::norm(s1.x[b] - s0.x[b]), rate = (dx + hdiag * std::sqrt(dR)) / (t_drift * 2 * hb.z);
    worst = std::fmax(worst, rate);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "block %d: centre (%+.5f, %+.5f, %.6f), drift over %.2f s: |dx| %.2e, |dR|_F %.2e -> %.2e block heights per second\n", (int)b, s1.x[b].x, s1.x[b].y, s1.x[b].z,
                          (double)t_drift, dx, std::sqrt(dR), rate));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "largest drift %.2e block heights per second (bound %.1e); kinetic energy at the end %.3e J (potential energy scale m g h = %.3e J)\n", (double)worst, (double)drift_bound,
                        (double)E, (double)(m * g * 2 * hb.z)));
  CHECK(worst < drift_bound, "a block drifts %.3e block heights per second > %.1e", (double)worst, (double)drift_bound);
  CHECK(E < 1e-9 * m * g * 2 * hb.z, "the stack has not settled: kinetic energy %.3e J", (double)E);

  // 2. penetration at each contact against the static estimate
  for (PetscInt b = 0; b < nblocks; ++b) {
    const PetscReal below = b == 0 ? 0 : s1.x[b - 1].z + hb.z; // top of what lies below
    const PetscReal d     = below - (s1.x[b].z - hb.z);
    const PetscReal area  = b == 0 ? 4 * hb.x * hb.y : (2 * hb.x - std::fabs(s1.x[b].x - s1.x[b - 1].x)) * (2 * hb.y - std::fabs(s1.x[b].y - s1.x[b - 1].y));
    const PetscReal p     = (nblocks - b) * m * g / area;
    const PetscReal d_est = p / (penalty * (1 / Hb + 1 / (b == 0 ? Hf : Hb)));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "contact %s / block %d: penetration %.4e m, static estimate %.4e m (ratio %.3f), %.2e of the block height\n", b == 0 ? "floor" : "block", (int)b, (double)d,
                          (double)d_est, (double)(d / d_est), (double)(d / (2 * hb.z))));
    CHECK(std::fabs(d - d_est) < pen_tol * d_est, "contact below block %d: penetration %.4e m, estimate %.4e m (tolerance %.0f%%)", (int)b, (double)d, (double)d_est, (double)(100 * pen_tol));
  }
  // 3. still stacked: no sideways slip from the initial offsets beyond the drift
  for (PetscInt b = 0; b < nblocks; ++b) {
    const PetscReal x0 = b % 2 ? -offset : offset, y0 = yoff * (b % 3 - 1);
    CHECK(std::hypot(s1.x[b].x - x0, s1.x[b].y - y0) < 0.01 * 2 * hb.z, "block %d slid sideways to (%g, %g) from (%g, %g)", (int)b, s1.x[b].x, s1.x[b].y, (double)x0, (double)y0);
  }
  PetscCall(FDEMContactDestroy(&c));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
