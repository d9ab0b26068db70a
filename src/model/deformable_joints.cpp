// Deformable bodies, fracture joints (doc/fracture.md): the bodies of a
// fracturable material are split at set-up (every tetrahedron its own nodes,
// or only those in the body's fracture zones; a joint on every face a split
// tetrahedron shares with another of its body); each joint is computed by the
// rank that holds its tetrahedron a, which reads triangle b's nodes in place
// when they are on that rank too, and otherwise gets their coordinates through
// a PetscSF and returns their forces through it.
#include "../util/guard.hpp"
#include "deformable_impl.hpp"
#include "deformable_object.hpp"

#include <fdem/kernels/error.hpp>
#include <fdem/kernels/gather.hpp>
#include <fdem/ts.h>
#include <petscsf.h>
#include <petscviewerhdf5.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cmath>
#include <functional>
#include <string>
#include <unordered_map>

using namespace fdem::model::deformable;
using fdem::kernels::JointLaw;
using fdem::kernels::norm;

static_assert(sizeof(JointLaw) == 14 * sizeof(double), "JointLaw is sent as its first 13 doubles; face_compression is set on each rank");

// The element size of a joint's law: the mean edge of its triangle.
static double JointSize(const fdem::kernels::SplitMesh &f, const fdem::kernels::JointFace &j) {
  const auto &x = f.mesh.nodes;
  return (norm(x[j.a[1]] - x[j.a[0]]) + norm(x[j.a[2]] - x[j.a[1]]) + norm(x[j.a[0]] - x[j.a[2]])) / 3;
}

// The joints' largest frequency in the split f, estimated node by node: a joint point of area
// A/3 is a spring of stiffness p (A/3) / h (the law's slope at zero opening or slip, p / h per
// area) between a node pair of the two sides, half of it on each of its edge's nodes; a node
// of mass m tied by springs of total stiffness K to its twins has omega^2 <= 2 K / m (the row
// sum of its stiffness, Gershgorin).
static double JointFrequency(FDEMDeformable d, const std::vector<int> &mob, const fdem::kernels::SplitMesh &f) {
  std::vector<double> K(f.mesh.nodes.size(), 0.0), m(f.mesh.nodes.size(), 0.0);
  for (std::size_t t = 0; t < f.mesh.tets.size(); ++t) {
    const double q = d->materials[mob[f.mesh.body[t]]].rho * std::fabs(fdem::kernels::TetSignedVolume(f.mesh, (int)t)) / 4;
    for (int n : f.mesh.tets[t]) m[n] += q;
  }
  for (const auto &J : f.joints) {
    const auto  &x = f.mesh.nodes;
    const double A = 0.5 * norm(fdem::kernels::cross(x[J.a[1]] - x[J.a[0]], x[J.a[2]] - x[J.a[0]]));
    const double p = d->fracture.at(d->materials[mob[f.mesh.body[J.tet_a]]].name).penalty;
    const double k = p * (A / 3) / JointSize(f, J); // per point; a node gets two halves
    for (int i = 0; i < 3; ++i) {
      K[J.a[i]] += k;
      K[J.b[i]] += k;
    }
  }
  double w2 = 0;
  for (std::size_t i = 0; i < K.size(); ++i)
    if (K[i] > 0 && m[i] > 0) w2 = std::fmax(w2, 2 * K[i] / m[i]);
  return std::sqrt(w2);
}

void fdem::model::deformable::SplitFracturable(FDEMDeformable d, const std::vector<int> &mob) {
  d->split_parent.clear();
  d->split_tet.clear();
  d->split_boundary.clear();
  d->joints_input.clear();
  d->laws_input.clear();
  if (d->fracture.empty()) return;
  std::vector<char> split(mob.size(), 0);
  bool              any = false;
  for (std::size_t b = 0; b < mob.size(); ++b) any |= (split[b] = d->fracture.count(d->materials[mob[b]].name) > 0);
  // fracture zones: a body with zones is split only at the tetrahedra whose centroids lie in one
  // (one pass over the tetrahedra, each testing its own body's zones)
  std::vector<char>                                          in_zone;
  std::vector<const std::vector<std::array<double, 6>> *>   zones(mob.size(), nullptr);
  std::vector<std::vector<long long>>                        held(mob.size());
  // the fracturable body a zone or an insertion names (what: the call and what the body has)
  auto fracturable_body = [&](const std::string &name, const char *api, const char *has) {
    const auto &names = d->mesh.body_names;
    const int   b     = (int)(std::find(names.begin(), names.end(), name) - names.begin());
    if (b == (int)names.size()) {
      std::string list;
      for (const auto &n : names) list += (list.empty() ? "" : ", ") + n;
      throw fdem::kernels::InputError(std::string(api) + " names body '" + name + "', which is not in the mesh (its bodies: " + list + ")");
    }
    if (!split[b])
      throw fdem::kernels::InputError("body '" + name + "' has " + has + ", but its material '" + d->materials[mob[b]].name + "' is not fracturable (give the material fracture properties: FDEMDeformableSetMaterialFracture)");
    return b;
  };
  for (const auto &kv : d->fracture_zones) {
    const int b = fracturable_body(kv.first, "FDEMDeformableAddFractureZone", "a fracture zone");
    zones[b]    = &kv.second;
    held[b].assign(kv.second.size(), 0);
  }
  // bodies with joints inserted during a run: split only in their zones (if any) and at the
  // tetrahedra inserted so far
  std::vector<char> inserting(mob.size(), 0);
  for (const auto &kv : d->insertion) inserting[fracturable_body(kv.first, "FDEMDeformableSetFractureInsertion", "joints inserted during the run")] = 1;
  for (PetscInt t : d->inserted) {
    if (t < 0 || t >= (PetscInt)d->mesh.tets.size()) throw fdem::kernels::InputError("FDEMDeformableAddFractureCells: tetrahedron " + std::to_string(t) + " is not in the mesh (" + std::to_string(d->mesh.tets.size()) + " tetrahedra)");
    if (!inserting[d->mesh.body[t]]) throw fdem::kernels::InputError("FDEMDeformableAddFractureCells: tetrahedron " + std::to_string(t) + " is in body '" + d->mesh.body_names[d->mesh.body[t]] + "', which has no joints inserted during the run (FDEMDeformableSetFractureInsertion)");
  }
  if (!d->fracture_zones.empty() || !d->insertion.empty()) {
    in_zone.assign(d->mesh.tets.size(), 1);
    for (std::size_t t = 0; t < d->mesh.tets.size(); ++t) {
      const int b = d->mesh.body[t];
      if (inserting[b] && !zones[b]) in_zone[t] = 0;
      if (!zones[b]) continue;
      fdem::kernels::Vec3 c;
      for (int n : d->mesh.tets[t]) c = c + 0.25 * d->mesh.nodes[n];
      in_zone[t] = 0;
      for (std::size_t z = 0; z < zones[b]->size(); ++z) {
        const auto &Z  = (*zones[b])[z];
        const bool  in = c.x >= Z[0] && c.x <= Z[3] && c.y >= Z[1] && c.y <= Z[4] && c.z >= Z[2] && c.z <= Z[5];
        held[b][z] += in;
        in_zone[t] = in_zone[t] || in;
      }
    }
    for (std::size_t b = 0; b < mob.size(); ++b)
      for (std::size_t z = 0; z < held[b].size(); ++z)
        if (!held[b][z]) {
          const auto &Z = (*zones[b])[z];
          throw fdem::kernels::InputError("body '" + d->mesh.body_names[b] + "': fracture zone " + std::to_string(z) + " [" + std::to_string(Z[0]) + ", " + std::to_string(Z[1]) + ", " + std::to_string(Z[2]) + "] to [" + std::to_string(Z[3]) + ", " +
                                          std::to_string(Z[4]) + ", " + std::to_string(Z[5]) + "] holds the centroid of none of its tetrahedra");
        }
  }
  if (!any) return;
  std::shared_ptr<fdem::model::deformable::InsertionInput> made; // (made here, not reused)
  if (!d->insertion.empty()) { // kept to find the split of a checkpoint written before some insertion
    d->split_body = split;
    d->box_split  = in_zone;
    for (PetscInt t : d->inserted) in_zone[t] = 1;
    d->tet_split = in_zone;
    // what the joints' frequency and the check of the joints that may come depend on besides
    // the mesh: per body its material's density and fracture properties, whether it is
    // fracturable and inserts joints; the zones' tetrahedra
    std::vector<double> key;
    for (std::size_t b = 0; b < mob.size(); ++b) {
      const fdem::kernels::JointMaterial J = split[b] ? d->fracture.at(d->materials[mob[b]].name) : fdem::kernels::JointMaterial{};
      key.insert(key.end(), {(double)split[b], (double)inserting[b], d->materials[mob[b]].rho, J.tensile_strength, J.cohesion, J.friction_angle, J.GI, J.GII, J.penalty});
    }
    for (char z : d->box_split) key.push_back(z);
    if (d->reuse && SameInput(*d->reuse, key, d->mesh)) d->insertion_input = d->reuse; // a model of this mesh and scene made it
    else {
      made           = std::make_shared<fdem::model::deformable::InsertionInput>();
      made->mesh     = d->mesh;
      made->key      = key;
      made->splitter = std::make_unique<fdem::kernels::JointSplitter>(made->mesh, split); // (the faces sorted once for every split of this mesh)
      d->insertion_input = made;
    }
    d->reuse.reset();
  }
  fdem::kernels::SplitMesh s = d->insertion_input ? d->insertion_input->splitter->Split(in_zone) : fdem::kernels::SplitForJoints(d->mesh, split, in_zone);
  d->laws_input.reserve(s.joints.size());
  for (const auto &j : s.joints) {
    const int   b   = s.mesh.body[j.tet_a];
    const auto &mat = d->fracture.at(d->materials[mob[b]].name);
    try {
      d->laws_input.push_back(fdem::kernels::MakeJointLaw(mat, JointSize(s, j)));
    } catch (const fdem::kernels::InputError &e) {
      throw fdem::kernels::InputError("body '" + s.mesh.body_names[b] + "', the joint between elements " + std::to_string(j.tet_a) + " and " + std::to_string(j.tet_b) + ": " + e.what());
    }
  }
  // The joints' largest frequency. With joints inserted during the run, the estimate is that
  // of the bodies split wherever joints may come (the time step is chosen at the start), and
  // every joint that may come must have a valid law (checked now, not during the run); a model
  // of the same input mesh, materials and insertion bodies made both already.
  if (d->insertion.empty()) d->joint_omega = JointFrequency(d, mob, s);
  else if (!made) d->joint_omega = d->insertion_input->joint_omega;
  else {
    std::vector<char> all = in_zone;
    for (std::size_t t = 0; t < all.size(); ++t) all[t] = all[t] || inserting[d->mesh.body[t]];
    const fdem::kernels::SplitMesh full = made->splitter->Split(all);
    for (const auto &j : full.joints) {
      const int b = full.mesh.body[j.tet_a];
      try {
        (void)fdem::kernels::MakeJointLaw(d->fracture.at(d->materials[mob[b]].name), JointSize(full, j));
      } catch (const fdem::kernels::InputError &e) {
        throw fdem::kernels::InputError("body '" + full.mesh.body_names[b] + "', the joint that insertion would make between elements " + std::to_string(j.tet_a) + " and " + std::to_string(j.tet_b) + ": " + e.what());
      }
    }
    d->joint_omega = made->joint_omega = JointFrequency(d, mob, full);
  }
  if (!d->insertion.empty()) {
    auto r      = std::make_shared<fdem::model::deformable::SplitRecord>();
    r->inserted = d->inserted;
    r->tets     = s.mesh.tets;
    r->parent   = s.parent;
    r->joints   = s.joints;
    d->own_split = std::move(r);
  }
  d->mesh         = std::move(s.mesh);
  d->split_parent = std::move(s.parent);
  d->split_tet    = std::move(s.split);
  d->split_boundary = std::move(s.boundary);
  d->joints_input = std::move(s.joints);
}

