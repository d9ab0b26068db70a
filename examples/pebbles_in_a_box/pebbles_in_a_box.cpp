// Pebbles in a box (the idea of Munjiza's Figs 5.10-5.17): irregular rigid
// pebbles -- convex hulls of random points on squashed ellipsoids, of
// different sizes, fixed seed -- are dropped into a box (a floor and four
// walls, fixed rigid boxes) and tumble, rock and come to rest under gravity
// with contact damping and Coulomb friction. The box is split into slabs, one
// per rank (FDEMRigidSetDomain); pebbles migrate between ranks as they move.
//
// Checks its own result (exit status 1 when a check fails):
//   - every pebble ends inside the box: its centre between the walls and
//     below their top, its lowest vertex above the floor less the allowed
//     penetration;
//   - no tunnelling: the deepest vertex of any body inside any other
//     (convex) body is below -fdem_expect_penetration times the pebble's
//     equivalent diameter (6V/pi)^(1/3) (measured vertex-into-polytope, so
//     edge-edge overlaps are not seen);
//   - at rest: the kinetic energy at the end is below -fdem_expect_ke times the
//     potential energy released, sum m g (z0 - z);
//   - -fdem_compare FILE: the final state written by another run (final_state.csv,
//     e.g. with another number of ranks) gives the same pile: mean pebble
//     height within -fdem_compare_tol pebble diameters, and every pebble within
//     -fdem_compare_pebble_tol diameters of its place in the other run (default
//     off: the rounding differences of the force sums, which differ between
//     rank counts, may grow in chaotic tumbling; for the CTest scene, 8
//     pebbles, 1 vs 2 ranks agree to 1.6e-13 diameters and the test asserts 1e-8).
//
// Options (doc/examples.md): -fdem_bodies (pebbles), -fdem_seed, -fdem_pebble_size
// (mean long semi-axis), -fdem_box_x, -fdem_box_y, -fdem_density, -fdem_drop,
// -ts_max_time, -ts_dt, -ts_type, -fdem_output_every (output, monitor and
// migration every k steps), -fdem_output DIR (default out/pebbles_in_a_box:
// pebbles.h5 + .xmf, energy.csv with t, kinetic energy, potential energy
// released, mean/max pebble height, max speed, and final_state.csv), -fdem_compare FILE,
// and the contact options -fdem_contact_penalty/damping/friction/tangential_viscosity/buffer
// (defaults below), -fdem_rigid_rotation.
//
// Run: mpiexec -n 2 ./pebbles_in_a_box -fdem_bodies 60 -fdem_output out/pebbles
// then open out/pebbles/pebbles.xmf in ParaView (examples/pebbles_in_a_box/run.sh).
#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/rigid.h>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/pebble.hpp>
#include <fdem/kernels/rotation.hpp>

#include "../common/options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using fdem::kernels::Mat3;
using fdem::kernels::Vec3;

