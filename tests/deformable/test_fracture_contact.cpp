// Broken joints as contact surfaces, and fragments (doc/fracture.md). A fracturable bar
// (0.4 x 0.1 x 0.1 m, 8 x 2 x 2 cubes of 6 tetrahedra) is given a velocity jump at its
// middle: the left half moves at -V1, the right half at +V1 along x, so the joints of the
// middle plane open at once and break within a few steps while the stress wave they send into
// the halves stays below the strength. Then the two fragments are sent back towards each
// other at 2 V2 and pressed together. Asserted:
//  0. two tetrahedra of two bodies sharing a face are two fragments, one per body, of their
//     own masses (whether the bodies are fracturable or not: no joint joins two bodies, and
//     a node shared by two bodies counts in each with its tetrahedron's quarter);
//  1. an intact fracturable bar is one fragment of the bar's mass, and its contact
//     primitives are those of the unsplit bar (the tetrahedra with a face on its surface);
//  2. a ringing intact fracturable bar gives bitwise the same state with contact on and off
//     (the pairs of one body held by intact joints get no contact force);
//  3. the middle breaks: exactly the 8 joints of the middle plane, 2 fragments of 96
//     tetrahedra and 4 kg each (the bar's mass split in halves, to 1e-12), the left one first
//     and moving left;
//  4. pushed back together with contact, the fragments do not pass through each other: the
//     gap between them (smallest x of the right one's nodes minus largest x of the left
//     one's) never goes below -1e-4 m, 0.2% of the element size (measured: -3.4e-5 m; the
//     halves still ring axially from the break with amplitudes of about f_t / E times their
//     half-length, 1e-4 m, which shakes the faces' pressure), the contact energy is positive
//     while they are pressed, and they bounce apart; without contact the same run lets them
//     pass through each other by more than 5e-4 m (so the bound above is a real test);
//  5. one rank holding the whole bar and all ranks of the run agree on the gap history and
//     the fragments' final states to 1e-10 relative (the crack straddles the ranks: some
//     contact tetrahedra are ghosts).
//  6. a partial crack: the halves are given the velocity of a hinge at the bar's bottom
//     (x-velocity 5 m/s z / 0.1 m, apart), which breaks the 4 joints of the middle plane's top
//     row and no other (one fragment); closed again (0.5 m/s at the top), the crack's faces,
//     whose nodes are still glued to each other at the crack's tip through the bottom row's
//     intact joints, must meet as contact surfaces: the gap stays above -1e-4 m (measured
//     -4.8e-5 m; with the two sides of broken joints not paired, as they would be by the
//     shared-node rule alone, it reaches -3.4e-4 m) and the contact energy is positive.
// With -zone, the bar is fracturable only in its two middle cubes, 0.15 < x < 0.25
// (FDEMDeformableAddFractureZone): the rest keeps shared nodes, so the fragments are split
// and unsplit tetrahedra together and their contact surfaces are made of both. All of the
// above must hold unchanged.
#include "common.hpp"

#include <fdem/deformable_contact.h>

#include <cstdio>
#include <cstring>
#include <unordered_map>

namespace {
constexpr double L = 0.4, E = 1.0e9, rho = 2000, nu = 0.25, V1 = 5, V2 = 0.5, penalty = 1.0e10;

PetscErrorCode MakeBar(MPI_Comm comm, bool fracturable, FDEMDeformable *bar, bool allow_zone = true) {
  FDEMDeformable d;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableCreate(comm, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rock", E, nu, rho, 0, FDEM_MATERIAL_MUNJIZA_CST));
  if (fracturable) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1.0e6, 3.0e6, 30, 50, 200, 10 * E));
  const PetscReal lo[3] = {0, 0, 0}, hi[3] = {L, 0.1, 0.1};
  PetscCall(FDEMDeformableSetMeshBox(d, lo, hi, 8, 2, 2));
  PetscBool zone = PETSC_FALSE;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-zone", &zone, nullptr));
  if (fracturable && zone && allow_zone) {
    const PetscReal zlo[3] = {0.15, -1, -1}, zhi[3] = {0.25, 1, 1};
    PetscCall(FDEMDeformableAddFractureZone(d, "box", zlo, zhi)); // the box mesh's one body
  }
  PetscCall(FDEMDeformableSetUp(d));
  *bar = d;
  PetscFunctionReturn(0);
}