PetscErrorCode fdem::model::deformable::SetUpJoints(FDEMDeformable d) {
  PetscFunctionBegin;
  PetscInt sizes[3] = {d->rank == 0 ? (PetscInt)d->joints_input.size() : 0, d->rank == 0 ? (PetscInt)d->split_parent.size() : 0, d->rank == 0 ? (PetscInt)(!d->fracture_zones.empty() || !d->insertion.empty()) : 0};
  PetscCallMPI(MPI_Bcast(sizes, 3, MPIU_INT, 0, d->comm));
  const PetscInt nj = sizes[0];
  d->zoned          = sizes[2] != 0;
  d->njoints_global = nj;
  PetscBool prestress = PETSC_TRUE; // joints inserted under load start with their faces' forces
  PetscBool face = PETSC_TRUE; // the compression over the face (doc/fracture.md, "One joint element")
  PetscOptionsBegin(d->comm, nullptr, "fdem fracture joints", "FDEMDeformable");
  PetscCall(PetscOptionsBool("-fdem_insert_prestress", "Joints inserted during a run (insert_at) start with the forces their faces carried, balanced so that the copies of each node move together, and the insertion does not release the stress (false: they start unloaded; doc/fracture.md)", "FDEMDeformableSetFractureInsertion", prestress, &prestress, nullptr));
  PetscCall(PetscOptionsReal("-fdem_insert_ahead", "When a search for joints to insert during a run (insert_at) finds a tetrahedron at its stress ratio, the tetrahedra at (1 - this) of the ratio or above that a chain of such tetrahedra links to it get joints in the same rebuild (0: only those at the ratio; doc/fracture.md)", "FDEMDeformableFindCellsToSplit", d->insert_ahead, &d->insert_ahead, nullptr));
  PetscCall(PetscOptionsBool("-fdem_joint_face_compression", "A joint's compression over the pressed part of its face, not only at its three points (false: at its three points only; doc/fracture.md)", "FDEMDeformableSetMaterialFracture", face, &face, nullptr));
  PetscOptionsEnd();
  PetscCheck(d->insert_ahead >= 0 && d->insert_ahead < 1, d->comm, PETSC_ERR_USER_INPUT, "-fdem_insert_ahead %g: give a fraction in [0, 1)", (double)d->insert_ahead);
  d->prestress         = prestress;
  d->prestress_pending = false;
  d->jofs.clear();
  if (sizes[1] == 0) { // nothing was split: every node is its own input node
    d->owned_input  = d->owned_gid;
    d->ninput_nodes = d->nnodes_global;
    PetscFunctionReturn(0);
  }
  PetscCallMPI(MPI_Bcast(&d->joint_omega, 1, MPIU_REAL, 0, d->comm));
  // where every node and cell went: (rank, local index) gathered on rank 0
  const PetscMPIInt      size = d->size;
  std::vector<PetscMPIInt> nn(size), nc(size), offn(size + 1, 0), offc(size + 1, 0);
  PetscMPIInt            mine[2] = {(PetscMPIInt)d->nlocal, (PetscMPIInt)d->cell_gid.size()};
  std::vector<PetscMPIInt> both(2 * size);
  PetscCallMPI(MPI_Gather(mine, 2, MPI_INT, both.data(), 2, MPI_INT, 0, d->comm));
  for (int r = 0; r < size; ++r) {
    nn[r]       = both[2 * r];
    nc[r]       = both[2 * r + 1];
    offn[r + 1] = offn[r] + nn[r];
    offc[r + 1] = offc[r] + nc[r];
  }
  std::vector<PetscInt> allnodes(d->rank == 0 ? offn[size] : 0), allcells(d->rank == 0 ? offc[size] : 0);
  PetscCallMPI(MPI_Gatherv(d->node_gid.data(), mine[0], MPIU_INT, allnodes.data(), nn.data(), offn.data(), MPIU_INT, 0, d->comm));
  PetscCallMPI(MPI_Gatherv(d->cell_gid.data(), mine[1], MPIU_INT, allcells.data(), nc.data(), offc.data(), MPIU_INT, 0, d->comm));
  // the input node of every local node, back to its rank (FixNodes/MoveNodes take input ids)
  {
    std::vector<PetscInt> parents(d->rank == 0 ? offn[size] : 0), mine_p(d->nlocal);
    if (d->rank == 0) {
      for (std::size_t i = 0; i < parents.size(); ++i) parents[i] = d->split_parent[allnodes[i]];
      d->ninput_nodes = 1 + *std::max_element(d->split_parent.begin(), d->split_parent.end());
    }
    PetscCallMPI(MPI_Scatterv(parents.data(), nn.data(), offn.data(), MPIU_INT, mine_p.data(), (PetscMPIInt)d->nlocal, MPIU_INT, 0, d->comm));
    PetscCallMPI(MPI_Bcast(&d->ninput_nodes, 1, MPIU_INT, 0, d->comm));
    d->owned_input.resize(d->nown);
    for (PetscInt k = 0; k < d->nown; ++k) d->owned_input[k] = mine_p[d->owned_local[k]];
    d->local_input = std::move(mine_p);
  }
  if (nj == 0) PetscFunctionReturn(0);
  // rank 0: each joint's record (11 ints, 13 reals) to the rank of its tetrahedron a
  constexpr int          NI = 11, NR = 13; // the reals: the law's fields before face_compression, which is set on each rank
  static_assert(offsetof(fdem::kernels::JointLaw, face_compression) == NR * sizeof(double), "the joint record's reals are the law's first NR fields");
  std::vector<PetscInt>  ibuf;
  std::vector<PetscReal> rbuf;
  std::vector<PetscMPIInt> cnt(size, 0), icnt(size), rcnt(size), ioff(size, 0), roff(size, 0);
  if (d->rank == 0) {
    std::vector<PetscMPIInt> node_rank(d->nnodes_global, -1), cell_rank(d->ncells_global, -1);
    std::vector<PetscInt>    node_lidx(d->nnodes_global, -1), cell_lidx(d->ncells_global, -1);
    std::unordered_map<long long, PetscInt> more; // node * size + rank -> local index, for a node on more ranks than one
    for (int r = 0; r < size; ++r) {
      for (PetscMPIInt i = 0; i < nn[r]; ++i) {
        const PetscInt g = allnodes[offn[r] + i];
        if (node_rank[g] < 0) node_rank[g] = r, node_lidx[g] = i;
        else more[(long long)g * size + r] = i;
      }
      for (PetscMPIInt i = 0; i < nc[r]; ++i) {
        cell_rank[allcells[offc[r] + i]] = r;
        cell_lidx[allcells[offc[r] + i]] = i;
      }
    }
    std::vector<int> dest(nj);
    for (PetscInt j = 0; j < nj; ++j) cnt[dest[j] = cell_rank[d->joints_input[j].tet_a]]++;
    for (int r = 0; r < size; ++r) {
      icnt[r] = NI * cnt[r];
      rcnt[r] = NR * cnt[r];
      if (r) {
        ioff[r] = ioff[r - 1] + icnt[r - 1];
        roff[r] = roff[r - 1] + rcnt[r - 1];
      }
    }
    ibuf.resize(NI * (size_t)nj);
    rbuf.resize(NR * (size_t)nj);
    std::vector<PetscMPIInt> at(size, 0);
    for (PetscInt j = 0; j < nj; ++j) {
      const auto  &J = d->joints_input[j];
      const int    r = dest[j];
      PetscInt    *I = &ibuf[ioff[r] + NI * (size_t)at[r]];
      PetscReal   *R = &rbuf[roff[r] + NR * (size_t)at[r]];
      ++at[r];
      // triangle b's nodes as the rank of tetrahedron b holds them (an unsplit tetrahedron's
      // nodes may be on other ranks too)
      const int rb    = cell_rank[J.tet_b];
      auto      local = [&](PetscInt g, int q) -> PetscInt {
        if (node_rank[g] == q) return node_lidx[g];
        const auto it = more.find((long long)g * size + q);
        return it == more.end() ? -1 : it->second;
      };
      for (int i = 0; i < 3; ++i) {
        PetscCheck(node_rank[J.a[i]] == r, PETSC_COMM_SELF, PETSC_ERR_PLIB, "joint %" PetscInt_FMT ": a node of triangle a is not on the rank of its tetrahedron", j);
        I[i]     = node_lidx[J.a[i]];
        I[4 + i] = local(J.b[i], rb);
        PetscCheck(I[4 + i] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "joint %" PetscInt_FMT ": a node of triangle b is not on the rank of its tetrahedron", j);
      }
      I[3]  = rb;
      I[7]  = j;
      I[8]  = cell_lidx[J.tet_a]; // its local cell there (the joint's body)
      I[9]  = J.tet_b;            // tetrahedron b's id and its local cell on its rank
      I[10] = cell_lidx[J.tet_b];
      const double *L = reinterpret_cast<const double *>(&d->laws_input[j]);
      for (int k = 0; k < NR; ++k) R[k] = L[k];
    }
    d->joints_input.clear();
    d->joints_input.shrink_to_fit();
    d->laws_input.clear();
    d->laws_input.shrink_to_fit();
  }
  PetscMPIInt mycnt;
  PetscCallMPI(MPI_Scatter(cnt.data(), 1, MPI_INT, &mycnt, 1, MPI_INT, 0, d->comm));
  std::vector<PetscInt>  imine(NI * (size_t)mycnt);
  std::vector<PetscReal> rmine(NR * (size_t)mycnt);
  PetscCallMPI(MPI_Scatterv(ibuf.data(), icnt.data(), ioff.data(), MPIU_INT, imine.data(), NI * mycnt, MPIU_INT, 0, d->comm));
  PetscCallMPI(MPI_Scatterv(rbuf.data(), rcnt.data(), roff.data(), MPIU_REAL, rmine.data(), NR * mycnt, MPIU_REAL, 0, d->comm));
  d->jnode_a.resize(mycnt);
  d->jnode_b.resize(mycnt);
  d->jlaw.resize(mycnt);
  d->jstate.assign(mycnt, {});
  d->jgid.resize(mycnt);
  d->jdiss.assign(mycnt, 0);
  d->jbody.resize(mycnt);
  d->jgone.assign(mycnt, 0);
  d->jcell_a.resize(mycnt);
  d->jtet_b.resize(mycnt);
  d->jfresh.assign(mycnt, 0);
  d->jbreaks.clear();
  std::vector<PetscSFNode> remote(9 * (size_t)mycnt), remote_only;
  std::vector<PetscInt>    remote_leaf; // where remote_only's leaves are in jxb
  for (PetscMPIInt j = 0; j < mycnt; ++j) {
    const PetscInt *I = &imine[NI * (size_t)j];
    d->jgid[j]        = I[7];
    d->jbody[j]       = d->ed.body[I[8]];
    d->jcell_a[j]     = I[8];
    d->jtet_b[j]      = {I[9], I[3], I[10], -1};
    for (int i = 0; i < 3; ++i) {
      d->jnode_a[j][i] = (int)I[i];
      d->jnode_b[j][i] = I[3] == d->rank ? (int)I[4 + i] : -1;
      for (int k = 0; k < 3; ++k) {
        remote[9 * (size_t)j + 3 * i + k].rank  = (PetscInt)I[3];
        remote[9 * (size_t)j + 3 * i + k].index = 3 * I[4 + i] + k;
        if (I[3] != d->rank) {
          remote_only.push_back(remote[9 * (size_t)j + 3 * i + k]);
          remote_leaf.push_back(9 * (PetscInt)j + 3 * i + k);
        }
      }
    }
    std::copy(&rmine[NR * (size_t)j], &rmine[NR * (size_t)j] + NR, reinterpret_cast<double *>(&d->jlaw[j]));
    d->jlaw[j].face_compression = face ? 1.0 : 0.0;
  }
  PetscCall(PetscSFCreate(d->comm, &d->jsf));
  PetscCall(PetscSFSetGraph(d->jsf, 3 * d->nlocal, 9 * (PetscInt)mycnt, nullptr, PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(d->jsf));
  // the joint forces read and write a triangle b on this rank in place, and send only the others
  PetscCall(PetscSFCreate(d->comm, &d->jsf_remote));
  PetscCall(PetscSFSetGraph(d->jsf_remote, 3 * d->nlocal, (PetscInt)remote_only.size(), remote_leaf.data(), PETSC_COPY_VALUES, remote_only.data(), PETSC_COPY_VALUES));
  PetscCall(PetscSFSetUp(d->jsf_remote));
  d->jxb.assign(9 * (size_t)mycnt, 0);
  d->jfb.assign(9 * (size_t)mycnt, 0);
  // the face of tetrahedron b that each joint glues (the node of it not in triangle b, as
  // the rank of tetrahedron b orders its cell), from that rank's cells; then the SF from
  // each joint to that face (3 leaves a joint, 3 roots a face, 12 a cell)
  {
    const PetscInt        nc = (PetscInt)d->ed.size();
    std::vector<PetscInt> cnodes(4 * (size_t)nc), jn(4 * (size_t)mycnt);
    std::vector<PetscSFNode> cr(4 * (size_t)mycnt), fr(3 * (size_t)mycnt);
    for (PetscInt e = 0; e < nc; ++e)
      for (int a = 0; a < 4; ++a) cnodes[4 * e + a] = d->ed.elems[e].n[a];
    for (PetscMPIInt j = 0; j < mycnt; ++j)
      for (int a = 0; a < 4; ++a) cr[4 * (size_t)j + a] = {d->jtet_b[j][1], 4 * d->jtet_b[j][2] + a};
    PetscSF csf;
    PetscCall(PetscSFCreate(d->comm, &csf));
    PetscCall(PetscSFSetGraph(csf, 4 * nc, 4 * (PetscInt)mycnt, nullptr, PETSC_COPY_VALUES, cr.data(), PETSC_COPY_VALUES));
    PetscCall(PetscSFBcastBegin(csf, MPIU_INT, cnodes.data(), jn.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(csf, MPIU_INT, cnodes.data(), jn.data(), MPI_REPLACE));
    PetscCall(PetscSFDestroy(&csf));
    for (PetscMPIInt j = 0; j < mycnt; ++j) {
      const PetscInt *I = &imine[NI * (size_t)j];
      int             o = -1;
      for (int a = 0; a < 4; ++a)
        if (jn[4 * (size_t)j + a] != I[4] && jn[4 * (size_t)j + a] != I[5] && jn[4 * (size_t)j + a] != I[6]) o = a;
      PetscCheck(o >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "joint %" PetscInt_FMT ": triangle b is not a face of its tetrahedron", d->jgid[j]);
      d->jtet_b[j][3] = o;
      for (int q = 0; q < 3; ++q) fr[3 * (size_t)j + q] = {d->jtet_b[j][1], 12 * d->jtet_b[j][2] + 3 * o + q};
    }
    PetscCall(PetscSFCreate(d->comm, &d->jfsf));
    PetscCall(PetscSFSetGraph(d->jfsf, 12 * nc, 3 * (PetscInt)mycnt, nullptr, PETSC_COPY_VALUES, fr.data(), PETSC_COPY_VALUES));
    PetscCall(PetscSFSetUp(d->jfsf));
  }
  PetscFunctionReturn(0);
}

// Brings the coordinates of the local joints' triangles b from their ranks (d->jxb), from
// the local positions xl, through sf: d->jsf (every joint) or d->jsf_remote (the joints
// whose triangle b is on another rank); collective.
static PetscErrorCode BringTrianglesB(FDEMDeformable d, PetscSF sf, const PetscScalar *xl) {
  PetscFunctionBegin;
  PetscCall(PetscSFBcastBegin(sf, MPIU_SCALAR, xl, d->jxb.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_SCALAR, xl, d->jxb.data(), MPI_REPLACE));
  PetscFunctionReturn(0);
}

// The two triangles of local joint j: a from the local positions, b from d->jxb.
static inline void JointTriangles(FDEMDeformable d, const PetscScalar *xl, std::size_t j, double xa[3][3], double xb[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      xa[i][k] = xl[3 * d->jnode_a[j][i] + k];
      xb[i][k] = d->jxb[9 * j + 3 * i + k];
    }
}

// The triangles of joints j0 .. j0 + B.n - 1 into B.xa and B.xb: from the local positions xl, a
// triangle b on another rank from d->jxb.
static void GatherJointsColumns(FDEMDeformable d, const PetscScalar *xl, std::size_t j0, int b0, fdem::kernels::JointBlock &B) {
  for (int b = b0; b < B.n; ++b) {
    const std::size_t j = j0 + b;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        B.xa[3 * i + k][b] = xl[3 * d->jnode_a[j][i] + k];
        B.xb[3 * i + k][b] = d->jnode_b[j][0] >= 0 ? xl[3 * d->jnode_b[j][i] + k] : d->jxb[9 * j + 3 * i + k];
      }
  }
}

#if defined(__x86_64__)
// As GatherJointsColumns, four joints at a time where their four triangles b are on this rank
// (GatherRows4): the same values.
__attribute__((target("avx2"))) static void GatherJointsAVX2(FDEMDeformable d, const PetscScalar *xl, std::size_t j0, fdem::kernels::JointBlock &B) {
  const std::array<int, 3> *na = d->jnode_a.data() + j0, *nb = d->jnode_b.data() + j0;
  int                       b  = 0;
  for (; b + 4 <= B.n; b += 4) {
    if (nb[b][0] < 0 || nb[b + 1][0] < 0 || nb[b + 2][0] < 0 || nb[b + 3][0] < 0) break;
    for (int i = 0; i < 3; ++i) {
      const int a4[4] = {na[b][i], na[b + 1][i], na[b + 2][i], na[b + 3][i]}, b4[4] = {nb[b][i], nb[b + 1][i], nb[b + 2][i], nb[b + 3][i]};
      fdem::kernels::GatherRows4(xl, a4, &B.xa[3 * i][b], &B.xa[3 * i + 1][b], &B.xa[3 * i + 2][b]);
      fdem::kernels::GatherRows4(xl, b4, &B.xb[3 * i][b], &B.xb[3 * i + 1][b], &B.xb[3 * i + 2][b]);
    }
  }
  GatherJointsColumns(d, xl, j0, b, B);
}
#endif

static void GatherJointBlock(FDEMDeformable d, const PetscScalar *xl, std::size_t j0, fdem::kernels::JointBlock &B) {
#if defined(__x86_64__)
  if (fdem::kernels::kHasAVX2) return GatherJointsAVX2(d, xl, j0, B);
#endif
  GatherJointsColumns(d, xl, j0, 0, B);
}

// The frame of joint j's offset at triangle a's current nodes xa: E[0] = e1, E[1] = e2, E[2] =
// n, times the sign of the side, and the face's nodes in the order of their input nodes (ord).
// Both sides of a face agree on them: e1 along the first edge of that order, n the unit normal,
// e2 = n x e1; and the offset is kept as the separation of the side of the larger tetrahedron id
// from the other, so that it survives a rebuild that swaps triangles a and b. A collapsed
// triangle (which carries nothing) gets a zero frame: no offset rather than NaN.
static void OffsetFrame(FDEMDeformable d, std::size_t j, const double xa[3][3], double E[3][3], int ord[3]) {
  const std::array<int, 3> &na = d->jnode_a[j];
  int                       i0 = 0, i1 = 1, i2 = 2;
  auto                      in = [&](int i) { return d->local_input[na[i]]; };
  if (in(i1) < in(i0)) std::swap(i0, i1);
  if (in(i2) < in(i1)) std::swap(i1, i2);
  if (in(i1) < in(i0)) std::swap(i0, i1);
  ord[0] = i0, ord[1] = i1, ord[2] = i2;
  double *u = E[0], *e2 = E[1], *n = E[2], v[3];
  for (int k = 0; k < 3; ++k) u[k] = xa[i1][k] - xa[i0][k], v[k] = xa[i2][k] - xa[i0][k];
  n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
  const double sign = d->cell_gid[d->jcell_a[j]] < d->jtet_b[j][0] ? 1.0 : -1.0;
  const double lu = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(lu > 0 && ln > 0)) {
    for (int r = 0; r < 3; ++r) E[r][0] = E[r][1] = E[r][2] = 0;
    return;
  }
  for (int k = 0; k < 3; ++k) u[k] /= lu, n[k] /= ln;
  e2[0] = n[1] * u[2] - n[2] * u[1], e2[1] = n[2] * u[0] - n[0] * u[2], e2[2] = n[0] * u[1] - n[1] * u[0];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) E[r][k] *= sign;
}

