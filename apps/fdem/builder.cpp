// The builder: every call of the driver into the fdem library is in this file.
#include "builder.hpp"

#include <fdem.h>
#include <fdem/contact.h>
#include <fdem/deformable.h>
#include <fdem/deformable_contact.h>
#include <fdem/rigid.h>
#include <fdem/scene.h>
#include <fdem/ts.h>

#include <petscviewerhdf5.h>

#include <algorithm>
#include <numeric>
#include <cstring>
#include <cmath>

namespace fdem::driver {
namespace {

FDEMMaterialModel ModelOf(const std::string &name) {
  for (int i = 0; i < 3; ++i)
    if (name == FDEMMaterialModels[i]) return (FDEMMaterialModel)i;
  return FDEM_MATERIAL_MUNJIZA_CST; // names are checked by the reader
}

void RowMajor(const Mat3 &Q, PetscReal out[9]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = Q.m[r][c];
}

// The initial velocity of the deformable bodies: v + w x (X - centroid) + the velocity_field of the node's body.
struct InitialField {
  const Scene      *scene;
  std::vector<int>  node_body; // scene body index per merged node
  std::vector<Vec3> centroid;  // per scene body: the volume centroid of the placed mesh
};
PetscErrorCode InitialVelocity(PetscInt id, const PetscReal X[3], PetscReal out[3], void *ctx) {
  const auto &f  = *(InitialField *)ctx;
  const int   bi = f.node_body[id];
  const Body &b  = f.scene->bodies[bi];
  const Vec3  x(X[0], X[1], X[2]);
  Vec3        v = b.velocity + cross(b.angular_velocity, x - f.centroid[bi]);
  if (b.velocity_field.kind != VelocityField::None) {
    const auto &vf = b.velocity_field;
    v              = v + vf.direction * (vf.amplitude * vf.Profile((x[vf.axis] - vf.from) / (vf.to - vf.from)));
  }
  out[0] = v.x, out[1] = v.y, out[2] = v.z;
  return 0;
}

// Volume centroid of mesh m placed at b.position + b.rotation * X.
Vec3 PlacedCentroid(const kernels::TetMesh &m, const Body &b) {
  Vec3   c;
  double V = 0;
  for (const auto &t : m.tets) {
    const Vec3  &p0 = m.nodes[t[0]], &p1 = m.nodes[t[1]], &p2 = m.nodes[t[2]], &p3 = m.nodes[t[3]];
    const double v  = std::fabs(kernels::TetSignedVolume(p0, p1, p2, p3));
    c               = c + (p0 + p1 + p2 + p3) * (0.25 * v);
    V += v;
  }
  return b.position + b.rotation * (V > 0 ? c * (1 / V) : c);
}

PetscErrorCode BuildRigid(Sim &s, const Vec3 &lo, const Vec3 &hi) {
  const Scene &sc = *s.scene;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidCreate(s.comm, &s.rb));
  PetscReal       l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  const PetscReal g[3] = {sc.gravity.x, sc.gravity.y, sc.gravity.z};
  if (sc.periodic.Any()) { // the periodic cell is the domain along its axes
    PetscBool per[3];
    for (int k = 0; k < 3; ++k) {
      per[k] = sc.periodic.axis[k] ? PETSC_TRUE : PETSC_FALSE;
      if (per[k]) l[k] = sc.periodic.lo[k], h[k] = sc.periodic.hi[k];
    }
    PetscCall(FDEMRigidSetDomain(s.rb, l, h));
    PetscCall(FDEMRigidSetPeriodic(s.rb, per));
  } else PetscCall(FDEMRigidSetDomain(s.rb, l, h));
  PetscCall(FDEMRigidSetGravity(s.rb, g));
  PetscCall(FDEMRigidSetFromOptions(s.rb));
  PetscInt moving = 0, spheres = 0;
  for (int i : s.rigid_bodies) moving += !sc.bodies[i].fixed && !sc.bodies[i].moved;
  for (int i : s.rigid_bodies) spheres += sc.bodies[i].Granular();
  // every material as a granular material (index = its place in the scene), for the contacts of spheres
  for (const Material &m : sc.materials) {
    FDEMGranularMaterial g;
    PetscCall(FDEMGranularMaterialInitialize(&g));
    g.law_set = m.contact_law.empty() ? PETSC_FALSE : PETSC_TRUE;
    g.law     = m.contact_law == "hooke" ? FDEM_GRANULAR_HOOKE : FDEM_GRANULAR_HERTZ;
    if (m.young > 0) g.young = m.young, g.poisson = m.poisson;
    g.kn               = m.kn;
    g.kt               = m.kt >= 0 ? m.kt : (m.kn > 0 ? 2.0 / 7.0 * m.kn : -1);
    g.gamma_n          = m.gamma_n;
    g.gamma_t          = m.gamma_t >= 0 ? m.gamma_t : (m.gamma_n > 0 ? 0.5 * m.gamma_n : -1); // LAMMPS's default: half of gamma_n
    g.restitution      = m.restitution;
    g.friction         = m.friction;
    g.rolling_friction = m.rolling_friction;
    PetscCall(FDEMRigidAddGranularMaterial(s.rb, m.name.c_str(), &g, nullptr));
  }
  if (!sc.contact.present && spheres > 0) {
    // the spheres bring the rigid bodies' contact, and with it the potential contact force
    // between polyhedral bodies, which needs a penalty: a moving polyhedral body and another
    // polyhedral body (not both held) form such pairs (without spheres and without contact:,
    // polyhedra do not touch)
    const Body *mover = nullptr, *other = nullptr;
    for (int i : s.rigid_bodies) {
      const Body &b = sc.bodies[i];
      if (b.Granular()) continue;
      if (!mover && !b.fixed && !b.moved) mover = &b;
      else if (!other) other = &b;
    }
    PetscCheck(!(mover && other), s.comm, PETSC_ERR_USER_INPUT,
               "%s: body '%s' is a moving rigid body with a polyhedral shape, and it meets body '%s' (%s) through the potential contact force between tetrahedra, which needs a penalty: give contact: {penalty: Pa} (the spheres' granular laws act on pairs with a sphere only)",
               mover ? mover->where.c_str() : "", mover ? mover->name.c_str() : "", other ? other->name.c_str() : "", other ? other->where.c_str() : "");
  }
  if ((sc.contact.present || spheres > 0) && s.rigid_bodies.size() >= 2 && moving > 0) {
    PetscCall(FDEMContactCreate(s.rb, &s.rc));
    if (sc.contact.penalty > 0) PetscCall(FDEMContactSetPenalty(s.rc, sc.contact.penalty));
    PetscCall(FDEMContactSetDissipation(s.rc, sc.contact.normal_damping, sc.contact.friction, sc.contact.tangential_viscosity));
    if (sc.contact.buffer > 0) PetscCall(FDEMContactSetBuffer(s.rc, sc.contact.buffer));
    PetscCall(FDEMContactSetFromOptions(s.rc));
  }
  for (int i : s.rigid_bodies) {
    const Body            &b = sc.bodies[i];
    const auto            &m = s.meshes[i];
    std::vector<PetscReal> nodes;
    std::vector<PetscInt>  tets;
    for (const auto &p : m.nodes) nodes.insert(nodes.end(), {p.x, p.y, p.z});
    for (const auto &t : m.tets) tets.insert(tets.end(), t.begin(), t.end());
    const Material *mat     = sc.FindMaterial(b.material);
    const PetscReal density = mat ? mat->density : 1000; // a fixed or moved body without material: any density
    PetscReal       Q[9], x[3] = {b.position.x, b.position.y, b.position.z}, v[3] = {b.velocity.x, b.velocity.y, b.velocity.z},
              w[3] = {b.angular_velocity.x, b.angular_velocity.y, b.angular_velocity.z};
    RowMajor(b.rotation, Q);
    PetscInt id;
    const PetscInt gm = mat ? (PetscInt)(mat - sc.materials.data()) : -1;
    if (b.model == "sphere") PetscCall(FDEMRigidAddSphere(s.rb, b.name.c_str(), b.shape.radius, density, gm, x, v, w, &id));
    else if (b.shape.kind == ShapeKind::Spheres) {
      PetscCheck(gm >= 0, s.comm, PETSC_ERR_USER_INPUT, "%s: body '%s': a clump (shape {spheres: ...}) needs a material: its spheres' contacts take the material's granular law", b.where.c_str(), b.name.c_str());
      std::vector<PetscReal> balls;
      for (size_t k = 0; k < b.shape.points.size(); ++k) balls.insert(balls.end(), {b.shape.points[k].x, b.shape.points[k].y, b.shape.points[k].z, b.shape.radii[k]});
      PetscCall(FDEMRigidAddClump(s.rb, b.name.c_str(), (PetscInt)b.shape.radii.size(), balls.data(), density, gm, x, Q, v, w, &id));
    } else {
      PetscCall(FDEMRigidAddBodyFromMesh(s.rb, b.name.c_str(), (PetscInt)m.nodes.size(), nodes.data(), (PetscInt)m.tets.size(), tets.data(), density, x, Q, v, w, &id));
      if (gm >= 0) PetscCall(FDEMRigidSetBodyMaterial(s.rb, id, gm));
    }
    if (b.fixed) PetscCall(FDEMRigidFixBody(s.rb, id));
    if (b.moved) {
      const PetscReal mv[3] = {b.move_velocity.x, b.move_velocity.y, b.move_velocity.z};
      PetscCall(FDEMRigidMoveBody(s.rb, id, mv));
    }
  }
  PetscFunctionReturn(0);
}

// The nodes of node set `ns` of body b (mesh m, merged numbering from `base`), appended to ids.
PetscErrorCode SelectNodes(const Sim &s, const Body &b, const NodeSet &ns, const char *key, const kernels::TetMesh &m, PetscInt base, std::vector<PetscInt> &ids) {
  PetscFunctionBeginUser;
  if (ns.kind == NodeSet::Below || ns.kind == NodeSet::Above)
    for (size_t n = 0; n < m.nodes.size(); ++n) {
      const Vec3 p = b.position + b.rotation * m.nodes[n];
      if ((ns.kind == NodeSet::Below && p[ns.axis] <= ns.value) || (ns.kind == NodeSet::Above && p[ns.axis] >= ns.value)) ids.push_back(base + (PetscInt)n);
    }
  if (ns.kind == NodeSet::Group) {
    const auto it = std::find(m.body_names.begin(), m.body_names.end(), ns.group);
    if (it == m.body_names.end()) {
      std::string known;
      for (const auto &n : m.body_names) known += (known.empty() ? "" : ", ") + n;
      SETERRQ(s.comm, PETSC_ERR_USER_INPUT, "%s: body '%s'.%s.group: the mesh has no physical volume '%s' (it has: %s)", ns.where.c_str(), b.name.c_str(), key, ns.group.c_str(), known.c_str());
    }
    const int g = (int)(it - m.body_names.begin());
    for (size_t e = 0; e < m.tets.size(); ++e)
      if (m.body[e] == g)
        for (int c : m.tets[e]) ids.push_back(base + c);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  PetscFunctionReturn(0);
}

PetscErrorCode BuildDeformable(Sim &s, const std::vector<PetscInt> &fracture_cells, FDEMDeformable previous) {
  const Scene                 &sc = *s.scene;
  std::vector<PetscReal>       nodes;
  std::vector<PetscInt>        tets, body, fixed;
  std::vector<std::vector<PetscInt>> moved(s.deformable_bodies.size()); // per deformable body
  std::vector<std::string>     names;
  std::vector<const char *>    cnames;
  InitialField                 vf{&sc, {}, std::vector<Vec3>(sc.bodies.size())};
  PetscMPIInt                  rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  // one merged mesh, one library body per scene body; nodes placed by position + rotation
  for (size_t k = 0; k < s.deformable_bodies.size(); ++k) {
    const Body    &b    = sc.bodies[s.deformable_bodies[k]];
    const auto    &m    = s.meshes[s.deformable_bodies[k]];
    const PetscInt base = (PetscInt)(nodes.size() / 3);
    vf.centroid[s.deformable_bodies[k]] = PlacedCentroid(m, b);
    for (size_t n = 0; n < m.nodes.size(); ++n) {
      const Vec3 p = b.position + b.rotation * m.nodes[n];
      nodes.insert(nodes.end(), {p.x, p.y, p.z});
      vf.node_body.push_back(s.deformable_bodies[k]);
    }
    PetscCall(SelectNodes(s, b, b.fix, "fix", m, base, fixed));
    if (b.moved) {
      PetscCall(SelectNodes(s, b, b.move, "move", m, base, moved[k]));
      PetscCheck(!moved[k].empty(), s.comm, PETSC_ERR_USER_INPUT, "%s: body '%s'.move: the node set holds no node", b.move.where.c_str(), b.name.c_str());
    }
    for (size_t e = 0; e < m.tets.size(); ++e) {
      for (int c : m.tets[e]) tets.push_back(base + c);
      body.push_back((PetscInt)k);
    }
    names.push_back(b.name);
  }
  for (const auto &n : names) cnames.push_back(n.c_str());
  s.ntets  = (PetscInt)body.size();
  s.nnodes = (PetscInt)(nodes.size() / 3);
  PetscCall(FDEMDeformableCreate(s.comm, &s.dfm));
  std::vector<std::string> added;
  for (int i : s.deformable_bodies) {
    const Material &m = *sc.FindMaterial(sc.bodies[i].material);
    if (std::find(added.begin(), added.end(), m.name) == added.end()) {
      PetscCall(FDEMDeformableAddMaterial(s.dfm, m.name.c_str(), m.young, m.poisson, m.density, m.damping, ModelOf(m.model)));
      const Fracture &F = m.fracture;
      if (F.present) PetscCall(FDEMDeformableSetMaterialFracture(s.dfm, m.name.c_str(), F.tensile_strength, F.cohesion, F.friction_angle, F.GI, F.GII, F.joint_penalty));
      added.push_back(m.name);
    }
    PetscCall(FDEMDeformableSetBodyMaterial(s.dfm, sc.bodies[i].name.c_str(), m.name.c_str()));
    for (const FractureZone &z : sc.bodies[i].fracture_zones) { // world coordinates, as the placed nodes below
      const PetscReal lo[3] = {z.lo.x, z.lo.y, z.lo.z}, hi[3] = {z.hi.x, z.hi.y, z.hi.z};
      PetscCall(FDEMDeformableAddFractureZone(s.dfm, sc.bodies[i].name.c_str(), lo, hi));
    }
    if (m.fracture.present && m.fracture.insert_at > 0) {
      PetscCall(FDEMDeformableSetFractureInsertion(s.dfm, sc.bodies[i].name.c_str(), m.fracture.insert_at));
      s.inserting = true;
    }
  }
  PetscCall(FDEMDeformableAddFractureCells(s.dfm, (PetscInt)fracture_cells.size(), fracture_cells.data()));
  if (previous) PetscCall(FDEMDeformableReuseSetUp(s.dfm, previous));
  const bool root = rank == 0;
  PetscCall(FDEMDeformableSetMesh(s.dfm, root ? s.nnodes : 0, nodes.data(), root ? s.ntets : 0, tets.data(), body.data(), (PetscInt)names.size(), cnames.data()));
  const PetscReal g[3] = {sc.gravity.x, sc.gravity.y, sc.gravity.z};
  PetscCall(FDEMDeformableSetGravity(s.dfm, g));
  PetscCall(FDEMDeformableSetFromOptions(s.dfm));
  PetscCall(FDEMDeformableSetUp(s.dfm));
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  PetscCall(FDEMDeformableFixNodes(s.dfm, root ? (PetscInt)fixed.size() : 0, fixed.data(), &s.nfixed_nodes));
  for (size_t k = 0; k < moved.size(); ++k) { // a node both fixed and moved moves
    const Body &b = sc.bodies[s.deformable_bodies[k]];
    if (!b.moved) continue;
    const PetscReal v[3] = {b.move_velocity.x, b.move_velocity.y, b.move_velocity.z};
    PetscInt        n;
    PetscCall(FDEMDeformableMoveNodes(s.dfm, root ? (PetscInt)moved[k].size() : 0, moved[k].data(), v, &n));
    s.nmoved_nodes += n;
  }
  std::vector<PetscInt> held = fixed;
  for (const auto &m : moved) held.insert(held.end(), m.begin(), m.end());
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  PetscCall(FDEMDeformableSetVelocityField(s.dfm, InitialVelocity, &vf));
  PetscInt njoints;
  PetscCall(FDEMDeformableGetJointStats(s.dfm, &njoints, nullptr, nullptr));
  if (njoints > 0) { // fracturable bodies were split: count the split mesh's nodes (fixed and moved copies too)
    PetscCall(FDEMDeformableGetSizes(s.dfm, nullptr, nullptr, nullptr, &s.nnodes));
    s.ndofs += 3 * (s.nnodes - s.nfixed_nodes - s.nmoved_nodes);
    s.njoints = njoints;
  } else s.ndofs += 3 * (s.nnodes - (PetscInt)held.size());
  if (sc.contact.present && (s.deformable_bodies.size() >= 2 || njoints > 0)) { // the fragments of one fracturable body collide too
    PetscCall(FDEMDeformableContactCreate(s.dfm, &s.dc));
    PetscCall(FDEMDeformableContactSetPenalty(s.dc, sc.contact.penalty));
    PetscCall(FDEMDeformableContactSetDissipation(s.dc, sc.contact.normal_damping, sc.contact.friction, sc.contact.tangential_viscosity));
    if (sc.contact.buffer > 0) PetscCall(FDEMDeformableContactSetBuffer(s.dc, sc.contact.buffer));
    PetscCall(FDEMDeformableContactSetFromOptions(s.dc));
  }
  PetscFunctionReturn(0);
}

} // namespace

double ElementFrequency(const kernels::TetMesh &m, const Material &mat) {
  const double E = mat.young, nu = mat.poisson, cp = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * mat.density));
  double       hmin = 1e300;
  for (const auto &t : m.tets) {
    const Vec3 *p[4] = {&m.nodes[t[0]], &m.nodes[t[1]], &m.nodes[t[2]], &m.nodes[t[3]]};
    const double V    = std::fabs(kernels::TetSignedVolume(*p[0], *p[1], *p[2], *p[3]));
    double       amax = 0;
    for (int f = 0; f < 4; ++f) {
      const Vec3 &a = *p[(f + 1) % 4], &b = *p[(f + 2) % 4], &c = *p[(f + 3) % 4];
      amax          = std::max(amax, 0.5 * norm(cross(b - a, c - a)));
    }
    hmin = std::min(hmin, 3 * V / amax);
  }
  return 2 * cp / hmin;
}