// The side of every owned node: -1 if its tetrahedron (a split node has one) lies left of the
// middle, +1 if right.
PetscErrorCode Sides(FDEMDeformable d, std::vector<int> &side) {
  DM                 dm;
  Vec                X, Xl;
  const PetscScalar *xa;
  PetscInt           nc, nl, n;
  const PetscInt    *ids;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, nullptr, nullptr, nullptr, nullptr));
  std::vector<PetscInt> conn(4 * (size_t)nc), gid(nl);
  PetscCall(FDEMDeformableGetLocalCells(d, &nc, &nl, conn.data(), nullptr, nullptr, gid.data()));
  PetscCall(FDEMDeformableGetDM(d, &dm));
  PetscCall(FDEMDeformableGetReferencePositions(d, &X));
  PetscCall(DMGetLocalVector(dm, &Xl));
  PetscCall(DMGlobalToLocal(dm, X, INSERT_VALUES, Xl));
  PetscCall(VecGetArrayRead(Xl, &xa));
  std::unordered_map<PetscInt, int> of;
  for (PetscInt e = 0; e < nc; ++e) {
    double cx = 0;
    for (int a = 0; a < 4; ++a) cx += 0.25 * xa[3 * conn[4 * e + a]];
    for (int a = 0; a < 4; ++a) of[gid[conn[4 * e + a]]] = cx < L / 2 ? -1 : 1;
  }
  PetscCall(VecRestoreArrayRead(Xl, &xa));
  PetscCall(DMRestoreLocalVector(dm, &Xl));
  PetscCall(FDEMDeformableGetNodeIds(d, &n, &ids));
  side.resize(n);
  for (PetscInt k = 0; k < n; ++k) side[k] = of.at(ids[k]);
  PetscFunctionReturn(0);
}

// Sets the x-velocity of every owned node in the state U to s * side.
PetscErrorCode SetSideVelocity(Vec U, const std::vector<int> &side, double s) {
  PetscScalar *u;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(U, &u));
  const size_t n = side.size();
  for (size_t k = 0; k < n; ++k) {
    u[3 * n + 3 * k]     = s * side[k];
    u[3 * n + 3 * k + 1] = u[3 * n + 3 * k + 2] = 0;
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

// Sets the x-velocity of every owned node in the state U to s * side * z / H (a hinge at z = 0
// opening the middle from the top when s > 0), H = 0.1 m the bar's height.
PetscErrorCode SetHingeVelocity(Vec U, const std::vector<int> &side, double s) {
  PetscScalar *u;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(U, &u));
  const size_t n = side.size();
  for (size_t k = 0; k < n; ++k) {
    u[3 * n + 3 * k]     = s * side[k] * u[3 * k + 2] / 0.1;
    u[3 * n + 3 * k + 1] = u[3 * n + 3 * k + 2] = 0;
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

struct Probe {
  std::vector<int>      side;
  FDEMDeformableContact c = nullptr;
  bool                  record = false;
  std::vector<double>   gap, energy;
};

PetscErrorCode Monitor(TS, PetscInt, PetscReal, Vec U, void *ctx) {
  Probe             *p = (Probe *)ctx;
  const PetscScalar *u;
  PetscFunctionBeginUser;
  if (!p->record) PetscFunctionReturn(0);
  double loc[2] = {-INFINITY, -INFINITY}, glob[2]; // largest x of the left side, -(smallest x of the right)
  PetscCall(VecGetArrayRead(U, &u));
  for (size_t k = 0; k < p->side.size(); ++k) {
    if (p->side[k] < 0) loc[0] = std::fmax(loc[0], u[3 * k]);
    else loc[1] = std::fmax(loc[1], -u[3 * k]);
  }
  PetscCall(VecRestoreArrayRead(U, &u));
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPI_DOUBLE, MPI_MAX, PetscObjectComm((PetscObject)U)));
  p->gap.push_back(-glob[1] - glob[0]);
  FDEMDeformableContactStats st{};
  if (p->c) PetscCall(FDEMDeformableContactGetStats(p->c, &st));
  p->energy.push_back(st.energy);
  PetscFunctionReturn(0);
}

struct Result {
  PetscInt                  intact_fragments = 0, broken = 0, fragments = 0, broken_end = 0;
  PetscReal                 intact_mass = 0, mass = 0;
  std::vector<FDEMFragment> after_break, at_end;
  std::vector<double>       gap, energy;
  PetscInt                  primitives_intact = 0, primitives_broken = 0, ghosts = 0;
};

