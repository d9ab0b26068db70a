// Hertz validation of the deformable contact (doc/contact_hertz.md): an elastic
// ball (R = 1, E = 1, nu = 0.3, rho = 1, neo-Hookean) meshed by Gmsh with
// elements refined at its south pole (tests/contact/data/hertz_ball.geo) hits a
// plate whose nodes are all fixed (a rigid flat) at v0 = 0.03. Peak contact
// force, contact time and peak approach against Hertz theory for a sphere on a
// rigid flat (E* = E / (1 - nu^2), m = the ball mesh's mass):
//   delta_max = (15 m v0^2 / (16 E* sqrt(R)))^(2/5),  F_max = 4/3 E* sqrt(R) delta_max^(3/2),
//   t_c = 2.868 (m^2 / (R E*^2 v0))^(1/5).
// Asserted (ctest: hertz_ball_h10.msh, v0 = 0.01): 0 < F_max/F_H - 1 < 0.22, |t_c/t_H - 1|
// < 0.12, |delta_max/delta_H - 1| < 0.12, rebound within 1% of v0; with several meshes,
// the F_max error smaller on the last (finest) than on the first. At v0 = 0.03
// (delta = 0.1 R) the model stays 20% stiffer than Hertz however fine the contact
// mesh: the regime, not the mesh (doc/contact_hertz.md).
//
// Options: -hertz_mesh a.msh[,b.msh]  meshes, coarse to fine (physical volumes "ball", "plate")
//          -hertz_penalty <multiple of E> (10), -hertz_cfl <dt c_p / h_min> (0.4), -hertz_dt,
//          -hertz_v0 (0.03), -hertz_study (print only, no asserts; for doc/contact_hertz.md).
#include <fdem.h>
#include <fdem/deformable.h>
#include <fdem/deformable_contact.h>
#include <fdem/kernels/tetmesh.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "../common/check.hpp"

namespace {

using fdem::kernels::Vec3;

struct Result {
  PetscInt tets_ball = 0, tets_plate = 0;
  double   h_contact = 0, h_min = 0, dt = 0, m = 0;
  double   Fmax = 0, F_hertz = 0, tc = 0, tc_hertz = 0, dmax = 0, dmax_hertz = 0, d_at_Fmax = 0;
  double   rebound = 0, dt_ratio = 0, seconds = 0;
  PetscInt steps = 0, searches = 0, surface = 0, pairs = 0;
  double   eF() const { return Fmax / F_hertz - 1; }
  double   eT() const { return tc / tc_hertz - 1; }
  double   eD() const { return dmax / dmax_hertz - 1; }
};

// Mesh facts from the file (every rank reads it; it is small): ball tets, the
// smallest altitude of a ball tet (sets the stable time step) and the mean edge of
// the ball's surface faces within 0.3 R of the contact point.
struct MeshFacts {
  PetscInt ball = -1, tets_ball = 0, tets_plate = 0;
  double   h_min = 1e300, h_contact = 0;
};
// A bad file is a PETSc error naming it (every rank reads it: collective).
PetscErrorCode ReadFacts(const std::string &path, double gap, MeshFacts &f) {
  fdem::kernels::TetMesh M;
  PetscFunctionBeginUser;
  try {
    M = fdem::kernels::ReadGmsh(path);
  } catch (const std::exception &e) {
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED, "-hertz_mesh: %s", e.what());
  }
  for (int b = 0; b < M.NumBodies(); ++b)
    if (M.body_names[b] == "ball") f.ball = b;
  if (f.ball < 0) PetscFunctionReturn(0);
  for (size_t e = 0; e < M.tets.size(); ++e) {
    if (M.body[e] != f.ball) {
      f.tets_plate++;
      continue;
    }
    f.tets_ball++;
    const auto &t = M.tets[e];
    const Vec3  p[4] = {M.nodes[t[0]], M.nodes[t[1]], M.nodes[t[2]], M.nodes[t[3]]};
    const double V = std::fabs(fdem::kernels::TetSignedVolume(p[0], p[1], p[2], p[3]));
    double       Amax = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec3 &a = p[(k + 1) % 4], &b = p[(k + 2) % 4], &c = p[(k + 3) % 4];
      Amax          = std::fmax(Amax, 0.5 * fdem::kernels::norm(fdem::kernels::cross(b - a, c - a)));
    }
    f.h_min = std::fmin(f.h_min, 3 * V / Amax);
  }
  const fdem::kernels::SurfaceInfo S = fdem::kernels::SurfaceTets(M);
  double                           sum = 0;
  int                              n   = 0;
  for (size_t i = 0; i < S.faces.size(); ++i) {
    if (M.body[S.face_tet[i]] != f.ball) continue;
    const auto &fc = S.faces[i];
    const Vec3  c  = (M.nodes[fc[0]] + M.nodes[fc[1]] + M.nodes[fc[2]]) / 3.0;
    if (fdem::kernels::norm(c - Vec3(0, 0, gap)) > 0.3) continue;
    for (int k = 0; k < 3; ++k) sum += fdem::kernels::norm(M.nodes[fc[k]] - M.nodes[fc[(k + 1) % 3]]);
    n += 3;
  }
  f.h_contact = n ? sum / n : 0;
  PetscFunctionReturn(0);
}