PetscErrorCode SimBuild(MPI_Comm comm, const Scene &sc, std::vector<kernels::TetMesh> meshes, Sim &s, const std::vector<PetscInt> &fracture_cells, FDEMDeformable previous) {
  PetscFunctionBeginUser;
  s.comm   = comm;
  s.scene  = &sc;
  s.meshes = std::move(meshes);
  // the box of every body, placed: the rigid bodies' slab domain
  Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
  for (size_t i = 0; i < sc.bodies.size(); ++i) {
    const Body &b = sc.bodies[i];
    (b.model != "deformable" ? s.rigid_bodies : s.deformable_bodies).push_back((int)i);
    for (const auto &p : s.meshes[i].nodes) {
      const Vec3 q = b.position + b.rotation * p;
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
    }
    if (b.model == "sphere")
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.position[k] - b.shape.radius), hi[k] = std::max(hi[k], b.position[k] + b.shape.radius);
  }
  if (!s.rigid_bodies.empty() && !s.rb) PetscCall(BuildRigid(s, lo, hi)); // (s.rb given: kept)
  if (s.rb) PetscCall(FDEMRigidGetNumBodies(s.rb, nullptr, &s.nrigid));
  for (int i : s.rigid_bodies) s.ndofs += sc.bodies[i].fixed || sc.bodies[i].moved ? 0 : 6;
  PetscCheck(!sc.periodic.Any() || s.deformable_bodies.empty(), comm, PETSC_ERR_USER_INPUT, "%s: periodic boundaries (periodic: at %s) hold rigid bodies and spheres only; body '%s' is deformable (model: auto chose it; give it model: rigid or sphere)",
             s.deformable_bodies.empty() ? sc.file.c_str() : sc.bodies[s.deformable_bodies[0]].where.c_str(),
             sc.periodic.where.c_str(), s.deformable_bodies.empty() ? "" : sc.bodies[s.deformable_bodies[0]].name.c_str());
  if (!s.deformable_bodies.empty()) PetscCall(BuildDeformable(s, fracture_cells, previous));
  PetscCall(FDEMSceneCreate(comm, &s.sc));
  if (s.rb) PetscCall(FDEMSceneSetRigid(s.sc, s.rb));
  if (s.dfm) PetscCall(FDEMSceneSetDeformable(s.sc, s.dfm));
  if (sc.contact.present && s.rb && s.dfm) {
    PetscCall(FDEMSceneSetContact(s.sc, sc.contact.penalty, sc.contact.normal_damping, sc.contact.friction, sc.contact.buffer > 0 ? sc.contact.buffer : -1));
    PetscCall(FDEMSceneSetContactTangentialViscosity(s.sc, sc.contact.tangential_viscosity));
  }
  PetscCall(FDEMSceneSetFromOptions(s.sc));
  PetscFunctionReturn(0);
}