PetscErrorCode Fragments(FDEMDeformable d, Vec U, std::vector<FDEMFragment> &out) {
  PetscInt      n;
  FDEMFragment *f;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetFragments(d, U, &n, &f));
  out.assign(f, f + n);
  PetscCall(PetscFree(f));
  PetscFunctionReturn(0);
}

// Break the middle, then press the fragments together for t2 seconds (contact on or off).
PetscErrorCode Collide(MPI_Comm comm, bool contact, Result *r) {
  FDEMDeformable d;
  TS             ts;
  Vec            U;
  Probe          p;
  PetscReal      omega;
  PetscFunctionBeginUser;
  PetscCall(MakeBar(comm, true, &d));
  PetscCall(Sides(d, p.side));
  PetscCall(FDEMDeformableGetFragments(d, nullptr, &r->intact_fragments, nullptr));
  PetscCall(FDEMDeformableGetMomentum(d, nullptr, &r->intact_mass, nullptr, nullptr, nullptr));
  if (contact) {
    PetscCall(FDEMDeformableContactCreate(d, &p.c));
    PetscCall(FDEMDeformableContactSetPenalty(p.c, penalty));
  }
  PetscCall(FDEMDeformableGetJointFrequency(d, &omega));
  PetscCall(TSCreate(comm, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(SetSideVelocity(U, p.side, V1));
  PetscCall(TSSetTimeStep(ts, 0.25 * 2 / omega));
  PetscCall(TSSetMaxSteps(ts, 1000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSMonitorSet(ts, Monitor, &p, nullptr));
  // 1. the middle breaks; the fragments fly apart
  PetscCall(TSSetMaxTime(ts, 5e-5));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMDeformableGetJointStats(d, nullptr, &r->broken, nullptr));
  PetscCall(Fragments(d, U, r->after_break));
  if (p.c) {
    FDEMDeformableContactStats st;
    PetscCall(FDEMDeformableContactGetStats(p.c, &st));
    r->primitives_broken = st.primitives;
  }
  // 2. sent back towards each other and pressed together
  PetscCall(SetSideVelocity(U, p.side, -V2));
  p.record = true;
  PetscCall(TSSetMaxTime(ts, 5e-5 + 1.5e-3));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMDeformableGetJointStats(d, nullptr, &r->broken_end, nullptr));
  if (p.c) {
    FDEMDeformableContactStats st;
    PetscCall(FDEMDeformableContactGetStats(p.c, &st));
    r->ghosts = st.ghosts;
  }
  PetscCall(Fragments(d, U, r->at_end));
  r->gap    = p.gap;
  r->energy = p.energy;
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  if (p.c) PetscCall(FDEMDeformableContactDestroy(&p.c));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

PetscErrorCode Ring(PetscInt, const PetscReal X[3], PetscReal v[3], void *) {
  v[0] = 0.05 * std::cos(M_PI * X[0] / L);
  v[1] = 0.01 * std::sin(M_PI * X[0] / L); // some bending too
  v[2] = 0;
  return 0;
}

struct HingeResult {
  PetscInt broken = 0, fragments = 0, broken_end = 0, fragments_end = 0;
  double   emax = 0, gmin = INFINITY, gap0 = 0;
};

// A partial crack: the middle opened from the top (hinge velocity, HV at the top), then
// closed again at HV2 at the top (contact on).
PetscErrorCode Hinge(MPI_Comm comm, double HV, double t1, double HV2, double t2, HingeResult *r) {
  FDEMDeformable d;
  TS             ts;
  Vec            U;
  Probe          p;
  PetscReal      omega;
  std::vector<FDEMFragment> fr;
  PetscFunctionBeginUser;
  PetscCall(MakeBar(comm, true, &d));
  PetscCall(Sides(d, p.side));
  PetscCall(FDEMDeformableContactCreate(d, &p.c));
  PetscCall(FDEMDeformableContactSetPenalty(p.c, penalty));
  PetscCall(FDEMDeformableGetJointFrequency(d, &omega));
  PetscCall(TSCreate(comm, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(SetHingeVelocity(U, p.side, HV));
  PetscCall(TSSetTimeStep(ts, 0.25 * 2 / omega));
  PetscCall(TSSetMaxSteps(ts, 1000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSMonitorSet(ts, Monitor, &p, nullptr));
  PetscCall(TSSetMaxTime(ts, t1));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMDeformableGetJointStats(d, nullptr, &r->broken, nullptr));
  PetscCall(FDEMDeformableGetFragments(d, U, &r->fragments, nullptr));
  PetscCall(SetHingeVelocity(U, p.side, -HV2));
  p.record = true;
  PetscCall(TSSetMaxTime(ts, t1 + t2));
  PetscCall(TSSolve(ts, U));
  PetscCall(FDEMDeformableGetJointStats(d, nullptr, &r->broken_end, nullptr));
  PetscCall(FDEMDeformableGetFragments(d, U, &r->fragments_end, nullptr));
  for (double g : p.gap) r->gmin = std::fmin(r->gmin, g);
  for (double e : p.energy) r->emax = std::fmax(r->emax, e);
  r->gap0 = p.gap.empty() ? 0 : p.gap.front();
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableContactDestroy(&p.c));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

// A ringing bar for 200 steps: its final state, and the contact primitives and candidate
// pairs (contact on); zone: the bar split only in the zone with -zone.
PetscErrorCode Ringing(bool fracturable, bool contact, std::vector<PetscScalar> &state, PetscInt *primitives, PetscInt *pairs = nullptr, bool zone = true) {
  FDEMDeformable        d;
  FDEMDeformableContact c = nullptr;
  TS                    ts;
  Vec                   U;
  PetscInt              n;
  const PetscScalar    *u;
  PetscFunctionBeginUser;
  PetscCall(MakeBar(PETSC_COMM_WORLD, fracturable, &d, zone));
  PetscCall(FDEMDeformableSetVelocityField(d, Ring, nullptr));
  if (contact) {
    PetscCall(FDEMDeformableContactCreate(d, &c));
    PetscCall(FDEMDeformableContactSetPenalty(c, penalty));
  }
  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, 2e-6));
  PetscCall(TSSetMaxSteps(ts, 200));
  PetscCall(TSSetMaxTime(ts, 1));
  PetscCall(TSSolve(ts, U));
  PetscCall(VecGetLocalSize(U, &n));
  PetscCall(VecGetArrayRead(U, &u));
  state.assign(u, u + n);
  PetscCall(VecRestoreArrayRead(U, &u));
  *primitives = -1;
  if (c) {
    FDEMDeformableContactStats st;
    PetscCall(FDEMDeformableContactGetStats(c, &st));
    *primitives = st.primitives;
    if (pairs) *pairs = st.candidate_pairs;
    PetscCall(FDEMDeformableContactDestroy(&c));
  }
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}
} // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscMPIInt size, rank;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  const double mass = rho * L * 0.1 * 0.1;

  // 0. two bodies sharing a face (not fracturable) are two fragments, one per body, of their
  //    own masses; the same bodies fracturable are two fragments too (no joint between bodies)
  for (int frac = 0; frac < 2; ++frac) {
    FDEMDeformable    d;
    FDEMFragment     *f;
    PetscInt          n;
    const PetscReal   X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    const PetscInt    T[] = {0, 1, 2, 3, 1, 2, 3, 4}, B[] = {0, 1};
    const char *const names[] = {"anchor", "pebble"};
    PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
    PetscCall(FDEMDeformableAddMaterial(d, "rock", E, nu, rho, 0, FDEM_MATERIAL_MUNJIZA_CST));
    if (frac) PetscCall(FDEMDeformableSetMaterialFracture(d, "rock", 1.0e6, 3.0e6, 30, 50, 200, 10 * E));
    PetscCall(FDEMDeformableSetMesh(d, 5, X, 2, T, B, 2, names));
    PetscCall(FDEMDeformableSetUp(d));
    PetscCall(FDEMDeformableGetFragments(d, nullptr, &n, &f));
    CHECK(n == 2 && f[0].body == 0 && f[1].body == 1 && f[0].cells == 1 && f[1].cells == 1, "two bodies sharing a face (%s): %" PetscInt_FMT " fragments", frac ? "fracturable" : "whole", n);
    if (n == 2) CHECK(std::fabs(f[0].mass - rho / 6) < 1e-12 * rho && std::fabs(f[1].mass - rho / 3) < 1e-12 * rho, "two bodies: fragment masses %g and %g, expected %g and %g", (double)f[0].mass, (double)f[1].mass, rho / 6, rho / 3);
    PetscCall(PetscFree(f));
    PetscCall(FDEMDeformableDestroy(&d));
  }

  // 1-2. the intact fracturable bar: contact on = off bitwise; primitives of the unsplit bar
  {
    std::vector<PetscScalar> on, off, whole;
    PetscInt                 pon, poff, pwhole, pairs, pairs_whole;
    PetscCall(Ringing(true, true, on, &pon, &pairs));
    PetscCall(Ringing(true, false, off, &poff));
    PetscCall(Ringing(false, true, whole, &pwhole, &pairs_whole));
    int same = on.size() == off.size() && std::memcmp(on.data(), off.data(), on.size() * sizeof(PetscScalar)) == 0, all;
    PetscCallMPI(MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ringing intact fracturable bar: contact on and off %s; contact primitives %" PetscInt_FMT " (unsplit bar: %" PetscInt_FMT ")\n", all ? "bitwise equal" : "DIFFER", pon, pwhole));
    CHECK(all, "an intact fracturable bar moves differently with contact on");
    CHECK(pon == pwhole && pon > 0, "the intact fracturable bar lends %" PetscInt_FMT " contact tetrahedra, the unsplit bar %" PetscInt_FMT, pon, pwhole);
    PetscBool zone = PETSC_FALSE;
    PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-zone", &zone, nullptr));
    // the tetrahedra of one fragment held in it (unsplit, or split with no damaged joint) are not
    // paired: the intact bar, split in its zone or everywhere, has the unsplit bar's candidate pairs
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "candidate pairs of the intact bar: %" PetscInt_FMT " split %s, %" PetscInt_FMT " unsplit\n", pairs, zone ? "in the zone" : "everywhere", pairs_whole));
    CHECK(pairs == pairs_whole, "the intact bar split %s has %" PetscInt_FMT " candidate pairs, the unsplit bar %" PetscInt_FMT ": tetrahedra held in one fragment should not pair with each other", zone ? "in its zone" : "everywhere", pairs, pairs_whole);
    if (zone) {
      std::vector<PetscScalar> split;
      PetscInt                 psplit, pairs_split;
      PetscCall(Ringing(true, true, split, &psplit, &pairs_split, false));
      CHECK(pairs_split == pairs_whole, "the intact bar split everywhere has %" PetscInt_FMT " candidate pairs, the unsplit bar %" PetscInt_FMT, pairs_split, pairs_whole);
    }
  }

  // 3-4. break, then press together, with and without contact
  Result with, without;
  PetscCall(Collide(PETSC_COMM_WORLD, true, &with));
  PetscCall(Collide(PETSC_COMM_WORLD, false, &without));
  CHECK(with.intact_fragments == 1, "the intact bar is %" PetscInt_FMT " fragments", with.intact_fragments);
  CHECK(std::fabs(with.intact_mass - mass) < 1e-12 * mass, "the bar's mass is %.15g, expected %.15g", (double)with.intact_mass, mass);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "after the jump: %" PetscInt_FMT " joints broken, %d fragments, contact primitives %" PetscInt_FMT "\n", with.broken, (int)with.after_break.size(), with.primitives_broken));
  CHECK(with.broken == 8, "%" PetscInt_FMT " joints broke, expected the 8 of the middle plane", with.broken);
  CHECK(with.after_break.size() == 2, "%d fragments after the middle broke, expected 2", (int)with.after_break.size());
  if (with.after_break.size() == 2) {
    const FDEMFragment &a = with.after_break[0], &b = with.after_break[1];
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fragments: %" PetscInt_FMT " cells, %.12g kg at x = %.6f, vx = %.4f; %" PetscInt_FMT " cells, %.12g kg at x = %.6f, vx = %.4f\n", a.cells, (double)a.mass, (double)a.x[0], (double)a.v[0], b.cells, (double)b.mass, (double)b.x[0], (double)b.v[0]));
    CHECK(a.cells == 96 && b.cells == 96, "fragments of %" PetscInt_FMT " and %" PetscInt_FMT " tetrahedra, expected 96 each", a.cells, b.cells);
    CHECK(std::fabs(a.mass - mass / 2) < 1e-12 * mass && std::fabs(b.mass - mass / 2) < 1e-12 * mass, "fragment masses %.15g and %.15g, expected %.15g each", (double)a.mass, (double)b.mass, mass / 2);
    CHECK(std::fabs(a.mass + b.mass - with.intact_mass) < 1e-12 * mass, "the fragments' masses do not sum to the bar's");
    CHECK(a.body == 0 && b.body == 0, "the fragments' body");
    CHECK(a.x[0] < L / 2 && b.x[0] > L / 2 && a.v[0] < 0 && b.v[0] > 0, "the left fragment should come first, both moving apart");
    CHECK(std::fabs(a.x[1] - 0.05) < 1e-3 && std::fabs(a.x[2] - 0.05) < 1e-3, "the left fragment's centre is off the bar's axis");
  }
  double gmin = INFINITY, gmin0 = INFINITY, emax = 0;
  for (double g : with.gap) gmin = std::fmin(gmin, g);
  for (double g : without.gap) gmin0 = std::fmin(gmin0, g);
  for (double e : with.energy) emax = std::fmax(emax, e);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "pressed together: smallest gap %.3e m with contact (largest contact energy %.3e J), %.3e m without; joints broken at the end %" PetscInt_FMT "\n", gmin, emax, gmin0, with.broken_end));
  CHECK(!with.gap.empty() && with.gap.front() > 0, "the fragments should start phase 2 apart");
  CHECK(gmin > -1e-4, "with contact the fragments overlap by %.3e m (bound 1e-4)", -gmin);
  CHECK(emax > 0, "no contact energy while the fragments are pressed together");
  CHECK(gmin0 < -5e-4, "without contact the fragments should pass through each other (smallest gap %.3e)", gmin0);
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ghost contact tetrahedra at the last search: %" PetscInt_FMT "\n", with.ghosts));
  if (size > 1) CHECK(with.ghosts > 0, "on %d ranks no contact tetrahedron is a ghost: the crack does not straddle the ranks, so the test does not test that", size);
  if (with.at_end.size() == 2) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "at the end: vx %.4f and %.4f\n", (double)with.at_end[0].v[0], (double)with.at_end[1].v[0]));
    CHECK(with.at_end[0].v[0] < 0 && with.at_end[1].v[0] > 0, "the fragments did not bounce apart");
  } else CHECK(false, "%d fragments at the end, expected 2", (int)with.at_end.size());

  // 5. one rank against all
  if (size > 1) {
    int ok = 1;
    if (rank == 0) {
      Result one;
      PetscCall(Collide(PETSC_COMM_SELF, true, &one));
      double dg = 0, dx = 0;
      ok        = one.gap.size() == with.gap.size() && one.at_end.size() == with.at_end.size() && one.broken_end == with.broken_end;
      for (size_t i = 0; ok && i < one.gap.size(); ++i) dg = std::fmax(dg, std::fabs(one.gap[i] - with.gap[i]));
      for (size_t f = 0; ok && f < one.at_end.size(); ++f)
        for (int k = 0; k < 3; ++k) dx = std::fmax(dx, std::fmax(std::fabs(one.at_end[f].x[k] - with.at_end[f].x[k]) / L, std::fabs(one.at_end[f].v[k] - with.at_end[f].v[k]) / V2));
      std::printf("one rank against %d: gap history %.3e relative (to 1e-3 m), fragments' x and v %.3e relative\n", size, dg / 1e-3, dx);
      ok = ok && dg <= 1e-10 * 1e-3 && dx <= 1e-10;
    }
    PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, PETSC_COMM_WORLD));
    CHECK(ok, "one rank and all ranks disagree on the broken bar");
  }
  // 6. a partial crack: the middle opened from the top, closed again
  {
    HingeResult h;
    PetscCall(Hinge(PETSC_COMM_WORLD, 5, 3e-5, 0.5, 1e-3, &h));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "partial crack: %" PetscInt_FMT " joints broken, %" PetscInt_FMT " fragment(s); closed again: smallest gap %.3e m, largest contact energy %.3e J, %" PetscInt_FMT " joints broken at the end\n", h.broken, h.fragments, h.gmin, h.emax, h.broken_end));
    CHECK(h.broken == 4 && h.fragments == 1, "the hinge should break the 4 joints of the middle plane's top row and leave one fragment (%" PetscInt_FMT " broken, %" PetscInt_FMT " fragments)", h.broken, h.fragments);
    CHECK(h.emax > 0, "no contact energy while the partial crack closes");
    CHECK(h.gmin > -1e-4, "the faces of the partial crack overlap by %.3e m when it closes (bound 1e-4)", -h.gmin);
  }

  PetscCall(ReportChecks());
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