// The separation (b - a) that joint j's offset adds at node i of triangle a (O[i]), at triangle
// a's current nodes xa.
static void OffsetSeparation(FDEMDeformable d, std::size_t j, const double xa[3][3], double O[3][3]) {
  const auto &c = d->jofs[j].c;
  double      E[3][3];
  int         ord[3];
  OffsetFrame(d, j, xa, E, ord);
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) O[ord[r]][k] = c[r][0] * E[0][k] + c[r][1] * E[1][k] + c[r][2] * E[2][k];
}

// Sets joint j's offset to the separations O[i] at the nodes of triangle a (the inverse of
// OffsetSeparation at these positions).
static void SetOffset(FDEMDeformable d, std::size_t j, const double xa[3][3], const double O[3][3]) {
  double E[3][3];
  int    ord[3];
  OffsetFrame(d, j, xa, E, ord);
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) d->jofs[j].c[r][a] = E[a][0] * O[ord[r]][0] + E[a][1] * O[ord[r]][1] + E[a][2] * O[ord[r]][2];
}

// Triangles a and b of a joint with the offsets O (b - a) at its nodes, as its law sees them:
// a moved by -O/2 and b by +O/2, so that the separation grows by O and the mid-surface (whose
// normal and area the law takes) stays where the two triangles put it, whichever side is a.
static void ApplyOffset(const double O[3][3], double xa[3][3], double xb[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) xa[i][k] -= 0.5 * O[i][k], xb[i][k] += 0.5 * O[i][k];
}

// Adds the offsets of the block's joints (from j0) to their triangles (ApplyOffset).
static void AddBlockOffsets(FDEMDeformable d, std::size_t j0, fdem::kernels::JointBlock &B) {
  for (int b = 0; b < B.n; ++b) {
    if (!d->jofs[j0 + b].any()) continue;
    double xa[3][3], O[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) xa[i][k] = B.xa[3 * i + k][b];
    OffsetSeparation(d, j0 + b, xa, O);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) B.xa[3 * i + k][b] -= 0.5 * O[i][k], B.xb[3 * i + k][b] += 0.5 * O[i][k];
  }
}