PetscErrorCode SimSetUpTS(Sim &s, const char *scheme, PetscReal t, PetscInt step) {
  PetscFunctionBeginUser;
  PetscCall(TSCreate(s.comm, &s.ts));
  PetscCall(TSSetType(s.ts, scheme));
  PetscCall(FDEMSceneSetUpTS(s.sc, s.ts, &s.U));
  PetscCall(TSSetTime(s.ts, t));
  PetscCall(TSSetStepNumber(s.ts, step));
  PetscFunctionReturn(0);
}

PetscErrorCode SimRestore(Sim &s) {
  PetscFunctionBeginUser;
  PetscCall(FDEMSceneRestoreState(s.sc, s.U));
  PetscFunctionReturn(0);
}

PetscErrorCode SimEndTS(Sim &s) {
  PetscFunctionBeginUser;
  if (s.U) PetscCall(FDEMSceneRestoreState(s.sc, s.U));
  PetscCall(VecDestroy(&s.U));
  PetscCall(TSDestroy(&s.ts));
  PetscFunctionReturn(0);
}

// Rigid bodies migrate wherever the scene is built again (a restart, joints inserted), and at
// the end of an output segment when SimMigrationDue says so.
PetscBool SimNeedsMigration(const Sim &s) { return s.rb ? PETSC_TRUE : PETSC_FALSE; }