struct Watch {
  FDEMDeformable        d;
  FDEMDeformableContact c;
  PetscInt              ball;
  double                m_total, m_ball, z0, v0, gap;
  double                Fmax = 0, t_on = -1, t_off = -1, dmax = 0, d_at_Fmax = 0;
  PetscInt              quiet = 0; // steps without force after the contact
  std::vector<double>   hist;      // t, F_z, delta per step
};

// After each step: contact force on the ball (at the last evaluation: cd evaluates at the
// end of the step) and its approach delta = the fall of the ball's centre of mass beyond
// the gap (the plate does not move, so the ball's centre moves by m_total/m_ball times the
// whole mesh's). Ends the run 20 steps after the contact ends.
PetscErrorCode PostStep(TS ts) {
  Watch    *w;
  PetscReal t, F[3], com[3];
  Vec       U;
  PetscFunctionBeginUser;
  PetscCall(TSGetApplicationContext(ts, &w));
  PetscCall(TSGetTime(ts, &t));
  PetscCall(TSGetSolution(ts, &U));
  PetscCall(FDEMDeformableContactGetBodyForce(w->c, w->ball, F));
  PetscCall(FDEMDeformableGetMomentum(w->d, U, nullptr, com, nullptr, nullptr));
  const double delta = (w->z0 - com[2]) * w->m_total / w->m_ball - w->gap;
  w->dmax            = std::fmax(w->dmax, delta);
  w->hist.insert(w->hist.end(), {t, F[2], delta});
  if (F[2] > 0) {
    if (w->t_on < 0) w->t_on = t;
    w->t_off = t;
    w->quiet = 0;
    if (F[2] > w->Fmax) {
      w->Fmax      = F[2];
      w->d_at_Fmax = delta;
    }
  } else if (w->t_on >= 0 && ++w->quiet >= 20) PetscCall(TSSetConvergedReason(ts, TS_CONVERGED_USER));
  PetscFunctionReturn(0);
}

PetscErrorCode VelocityField(PetscInt, const PetscReal X[3], PetscReal v[3], void *ctx) {
  const Watch *w = (const Watch *)ctx;
  v[0] = v[1] = 0;
  v[2]        = X[2] > 0.5 * w->gap ? -w->v0 : 0; // ball nodes have z >= gap, plate nodes z <= 0
  return 0;
}