// The unit normal of triangle a (towards b) and its area; false where it has collapsed.
static bool TriangleNormal(const double xa[3][3], double n[3], double *area) {
  const double u[3] = {xa[1][0] - xa[0][0], xa[1][1] - xa[0][1], xa[1][2] - xa[0][2]}, v[3] = {xa[2][0] - xa[0][0], xa[2][1] - xa[0][1], xa[2][2] - xa[0][2]};
  n[0] = u[1] * v[2] - u[2] * v[1], n[1] = u[2] * v[0] - u[0] * v[2], n[2] = u[0] * v[1] - u[1] * v[0];
  const double ln = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(ln > 0)) return false;
  for (int k = 0; k < 3; ++k) n[k] /= ln;
  *area = 0.5 * ln;
  return true;
}

// The separation at which joint j's law carries the traction t (on triangle a, normal n): the
// opening along n and the slip along t's tangential part (JointSeparationFor).
static void SeparationForTraction(const JointLaw &law, const double n[3], const double t[3], double o[3]) {
  const double sn    = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
  const double tt[3] = {t[0] - sn * n[0], t[1] - sn * n[1], t[2] - sn * n[2]};
  const double tau   = std::sqrt(tt[0] * tt[0] + tt[1] * tt[1] + tt[2] * tt[2]);
  double       dn0, s0;
  fdem::kernels::JointSeparationFor(law, sn, tau, &dn0, &s0);
  for (int k = 0; k < 3; ++k) o[k] = dn0 * n[k] + (tau > 0 ? s0 / tau * tt[k] : 0.0);
}

// Joint j with the separations o[q] at its three points (the edge midpoints; node offsets O[i]
// with o[q] = (O[q] + O[q+1]) / 2): the node offsets, fresh point histories evaluated there (the
// shear's secant), and the energy it stores at zero separation, where its stored energy is
// counted from. fa (may be null): the forces on triangle a's nodes of that evaluation, which
// the next evaluation at zero separation repeats (the secant it raised holds).
static void StartJointAt(FDEMDeformable d, std::size_t j, const double xa[3][3], const double o[3][3], double (*fa)[3] = nullptr) {
  double O[3][3], ya[3][3], yb[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) O[i][k] = o[i][k] - o[(i + 1) % 3][k] + o[(i + 2) % 3][k], ya[i][k] = yb[i][k] = xa[i][k];
  ApplyOffset(O, ya, yb);
  // the points' histories from a first evaluation at these positions (the kernel's own geometry)
  for (int q = 0; q < 3; ++q) d->jstate[j][q] = fdem::kernels::JointState{};
  double f[3][3] = {}, fb[3][3] = {};
  (void)fdem::kernels::JointElementForces(d->jlaw[j], ya, yb, d->jstate[j].data(), f, fb);
  if (fa) std::copy(&f[0][0], &f[0][0] + 9, &fa[0][0]);
  SetOffset(d, j, xa, O);
  d->jofs[j].energy = fdem::kernels::JointElementEnergy(d->jlaw[j], ya, yb, d->jstate[j].data());
}

// Gives each joint inserted by the last load of a joint state (d->jfresh) the separation at
// which it carries the traction its face carries at the positions xl: the mean of its two
// tetrahedra's Cauchy stresses (their elastic part: a viscous stress stays with the
// tetrahedra) on the face's normal (JointSeparationFor). Its points' histories are those of a
// first evaluation there (the shear's secant), and the energy it then stores is where its
// stored energy is counted from, so that the scene's total does not jump. Collective.
static PetscErrorCode PrestressNewJoints(FDEMDeformable d, const PetscScalar *xl) {
  PetscSF      sf;
  MPI_Datatype six;
  PetscFunctionBegin;
  d->prestress_pending = false;
  const std::size_t nj = d->jnode_a.size(), nc = d->ed.size();
  // the stresses of the fresh joints' two tetrahedra only: tetrahedron b (on any rank) over an
  // SF with a leaf per fresh joint, which first tells each rank which of its cells are asked for
  std::vector<PetscSFNode> remote;
  std::vector<PetscInt>    leaf;
  for (std::size_t j = 0; j < nj; ++j)
    if (d->jfresh[j]) {
      remote.push_back({d->jtet_b[j][1], d->jtet_b[j][2]});
      leaf.push_back((PetscInt)j);
    }
  PetscCall(PetscSFCreate(d->comm, &sf));
  PetscCall(PetscSFSetGraph(sf, (PetscInt)nc, (PetscInt)leaf.size(), leaf.data(), PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES));
  std::vector<int> asked(nc, 0), ask(nj, 1);
  PetscCall(PetscSFReduceBegin(sf, MPI_INT, ask.data(), asked.data(), MPI_MAX));
  PetscCall(PetscSFReduceEnd(sf, MPI_INT, ask.data(), asked.data(), MPI_MAX));
  for (PetscInt j : leaf) asked[d->jcell_a[j]] = 1;
  std::vector<PetscReal> S(6 * nc, 0.0), Sb(6 * nj, 0.0);
  for (std::size_t e = 0; e < nc; ++e) {
    if (!asked[e]) continue;
    fdem::kernels::TetState st;
    const bool              ok   = fdem::kernels::EvaluateTet(d->ed, e, xl, nullptr, st);
    const double            T[6] = {st.T(0, 0), st.T(1, 1), st.T(2, 2), st.T(0, 1), st.T(1, 2), st.T(0, 2)};
    for (int k = 0; k < 6; ++k) S[6 * e + k] = ok ? T[k] : NAN;
  }
  PetscCallMPI(MPI_Type_contiguous(6, MPIU_REAL, &six));
  PetscCallMPI(MPI_Type_commit(&six));
  PetscCall(PetscSFBcastBegin(sf, six, S.data(), Sb.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, six, S.data(), Sb.data(), MPI_REPLACE));
  PetscCallMPI(MPI_Type_free(&six));
  PetscCall(PetscSFDestroy(&sf));
  if (d->jofs.size() != nj) d->jofs.assign(nj, {});
  d->jequil.assign(nj, 0);
  PetscInt any = 0;
  for (std::size_t j = 0; j < nj; ++j) {
    if (!d->jfresh[j]) continue;
    d->jfresh[j] = 0;
    double xa[3][3], n[3], T[6], area;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) xa[i][k] = xl[3 * d->jnode_a[j][i] + k];
    for (int k = 0; k < 6; ++k) T[k] = 0.5 * (S[6 * d->jcell_a[j] + k] + Sb[6 * j + k]);
    bool finite = TriangleNormal(xa, n, &area);
    for (int k = 0; k < 6; ++k) finite = finite && std::isfinite(T[k]);
    if (!finite) continue; // an inverted tetrahedron: the joint starts unloaded
    // the traction on triangle a (outward normal n, towards b): T n, the same at the three points
    const double t[3] = {T[0] * n[0] + T[3] * n[1] + T[5] * n[2], T[3] * n[0] + T[1] * n[1] + T[4] * n[2], T[5] * n[0] + T[4] * n[1] + T[2] * n[2]};
    double       o[3][3];
    for (int q = 0; q < 3; ++q) SeparationForTraction(d->jlaw[j], n, t, o[q]);
    StartJointAt(d, j, xa, o);
    d->jequil[j] = 1;
    any          = 1;
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &any, 1, MPIU_INT, MPI_MAX, d->comm));
  d->equilibrate_pending = any != 0;
  PetscFunctionReturn(0);
}

// Sends the records of `per` doubles in out[r] to rank r, and gets those sent here (in) with
// the rank each came from (from). Collective.
static PetscErrorCode Exchange(MPI_Comm comm, int per, const std::vector<std::vector<double>> &out, std::vector<double> &in, std::vector<int> &from) {
  const int                size = (int)out.size();
  std::vector<PetscMPIInt> sc(size), rc(size), sd(size, 0), rd(size, 0);
  std::vector<double>      buf;
  std::size_t              nout = 0, nin = 0;
  PetscMPIInt              big[2];
  PetscFunctionBegin;
  for (int r = 0; r < size; ++r) nout += out[r].size();
  big[0] = nout > (std::size_t)INT_MAX;
  if (!big[0])
    for (int r = 0; r < size; ++r) {
      sc[r] = (PetscMPIInt)out[r].size();
      if (r) sd[r] = sd[r - 1] + sc[r - 1];
      buf.insert(buf.end(), out[r].begin(), out[r].end());
    }
  PetscCallMPI(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm));
  for (int r = 0; r < size; ++r) nin += (std::size_t)rc[r];
  big[1] = nin > (std::size_t)INT_MAX;
  // (MPI's counts and displacements are int: every rank stops if one rank's totals do not fit)
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, big, 2, MPI_INT, MPI_MAX, comm));
  PetscCheck(!big[0] && !big[1], comm, PETSC_ERR_SUP, "the balance of new joints would %s more than %d numbers on one rank (MPI's int counts): use more ranks", big[0] ? "send" : "receive", INT_MAX);
  for (int r = 1; r < size; ++r) rd[r] = rd[r - 1] + rc[r - 1];
  in.resize(nin);
  PetscCallMPI(MPI_Alltoallv(buf.data(), sc.data(), sd.data(), MPI_DOUBLE, in.data(), rc.data(), rd.data(), MPI_DOUBLE, comm));
  from.clear();
  for (int r = 0; r < size; ++r)
    for (int k = 0; k < rc[r] / per; ++k) from.push_back(r);
  PetscFunctionReturn(0);
}

// The potentials phi (n x 3) of L phi = e on a graph of n vertices and its edges (pairs), L the
// graph Laplacian: one vertex of each connected part held at 0 (its equation dropped: the part's
// e sum to 0), an isolated vertex 0. Gaussian elimination on the rest (n is the number of copies
// of one node: a few tens).
static void GraphPotentials(int n, const std::vector<std::pair<int, int>> &edges, const std::vector<double> &e, std::vector<double> &phi) {
  std::vector<int> part(n);
  for (int v = 0; v < n; ++v) part[v] = v;
  std::function<int(int)> root = [&](int v) { return part[v] == v ? v : part[v] = root(part[v]); };
  for (const auto &[a, b] : edges) part[root(a)] = root(b);
  std::vector<int> idx(n, -1);
  int              m = 0;
  for (int v = 0; v < n; ++v)
    if (root(v) != v) idx[v] = m++; // each part's root is held at 0
  phi.assign(3 * (size_t)n, 0.0);
  if (m == 0) return;
  std::vector<double> A((size_t)m * m, 0.0), B(3 * (size_t)m, 0.0);
  for (const auto &[a, b] : edges) {
    const int ia = idx[a], ib = idx[b];
    if (ia >= 0) A[(size_t)ia * m + ia] += 1;
    if (ib >= 0) A[(size_t)ib * m + ib] += 1;
    if (ia >= 0 && ib >= 0) A[(size_t)ia * m + ib] -= 1, A[(size_t)ib * m + ia] -= 1;
  }
  for (int v = 0; v < n; ++v)
    if (idx[v] >= 0)
      for (int k = 0; k < 3; ++k) B[3 * (size_t)idx[v] + k] = e[3 * (size_t)v + k];
  for (int c = 0; c < m; ++c) { // symmetric positive definite once grounded: no pivoting needed
    const double p = A[(size_t)c * m + c];
    for (int r = c + 1; r < m; ++r) {
      const double f = A[(size_t)r * m + c] / p;
      if (f == 0) continue;
      for (int k = c; k < m; ++k) A[(size_t)r * m + k] -= f * A[(size_t)c * m + k];
      for (int k = 0; k < 3; ++k) B[3 * (size_t)r + k] -= f * B[3 * (size_t)c + k];
    }
  }
  for (int c = m - 1; c >= 0; --c)
    for (int k = 0; k < 3; ++k) {
      double s = B[3 * (size_t)c + k];
      for (int r = c + 1; r < m; ++r) s -= A[(size_t)c * m + r] * B[3 * (size_t)r + k];
      B[3 * (size_t)c + k] = s / A[(size_t)c * m + c];
    }
  for (int v = 0; v < n; ++v)
    if (idx[v] >= 0)
      for (int k = 0; k < 3; ++k) phi[3 * (size_t)v + k] = B[3 * (size_t)idx[v] + k];
}