// At the end of an output segment (the models holding the TS's state: after SimBalance or SimRestore): whether the rigid bodies are to migrate
// there, ending the TS (FDEMRigidMigrationNeeded: the same steps on every number of ranks).
PetscErrorCode SimMigrationDue(Sim &s, PetscBool *due) {
  PetscFunctionBeginUser;
  *due = PETSC_FALSE;
  if (s.rb) PetscCall(FDEMRigidMigrationNeeded(s.rb, due));
  PetscFunctionReturn(0);
}

PetscErrorCode SimMigrate(Sim &s) {
  PetscFunctionBeginUser;
  if (s.rb) PetscCall(FDEMRigidMigrate(s.rb));
  PetscFunctionReturn(0);
}

PetscErrorCode SimStableStep(Sim &s, const char *scheme, PetscReal safety, StableStep &st) {
  const Scene   &sc = *s.scene;
  FDEMSchemeInfo info;
  PetscBool      found;
  PetscFunctionBeginUser;
  PetscCall(FDEMSchemeInfoFind(scheme, &found, &info));
  PetscCheck(found, s.comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "%s: time.scheme / -ts_type %s is not an fdem scheme", sc.file.c_str(), scheme);
  st.kcrit = info.kcrit;
  st.limit = "nothing (no deformable body, no contact): end / 1000";
  for (int i : s.deformable_bodies) {
    const double w = ElementFrequency(s.meshes[i], *sc.FindMaterial(sc.bodies[i].material));
    if (w > st.omega_elements) {
      st.omega_elements = w;
      st.limit          = "the elements of body '" + sc.bodies[i].name + "' (2 c_p / smallest altitude)";
    }
  }
  // The library's contact checks return omega_c dt / K_crit; asked at a tiny dt they print no warning.
  const PetscReal tiny = 1e-30;
  PetscReal       ratio;
  if (s.rc) {
    PetscCall(FDEMContactCheckTimeStep(s.rc, scheme, tiny, &ratio));
    st.omega_contact = std::max(st.omega_contact, ratio * st.kcrit / tiny);
  }
  if (s.dc) {
    PetscCall(FDEMDeformableContactCheckTimeStep(s.dc, scheme, tiny, &ratio));
    st.omega_contact = std::max(st.omega_contact, ratio * st.kcrit / tiny);
  }
  if (sc.contact.present && s.rb && s.dfm) {
    PetscCall(FDEMSceneCheckTimeStep(s.sc, scheme, tiny, &ratio));
    st.omega_contact = std::max(st.omega_contact, ratio * st.kcrit / tiny);
  }
  if (st.omega_contact > st.omega_elements) st.limit = "contact (the penalty or a granular law against the lightest body or element)";
  if (s.dfm) PetscCall(FDEMDeformableGetJointFrequency(s.dfm, &st.omega_joints));
  if (st.omega_joints > std::max(st.omega_contact, st.omega_elements)) st.limit = "the fracture joints (the joint penalty against the nodal masses)";
  const double w = std::max({st.omega_contact, st.omega_elements, st.omega_joints});
  st.dt          = w > 0 ? safety * st.kcrit / w * (1 - 1e-9) : sc.end / 1000;
  PetscFunctionReturn(0);
}