namespace {

// One body as built here, kept on every rank for the checks: its boundary
// vertices and faces in its own body frame (principal axes about the centre
// of mass), as FDEMRigidAddBodyFromMesh stores them.
struct Body {
  std::string                     name;
  bool                            fixed = false;
  std::vector<Vec3>               verts; // body frame
  std::vector<std::array<int, 3>> faces; // outward
  double                          volume = 0, mass = 0, deq = 0, z0 = 0;
};

struct Ctx {
  std::vector<Body> bodies;
  PetscInt          first_pebble = 0, npebbles = 0, write_every = 50;
  PetscReal         g = 9.81, t_final = 0, pebble_size = 0;
  std::string       output; // DIR/pebbles, or empty: no HDF5
  std::vector<std::array<double, 6>> history; // t, KE, PE released, mean z, max z, max speed
  PetscInt          writes = 0;
  FDEMContact       contact = nullptr;
  PetscLogDouble    wall0 = 0;
};

Mat3 RowMajor(const PetscReal *a) {
  Mat3 M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M.m[r][c] = a[3 * r + c];
  return M;
}

PetscErrorCode AddMesh(FDEMRigid rb, Ctx &c, const char *name, const std::vector<Vec3> &X, const std::vector<std::array<int, 4>> &T, double density, const Vec3 &x, const Mat3 &Q, const Vec3 &v, const Vec3 &w,
                       bool fixed) {
  PetscInt id;
  PetscFunctionBeginUser;
  std::vector<PetscReal> nodes;
  std::vector<PetscInt>  tets;
  for (const Vec3 &p : X) nodes.insert(nodes.end(), {p.x, p.y, p.z});
  for (const auto &t : T) tets.insert(tets.end(), {t[0], t[1], t[2], t[3]});
  PetscReal Qr[9], vv[3] = {v.x, v.y, v.z}, ww[3] = {w.x, w.y, w.z}, xx[3] = {x.x, x.y, x.z};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) Qr[3 * r + k] = Q.m[r][k];
  PetscCall(FDEMRigidAddBodyFromMesh(rb, name, (PetscInt)X.size(), nodes.data(), (PetscInt)T.size(), tets.data(), density, xx, Qr, vv, ww, &id));
  PetscCheck(id == (PetscInt)c.bodies.size(), PETSC_COMM_WORLD, PETSC_ERR_PLIB, "unexpected body id");
  if (fixed) PetscCall(FDEMRigidFixBody(rb, id));
  Body b;
  b.name  = name;
  b.fixed = fixed;
  const auto mp = fdem::kernels::ComputeMassProperties(X, T, density, name);
  b.volume      = mp.volume;
  b.mass        = mp.mass;
  b.deq         = std::cbrt(6 * mp.volume / M_PI);
  b.z0          = x.z;
  b.faces       = fdem::kernels::BoundaryFaces(T);
  for (const Vec3 &p : X) b.verts.push_back(transpose(mp.principal_axes) * (p - mp.com));
  c.bodies.push_back(std::move(b));
  PetscFunctionReturn(0);
}

// Box [lo, hi] meshed with cells of about `cell` (at least one per direction).
void BoxMesh(const Vec3 &lo, const Vec3 &hi, double cell, std::vector<Vec3> &X, std::vector<std::array<int, 4>> &T) {
  const Vec3 h = 0.5 * (hi - lo);
  int        n[3];
  for (int k = 0; k < 3; ++k) n[k] = std::max(1, (int)std::lround(2 * h[k] / cell));
  fdem::kernels::MakeBoxTets(-1.0 * h, h, n[0], n[1], n[2], X, T);
}

struct AllStates {
  std::vector<FDEMRigidBodyState> s;
};
PetscErrorCode GetAll(FDEMRigid rb, const Ctx &c, AllStates &a) {
  PetscFunctionBeginUser;
  a.s.resize(c.bodies.size());
  for (size_t i = 0; i < c.bodies.size(); ++i) PetscCall(FDEMRigidGetBodyState(rb, (PetscInt)i, &a.s[i]));
  PetscFunctionReturn(0);
}

std::vector<Vec3> WorldVerts(const Body &b, const FDEMRigidBodyState &s) {
  const Mat3        R = RowMajor(s.R);
  const Vec3        x(s.x[0], s.x[1], s.x[2]);
  std::vector<Vec3> w;
  for (const Vec3 &p : b.verts) w.push_back(x + R * p);
  return w;
}