// owned[3 k + c]: the sum over the ranks of component c of the local vector `local` at owned
// node k (a ghost's value added to its owner's). Collective.
static PetscErrorCode SumToOwned(FDEMDeformable d, Vec local, std::vector<double> &owned) {
  const PetscScalar *f;
  Vec                G = local;
  PetscFunctionBegin;
  if (!d->local_is_owned) {
    PetscCall(VecDuplicate(d->x, &G));
    PetscCall(VecSet(G, 0));
    PetscCall(DMLocalToGlobalBegin(d->dm, local, ADD_VALUES, G));
    PetscCall(DMLocalToGlobalEnd(d->dm, local, ADD_VALUES, G));
  }
  owned.resize(3 * (size_t)d->nown);
  PetscCall(VecGetArrayRead(G, &f));
  for (PetscInt i = 0; i < 3 * d->nown; ++i) owned[i] = PetscRealPart(f[i]);
  PetscCall(VecRestoreArrayRead(G, &f));
  if (G != local) PetscCall(VecDestroy(&G));
  PetscFunctionReturn(0);
}

// touched[k]: whether owned node k is a corner of a joint still to balance (d->jequil), on
// either side of it and on any rank. Collective.
static PetscErrorCode TouchedByNewJoints(FDEMDeformable d, std::vector<char> &touched) {
  const std::size_t   nj = d->jnode_a.size();
  std::vector<int>    on(3 * (size_t)d->nlocal, 0), leaf(9 * nj, 0);
  std::vector<double> sum;
  Vec                 L;
  PetscScalar        *l;
  PetscFunctionBegin;
  for (std::size_t j = 0; j < nj; ++j)
    if (d->jequil[j])
      for (int i = 0; i < 9; ++i) leaf[9 * j + i] = 1, on[3 * (size_t)d->jnode_a[j][i / 3] + i % 3] = 1;
  PetscCall(PetscSFReduceBegin(d->jsf, MPI_INT, leaf.data(), on.data(), MPI_MAX)); // triangle b's corners
  PetscCall(PetscSFReduceEnd(d->jsf, MPI_INT, leaf.data(), on.data(), MPI_MAX));
  PetscCall(VecDuplicate(d->floc, &L));
  PetscCall(VecGetArray(L, &l));
  for (std::size_t i = 0; i < on.size(); ++i) l[i] = on[i];
  PetscCall(VecRestoreArray(L, &l));
  PetscCall(SumToOwned(d, L, sum));
  PetscCall(VecDestroy(&L));
  touched.resize(d->nown);
  for (PetscInt k = 0; k < d->nown; ++k) touched[k] = sum[3 * (size_t)k] > 0;
  PetscFunctionReturn(0);
}