// The work of the prescribed motions (moved rigid bodies and mesh nodes) so far. Collective.
static PetscErrorCode ExternalWork(Sim &s, PetscReal *W) {
  PetscReal w;
  PetscFunctionBeginUser;
  *W = 0;
  if (s.rb) {
    PetscCall(FDEMRigidGetExternalWork(s.rb, &w));
    *W += w;
  }
  if (s.dfm) {
    PetscCall(FDEMDeformableGetExternalWork(s.dfm, &w));
    *W += w;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SimBalance(Sim &s, Balance &b) {
  PetscReal                  E[4];
  FDEMDeformableContactStats dc{};
  PetscFunctionBeginUser;
  if (s.dc) PetscCall(FDEMDeformableContactGetStats(s.dc, &dc));
  PetscCall(FDEMSceneGetInvariants(s.sc, s.U, b.t, b.P, b.L, E)); // also copies U into the models
  b.kinetic = E[0] + E[1];
  b.strain  = E[2];
  b.contact = E[3];
  b.gravity = 0;
  if (s.rc) {
    FDEMContactStats st;
    PetscCall(FDEMContactGetStats(s.rc, &st));
    b.contact += st.energy;
  }
  if (s.dc) {
    // the invariants evaluate the mesh's force hooks at U where the scene has rigid-deformable
    // contact, and the deformable contact is one of them: its energy is that evaluation's
    const PetscInt evaluations = dc.evaluations;
    PetscCall(FDEMDeformableContactGetStats(s.dc, &dc));
    if (dc.evaluations == evaluations) PetscCall(FDEMDeformableContactComputeEnergy(s.dc, nullptr, &dc.energy));
    b.contact += dc.energy;
  }
  if (s.dfm) {
    PetscReal g, stored;
    PetscCall(FDEMDeformableGetEnergy(s.dfm, nullptr, nullptr, nullptr, &g)); // (the rest came with the invariants)
    PetscCall(FDEMDeformableGetJointEnergy(s.dfm, nullptr, &stored, &b.fracture));
    b.gravity += g;
    b.strain += stored; // the joints' recoverable energy is strain energy of the body
  }
  if (s.rb) {
    DM         sw;
    PetscInt   n, *fixed;
    PetscReal *x, *m, loc = 0, glob;
    const Vec3 g = s.scene->gravity;
    PetscCall(FDEMRigidGetDM(s.rb, &sw));
    PetscCall(DMSwarmGetLocalSize(sw, &n));
    PetscCall(DMSwarmGetField(sw, "x", nullptr, nullptr, (void **)&x));
    PetscCall(DMSwarmGetField(sw, "mass", nullptr, nullptr, (void **)&m));
    PetscCall(DMSwarmGetField(sw, "fixed", nullptr, nullptr, (void **)&fixed));
    PetscReal *v, plo[3], phi[3];
    PetscInt  *image;
    PetscCall(FDEMRigidGetPeriodic(s.rb, nullptr, plo, phi));
    PetscCall(DMSwarmGetField(sw, "v", nullptr, nullptr, (void **)&v));
    PetscCall(DMSwarmGetField(sw, "image", nullptr, nullptr, (void **)&image));
    for (PetscInt i = 0; i < n; ++i) // moving and moved bodies (a moved body is fixed with v != 0), at their unwrapped centres
      if (!fixed[i] || v[3 * i] != 0 || v[3 * i + 1] != 0 || v[3 * i + 2] != 0) {
        PetscReal u[3];
        for (int k = 0; k < 3; ++k) u[k] = x[3 * i + k] + image[3 * i + k] * (phi[k] - plo[k]);
        loc -= m[i] * (g.x * u[0] + g.y * u[1] + g.z * u[2]);
      }
    PetscCall(DMSwarmRestoreField(sw, "image", nullptr, nullptr, (void **)&image));
    PetscCall(DMSwarmRestoreField(sw, "v", nullptr, nullptr, (void **)&v));
    PetscCall(DMSwarmRestoreField(sw, "fixed", nullptr, nullptr, (void **)&fixed));
    PetscCall(DMSwarmRestoreField(sw, "mass", nullptr, nullptr, (void **)&m));
    PetscCall(DMSwarmRestoreField(sw, "x", nullptr, nullptr, (void **)&x));
    PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPIU_REAL, MPI_SUM, s.comm));
    b.gravity += glob;
  }
  PetscCall(ExternalWork(s, &b.external_work));
  b.total = b.kinetic + b.strain + b.contact + b.gravity + b.fracture;
  if (!s.have_E0) {
    s.E0      = b.total;
    s.have_E0 = true;
  }
  b.dissipated = s.E0 + b.external_work - b.total;
  PetscFunctionReturn(0);
}

PetscErrorCode SimWriteOutput(Sim &s, const std::string &dir, PetscInt step, PetscReal t) {
  PetscFunctionBeginUser;
  if (s.rb) PetscCall(FDEMRigidWriteHDF5(s.rb, (dir + "/rigid").c_str(), step, t));
  if (s.dfm) PetscCall(FDEMDeformableWriteHDF5(s.dfm, nullptr, (dir + "/mesh").c_str(), step, t));
  PetscFunctionReturn(0);
}