PetscErrorCode Hertz(const std::string &path, double penalty, double cfl, double dt_opt, double v0, FDEMMaterialModel model, const char *history, Result &r) {
  const double          R = 1, E = 1, nu = 0.3, rho = 1, gap = 0.002; // gap: hertz_ball.geo
  FDEMDeformable        d;
  FDEMDeformableContact c;
  TS                    ts;
  Vec                   U;
  PetscFunctionBeginUser;
  MeshFacts f;
  PetscCall(ReadFacts(path, gap, f));
  PetscCheck(f.ball >= 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "%s has no physical volume \"ball\"", path.c_str());
  const double cp = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho)); // P-wave speed
  r.tets_ball     = f.tets_ball;
  r.tets_plate    = f.tets_plate;
  r.h_min         = f.h_min;
  r.h_contact     = f.h_contact;
  r.dt            = dt_opt > 0 ? dt_opt : cfl * f.h_min / cp;

  PetscCall(FDEMDeformableCreate(PETSC_COMM_WORLD, &d));
  PetscCall(FDEMDeformableAddMaterial(d, "rubber", E, nu, rho, 0.0, model));
  PetscCall(FDEMDeformableSetMeshFromGmsh(d, path.c_str()));
  PetscCall(FDEMDeformableSetUp(d));
  const PetscReal lo[3] = {-10, -10, -10}, hi[3] = {10, 10, 0.5 * gap};
  PetscInt        nfixed;
  PetscCall(FDEMDeformableFixNodesInBox(d, lo, hi, &nfixed));
  Watch w;
  w.d   = d;
  w.v0  = v0;
  w.gap = gap;
  PetscCall(FDEMDeformableSetVelocityField(d, VelocityField, &w));
  PetscInt nb;
  for (PetscInt b = 0, done = 0; !done; ++b) {
    const char *name;
    PetscCall(FDEMDeformableGetBodyName(d, b, &nb, &name));
    if (!std::strcmp(name, "ball")) {
      w.ball = b;
      done   = 1;
    }
  }
  PetscReal mass, com[3], P[3];
  PetscCall(FDEMDeformableGetMomentum(d, nullptr, &mass, com, P, nullptr));
  w.m_total = mass;
  w.m_ball  = -P[2] / v0;
  w.z0      = com[2];
  r.m       = w.m_ball;
  PetscCall(FDEMDeformableContactCreate(d, &c));
  PetscCall(FDEMDeformableContactSetPenalty(c, penalty * E));
  PetscCall(FDEMDeformableContactSetFromOptions(c));
  w.c = c;

  const double m = w.m_ball, Es = E / (1 - nu * nu);
  r.dmax_hertz   = std::pow(15 * m * v0 * v0 / (16 * Es * std::sqrt(R)), 0.4);
  r.F_hertz      = 4.0 / 3 * Es * std::sqrt(R) * std::pow(r.dmax_hertz, 1.5);
  r.tc_hertz     = 2.868 * std::pow(m * m / (R * Es * Es * v0), 0.2);

  PetscCall(TSCreate(PETSC_COMM_WORLD, &ts));
  PetscCall(TSSetType(ts, TSFDEMCD));
  PetscCall(FDEMDeformableSetUpTS(d, ts, &U));
  PetscCall(TSSetTimeStep(ts, r.dt));
  PetscCall(TSSetMaxTime(ts, gap / v0 + 2 * r.tc_hertz)); // the run ends when the contact does
  PetscCall(TSSetMaxSteps(ts, 10000000));
  PetscCall(TSSetExactFinalTime(ts, TS_EXACTFINALTIME_MATCHSTEP));
  PetscCall(TSSetApplicationContext(ts, &w));
  PetscCall(TSSetPostStep(ts, PostStep));
  PetscCall(FDEMDeformableContactCheckTimeStep(c, "cd", r.dt, &r.dt_ratio));
  PetscLogDouble t0, t1;
  PetscCall(PetscTime(&t0));
  PetscCall(TSSolve(ts, U));
  PetscCall(PetscTime(&t1));
  TSConvergedReason reason;
  PetscCall(TSGetConvergedReason(ts, &reason));
  PetscCall(TSGetStepNumber(ts, &r.steps));
  PetscCheck(reason == TS_CONVERGED_USER, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "the ball did not leave the plate by t = %g (reason %s)", (double)(gap / v0 + 2 * r.tc_hertz), TSConvergedReasons[reason]);
  PetscReal Pend[3];
  PetscCall(FDEMDeformableGetMomentum(d, U, nullptr, nullptr, Pend, nullptr));
  FDEMDeformableContactStats st;
  PetscCall(FDEMDeformableContactGetStats(c, &st));
  r.searches = st.searches;
  r.surface  = st.primitives;
  r.pairs    = st.candidate_pairs;
  r.Fmax      = w.Fmax;
  r.tc        = w.t_off - w.t_on + r.dt; // force > 0 at the ends of steps t_on .. t_off
  r.dmax      = w.dmax;
  r.d_at_Fmax = w.d_at_Fmax;
  r.rebound   = Pend[2] / (m * v0);
  r.seconds   = t1 - t0;
  if (history[0]) {
    FILE *fp;
    PetscCall(PetscFOpen(PETSC_COMM_WORLD, history, "w", &fp));
    PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "t,F,delta\n"));
    for (size_t i = 0; i + 2 < w.hist.size(); i += 3) PetscCall(PetscFPrintf(PETSC_COMM_WORLD, fp, "%.6g,%.6e,%.6e\n", w.hist[i], w.hist[i + 1], w.hist[i + 2]));
    PetscCall(PetscFClose(PETSC_COMM_WORLD, fp));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                        "Hertz %s: ball %d tets (plate %d), h at contact %.3f, h_min %.4f, penalty %g E, dt %.4g (contact dt ratio %.2f), %d steps, %.1f s; %d surface tets, %d searches, %d candidate pairs at the last\n"
                        "  F_max %.4e (Hertz %.4e, %+.1f%%), t_c %.3f (Hertz %.3f, %+.1f%%), delta_max %.4f (Hertz %.4f, %+.1f%%), "
                        "F_max / (4/3 E* sqrt(R) delta^1.5) at the peak %.3f, rebound v/v0 %.3f\n",
                        path.substr(path.find_last_of('/') + 1).c_str(), (int)r.tets_ball, (int)r.tets_plate, r.h_contact, r.h_min, penalty, r.dt, r.dt_ratio, (int)r.steps, r.seconds, (int)r.surface, (int)r.searches, (int)r.pairs,
                        r.Fmax, r.F_hertz, 100 * r.eF(), r.tc, r.tc_hertz, 100 * r.eT(), r.dmax, r.dmax_hertz, 100 * r.eD(),
                        r.Fmax / (4.0 / 3 * Es * std::sqrt(R) * std::pow(r.d_at_Fmax, 1.5)), r.rebound));
  PetscCall(VecDestroy(&U));
  PetscCall(TSDestroy(&ts));
  PetscCall(FDEMDeformableContactDestroy(&c));
  PetscCall(FDEMDeformableDestroy(&d));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv) {
  char      paths[4096] = "", history[PETSC_MAX_PATH_LEN] = "";
  PetscReal penalty = 10, cfl = 0.4, dt = -1, v0 = 0.03;
  PetscBool set, study = PETSC_FALSE;
  PetscEnum model = (PetscEnum)FDEM_MATERIAL_NEO_HOOKEAN;
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  PetscCall(FDEMInitializePackage());
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-hertz_mesh", paths, sizeof(paths), &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_USER_INPUT, "give -hertz_mesh a.msh[,b.msh,...] (tests/contact/data/hertz_ball_*.msh)");
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-hertz_penalty", &penalty, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-hertz_cfl", &cfl, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-hertz_dt", &dt, nullptr));
  PetscCall(PetscOptionsGetReal(nullptr, nullptr, "-hertz_v0", &v0, nullptr));
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-hertz_study", &study, nullptr));
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-hertz_history", history, sizeof(history), nullptr));
  PetscCall(PetscOptionsGetEnum(nullptr, nullptr, "-hertz_material", FDEMMaterialModels, &model, nullptr));
  std::vector<Result> res;
  for (std::string rest = paths; !rest.empty();) {
    const size_t      k = rest.find(',');
    const std::string p = rest.substr(0, k);
    rest                = k == std::string::npos ? "" : rest.substr(k + 1);
    res.emplace_back();
    PetscCall(Hertz(p, penalty, cfl, dt, v0, (FDEMMaterialModel)model, history, res.back()));
  }
  if (!study) {
    // Measured (doc/contact_hertz.md), hertz_ball_h10.msh, v0 = 0.01, penalty 10 E:
    // F_max +15.8%, t_c -8.5%, delta_max -7.9%, rebound 0.999.
    const Result &f = res.back();
    CHECK(f.eF() > 0 && f.eF() < 0.22, "F_max off Hertz by %+.1f%% (measured +15.8%%)", 100 * f.eF());
    CHECK(std::fabs(f.eT()) < 0.12, "t_c off Hertz by %+.1f%% (measured -8.5%%)", 100 * f.eT());
    CHECK(std::fabs(f.eD()) < 0.12, "delta_max off Hertz by %+.1f%% (measured -7.9%%)", 100 * f.eD());
    CHECK(std::fabs(f.rebound - 1) < 0.01, "rebound speed %.4f v0 (elastic, measured 0.999)", f.rebound);
    if (res.size() > 1) CHECK(std::fabs(f.eF()) < std::fabs(res.front().eF()), "the F_max error does not fall with refinement: %+.1f%% (coarse) vs %+.1f%% (fine)", 100 * res.front().eF(), 100 * f.eF());
  }
  if (failures) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%d FAILURES\n", failures));
  else PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Hertz contact test passed\n"));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