// Joints inserted under load (PrestressNewJoints) start at the mean of their two sides'
// tractions; where the stress jumps from one tetrahedron to the next, each copy of a node is
// then left a part of the jump, and rings. Here, at the first evaluation after the insertion,
// with every force of the evaluation on the copies (the elements, the joints, the contact and
// the other hooks): the copies that new joints join at an input node (a part) were one node
// before the insertion (a new joint lies on a face that had none, between two tetrahedra that
// shared their nodes), and should accelerate as that node did, F_c = m_c R / M (R, M the part's
// force and mass). The new joints' forces at the node are shifted by the flows of the graph
// Laplacian (the copies of the input node as vertices, the new joints as edges) that take each
// copy's residual F_c - m_c R / M away. Each joint's forces at its three nodes then give the
// tractions at its three points, and its points start at the separations whose law gives them
// (the node offsets of StartJointAt). The change of the joints' forces is added to this
// evaluation's local forces. A part with a fixed or moved copy is left as it is. Each input
// node is solved on one rank (its id modulo the ranks). Collective.
PetscErrorCode fdem::model::deformable::EquilibrateNewJoints(FDEMDeformable d) {
  const int         size = d->size;
  const std::size_t nj   = d->jnode_a.size();
  PetscFunctionBegin;
  d->equilibrate_pending = false;
  // the ids of triangle b's nodes (for the edges of the input nodes' graphs)
  std::vector<PetscInt> bid(9 * nj, -1), gid3(3 * (size_t)d->nlocal);
  for (PetscInt l = 0; l < d->nlocal; ++l) gid3[3 * l] = gid3[3 * l + 1] = gid3[3 * l + 2] = d->node_gid[l];
  PetscCall(PetscSFBcastBegin(d->jsf, MPIU_INT, gid3.data(), bid.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(d->jsf, MPIU_INT, gid3.data(), bid.data(), MPI_REPLACE));
  // A joint whose forces cannot be brought to its share (the face rule of the compression, which
  // takes over where its vertices are pressed in and open, answers otherwise than its points'
  // law; or a traction beyond a peak) keeps its forces and leaves the flow to the others: a
  // few rounds, each with the forces the last one left.
  for (int round = 0; round < 3; ++round) {
    // 1. each owned node's force over all ranks
    std::vector<double> F;
    PetscCall(SumToOwned(d, d->floc, F));
    // 2. to the rank of each input node (its id modulo the ranks): the copies that adjustable
    //    joints join (node, id, F, m, fixed; a copy that no such joint touches is a part of its
    //    own, balanced already) and those joints' edges there (node, a's id, b's id, joint, slot)
    std::vector<char> touched;
    PetscCall(TouchedByNewJoints(d, touched));
    std::vector<std::vector<double>> copies_out(size), edges_out(size);
    {
      const PetscScalar *m;
      PetscCall(VecGetArrayRead(d->m, &m));
      for (PetscInt k = 0; k < d->nown; ++k) {
        if (!touched[k]) continue;
        const PetscInt g = d->local_input[d->owned_local[k]];
        auto          &o = copies_out[g % size];
        o.insert(o.end(), {(double)g, (double)d->owned_gid[k], F[3 * k], F[3 * k + 1], F[3 * k + 2], PetscRealPart(m[3 * k]), (double)d->fixed[k]});
      }
      PetscCall(VecRestoreArrayRead(d->m, &m));
    }
    for (std::size_t j = 0; j < nj; ++j) {
      if (!d->jequil[j]) continue;
      for (int i = 0; i < 3; ++i) {
        const PetscInt la = d->jnode_a[j][i], g = d->local_input[la];
        auto          &o = edges_out[g % size];
        o.insert(o.end(), {(double)g, (double)d->node_gid[la], (double)bid[9 * j + 3 * i], (double)j, (double)i});
      }
    }
    std::vector<double> cin, ein;
    std::vector<int>    cfrom, efrom;
    PetscCall(Exchange(d->comm, 7, copies_out, cin, cfrom));
    PetscCall(Exchange(d->comm, 5, edges_out, ein, efrom));
    // 3. each input node's potentials, and the flows back to the joints' ranks (joint, slot, dF)
    struct Group {
      std::vector<std::size_t> copies, edges; // records in cin, ein
    };
    std::unordered_map<PetscInt, Group> groups;
    for (std::size_t r = 0; r < cin.size() / 7; ++r) groups[(PetscInt)cin[7 * r]].copies.push_back(r);
    for (std::size_t r = 0; r < ein.size() / 5; ++r) groups[(PetscInt)ein[5 * r]].edges.push_back(r);
    std::vector<std::vector<double>> rout(size);
    for (const auto &[g, G] : groups) {
      if (G.edges.empty()) continue;
      std::unordered_map<PetscInt, int> vertex;
      for (std::size_t r : G.copies) {
        const int v = (int)vertex.size();
        vertex[(PetscInt)cin[7 * r + 1]] = v;
      }
      const int                        n = (int)vertex.size();
      std::vector<std::pair<int, int>> edges;
      std::vector<char>                use(G.edges.size(), 1);
      for (std::size_t q = 0; q < G.edges.size(); ++q) {
        const std::size_t r = G.edges[q];
        const auto        a = vertex.find((PetscInt)ein[5 * r + 1]), b = vertex.find((PetscInt)ein[5 * r + 2]);
        if (a == vertex.end() || b == vertex.end()) use[q] = 0, edges.push_back({0, 0});
        else edges.push_back({a->second, b->second});
      }
      // the parts that the new joints join are the nodes they came from: each part's force R and
      // mass M; a part with a fixed or moved copy is left as it is
      std::vector<int> part(n);
      for (int v = 0; v < n; ++v) part[v] = v;
      std::function<int(int)> root = [&](int v) { return part[v] == v ? v : part[v] = root(part[v]); };
      for (std::size_t q = 0; q < edges.size(); ++q)
        if (use[q]) part[root(edges[q].first)] = root(edges[q].second);
      std::vector<double> R(4 * (size_t)n, 0.0), e(3 * (size_t)n, 0.0), phi;
      std::vector<char>   held(n, 0);
      for (std::size_t r : G.copies) {
        const double *c = &cin[7 * r];
        const int     p = root(vertex[(PetscInt)c[1]]);
        for (int k = 0; k < 3; ++k) R[4 * (size_t)p + k] += c[2 + k];
        R[4 * (size_t)p + 3] += c[5];
        held[p] = held[p] || c[6] != 0;
      }
      for (std::size_t r : G.copies) {
        const double *c = &cin[7 * r];
        const int     v = vertex[(PetscInt)c[1]], p = root(v);
        if (held[p] || !(R[4 * (size_t)p + 3] > 0)) continue;
        for (int k = 0; k < 3; ++k) e[3 * (size_t)v + k] = c[2 + k] - c[5] * R[4 * (size_t)p + k] / R[4 * (size_t)p + 3];
      }
      std::vector<std::pair<int, int>> used;
      for (std::size_t q = 0; q < edges.size(); ++q)
        if (use[q] && !held[root(edges[q].first)] && R[4 * (size_t)root(edges[q].first) + 3] > 0) used.push_back(edges[q]);
        else use[q] = 0;
      GraphPotentials(n, used, e, phi);
      for (std::size_t q = 0; q < G.edges.size(); ++q) {
        if (!use[q]) continue;
        const std::size_t r = G.edges[q];
        const auto [a, b]   = edges[q];
        auto &o             = rout[efrom[r]];
        o.insert(o.end(), {ein[5 * r + 3], ein[5 * r + 4], phi[3 * (size_t)b] - phi[3 * (size_t)a], phi[3 * (size_t)b + 1] - phi[3 * (size_t)a + 1], phi[3 * (size_t)b + 2] - phi[3 * (size_t)a + 2]});
      }
    }
    std::vector<double> rin;
    std::vector<int>    rfrom;
    PetscCall(Exchange(d->comm, 5, rout, rin, rfrom));
    // 4. each joint's new forces at its nodes -> its points' tractions -> their separations; the
    //    change of its forces into this evaluation's local forces (b's through the SF)
    std::vector<double> dF(9 * nj, 0.0), fbuf(9 * nj, 0.0);
    std::vector<char>   got(nj, 0);
    for (std::size_t r = 0; r < rin.size() / 5; ++r) {
      const std::size_t j = (std::size_t)rin[5 * r];
      const int         i = (int)rin[5 * r + 1];
      for (int k = 0; k < 3; ++k) dF[9 * j + 3 * i + k] = rin[5 * r + 2 + k];
      got[j] = 1;
    }
    const PetscScalar *xl;
    PetscScalar       *fl;
    PetscInt           failed = 0;
    PetscCall(VecGetArrayRead(d->xloc, &xl));
    PetscCall(VecGetArray(d->floc, &fl));
    for (std::size_t j = 0; j < nj; ++j) {
      if (!d->jequil[j]) continue;
      // (the copies of a and b coincide at this first evaluation: the joint's separation is its offset)
      double xa[3][3], ya[3][3], O[3][3], n[3], area, o[3][3];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) xa[i][k] = xl[3 * d->jnode_a[j][i] + k];
      if (!got[j] || !TriangleNormal(xa, n, &area)) {
        d->jequil[j] = 0;
        continue;
      }
      double yb[3][3];
      OffsetSeparation(d, j, xa, O);
      std::copy(&xa[0][0], &xa[0][0] + 9, &ya[0][0]);
      std::copy(&xa[0][0], &xa[0][0] + 9, &yb[0][0]);
      ApplyOffset(O, ya, yb);
      const std::array<fdem::kernels::JointState, 3> st0  = d->jstate[j];
      const JointOffset                              ofs0 = d->jofs[j];
      std::array<fdem::kernels::JointState, 3>       st   = st0;
      double                                         f0[3][3] = {}, f1[3][3] = {}, fb[3][3] = {};
      (void)fdem::kernels::JointElementForces(d->jlaw[j], ya, yb, st.data(), f0, fb);
      // the nodes' forces Fn -> the points' forces (node i gets half of points i and i - 1:
      // point q's is F_q + F_{q+1} - F_{q+2}) -> the points' tractions -> their separations;
      // then again with what the kernel gives there, which weighs the points by the
      // mid-surface's area and takes its normal
      double Fn[3][3], t[3][3], w = area / 3, big = 0, miss = 0;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) Fn[i][k] = f0[i][k] + dF[9 * j + 3 * i + k], big = std::max({big, std::fabs(Fn[i][k]), std::fabs(f0[i][k])});
      auto start = [&]() { // the joint's points at the separations o: its forces f1 and their miss
        StartJointAt(d, j, xa, o, f1);
        miss = 0;
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) miss = std::max(miss, std::fabs(Fn[i][k] - f1[i][k]));
      };
      for (int q = 0; q < 3; ++q)
        for (int k = 0; k < 3; ++k) t[q][k] = (Fn[q][k] + Fn[(q + 1) % 3][k] - Fn[(q + 2) % 3][k]) / w;
      for (int pass = 0; pass < 6; ++pass) {
        for (int q = 0; q < 3; ++q) SeparationForTraction(d->jlaw[j], n, t[q], o[q]);
        start();
        if (miss <= 1e-9 * big) break;
        for (int q = 0; q < 3; ++q)
          for (int k = 0; k < 3; ++k) t[q][k] += ((Fn[q][k] - f1[q][k]) + (Fn[(q + 1) % 3][k] - f1[(q + 1) % 3][k]) - (Fn[(q + 2) % 3][k] - f1[(q + 2) % 3][k])) / w;
      }
      if (!(miss <= 1e-6 * big)) {
        // The face rule of the compression (where the joint's vertices are pressed in and open)
        // answers otherwise than the points' law: Newton's method on the nodes' offsets, with a
        // Jacobian by differences of the kernel's forces and the step halved until the miss falls.
        auto forces = [&](const double Ov[9], double f[9]) {
          double ua[3][3], ub[3][3], fa[3][3] = {}, fbb[3][3] = {}, Om[3][3];
          for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) Om[i][k] = Ov[3 * i + k], ua[i][k] = ub[i][k] = xa[i][k];
          ApplyOffset(Om, ua, ub);
          std::array<fdem::kernels::JointState, 3> s{};
          (void)fdem::kernels::JointElementForces(d->jlaw[j], ua, ub, s.data(), fa, fbb);
          for (int i = 0; i < 9; ++i) f[i] = fa[i / 3][i % 3];
        };
        auto missof = [&](const double f[9]) {
          double m = 0;
          for (int i = 0; i < 9; ++i) m = std::max(m, std::fabs(Fn[i / 3][i % 3] - f[i]));
          return m;
        };
        double Ov[9], fv[9], scale = 0;
        for (int i = 0; i < 9; ++i) Ov[i] = O[i / 3][i % 3], scale = std::max(scale, std::fabs(Ov[i]));
        forces(Ov, fv);
        miss = missof(fv);
        const double hd = 1e-7 * std::max(scale, 1e-3 * d->jlaw[j].dn_peak);
        for (int it = 0; it < 12 && miss > 1e-9 * big; ++it) {
          double J[9][10];
          for (int c = 0; c < 9; ++c) {
            double Op[9], fp[9];
            std::copy(Ov, Ov + 9, Op);
            Op[c] += hd;
            forces(Op, fp);
            for (int r = 0; r < 9; ++r) J[r][c] = (fp[r] - fv[r]) / hd;
          }
          for (int r = 0; r < 9; ++r) J[r][9] = Fn[r / 3][r % 3] - fv[r];
          bool ok = true;
          for (int c = 0; c < 9 && ok; ++c) { // elimination with partial pivoting
            int p = c;
            for (int r = c + 1; r < 9; ++r)
              if (std::fabs(J[r][c]) > std::fabs(J[p][c])) p = r;
            ok = J[p][c] != 0;
            if (!ok) break;
            for (int k = 0; k < 10; ++k) std::swap(J[c][k], J[p][k]);
            for (int r = c + 1; r < 9; ++r) {
              const double f = J[r][c] / J[c][c];
              for (int k = c; k < 10; ++k) J[r][k] -= f * J[c][k];
            }
          }
          if (!ok) break;
          double step[9];
          for (int c = 8; c >= 0; --c) {
            double v = J[c][9];
            for (int k = c + 1; k < 9; ++k) v -= J[c][k] * step[k];
            step[c] = v / J[c][c];
          }
          double a = 1, tried = miss;
          for (int h = 0; h < 6; ++h, a *= 0.5) {
            double Ot[9], ft[9];
            for (int i = 0; i < 9; ++i) Ot[i] = Ov[i] + a * step[i];
            forces(Ot, ft);
            tried = missof(ft);
            if (tried < miss) {
              std::copy(Ot, Ot + 9, Ov), std::copy(ft, ft + 9, fv);
              break;
            }
          }
          if (!(tried < miss)) break;
          miss = tried;
        }
        if (miss <= 1e-6 * big) { // the joint at these node offsets (its points at the edges' midpoints)
          for (int q = 0; q < 3; ++q)
            for (int k = 0; k < 3; ++k) o[q][k] = 0.5 * (Ov[3 * q + k] + Ov[3 * ((q + 1) % 3) + k]);
          start();
        }
      }
      if (!(miss <= 1e-6 * big)) { // not reached: the joint keeps the forces it had
        d->jstate[j] = st0;
        d->jofs[j]   = ofs0;
        d->jequil[j] = 0;
        ++failed;
        continue;
      }
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
          fl[3 * d->jnode_a[j][i] + k] += f1[i][k] - f0[i][k];
          fbuf[9 * j + 3 * i + k] = f0[i][k] - f1[i][k];
        }
    }
    PetscCall(VecRestoreArray(d->floc, &fl));
    PetscCall(VecRestoreArrayRead(d->xloc, &xl));
    PetscCall(VecGetArray(d->floc, &fl));
    PetscCall(PetscSFReduceBegin(d->jsf, MPIU_SCALAR, fbuf.data(), fl, MPIU_SUM));
    PetscCall(PetscSFReduceEnd(d->jsf, MPIU_SCALAR, fbuf.data(), fl, MPIU_SUM));
    PetscCall(VecRestoreArray(d->floc, &fl));
    PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &failed, 1, MPIU_INT, MPI_SUM, d->comm));
    if (failed == 0) break;
  }
  std::fill(d->jequil.begin(), d->jequil.end(), 0);
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::AddJointForces(FDEMDeformable d, PetscReal t, const PetscScalar *xl, PetscScalar *fl) {
  PetscFunctionBegin;
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  if (d->ts && d->ts != d->joint_checked) { // once per TS, at its first evaluation
    TSType         type;
    PetscReal      dt;
    PetscBool      found;
    FDEMSchemeInfo info;
    d->joint_checked = d->ts;
    PetscCall(TSGetType(d->ts, &type));
    PetscCall(TSGetTimeStep(d->ts, &dt));
    PetscCall(FDEMSchemeInfoFind(type, &found, &info));
    const PetscReal r = found && info.kcrit > 0 ? d->joint_omega * dt / info.kcrit : 0;
    if (r > 0.5)
      PetscCall(PetscPrintf(d->comm,
                            "WARNING fdem joints: the joints' frequency omega_j = %g (estimated from the joint penalty and the nodal masses; see doc/fracture.md) makes omega_j dt = %g, %.3g%% of the stability limit K_crit = %.4f of -ts_type %s; reduce dt below %g or the joint penalty\n",
                            (double)d->joint_omega, (double)(d->joint_omega * dt), (double)(100 * r), (double)info.kcrit, type, (double)(0.5 * info.kcrit / d->joint_omega)));
  }
  if (d->prestress_pending) PetscCall(PrestressNewJoints(d, xl));
  PetscCall(BringTrianglesB(d, d->jsf_remote, xl));
  // a block of joints at a time (JointBlockForces): gathered component-major, the forces on
  // A added to the local nodes in joint order, and B's (their negatives) too where triangle
  // b is on this rank, else sent back through the SF
  const std::size_t          nj = d->jnode_a.size();
  fdem::kernels::JointBlock B;
  for (std::size_t j0 = 0; j0 < nj; j0 += fdem::kernels::kJointBlock) {
    B.n = (int)std::min<std::size_t>(fdem::kernels::kJointBlock, nj - j0);
    GatherJointBlock(d, xl, j0, B);
    if (!d->jofs.empty()) AddBlockOffsets(d, j0, B);
    for (int b = 0; b < B.n; ++b) {
      const std::size_t j = j0 + b;
      B.law[b] = &d->jlaw[j], B.state[b] = d->jstate[j].data(), B.dissipated[b] = &d->jdiss[j];
    }
    fdem::kernels::JointBlockForces(B);
    for (int b = 0; b < B.n; ++b) {
      const std::size_t j = j0 + b;
      if (!d->jgone[j] && fdem::kernels::JointBroken(d->jstate[j].data())) { // it broke now
        FDEMJointBreak e;
        e.joint = d->jgid[j];
        e.body  = d->jbody[j];
        e.t     = t;
        for (int k = 0; k < 3; ++k) e.x[k] = (B.xa[k][b] + B.xa[3 + k][b] + B.xa[6 + k][b] + B.xb[k][b] + B.xb[3 + k][b] + B.xb[6 + k][b]) / 6;
        d->jbreaks.push_back(e);
        d->jgone[j] = 1;
      }
      const std::array<int, 3> &na = d->jnode_a[j], &nb = d->jnode_b[j];
      for (int i = 0; i < 3; ++i) {
        double *fa = fl + 3 * na[i], *fb = nb[0] >= 0 ? fl + 3 * nb[i] : nullptr;
        for (int k = 0; k < 3; ++k) {
          const double f = B.fa[3 * i + k][b];
          fa[k] += f;
          if (fb) fb[k] -= f;
          else d->jfb[9 * j + 3 * i + k] = -f;
        }
      }
    }
  }
  PetscCall(PetscSFReduceBegin(d->jsf_remote, MPIU_SCALAR, d->jfb.data(), fl, MPIU_SUM));
  PetscCall(PetscSFReduceEnd(d->jsf_remote, MPIU_SCALAR, d->jfb.data(), fl, MPIU_SUM));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetJointEnergy(FDEMDeformable d, Vec U, PetscReal *stored, PetscReal *dissipated) {
  StateView          sv;
  const PetscScalar *xl;
  PetscReal          loc[2] = {0, 0}, glob[2] = {0, 0};
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetJointEnergy"));
  if (d->njoints_global > 0) {
    PetscCall(sv.Get(d, U));
    PetscCall(LocalPositions(d, sv.xa, nullptr));
    PetscCall(sv.Restore());
    PetscCall(VecGetArrayRead(d->xloc, &xl));
    if (d->prestress_pending) PetscCall(PrestressNewJoints(d, xl));
    PetscCall(BringTrianglesB(d, d->jsf, xl));
    for (std::size_t j = 0; j < d->jnode_a.size(); ++j) {
      double xa[3][3], xb[3][3];
      JointTriangles(d, xl, j, xa, xb);
      if (!d->jofs.empty() && d->jofs[j].any()) {
        double O[3][3];
        OffsetSeparation(d, j, xa, O);
        ApplyOffset(O, xa, xb);
        loc[0] -= d->jofs[j].energy; // counted from its insertion
      }
      loc[0] += fdem::kernels::JointElementEnergy(d->jlaw[j], xa, xb, d->jstate[j].data());
      loc[1] += d->jdiss[j];
    }
    PetscCall(VecRestoreArrayRead(d->xloc, &xl));
    PetscCall(MPIU_Allreduce(loc, glob, 2, MPIU_REAL, MPIU_SUM, d->comm));
  }
  if (stored) *stored = glob[0];
  if (dissipated) *dissipated = glob[1] - d->onset; // the contact took that over from the removed joints
  PetscFunctionReturn(0);
}

// A per-joint field in the split's joint order (per values per joint), laid out by PETSc,
// and the scatter from this rank's joints into it: the rank-count independent form of the
// joints' state in checkpoints.
static PetscErrorCode JointFieldLayout(FDEMDeformable d, const char *name, PetscInt per, Vec *nat, Vec *mine, VecScatter *sc) {
  IS idx;
  PetscFunctionBegin;
  const PetscInt        n = (PetscInt)d->jgid.size();
  std::vector<PetscInt> ids(per * (size_t)n);
  for (PetscInt j = 0; j < n; ++j)
    for (PetscInt q = 0; q < per; ++q) ids[per * j + q] = per * d->jgid[j] + q;
  PetscCall(VecCreateMPI(d->comm, PETSC_DECIDE, per * d->njoints_global, nat));
  PetscCall(PetscObjectSetName((PetscObject)*nat, name));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, per * n, mine));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, per * n, ids.data(), PETSC_COPY_VALUES, &idx));
  PetscCall(VecScatterCreate(*mine, nullptr, *nat, idx, sc));
  PetscCall(ISDestroy(&idx));
  PetscFunctionReturn(0);
}