namespace {
// Scatter between a vector in the models' layout, `width` entries per item (local item i's id
// ids[i]), and the vector by id (`nat`, created here of global size width N: item id's entries
// at width id, ..., width id + width - 1).
PetscErrorCode ByIdScatter(MPI_Comm comm, Vec local, const PetscInt *ids, PetscInt n, PetscInt width, PetscInt N, Vec *nat, VecScatter *sc) {
  IS       from, to;
  PetscInt lo;
  PetscFunctionBeginUser;
  PetscCall(VecCreateMPI(comm, PETSC_DECIDE, width * N, nat));
  // the entries in the order of their ids, both sides (PETSc sorts the other side's otherwise):
  // the items sorted, each one's entries in turn
  std::vector<PetscInt> item(n), order(width * n), sorted(width * n);
  PetscCall(VecGetOwnershipRange(local, &lo, nullptr));
  std::iota(item.begin(), item.end(), 0);
  std::sort(item.begin(), item.end(), [&](PetscInt a, PetscInt b) { return ids[a] < ids[b]; });
  for (PetscInt i = 0; i < n; ++i)
    for (PetscInt k = 0; k < width; ++k) sorted[width * i + k] = width * ids[item[i]] + k, order[width * i + k] = lo + width * item[i] + k;
  PetscCall(ISCreateGeneral(comm, (PetscInt)order.size(), order.data(), PETSC_COPY_VALUES, &from));
  PetscCall(ISCreateGeneral(comm, (PetscInt)sorted.size(), sorted.data(), PETSC_COPY_VALUES, &to));
  PetscCall(VecScatterCreate(local, from, *nat, to, sc));
  PetscCall(ISDestroy(&from));
  PetscCall(ISDestroy(&to));
  PetscFunctionReturn(0);
}

// The mesh's x and v by node id (3 per node), and the rigid state [x R v H] by body id (18 per body):
// one by-id vector per part, in the models' layout `lx` (created here) with its scatter.
// With spheres, also the rigid bodies' tangential-spring slots by body id (kSprings doubles each:
// the swarm field "history", its bytes copied as they are).
constexpr PetscInt kSprings = 48;
// And the periods each body crossed and its partition weight (the swarm fields "image", "work").
struct Parts {
  Vec        dx = nullptr, dv = nullptr, r = nullptr, ndx = nullptr, ndv = nullptr, nr = nullptr, h = nullptr, nh = nullptr, g = nullptr, ng = nullptr;
  VecScatter sd = nullptr, sr = nullptr, sh = nullptr, sg = nullptr;
  PetscErrorCode Destroy() {
    PetscFunctionBeginUser;
    PetscCall(VecDestroy(&g));
    PetscCall(VecDestroy(&ng));
    PetscCall(VecScatterDestroy(&sg));
    PetscCall(VecDestroy(&h));
    PetscCall(VecDestroy(&nh));
    PetscCall(VecScatterDestroy(&sh));
    PetscCall(VecDestroy(&r));
    PetscCall(VecDestroy(&ndx));
    PetscCall(VecDestroy(&ndv));
    PetscCall(VecDestroy(&nr));
    PetscCall(VecScatterDestroy(&sd));
    PetscCall(VecScatterDestroy(&sr));
    PetscFunctionReturn(0);
  }
};

// (rigid false: the deformable model's parts only)
PetscErrorCode MakeParts(Sim &s, Parts &p, bool rigid = true) {
  PetscFunctionBeginUser;
  if (s.dfm) {
    PetscInt        n;
    const PetscInt *ids;
    PetscCall(FDEMDeformableGetPositions(s.dfm, &p.dx));
    PetscCall(FDEMDeformableGetVelocities(s.dfm, &p.dv));
    PetscCall(FDEMDeformableGetNodeIds(s.dfm, &n, &ids));
    PetscCall(ByIdScatter(s.comm, p.dx, ids, n, 3, s.nnodes, &p.ndx, &p.sd));
    PetscCall(VecDuplicate(p.ndx, &p.ndv));
    PetscCall(PetscObjectSetName((PetscObject)p.ndx, "mesh_x"));
    PetscCall(PetscObjectSetName((PetscObject)p.ndv, "mesh_v"));
  }
  if (s.rb && rigid) {
    DM        sw;
    PetscInt  n, *id;
    PetscCall(FDEMRigidGetDM(s.rb, &sw));
    PetscCall(DMSwarmGetLocalSize(sw, &n));
    PetscCall(DMSwarmGetField(sw, "id", nullptr, nullptr, (void **)&id));
    const std::vector<PetscInt> ids(id, id + n);
    PetscCall(DMSwarmRestoreField(sw, "id", nullptr, nullptr, (void **)&id));
    // `width` numbers per body: the local vector (bodies in the swarm's order) and the one by id
    auto part = [&](PetscInt width, const char *name, Vec *local, Vec *nat, VecScatter *sc) -> PetscErrorCode {
      PetscCall(VecCreateMPI(s.comm, width * n, PETSC_DETERMINE, local));
      PetscCall(ByIdScatter(s.comm, *local, ids.data(), n, width, s.nrigid, nat, sc));
      PetscCall(PetscObjectSetName((PetscObject)*nat, name));
      return 0;
    };
    PetscCall(part(18, "rigid_xRvH", &p.r, &p.nr, &p.sr));
    bool spheres = false;
    for (int i : s.rigid_bodies) spheres = spheres || s.scene->bodies[i].Granular();
    if (spheres) PetscCall(part(kSprings, "rigid_springs", &p.h, &p.nh, &p.sh));
    PetscCall(part(4, "rigid_image_work", &p.g, &p.ng, &p.sg));
  }
  PetscFunctionReturn(0);
}

// Copies the swarm's image counts and partition weights (4 per body) into g (to_vec) or back:
// a restart then crosses the same periods and cuts the same partition as the straight run.
PetscErrorCode RigidImagesWork(Sim &s, Vec g, bool to_vec) {
  DM           sw;
  PetscInt     n, *f;
  PetscReal   *w;
  PetscScalar *a;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetDM(s.rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(VecGetArray(g, &a));
  PetscCall(DMSwarmGetField(sw, "image", nullptr, nullptr, (void **)&f));
  PetscCall(DMSwarmGetField(sw, "work", nullptr, nullptr, (void **)&w));
  for (PetscInt b = 0; b < n; ++b) {
    for (int k = 0; k < 3; ++k) {
      if (to_vec) a[4 * b + k] = (PetscScalar)f[3 * b + k];
      else f[3 * b + k] = (PetscInt)std::llround(PetscRealPart(a[4 * b + k]));
    }
    if (to_vec) a[4 * b + 3] = w[b];
    else w[b] = PetscRealPart(a[4 * b + 3]);
  }
  PetscCall(DMSwarmRestoreField(sw, "work", nullptr, nullptr, (void **)&w));
  PetscCall(DMSwarmRestoreField(sw, "image", nullptr, nullptr, (void **)&f));
  PetscCall(VecRestoreArray(g, &a));
  PetscFunctionReturn(0);
}

// Copies the swarm's spring slots into h (to_vec) or back, bit for bit.
PetscErrorCode RigidSprings(Sim &s, Vec h, bool to_vec) {
  DM           sw;
  PetscInt     n;
  char        *f;
  PetscScalar *a;
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetDM(s.rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(VecGetArray(h, &a));
  PetscCall(DMSwarmGetField(sw, "history", nullptr, nullptr, (void **)&f));
  if (to_vec) std::memcpy(a, f, sizeof(PetscScalar) * kSprings * (size_t)n);
  else std::memcpy(f, a, sizeof(PetscScalar) * kSprings * (size_t)n);
  PetscCall(DMSwarmRestoreField(sw, "history", nullptr, nullptr, (void **)&f));
  PetscCall(VecRestoreArray(h, &a));
  PetscFunctionReturn(0);
}

// Copies the swarm's x, R, v, H into r (to_vec) or back.
PetscErrorCode RigidFields(Sim &s, Vec r, bool to_vec) {
  DM           sw;
  PetscInt     n;
  PetscReal   *f[4];
  PetscScalar *a;
  const char  *names[4] = {"x", "R", "v", "H"};
  const int    width[4] = {3, 9, 3, 3};
  PetscFunctionBeginUser;
  PetscCall(FDEMRigidGetDM(s.rb, &sw));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(VecGetArray(r, &a));
  for (int k = 0; k < 4; ++k) PetscCall(DMSwarmGetField(sw, names[k], nullptr, nullptr, (void **)&f[k]));
  for (PetscInt b = 0; b < n; ++b)
    for (int k = 0, o = 0; k < 4; o += width[k], ++k)
      for (int c = 0; c < width[k]; ++c) {
        if (to_vec) a[18 * b + o + c] = f[k][width[k] * b + c];
        else f[k][width[k] * b + c] = a[18 * b + o + c];
      }
  for (int k = 0; k < 4; ++k) PetscCall(DMSwarmRestoreField(sw, names[k], nullptr, nullptr, (void **)&f[k]));
  PetscCall(VecRestoreArray(r, &a));
  PetscFunctionReturn(0);
}

// Moves the state between the models and its natural order (by node and body id, the layout
// of a checkpoint): `to` the natural vectors (the deformable nodes' x and v, the rigid bodies'
// fields, springs, images and work), or back from them, the springs only with has_h and the
// images with has_g (a checkpoint written before they were kept has none).
PetscErrorCode Natural(Sim &s, Parts &p, bool to, bool has_h = true, bool has_g = true) {
  const auto move = [to](VecScatter sc, Vec local, Vec nat) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(VecScatterBegin(sc, to ? local : nat, to ? nat : local, INSERT_VALUES, to ? SCATTER_FORWARD : SCATTER_REVERSE));
    PetscCall(VecScatterEnd(sc, to ? local : nat, to ? nat : local, INSERT_VALUES, to ? SCATTER_FORWARD : SCATTER_REVERSE));
    PetscFunctionReturn(0);
  };
  // a rigid part: the swarm's fields copied into `local` (fill), then moved
  const auto part = [&](PetscErrorCode (*fill)(Sim &, Vec, bool), VecScatter sc, Vec local, Vec nat) -> PetscErrorCode {
    PetscFunctionBeginUser;
    if (to) PetscCall(fill(s, local, true));
    PetscCall(move(sc, local, nat));
    if (!to) PetscCall(fill(s, local, false));
    PetscFunctionReturn(0);
  };
  PetscFunctionBeginUser;
  if (s.dfm) {
    PetscCall(move(p.sd, p.dx, p.ndx));
    PetscCall(move(p.sd, p.dv, p.ndv));
  }
  if (p.r) {
    PetscCall(part(RigidFields, p.sr, p.r, p.nr));
    if (p.h && has_h) PetscCall(part(RigidSprings, p.sh, p.h, p.nh));
    if (p.g && has_g) PetscCall(part(RigidImagesWork, p.sg, p.g, p.ng));
  }
  PetscFunctionReturn(0);
}

// The energy reference, the external work so far (on the deformable model when there is one)
// and, for a rebuild, that the reference is known.
PetscErrorCode SetClock(Sim &s, PetscReal E0, PetscReal W) {
  PetscFunctionBeginUser;
  if (s.rb) PetscCall(FDEMRigidSetExternalWork(s.rb, s.dfm ? 0 : W));
  if (s.dfm) PetscCall(FDEMDeformableSetExternalWork(s.dfm, W));
  s.E0      = E0;
  s.have_E0 = true;
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode SimWriteCheckpoint(Sim &s, const char *file, PetscReal t, PetscInt step, PetscReal dt) {
  Parts       p;
  PetscViewer v;
  Vec         meta;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCall(MakeParts(s, p));
  PetscCall(Natural(s, p, true));
  PetscCall(PetscViewerHDF5Open(s.comm, file, FILE_MODE_WRITE, &v));
  if (s.dfm) {
    PetscCall(VecView(p.ndx, v));
    PetscCall(VecView(p.ndv, v));
    PetscCall(FDEMDeformableViewJointState(s.dfm, v));
  }
  if (s.rb) {
    PetscCall(VecView(p.nr, v));
    if (p.h) PetscCall(VecView(p.nh, v));
    if (p.g) PetscCall(VecView(p.ng, v));
  }
  PetscReal W;
  PetscCall(ExternalWork(s, &W));
  PetscCall(VecCreateMPI(s.comm, rank == 0 ? 5 : 0, 5, &meta));
  PetscCall(PetscObjectSetName((PetscObject)meta, "meta_t_step_E0_dt_W"));
  if (rank == 0) {
    PetscCall(VecSetValue(meta, 0, t, INSERT_VALUES));
    PetscCall(VecSetValue(meta, 1, (PetscReal)step, INSERT_VALUES));
    PetscCall(VecSetValue(meta, 2, s.E0, INSERT_VALUES));
    PetscCall(VecSetValue(meta, 3, dt, INSERT_VALUES));
    PetscCall(VecSetValue(meta, 4, W, INSERT_VALUES));
  }
  PetscCall(VecAssemblyBegin(meta));
  PetscCall(VecAssemblyEnd(meta));
  PetscCall(VecView(meta, v));
  PetscCall(VecDestroy(&meta));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(p.Destroy());
  PetscFunctionReturn(0);
}

PetscErrorCode SimReadCheckpoint(Sim &s, const char *file, PetscReal *t, PetscInt *step, PetscReal *dt) {
  Parts       p;
  PetscViewer v;
  Vec         meta;
  PetscBool   has_h = PETSC_FALSE, has_g = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(MakeParts(s, p));
  PetscCall(PetscViewerHDF5Open(s.comm, file, FILE_MODE_READ, &v));
  if (s.dfm) {
    PetscCall(FDEMDeformableLoadNodeVector(s.dfm, v, p.ndx)); // (into a larger split after an insertion)
    PetscCall(FDEMDeformableLoadNodeVector(s.dfm, v, p.ndv));
    PetscCall(FDEMDeformableLoadJointState(s.dfm, v));
  }
  if (s.rb) {
    PetscCall(VecLoad(p.nr, v));
    if (p.h) PetscCall(PetscViewerHDF5HasDataset(v, "/rigid_springs", &has_h));
    if (has_h) PetscCall(VecLoad(p.nh, v)); // (a checkpoint written before the springs were kept has none: they start from zero)
    if (p.g) PetscCall(PetscViewerHDF5HasDataset(v, "/rigid_image_work", &has_g));
    if (has_g) PetscCall(VecLoad(p.ng, v));
  }
  PetscCall(Natural(s, p, false, has_h, has_g));
  PetscMPIInt rank0;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank0));
  PetscCall(VecCreateMPI(s.comm, rank0 == 0 ? 5 : 0, 5, &meta)); // all on rank 0
  PetscCall(PetscObjectSetName((PetscObject)meta, "meta_t_step_E0_dt_W"));
  PetscCall(VecLoad(meta, v));
  {
    const PetscScalar *m;
    PetscReal          buf[5] = {0, 0, 0, 0, 0};
    PetscInt           lo;
    PetscCall(VecGetOwnershipRange(meta, &lo, nullptr));
    PetscCall(VecGetArrayRead(meta, &m));
    if (lo == 0) {
      PetscInt nl;
      PetscCall(VecGetLocalSize(meta, &nl));
      for (PetscInt i = 0; i < nl && i < 5; ++i) buf[i] = m[i];
    }
    PetscCall(VecRestoreArrayRead(meta, &m));
    PetscCallMPI(MPI_Bcast(buf, 5, MPIU_REAL, 0, s.comm));
    PetscCall(SetClock(s, buf[2], buf[4]));
    *dt   = buf[3];
    *t    = buf[0];
    *step = (PetscInt)std::llround(buf[1]);
  }
  PetscCall(VecDestroy(&meta));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(p.Destroy());
  if (s.rb) PetscCall(FDEMRigidMigrate(s.rb));
  PetscFunctionReturn(0);
}

// What SimWriteCheckpoint of `from` and SimReadCheckpoint into `to` do for the deformable model,
// without the file: `to` is `from`'s scene built again with more joints around the same rigid
// bodies' model (kept as it is, its state in it).
static PetscErrorCode SimContinueState(Sim &to, Sim &from) {
  Parts     a, b;
  PetscReal W;
  PetscFunctionBeginUser;
  PetscCheck(to.rb == from.rb, to.comm, PETSC_ERR_PLIB, "SimContinueState: the rigid bodies' model is kept");
  PetscCall(MakeParts(from, a, false));
  PetscCall(MakeParts(to, b, false));
  PetscCall(Natural(from, a, true));
  if (to.dfm) {
    PetscCall(FDEMDeformableContinueNodeVector(to.dfm, from.dfm, a.ndx, b.ndx));
    PetscCall(FDEMDeformableContinueNodeVector(to.dfm, from.dfm, a.ndv, b.ndv));
    PetscCall(FDEMDeformableContinueJointState(to.dfm, from.dfm));
  }
  PetscCall(Natural(to, b, false));
  PetscCall(ExternalWork(from, &W));
  PetscCall(SetClock(to, from.E0, W));
  PetscCall(a.Destroy());
  PetscCall(b.Destroy());
  PetscFunctionReturn(0);
}

PetscErrorCode SimReadFractureCells(MPI_Comm comm, const char *file, std::vector<PetscInt> &cells) {
  PetscViewer v;
  PetscInt    n, *c;
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(comm, file, FILE_MODE_READ, &v));
  PetscCall(FDEMDeformableReadFractureCells(comm, v, &n, &c));
  cells.assign(c, c + n);
  PetscCall(PetscFree(c));
  PetscCall(PetscViewerDestroy(&v));
  PetscFunctionReturn(0);
}