PetscErrorCode Monitor(FDEMRigid rb, PetscInt step, PetscReal t, void *ptr) {
  Ctx      &c = *(Ctx *)ptr;
  AllStates a;
  PetscReal E;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetInvariants(rb, nullptr, nullptr, &E));
  PetscCall(GetAll(rb, c, a));
  double pe = 0, zsum = 0, zmax = -1e300, vmax = 0;
  for (PetscInt i = c.first_pebble; i < (PetscInt)c.bodies.size(); ++i) {
    const auto &s = a.s[i];
    pe += c.bodies[i].mass * c.g * (c.bodies[i].z0 - s.x[2]);
    zsum += s.x[2];
    zmax = std::max(zmax, (double)s.x[2]);
    vmax = std::max(vmax, std::sqrt(s.v[0] * s.v[0] + s.v[1] * s.v[1] + s.v[2] * s.v[2]));
  }
  c.history.push_back({t, E, pe, zsum / c.npebbles, zmax, vmax});
  FDEMContactStats st;
  PetscInt         nloc;
  PetscLogDouble   now;
  PetscCall(FDEMContactGetStats(c.contact, &st));
  PetscCall(FDEMRigidGetNumBodies(rb, &nloc, nullptr));
  PetscCall(PetscTime(&now));
  if (step % (10 * c.write_every) == 0 || t >= c.t_final * (1 - 1e-12)) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "step %6" PetscInt_FMT " t %7.4f  KE %10.4e J  PE released %10.4e J  mean height %.4f  max speed %9.3e  searches %5" PetscInt_FMT "  wall %6.1f s  bodies per rank:", step,
                          (double)t, (double)E, pe, zsum / c.npebbles, vmax, st.searches, now - c.wall0));
    PetscCall(PetscSynchronizedPrintf(PETSC_COMM_WORLD, " %" PetscInt_FMT, nloc));
    PetscCall(PetscSynchronizedFlush(PETSC_COMM_WORLD, PETSC_STDOUT));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\n"));
  }
  if (!c.output.empty()) {
    PetscCall(FDEMRigidWriteHDF5(rb, c.output.c_str(), step, t));
    c.writes++;
  }
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode RunExample(int *status) {
  PetscFunctionBeginUser;
  namespace ex = fdem::examples;
  Ctx         c;
  PetscInt    n = 60, seed = 5;
  PetscReal   dt = 4e-4, size = 0.08, box_x = 1.5, box_y = 0.7, density = 2600, drop = 0.05;
  PetscReal   expect_pen = 0.05, expect_ke = 1e-3, compare_tol = 0.25, compare_pebble_tol = 1e30;
  char        compare[PETSC_MAX_PATH_LEN] = "", ts_type[64] = "cd";
  ex::Output  out{"out/pebbles_in_a_box", 50};
  PetscMPIInt rank, nranks;
  c.t_final = 3.0;
  PetscCall(FDEMInitializePackage());
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &nranks));
  PetscOptionsBegin(PETSC_COMM_WORLD, nullptr, "Pebbles in a box; time steps: -ts_dt (4e-4), -ts_max_time (3), -ts_type (cd)", "");
  PetscCall(PetscOptionsInt("-fdem_bodies", "number of pebbles", "", n, &n, nullptr));
  PetscCall(PetscOptionsInt("-fdem_seed", "random seed (shapes, sizes, orientations)", "", seed, &seed, nullptr));
  PetscCall(PetscOptionsReal("-fdem_pebble_size", "mean long semi-axis of the pebbles (m)", "", size, &size, nullptr));
  PetscCall(PetscOptionsReal("-fdem_box_x", "inner length of the box (m)", "", box_x, &box_x, nullptr));
  PetscCall(PetscOptionsReal("-fdem_box_y", "inner width of the box (m)", "", box_y, &box_y, nullptr));
  PetscCall(PetscOptionsReal("-fdem_density", "pebble density (kg/m^3)", "", density, &density, nullptr));
  PetscCall(PetscOptionsReal("-fdem_drop", "gap below the lowest layer of pebbles at the start (m)", "", drop, &drop, nullptr));
  FDEM_EXAMPLE_OUTPUT_OPTIONS(out, " (HDF5 + XDMF, energy.csv), monitor lines and migrations");
  PetscCall(PetscOptionsString("-fdem_compare", "compare with the final state of another run (its final_state.csv)", "", compare, compare, sizeof(compare), nullptr));
  PetscCall(PetscOptionsReal("-fdem_expect_penetration", "bound on the deepest vertex penetration / pebble diameter", "", expect_pen, &expect_pen, nullptr));
  PetscCall(PetscOptionsReal("-fdem_expect_ke", "bound on the final kinetic energy / potential energy released", "", expect_ke, &expect_ke, nullptr));
  PetscCall(PetscOptionsReal("-fdem_compare_tol", "bound on the difference of the mean pebble height, in pebble diameters", "", compare_tol, &compare_tol, nullptr));
  PetscCall(PetscOptionsReal("-fdem_compare_pebble_tol", "bound on any pebble's distance from its place in the -fdem_compare run, in pebble diameters", "", compare_pebble_tol, &compare_pebble_tol, nullptr));
  PetscOptionsEnd();
  PetscCall(ex::CheckInt("-fdem_bodies", n, 1, 100000));
  PetscCall(ex::CheckInt("-fdem_seed", seed, 0, PETSC_MAX_INT));
  PetscCall(ex::CheckPositive("-fdem_pebble_size", size));
  PetscCall(ex::CheckReal("-fdem_box_x", box_x, 4 * size, true, std::numeric_limits<PetscReal>::infinity(), true)); // more than 4 pebble sizes
  PetscCall(ex::CheckReal("-fdem_box_y", box_y, 4 * size, true, std::numeric_limits<PetscReal>::infinity(), true));
  PetscCall(ex::CheckPositive("-fdem_density", density));
  PetscCall(ex::CheckNonNegative("-fdem_drop", drop));
  PetscCall(ex::CheckPositive("-fdem_expect_penetration", expect_pen));
  PetscCall(ex::CheckPositive("-fdem_expect_ke", expect_ke));
  PetscCall(ex::CheckPositive("-fdem_compare_tol", compare_tol));
  PetscCall(ex::CheckPositive("-fdem_compare_pebble_tol", compare_pebble_tol));
  if (compare[0]) { // before the run, not after it
    int readable = 0;
    if (rank == 0) {
      FILE *fp = std::fopen(compare, "r");
      readable = fp != nullptr;
      if (fp) std::fclose(fp);
    }
    PetscCallMPI(MPI_Bcast(&readable, 1, MPI_INT, 0, PETSC_COMM_WORLD));
    PetscCheck(readable, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN, "Option -fdem_compare %s: cannot open this file", compare);
  }
  PetscCall(ex::SetUpOutput(out));
  PetscCall(ex::PeekTimeOptions(ts_type, sizeof(ts_type), &dt, &c.t_final)); // for the time-step check and the monitor
  c.write_every = out.every;
  c.output      = out.path("pebbles");
  c.npebbles    = n;
  c.pebble_size = size;

  // the pebbles' lattice: sites `s` apart, layers from the floor up
  const double amax = 1.3 * size, s = 2.1 * amax, tw = 0.1;
  const int    nx = std::max(1, (int)std::floor(box_x / s)), ny = std::max(1, (int)std::floor(box_y / s)), nlayers = (int)((n + nx * ny - 1) / (nx * ny));
  const double z_first = amax + drop, z_top = z_first + (nlayers - 1) * s + amax, wall_h = z_top + s;
  const Vec3   lo(-tw, -tw, -tw), hi(box_x + tw, box_y + tw, wall_h);
  FDEMRigid    rb;
  FDEMContact  contact;
  PetscCall(FDEMRigidCreate(PETSC_COMM_WORLD, &rb));
  {
    const PetscReal l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z}, g[3] = {0, 0, -c.g};
    PetscCall(FDEMRigidSetDomain(rb, l, h));
    PetscCall(FDEMRigidSetGravity(rb, g));
  }
  PetscCall(FDEMRigidSetFromOptions(rb));
  PetscCall(FDEMContactCreate(rb, &contact));
  c.contact = contact;
  // defaults: penalty 3e6 Pa keeps the deepest overlap at rest ~1e-3..2e-2 pebble diameters
  // and omega_c dt / K_crit ~ 0.45 at dt = 4e-4 (FDEMContactCheckTimeStep); damping and
  // tangential viscosity 1e5 Pa s/m (they act per unit contact area, so vertex contacts need
  // them this large; c A dt / m < 1 for a face-on contact of the lightest pebble keeps the
  // explicit viscous terms stable); friction 0.6; buffer 0.15 pebble sizes
  PetscCall(FDEMContactSetPenalty(contact, 3e6));
  PetscCall(FDEMContactSetDissipation(contact, 1e5, 0.6, 1e5));
  PetscCall(FDEMContactSetBuffer(contact, 0.15 * size));
  PetscCall(FDEMContactSetFromOptions(contact));

  // the box: floor and four walls, fixed
  {
    const double cell = 2.5 * size;
    struct {
      const char *name;
      Vec3        lo, hi;
    } parts[5] = {{"floor", Vec3(-tw, -tw, -tw), Vec3(box_x + tw, box_y + tw, 0)},
                  {"wall_x0", Vec3(-tw, 0, 0), Vec3(0, box_y, wall_h)},
                  {"wall_x1", Vec3(box_x, 0, 0), Vec3(box_x + tw, box_y, wall_h)},
                  {"wall_y0", Vec3(-tw, -tw, 0), Vec3(box_x + tw, 0, wall_h)},
                  {"wall_y1", Vec3(-tw, box_y, 0), Vec3(box_x + tw, box_y + tw, wall_h)}};
    for (auto &p : parts) {
      std::vector<Vec3>               X;
      std::vector<std::array<int, 4>> T;
      BoxMesh(p.lo, p.hi, cell, X, T);
      PetscCall(AddMesh(rb, c, p.name, X, T, 2600, 0.5 * (p.lo + p.hi), Mat3::identity(), Vec3(), Vec3(), true));
    }
  }
  // the pebbles: convex hulls of fdem::kernels::RandomPebble (12 random points on an ellipsoid
  // a >= b >= c, pushed in by up to 15%), a = 0.7..1.3 size; every rank builds the same scene
  c.first_pebble = (PetscInt)c.bodies.size();
  fdem::kernels::PebbleRandom random((unsigned long)seed);
  for (PetscInt p = 0; p < n; ++p) {
    const double                    a = size * (0.7 + 0.6 * random.U());
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> T;
    fdem::kernels::MakeConvexPolyhedronTets(fdem::kernels::RandomPebble(a, random).points, X, T);
    const int    layer = (int)(p / (nx * ny)), k = (int)(p % (nx * ny));
    const double jitter = 0.1 * s;
    const Vec3   x((k % nx + 0.5) * box_x / nx + jitter * (2 * random.U() - 1), (k / nx + 0.5) * box_y / ny + jitter * (2 * random.U() - 1), z_first + layer * s);
    const Mat3 Q = fdem::kernels::RotationMatrix(Vec3(M_PI * (2 * random.U() - 1), M_PI * (2 * random.U() - 1), M_PI * (2 * random.U() - 1)));
    const Vec3 v(0.3 * (2 * random.U() - 1), 0.3 * (2 * random.U() - 1), 0), w(4 * (2 * random.U() - 1), 4 * (2 * random.U() - 1), 4 * (2 * random.U() - 1));
    char name[32];
    PetscCall(PetscSNPrintf(name, sizeof(name), "pebble%d", (int)p));
    PetscCall(AddMesh(rb, c, name, X, T, density, x, Q, v, w, false));
  }
  PetscInt nglobal;
  PetscCall(FDEMRigidGetNumBodies(rb, nullptr, &nglobal));
  double mtot = 0, mmin = 1e300, mmax = 0, dmin = 1e300, dmax = 0, dmean = 0;
  for (PetscInt i = c.first_pebble; i < (PetscInt)c.bodies.size(); ++i) {
    const Body &b = c.bodies[i];
    mtot += b.mass;
    mmin = std::min(mmin, b.mass);
    mmax = std::max(mmax, b.mass);
    dmin = std::min(dmin, b.deq);
    dmax = std::max(dmax, b.deq);
    dmean += b.deq / n;
  }
  PetscReal ratio;
  PetscCall(FDEMContactCheckTimeStep(contact, ts_type, dt, &ratio));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "%d pebbles (%d layers of up to %d x %d) in a %.2f x %.2f box with walls %.2f high, %d ranks: masses %.3f..%.3f kg (total %.2f), equivalent diameters %.3f..%.3f m\n"
                        "dt %g, -ts_type %s: omega_c dt / K_crit = %.3f (FDEMContactCheckTimeStep)\n",
                        (int)n, nlayers, nx, ny, box_x, box_y, wall_h, (int)nranks, mmin, mmax, mtot, dmin, dmax, (double)dt, ts_type, (double)ratio));
  PetscCheck(nglobal == (PetscInt)c.bodies.size(), PETSC_COMM_WORLD, PETSC_ERR_PLIB, "body count");

  PetscCall(PetscTime(&c.wall0));
  PetscCall(FDEMRigidSolve(rb, 0.0, c.t_final, dt, c.write_every, Monitor, &c));
  PetscLogDouble wall1;
  PetscCall(PetscTime(&wall1));
  {
    PetscReal tf;
    PetscInt  steps;
    PetscCall(FDEMRigidGetTime(rb, &tf, &steps));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " steps of %g to t = %g\n", steps, (double)dt, (double)tf));
  }

  // ---- checks
  int       failures = 0;
  AllStates a;
  PetscCall(GetAll(rb, c, a));
  const auto &last = c.history.back();
  // 1. inside the box
  double lowest = 1e300;
  for (PetscInt i = c.first_pebble; i < (PetscInt)c.bodies.size(); ++i) {
    const auto &st = a.s[i];
    double      zlow = 1e300;
    for (const Vec3 &p : WorldVerts(c.bodies[i], st)) zlow = std::min(zlow, p.z);
    lowest = std::min(lowest, zlow / c.bodies[i].deq);
    const bool inside = st.x[0] > 0 && st.x[0] < box_x && st.x[1] > 0 && st.x[1] < box_y && st.x[2] > 0 && st.x[2] < wall_h && zlow > -expect_pen * c.bodies[i].deq;
    if (!inside) {
      failures++;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: %s ended outside the box: centre (%g, %g, %g), lowest vertex z = %g\n", c.bodies[i].name.c_str(), (double)st.x[0], (double)st.x[1], (double)st.x[2], zlow));
    }
  }
  // 2. deepest vertex of a body inside another (all bodies are convex)
  double worst = 0;
  int    wa = -1, wb = -1;
  {
    const size_t                   nb = c.bodies.size();
    std::vector<std::vector<Vec3>> W(nb);
    std::vector<double>            rad(nb);
    for (size_t i = 0; i < nb; ++i) {
      W[i]   = WorldVerts(c.bodies[i], a.s[i]);
      rad[i] = 0;
      const Vec3 x(a.s[i].x[0], a.s[i].x[1], a.s[i].x[2]);
      for (const Vec3 &p : W[i]) rad[i] = std::max(rad[i], norm(p - x));
    }
    for (size_t i = 0; i < nb; ++i)
      for (size_t j = 0; j < nb; ++j) {
        if (i == j || (c.bodies[i].fixed && c.bodies[j].fixed)) continue;
        const Vec3 xi(a.s[i].x[0], a.s[i].x[1], a.s[i].x[2]), xj(a.s[j].x[0], a.s[j].x[1], a.s[j].x[2]);
        if (norm(xi - xj) > rad[i] + rad[j]) continue;
        // planes of j's faces
        std::vector<std::pair<Vec3, double>> planes;
        for (const auto &f : c.bodies[j].faces) {
          const Vec3 &A = W[j][f[0]], &B = W[j][f[1]], &C = W[j][f[2]];
          Vec3        nn = cross(B - A, C - A);
          const double l = norm(nn);
          if (l == 0) continue;
          nn = nn / l;
          planes.push_back({nn, dot(nn, A)});
        }
        std::vector<char> onb(W[i].size(), 0);
        for (const auto &f : c.bodies[i].faces) onb[f[0]] = onb[f[1]] = onb[f[2]] = 1;
        const PetscInt pebble = c.bodies[i].fixed ? (PetscInt)j : (PetscInt)i;
        for (size_t v = 0; v < W[i].size(); ++v) {
          if (!onb[v]) continue;
          double depth = 1e300;
          for (const auto &pl : planes) depth = std::min(depth, pl.second - dot(pl.first, W[i][v]));
          if (depth / c.bodies[pebble].deq > worst) {
            worst = depth / c.bodies[pebble].deq;
            wa    = (int)i;
            wb    = (int)j;
          }
        }
      }
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "deepest penetration: %.3e pebble diameters (a vertex of %s in %s; bound %.2g); lowest pebble vertex z = %.3e diameters\n", worst, wa >= 0 ? c.bodies[wa].name.c_str() : "-",
                        wb >= 0 ? c.bodies[wb].name.c_str() : "-", (double)expect_pen, lowest));
  if (!(worst < expect_pen)) {
    failures++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: penetration %.3e pebble diameters > %.2g\n", worst, (double)expect_pen));
  }
  // 3. at rest
  const double ke = last[1], pe = last[2];
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "at t = %.3f: kinetic energy %.3e J = %.3e of the potential energy released (%.4e J; bound %.1e); max pebble speed %.3e m/s; wall time %.1f s\n", last[0], ke, ke / pe, pe,
                        (double)expect_ke, last[5], wall1 - c.wall0));
  if (!(pe > 0 && ke < expect_ke * pe)) {
    failures++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: not at rest: kinetic energy %.3e J > %.1e x %.3e J\n", ke, (double)expect_ke, pe));
  }
  {
    FDEMContactStats st;
    PetscCall(FDEMContactGetStats(contact, &st));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "contact: %" PetscInt_FMT " searches, %" PetscInt_FMT " force evaluations, last: %" PetscInt_FMT " candidate / %" PetscInt_FMT " active tetrahedron pairs and %" PetscInt_FMT " ghost tetrahedra (all ranks), overlap energy %.3e J\n",
                          st.searches, st.evaluations, st.candidate_pairs, st.active_pairs, st.ghosts, (double)st.energy));
  }
  double mean_z = 0;
  for (PetscInt i = c.first_pebble; i < (PetscInt)c.bodies.size(); ++i) mean_z += a.s[i].x[2] / n;
  const std::string history = out.path("energy.csv"), final_state = out.path("final_state.csv");
  if (rank == 0 && out.on()) {
    FILE *fp = std::fopen(history.c_str(), "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", history.c_str());
    std::fprintf(fp, "t,kinetic_energy,potential_energy_released,mean_height,max_height,max_speed\n");
    for (const auto &h : c.history) std::fprintf(fp, "%.6f,%.10e,%.10e,%.8f,%.8f,%.6e\n", h[0], h[1], h[2], h[3], h[4], h[5]);
    std::fclose(fp);
  }
  if (rank == 0 && out.on()) {
    FILE *fp = std::fopen(final_state.c_str(), "w");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot open %s", final_state.c_str());
    std::fprintf(fp, "id,x,y,z,vx,vy,vz\n");
    for (PetscInt i = c.first_pebble; i < (PetscInt)c.bodies.size(); ++i)
      std::fprintf(fp, "%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", (int)i, a.s[i].x[0], a.s[i].x[1], a.s[i].x[2], a.s[i].v[0], a.s[i].v[1], a.s[i].v[2]);
    std::fclose(fp);
  }
  if (compare[0]) {
    // every rank reads the file (small)
    FILE *fp = std::fopen(compare, "r");
    PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "-fdem_compare: cannot open %s", compare);
    char   line[512];
    double other_mean = 0, dmaxp = 0;
    int    count = 0;
    PetscCheck(std::fgets(line, sizeof(line), fp), PETSC_COMM_SELF, PETSC_ERR_FILE_READ, "-fdem_compare: empty file %s", compare);
    while (std::fgets(line, sizeof(line), fp)) {
      int    id;
      double x, y, z, vx, vy, vz;
      if (std::sscanf(line, "%d,%lf,%lf,%lf,%lf,%lf,%lf", &id, &x, &y, &z, &vx, &vy, &vz) != 7) continue;
      PetscCheck(id >= c.first_pebble && id < (int)c.bodies.size(), PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "-fdem_compare: %s has pebble id %d, this scene has %d..%d", compare, id, (int)c.first_pebble,
                 (int)c.bodies.size() - 1);
      other_mean += z;
      count++;
      dmaxp = std::max(dmaxp, std::sqrt(PetscSqr(x - a.s[id].x[0]) + PetscSqr(y - a.s[id].x[1]) + PetscSqr(z - a.s[id].x[2])));
    }
    std::fclose(fp);
    PetscCheck(count == n, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED, "-fdem_compare: %s holds %d pebbles, this run has %d", compare, count, (int)n);
    other_mean /= count;
    const double diff = std::fabs(other_mean - mean_z) / dmean;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "compare with %s: mean pebble height %.5f vs %.5f (difference %.3e pebble diameters, bound %.2g); largest single-pebble distance %.3e m = %.3e diameters\n", compare,
                          mean_z, other_mean, diff, (double)compare_tol, dmaxp, dmaxp / dmean));
    if (!(diff < compare_tol)) {
      failures++;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: the piles differ: mean height %.5f vs %.5f\n", mean_z, other_mean));
    }
    if (!(dmaxp / dmean < compare_pebble_tol)) {
      failures++;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "FAIL: a pebble ended %.3e diameters from its place in %s (bound %.2g)\n", dmaxp / dmean, compare, (double)compare_pebble_tol));
    }
  }
  if (out.on()) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "wrote %d steps to %s.h5 and %s.xmf (open the .xmf in ParaView), %s, %s\n", (int)c.writes, c.output.c_str(), c.output.c_str(), history.c_str(), final_state.c_str()));
  PetscCall(FDEMContactDestroy(&contact));
  PetscCall(FDEMRigidDestroy(&rb));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d failures\n", failures));
  *status = failures ? 1 : 0;
  PetscFunctionReturn(0);
}

int main(int argc, char **argv) { return fdem::examples::Main(argc, argv, RunExample); }