// A joint field of this model's state (per values per joint, in its joints' order): the
// damages, shear damages, last energies (tension, shear) of the three points, the energy
// dissipated, and the offsets of joints inserted under load: c[3][3] and the energy counted
// from, NaN for a joint inserted by the last load whose offset is not made yet (it is made
// when loaded).
constexpr int kOffsetValues = 10; // a joint's offset: JointOffset::c, then its energy
static const struct {
  const char *name;
  PetscInt    per;
} kJointFields[] = {{"joint_damage", 3}, {"joint_shear_damage", 3}, {"joint_last_energy", 6}, {"joint_dissipated", 1}, {"joint_offset", kOffsetValues}};
static std::vector<PetscReal> JointFieldValues(FDEMDeformable d, const std::string &name) {
  const std::size_t      n = d->jstate.size();
  std::vector<PetscReal> v;
  if (name == "joint_damage" || name == "joint_shear_damage") {
    v.resize(3 * n);
    for (std::size_t j = 0; j < n; ++j)
      for (int q = 0; q < 3; ++q) v[3 * j + q] = name == "joint_damage" ? d->jstate[j][q].D : d->jstate[j][q].shear_damage; // (D: 1 once broken)
  } else if (name == "joint_last_energy") { // the points' energies at their last evaluation (JointState)
    v.resize(6 * n);
    for (std::size_t j = 0; j < n; ++j)
      for (int q = 0; q < 3; ++q) v[6 * j + 2 * q] = d->jstate[j][q].last_tension, v[6 * j + 2 * q + 1] = d->jstate[j][q].last_shear;
  } else if (name == "joint_dissipated") v = d->jdiss;
  else if (name == "joint_offset") {
    v.assign(kOffsetValues * n, 0.0);
    for (std::size_t j = 0; j < n; ++j) {
      PetscReal *o = &v[kOffsetValues * j];
      if ((d->prestress_pending && d->jfresh[j]) || (d->equilibrate_pending && d->jequil[j])) std::fill(o, o + kOffsetValues, NAN);
      else if (!d->jofs.empty()) std::copy(&d->jofs[j].c[0][0], &d->jofs[j].c[0][0] + 9, o), o[9] = d->jofs[j].energy;
    }
  }
  return v;
}

// The field `name` of this model's joints (values: per per joint, in their order) in the
// natural layout (*nat, named `name`). Collective.
static PetscErrorCode JointFieldNatural(FDEMDeformable d, const char *name, PetscInt per, const PetscReal *values, Vec *nat) {
  Vec          mine;
  VecScatter   sc;
  PetscScalar *a;
  PetscFunctionBegin;
  PetscCall(JointFieldLayout(d, name, per, nat, &mine, &sc));
  const PetscInt n = per * (PetscInt)d->jgid.size();
  PetscCall(VecGetArray(mine, &a));
  for (PetscInt i = 0; i < n; ++i) a[i] = values[i];
  PetscCall(VecRestoreArray(mine, &a));
  PetscCall(VecScatterBegin(sc, mine, *nat, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, mine, *nat, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&mine));
  PetscFunctionReturn(0);
}

// Reads the saved field `name` into this rank's values (per per joint); checks the saved size.
// With `origin` (a state saved with fewer joints, rank 0: nold of them), each joint takes its
// origin's values, its points those of the origin's points on the same edges (per is 1 for a
// value per joint, else a multiple of 3 for per / 3 values per point), and a new joint `fresh`.
struct JointRemap {
  const std::vector<JointOrigin> *origin = nullptr;
  PetscInt                        nold   = 0;
  PetscReal                       fresh  = 0;
  bool                            whole  = false; // per values of the joint, not per / 3 of each point
};
static PetscErrorCode LoadJointField(FDEMDeformable d, const SavedState &saved, const char *name, PetscInt per, PetscReal *values, const JointRemap &remap = {}) {
  Vec          nat, mine, old = nullptr;
  VecScatter   sc;
  PetscScalar *a;
  PetscInt     N;
  PetscFunctionBegin;
  PetscCall(JointFieldLayout(d, name, per, &nat, &mine, &sc));
  if (saved.from) PetscCall(JointFieldNatural(saved.from, name, per, JointFieldValues(saved.from, name).data(), &old));
  else if (remap.origin) {
    PetscCall(VecCreate(d->comm, &old));
    PetscCall(PetscObjectSetName((PetscObject)old, name));
    PetscCall(VecLoad(old, saved.viewer));
  }
  if (remap.origin) {
    const auto &from = *remap.origin;
    PetscCall(MapFromSplit(d, old, nat, remap.nold, per, [&](const PetscScalar *o, PetscScalar *n) {
      const PetscInt w = per == 1 ? 1 : per / 3; // values per point
      for (std::size_t j = 0; j < from.size(); ++j) {
        const JointOrigin &f = from[j];
        if (f.joint < 0) {
          for (PetscInt i = 0; i < per; ++i) n[per * j + i] = remap.fresh;
        } else if (per == 1 || remap.whole) {
          for (PetscInt i = 0; i < per; ++i) n[per * j + i] = o[per * f.joint + i];
        } else {
          for (int q = 0; q < 3; ++q)
            for (PetscInt i = 0; i < w; ++i) n[per * j + w * q + i] = o[per * f.joint + w * f.point[q] + i];
        }
      }
    }));
  } else if (old) {
    PetscCall(VecGetSize(old, &N));
    if (N == per * d->njoints_global) PetscCall(VecCopy(old, nat)); // (else the check below)
  } else {
    PetscCall(VecLoad(nat, saved.viewer));
    PetscCall(VecGetSize(nat, &N));
  }
  if (remap.origin) PetscCall(VecGetSize(nat, &N));
  PetscCall(VecDestroy(&old));
  PetscCheck(N == per * d->njoints_global, d->comm, PETSC_ERR_FILE_UNEXPECTED, "FDEMDeformableLoadJointState: the saved %s has %" PetscInt_FMT " entries, this mesh has %" PetscInt_FMT " joints x %" PetscInt_FMT " (another scene?)", name, N, d->njoints_global, per);
  PetscCall(VecScatterBegin(sc, nat, mine, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(sc, nat, mine, INSERT_VALUES, SCATTER_REVERSE));
  const PetscInt n = per * (PetscInt)d->jgid.size();
  PetscCall(VecGetArray(mine, &a));
  for (PetscInt i = 0; i < n; ++i) values[i] = PetscRealPart(a[i]);
  PetscCall(VecRestoreArray(mine, &a));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&mine));
  PetscCall(VecDestroy(&nat));
  PetscFunctionReturn(0);
}