PetscErrorCode SimFindCellsToSplit(Sim &s, std::vector<PetscInt> &cells) {
  PetscInt n = 0, *c = nullptr;
  PetscFunctionBeginUser;
  cells.clear();
  if (!s.inserting) PetscFunctionReturn(0);
  PetscCall(FDEMDeformableFindCellsToSplit(s.dfm, nullptr, &n, &c));
  cells.assign(c, c + n);
  PetscCall(PetscFree(c));
  PetscFunctionReturn(0);
}

PetscErrorCode SimInsertJoints(Sim &s, const std::vector<PetscInt> &cells) {
  Sim             n;
  PetscInt        nc;
  const PetscInt *have;
  PetscFunctionBeginUser;
  PetscCall(FDEMDeformableGetFractureCells(s.dfm, &nc, &have));
  std::vector<PetscInt> all(have, have + nc);
  all.insert(all.end(), cells.begin(), cells.end());
  PetscBool given; // the bodies' overlaps were made by the run, as at a restart
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-fdem_contact_initial_overlap_check", &given));
  if (!given) PetscCall(PetscOptionsSetValue(nullptr, "-fdem_contact_initial_overlap_check", "false"));
  // the rigid bodies do not change: their model and contact go on as they are (their cost then
  // does not grow with the number of rigid bodies), with the new deformable model and scene
  n.rb = s.rb;
  n.rc = s.rc;
  PetscCall(SimBuild(s.comm, *s.scene, s.meshes, n, all, s.dfm));
  if (n.dfm) PetscCall(FDEMDeformableContinueOutput(n.dfm, s.dfm));
  PetscCall(SimContinueState(n, s));
  s.rb = nullptr;
  s.rc = nullptr;
  PetscCall(SimDestroy(s));
  s = std::move(n);
  PetscFunctionReturn(0);
}

PetscErrorCode SimDestroy(Sim &s) {
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&s.U));
  PetscCall(TSDestroy(&s.ts));
  PetscCall(FDEMSceneDestroy(&s.sc));
  if (s.dc) PetscCall(FDEMDeformableContactDestroy(&s.dc));
  if (s.rc) PetscCall(FDEMContactDestroy(&s.rc));
  if (s.dfm) PetscCall(FDEMDeformableDestroy(&s.dfm));
  if (s.rb) PetscCall(FDEMRigidDestroy(&s.rb));
  PetscFunctionReturn(0);
}

std::string RigidBodyName(const Sim &s, PetscInt id) {
  if (id >= 0 && id < (PetscInt)s.rigid_bodies.size()) return s.scene->bodies[s.rigid_bodies[id]].name;
  return "?";
}

} // namespace fdem::driver