// The contact energy taken over from removed joints (DeformableAddOnset): one number, saved by
// rank 0 and read on every rank. A checkpoint written before it was kept has none: 0.
static PetscErrorCode ViewOnset(FDEMDeformable d, PetscViewer viewer) {
  Vec v;
  PetscFunctionBegin;
  PetscCall(VecCreateMPI(d->comm, d->rank == 0 ? 1 : 0, 1, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, "joint_contact_onset"));
  if (d->rank == 0) PetscCall(VecSetValue(v, 0, d->onset, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(v));
  PetscCall(VecAssemblyEnd(v));
  PetscCall(VecView(v, viewer));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

static PetscErrorCode LoadOnset(FDEMDeformable d, const SavedState &saved) {
  Vec                v;
  bool               has;
  const PetscScalar *a;
  PetscReal          e = 0;
  PetscFunctionBegin;
  d->onset = 0;
  if (saved.from) {
    d->onset = saved.from->onset;
    PetscFunctionReturn(0);
  }
  PetscCall(saved.Has("joint_contact_onset", &has));
  if (!has) PetscFunctionReturn(0);
  PetscCall(VecCreateMPI(d->comm, d->rank == 0 ? 1 : 0, 1, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, "joint_contact_onset"));
  PetscCall(VecLoad(v, saved.viewer));
  PetscCall(VecGetArrayRead(v, &a));
  if (d->rank == 0) e = PetscRealPart(a[0]);
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscCallMPI(MPI_Bcast(&e, 1, MPIU_REAL, 0, d->comm));
  PetscCall(VecDestroy(&v));
  PetscCheck(std::isfinite(e), d->comm, PETSC_ERR_FILE_UNEXPECTED, "FDEMDeformableLoadJointState: the saved joint_contact_onset is not a finite number");
  d->onset = e;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableViewJointState(FDEMDeformable d, PetscViewer viewer) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableViewJointState"));
  PetscCall(ViewInsertedCells(d, viewer));
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  for (const auto &f : kJointFields) {
    Vec nat;
    PetscCall(JointFieldNatural(d, f.name, f.per, JointFieldValues(d, f.name).data(), &nat));
    PetscCall(VecView(nat, viewer));
    PetscCall(VecDestroy(&nat));
  }
  PetscCall(ViewOnset(d, viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableLoadJointState(FDEMDeformable d, PetscViewer viewer) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableLoadJointState"));
  PetscCall(LoadJointState(d, SavedState{viewer, nullptr}));
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::LoadJointState(FDEMDeformable d, const SavedState &saved) {
  PetscFunctionBegin;
  d->topology_made = false; // (the joints' damage may go down)
  if (d->njoints_global == 0) PetscFunctionReturn(0);
  // a state saved with fewer tetrahedra split (joints inserted since): the joints it had keep
  // their state, the others start intact
  std::vector<PetscInt>    old;
  std::vector<JointOrigin> origin;
  bool                     differs;
  PetscInt                 nold = 0;
  PetscCall(SavedSplitDiffers(d, saved, old, &differs));
  if (differs) {
    PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
      if (d->rank == 0) JointOrigins(d, old, origin, &nold);
      return 0;
    }));
    PetscCallMPI(MPI_Bcast(&nold, 1, MPIU_INT, 0, d->comm));
  }
  d->jofs.clear();
  d->prestress_pending = d->equilibrate_pending = false;
  std::fill(d->jfresh.begin(), d->jfresh.end(), 0);
  if (differs && nold == 0) { // no joint was saved: all start intact (or at their faces' tractions), nothing dissipated
    for (std::size_t j = 0; j < d->jstate.size(); ++j) {
      for (int q = 0; q < 3; ++q) d->jstate[j][q] = fdem::kernels::JointState{};
      d->jdiss[j]  = 0;
      d->jgone[j]  = 0;
      d->jfresh[j] = d->prestress;
    }
    d->prestress_pending = d->prestress;
    PetscCall(LoadOnset(d, saved));
    PetscFunctionReturn(0);
  }
  const JointRemap       rm0{differs ? &origin : nullptr, nold, 0.0}, rm1{differs ? &origin : nullptr, nold, -1.0};
  const JointRemap       rmw{differs ? &origin : nullptr, nold, 0.0, true};
  std::vector<PetscReal> D(3 * d->jstate.size()), W(3 * d->jstate.size(), 0.0), O(kOffsetValues * d->jstate.size(), 0.0);
  PetscCall(LoadJointField(d, saved, "joint_damage", 3, D.data(), rm1)); // -1: a joint the saved split did not have
  bool has;
  PetscCall(saved.Has("joint_offset", &has));
  if (has) PetscCall(LoadJointField(d, saved, "joint_offset", kOffsetValues, O.data(), rmw)); // (an earlier fdem's checkpoint has none: no offsets)
  // A checkpoint written before the shear damage was kept has none: the joints' shear then
  // restarts from zero, and their first evaluation raises it to the law's secant, the same
  // tractions as the law without the secant at the positions saved.
  PetscCall(saved.Has("joint_shear_damage", &has));
  if (has) PetscCall(LoadJointField(d, saved, "joint_shear_damage", 3, W.data(), rm0));
  else PetscCall(PetscPrintf(d->comm, "Note: the checkpoint has no joint_shear_damage (written by an earlier fdem); the joints' shear damage restarts from their law\n"));
  // The points' energies at their last evaluation, for the release of damage at the step's
  // middle. Without them (an earlier fdem's checkpoint) each point takes its first step's
  // release at that step's end.
  std::vector<PetscReal> E(6 * d->jstate.size(), -1.0);
  PetscCall(saved.Has("joint_last_energy", &has));
  if (has) PetscCall(LoadJointField(d, saved, "joint_last_energy", 6, E.data(), rm1));
  else PetscCall(PetscPrintf(d->comm, "Note: the checkpoint has no joint_last_energy (written by an earlier fdem); each joint point takes its first step's release of energy at the step's end\n"));
  PetscCall(LoadJointField(d, saved, "joint_dissipated", 1, d->jdiss.data(), rm0));
  PetscCall(LoadOnset(d, saved));
  PetscInt bad = -1;
  bool     any = false;
  for (std::size_t j = 0; j < d->jstate.size(); ++j) {
    // a joint new to this split, or one saved before its offset was made, gets its offset
    // at the next evaluation (with -fdem_insert_prestress)
    PetscReal *o     = &O[kOffsetValues * j];
    const bool fresh = D[3 * j] == -1 || std::isnan(o[0]);
    d->jfresh[j]     = fresh && d->prestress;
    for (int q = 0; q < kOffsetValues; ++q) {
      if (fresh) o[q] = 0;
      if (!std::isfinite(o[q]) && bad < 0) bad = d->jgid[j];
      any = any || (q < 9 && o[q] != 0);
    }
    any = any || d->jfresh[j];
    for (int q = 0; q < 3; ++q) {
      if (D[3 * j + q] == -1) D[3 * j + q] = 0;
      const PetscReal v = D[3 * j + q], w = W[3 * j + q];
      if (!(v >= 0 && v <= 1 && w >= 0 && w <= 1) && bad < 0) bad = d->jgid[j];
      d->jstate[j][q].SetDamage(v);
      d->jstate[j][q].shear_damage = (float)w;
      const PetscReal et = E[6 * j + 2 * q], es = E[6 * j + 2 * q + 1];
      const bool      ok = (et == -1 || (et >= 0 && std::isfinite(et))) && (es == -1 || (es >= 0 && std::isfinite(es)));
      if (!ok && bad < 0) bad = d->jgid[j];
      d->jstate[j][q].last_tension = (float)et, d->jstate[j][q].last_shear = (float)es; // -1: none
    }
    d->jgone[j] = fdem::kernels::JointBroken(d->jstate[j].data()); // not reported as a break
    if (!(d->jdiss[j] >= 0) && bad < 0) bad = d->jgid[j];
  }
  if (any) {
    d->jofs.assign(d->jstate.size(), {});
    for (std::size_t j = 0; j < d->jstate.size(); ++j) std::copy(&O[kOffsetValues * j], &O[kOffsetValues * j] + 9, &d->jofs[j].c[0][0]), d->jofs[j].energy = O[kOffsetValues * j + 9];
  }
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_INT, MPI_MAX, d->comm));
  PetscCheck(bad < 0, d->comm, PETSC_ERR_FILE_UNEXPECTED, "FDEMDeformableLoadJointState: joint %" PetscInt_FMT " has a damage or shear damage outside [0, 1], a negative dissipated or last energy, or an offset that is not a finite number, in the saved state", bad);
  PetscInt pend = 0;
  for (char f : d->jfresh) pend |= f;
  PetscCallMPI(MPIU_Allreduce(MPI_IN_PLACE, &pend, 1, MPIU_INT, MPI_MAX, d->comm));
  d->prestress_pending = pend != 0;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetJointBreaks(FDEMDeformable d, PetscInt *count, FDEMJointBreak *breaks[]) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetJointBreaks"));
  // every rank's records, as bytes (the same struct on every rank), to every rank
  const PetscMPIInt        mine = (PetscMPIInt)(d->jbreaks.size() * sizeof(FDEMJointBreak));
  std::vector<PetscMPIInt> bytes(d->size), off(d->size + 1, 0);
  PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, bytes.data(), 1, MPI_INT, d->comm));
  for (int r = 0; r < d->size; ++r) off[r + 1] = off[r] + bytes[r];
  const PetscInt n = (PetscInt)(off[d->size] / sizeof(FDEMJointBreak));
  std::vector<FDEMJointBreak> all(n);
  PetscCallMPI(MPI_Allgatherv(d->jbreaks.data(), mine, MPI_BYTE, all.data(), bytes.data(), off.data(), MPI_BYTE, d->comm));
  d->jbreaks.clear();
  std::sort(all.begin(), all.end(), [](const FDEMJointBreak &a, const FDEMJointBreak &b) { return a.t < b.t || (a.t == b.t && a.joint < b.joint); });
  *count = n;
  if (breaks) {
    PetscCall(PetscMalloc1(n, breaks));
    std::copy(all.begin(), all.end(), *breaks);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode fdem::model::deformable::DestroyJoints(FDEMDeformable d) {
  PetscFunctionBegin;
  PetscCall(PetscSFDestroy(&d->jsf));
  PetscCall(PetscSFDestroy(&d->jsf_remote));
  PetscCall(PetscSFDestroy(&d->jfsf));
  PetscCall(PetscSFDestroy(&d->share_sf));
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableAddFractureZone(FDEMDeformable d, const char *body, const PetscReal lo[3], const PetscReal hi[3]) {
  PetscFunctionBegin;
  PetscCheck(body && body[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableAddFractureZone: the body needs a name");
  PetscCheck(lo && hi, d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableAddFractureZone: give the zone's corners lo and hi");
  PetscCall(CheckNotSetUp(d, "FDEMDeformableAddFractureZone"));
  for (int k = 0; k < 3; ++k)
    PetscCheck(std::isfinite(lo[k]) && std::isfinite(hi[k]) && lo[k] <= hi[k], d->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "FDEMDeformableAddFractureZone: body '%s': the zone [%g, %g, %g] to [%g, %g, %g] must have finite corners with lo <= hi in each coordinate", body, (double)lo[0], (double)lo[1], (double)lo[2], (double)hi[0], (double)hi[1], (double)hi[2]);
  d->fracture_zones[body].push_back({lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableSetMaterialFracture(FDEMDeformable d, const char *material, PetscReal tensile_strength, PetscReal cohesion, PetscReal friction_angle, PetscReal GI, PetscReal GII, PetscReal joint_penalty) {
  PetscFunctionBegin;
  PetscCheck(material && material[0], d->comm, PETSC_ERR_ARG_NULL, "FDEMDeformableSetMaterialFracture: the material needs a name");
  PetscCall(CheckNotSetUp(d, "FDEMDeformableSetMaterialFracture"));
  bool known = false;
  for (const auto &m : d->materials) known = known || m.name == material;
  PetscCheck(known, d->comm, PETSC_ERR_ARG_WRONG, "FDEMDeformableSetMaterialFracture: no material '%s' (add it first with FDEMDeformableAddMaterial)", material);
  fdem::kernels::JointMaterial m;
  m.name             = material;
  m.tensile_strength = tensile_strength;
  m.cohesion         = cohesion;
  m.friction_angle   = friction_angle;
  m.GI               = GI;
  m.GII              = GII;
  m.penalty          = joint_penalty;
  // the law's own checks of the material (element size 0 is not checked here: any positive size)
  PetscCall(fdem::Guard(d->comm, [&]() -> PetscErrorCode {
    (void)fdem::kernels::MakeJointLaw(m, 1e-30);
    return 0;
  }));
  d->fracture[material] = m;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetJointFrequency(FDEMDeformable d, PetscReal *omega) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetJointFrequency"));
  *omega = d->joint_omega;
  PetscFunctionReturn(0);
}

PetscErrorCode FDEMDeformableGetJointStats(FDEMDeformable d, PetscInt *joints, PetscInt *broken, PetscReal *max_damage) {
  PetscFunctionBegin;
  PetscCall(CheckSetUp(d, "FDEMDeformableGetJointStats"));
  PetscInt  nb = 0;
  PetscReal D  = 0;
  for (const auto &st : d->jstate) {
    bool all = true;
    for (const auto &p : st) {
      all = all && p.broken();
      D   = std::fmax(D, p.D);
    }
    nb += all ? 1 : 0;
  }
  if (broken) PetscCallMPI(MPI_Allreduce(&nb, broken, 1, MPIU_INT, MPI_SUM, d->comm));
  if (max_damage) PetscCallMPI(MPI_Allreduce(&D, max_damage, 1, MPIU_REAL, MPI_MAX, d->comm));
  if (joints) *joints = d->njoints_global;
  PetscFunctionReturn(0);
}
