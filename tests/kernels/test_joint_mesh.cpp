// Fracturable meshes (fdem/kernels/joint_mesh.hpp, doc/fracture.md): every
// tetrahedron of a split body gets its own nodes, every interior face of it
// becomes one joint of two coincident, correctly ordered triangles; other
// bodies are untouched; the joints of an undeformed or rigidly moved body
// carry no force.
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/joint.hpp>
#include <fdem/kernels/joint_mesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace fdem::kernels;

namespace {
TetMesh TwoBoxes() {
  TetMesh a = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 3, 2, 2);
  const TetMesh b = MakeBoxMesh({2, 0, 0}, {3, 1, 1}, 2, 2, 1);
  const int off = static_cast<int>(a.nodes.size());
  a.body.assign(a.tets.size(), 0);
  for (const auto &p : b.nodes) a.nodes.push_back(p);
  for (auto t : b.tets) {
    for (int &n : t) n += off;
    a.tets.push_back(t);
    a.body.push_back(1);
  }
  a.body_names = {"split", "whole"};
  return a;
}
JointMaterial Mortar() {
  JointMaterial m;
  m.name = "mortar";
  m.tensile_strength = 1e6, m.cohesion = 3e6, m.friction_angle = 30, m.GI = 10, m.GII = 50, m.penalty = 1e11;
  return m;
}
Vec3 Centroid(const TetMesh &m, int t) {
  return 0.25 * (m.nodes[m.tets[t][0]] + m.nodes[m.tets[t][1]] + m.nodes[m.tets[t][2]] + m.nodes[m.tets[t][3]]);
}
} // namespace

TEST(JointMesh, SplitsOneBodyIntoJoints) {
  const TetMesh m = TwoBoxes();
  const SplitMesh s = SplitForJoints(m, {1, 0});
  const int nt = static_cast<int>(m.tets.size()), nt0 = 6 * 3 * 2 * 2;
  ASSERT_EQ(s.mesh.tets.size(), m.tets.size());
  EXPECT_EQ(s.mesh.body, m.body);
  // nodes: four per split tetrahedron, the unsplit body's nodes once each (3 x 3 x 2 grid)
  EXPECT_EQ(s.mesh.nodes.size(), static_cast<std::size_t>(4 * nt0 + 3 * 3 * 2));
  ASSERT_EQ(s.parent.size(), s.mesh.nodes.size());
  for (std::size_t i = 0; i < s.parent.size(); ++i) EXPECT_EQ(norm(s.mesh.nodes[i] - m.nodes[s.parent[i]]), 0.0);
  for (int t = 0; t < nt; ++t) {
    EXPECT_NEAR(TetSignedVolume(s.mesh, t), TetSignedVolume(m, t), 1e-15) << "tet " << t;
    for (int j = 0; j < 4; ++j) EXPECT_EQ(s.parent[s.mesh.tets[t][j]], m.tets[t][j]);
  }
  // each split tetrahedron is its own component; the whole body is one
  int ncomp = 0;
  ConnectedComponents(s.mesh, &ncomp);
  EXPECT_EQ(ncomp, nt0 + 1);
  // joints: the interior faces of the split body, (4 n - boundary faces) / 2
  TetMesh first = m;
  first.tets.resize(nt0);
  first.body.resize(nt0);
  const int boundary = static_cast<int>(SurfaceTets(first).faces.size());
  EXPECT_EQ(boundary, 2 * 2 * (3 * 2 + 3 * 2 + 2 * 2)); // two triangles per square of the box's surface
  ASSERT_EQ(static_cast<int>(s.joints.size()), (4 * nt0 - boundary) / 2);
  std::set<std::array<int, 3>> seen;
  for (const JointFace &j : s.joints) {
    ASSERT_LT(j.tet_a, nt0);
    ASSERT_LT(j.tet_b, nt0);
    ASSERT_NE(j.tet_a, j.tet_b);
    std::array<int, 3> key{s.parent[j.a[0]], s.parent[j.a[1]], s.parent[j.a[2]]};
    std::sort(key.begin(), key.end());
    EXPECT_TRUE(seen.insert(key).second) << "a face joined twice";
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(norm(s.mesh.nodes[j.a[i]] - s.mesh.nodes[j.b[i]]), 0.0); // coincident, in order
      EXPECT_EQ(s.parent[j.a[i]], s.parent[j.b[i]]);
      const auto &ta = s.mesh.tets[j.tet_a], &tb = s.mesh.tets[j.tet_b];
      EXPECT_NE(std::find(ta.begin(), ta.end(), j.a[i]), ta.end()); // a's nodes are tet_a's own
      EXPECT_NE(std::find(tb.begin(), tb.end(), j.b[i]), tb.end());
    }
    // a's right-hand normal points out of tet_a, into tet_b
    const Vec3 n = cross(s.mesh.nodes[j.a[1]] - s.mesh.nodes[j.a[0]], s.mesh.nodes[j.a[2]] - s.mesh.nodes[j.a[0]]);
    EXPECT_GT(dot(n, Centroid(s.mesh, j.tet_b) - Centroid(s.mesh, j.tet_a)), 0);
    EXPECT_LT(dot(n, Centroid(s.mesh, j.tet_a) - s.mesh.nodes[j.a[0]]), 0);
  }
  // boundary faces of the split mesh: every face of a split tetrahedron, and the whole body's surface
  EXPECT_EQ(SurfaceTets(s.mesh).faces.size(), static_cast<std::size_t>(4 * nt0 + 2 * 2 * (2 * 2 + 2 * 1 + 2 * 1)));
}

// A fracture zone: only the tetrahedra flagged (the first box's cubes with x < 1/3, its
// first column) get nodes of their own; the rest of that body keeps shared nodes. Every
// face between a flagged tetrahedron and another of the body is a joint, triangle a on the
// flagged side; faces between two unflagged ones are not.
TEST(JointMesh, ZoneSplitsOnlyFlaggedTetrahedra) {
  const TetMesh m = TwoBoxes();
  const int nt = static_cast<int>(m.tets.size()), nt0 = 6 * 3 * 2 * 2;
  std::vector<char> zone(nt, 0);
  int nz = 0;
  for (int t = 0; t < nt; ++t) nz += zone[t] = m.body[t] == 0 && Centroid(m, t).x < 1.0 / 3;
  ASSERT_EQ(nz, 6 * 2 * 2);
  const SplitMesh s = SplitForJoints(m, {1, 0}, zone);
  EXPECT_EQ(s.split, zone); // the tetrahedra that got nodes of their own (the partition weighs them)
  // nodes: four per flagged tetrahedron, and each input node used by an unflagged one once
  std::set<int> kept;
  for (int t = 0; t < nt; ++t)
    if (!zone[t]) kept.insert(m.tets[t].begin(), m.tets[t].end());
  EXPECT_EQ(s.mesh.nodes.size(), 4 * static_cast<std::size_t>(nz) + kept.size());
  for (int t = 0; t < nt; ++t)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(s.parent[s.mesh.tets[t][j]], m.tets[t][j]);
  // joints: the faces of body 0 held by two tetrahedra with one flagged at least, counted
  // from the input mesh's faces
  const std::vector<TetFace> faces = SortedFaces(m.tets);
  int expect = 0, interface = 0;
  for (std::size_t i = 0; i + 1 < faces.size(); ++i)
    if (faces[i].key == faces[i + 1].key && m.body[faces[i].tet] == 0 && (zone[faces[i].tet] || zone[faces[i + 1].tet])) {
      ++expect;
      interface += zone[faces[i].tet] != zone[faces[i + 1].tet];
    }
  EXPECT_EQ(interface, 2 * 2 * 2); // the plane x = 1/3: two triangles per square of a 2 x 2 grid
  ASSERT_EQ(static_cast<int>(s.joints.size()), expect);
  int across = 0;
  for (const JointFace &j : s.joints) {
    ASSERT_LT(j.tet_a, nt0);
    ASSERT_LT(j.tet_b, nt0);
    EXPECT_TRUE(zone[j.tet_a]) << "triangle a on an unsplit tetrahedron";
    across += !zone[j.tet_b];
    const auto &tb = s.mesh.tets[j.tet_b];
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(norm(s.mesh.nodes[j.a[i]] - s.mesh.nodes[j.b[i]]), 0.0);
      EXPECT_NE(std::find(tb.begin(), tb.end(), j.b[i]), tb.end());
    }
    const Vec3 n = cross(s.mesh.nodes[j.a[1]] - s.mesh.nodes[j.a[0]], s.mesh.nodes[j.a[2]] - s.mesh.nodes[j.a[0]]);
    EXPECT_GT(dot(n, Centroid(s.mesh, j.tet_b) - Centroid(s.mesh, j.tet_a)), 0);
  }
  EXPECT_EQ(across, interface);
  // components: each flagged tetrahedron alone, the rest of body 0 one piece, body 1 one piece
  int ncomp = 0;
  ConnectedComponents(s.mesh, &ncomp);
  EXPECT_EQ(ncomp, nz + 2);
  // all flags set is the split of the whole body; a wrong number of flags is an error
  const SplitMesh all = SplitForJoints(m, {1, 0}, std::vector<char>(nt, 1)), whole = SplitForJoints(m, {1, 0});
  EXPECT_EQ(all.mesh.nodes.size(), whole.mesh.nodes.size());
  ASSERT_EQ(all.joints.size(), whole.joints.size());
  for (std::size_t j = 0; j < all.joints.size(); ++j) EXPECT_EQ(all.joints[j].a, whole.joints[j].a);
  EXPECT_THROW(SplitForJoints(m, {1, 0}, std::vector<char>(nt - 1, 1)), InputError);
}

// SplitMesh::boundary, which the model's contact takes for its surface instead of sorting
// every face of the split mesh again: each bit is a face that no other tetrahedron of the split
// mesh holds, counted here from the split mesh's own faces (whole split, a zone, nothing split).
TEST(JointMesh, BoundaryBitsAreTheSplitMeshFacesHeldOnce) {
  const TetMesh m = TwoBoxes();
  const int nt = static_cast<int>(m.tets.size());
  std::vector<char> zone(nt, 0);
  for (int t = 0; t < nt; ++t) zone[t] = m.body[t] == 0 && Centroid(m, t).x < 1.0 / 3;
  for (const SplitMesh &s : {SplitForJoints(m, {1, 0}), SplitForJoints(m, {1, 0}, zone), SplitForJoints(m, {0, 0}), SplitForJoints(m, {1, 1})}) {
    ASSERT_EQ(static_cast<int>(s.boundary.size()), nt);
    std::vector<char> expect(nt, 0);
    const std::vector<TetFace> faces = SortedFaces(s.mesh.tets);
    for (std::size_t i = 0; i < faces.size();) {
      std::size_t j = i + 1;
      while (j < faces.size() && faces[j].key == faces[i].key) ++j;
      if (j - i == 1) expect[faces[i].tet] |= static_cast<char>(1 << faces[i].local);
      i = j;
    }
    int nb = 0;
    for (int t = 0; t < nt; ++t) {
      EXPECT_EQ(s.boundary[t], expect[t]) << "tetrahedron " << t;
      for (int k = 0; k < 4; ++k) nb += expect[t] >> k & 1;
    }
    EXPECT_GT(nb, 0);
  }
}

TEST(JointMesh, NothingToSplit) {
  const TetMesh m = TwoBoxes();
  const SplitMesh s = SplitForJoints(m, {0, 0});
  EXPECT_TRUE(s.joints.empty());
  EXPECT_EQ(s.mesh.nodes.size(), m.nodes.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int j = 0; j < 4; ++j) EXPECT_EQ(s.parent[s.mesh.tets[t][j]], m.tets[t][j]);
  EXPECT_THROW(SplitForJoints(m, {1}), InputError);
}

// The joints of a split body moved rigidly (a rotation and a shift of every
// node) or strained uniformly, coincident nodes kept together: no force, no damage.
TEST(JointMesh, JointsOfAnIntactMotionCarryNoForce) {
  const SplitMesh s = SplitForJoints(MakeBoxMesh({0, 0, 0}, {0.1, 0.1, 0.2}, 2, 2, 4), {1});
  const JointMaterial mat = Mortar();
  const JointLaw law = MakeJointLaw(mat, 0.05);
  const double c = std::cos(0.7), sn = std::sin(0.7);
  auto rigid = [&](const Vec3 &p) { return Vec3{c * p.x - sn * p.y + 0.3, sn * p.x + c * p.y, p.z - 1.0}; };
  auto strain = [&](const Vec3 &p) { return Vec3{1.001 * p.x + 0.0005 * p.z, 0.999 * p.y, 1.002 * p.z}; };
  for (int motion = 0; motion < 2; ++motion) {
    double worst = 0, damage = 0;
    for (const JointFace &j : s.joints) {
      double xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
      for (int i = 0; i < 3; ++i) {
        const Vec3 pa = motion ? strain(s.mesh.nodes[j.a[i]]) : rigid(s.mesh.nodes[j.a[i]]);
        const Vec3 pb = motion ? strain(s.mesh.nodes[j.b[i]]) : rigid(s.mesh.nodes[j.b[i]]);
        xa[i][0] = pa.x, xa[i][1] = pa.y, xa[i][2] = pa.z;
        xb[i][0] = pb.x, xb[i][1] = pb.y, xb[i][2] = pb.z;
      }
      JointState st[3];
      damage = std::fmax(damage, JointElementForces(law, xa, xb, st, fa, fb));
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) worst = std::fmax(worst, std::fmax(std::fabs(fa[i][k]), std::fabs(fb[i][k])));
    }
    EXPECT_EQ(worst, 0.0) << (motion ? "uniform strain" : "rigid motion");
    EXPECT_EQ(damage, 0.0);
  }
}

// The upper half of a split column lifted by half the peak opening: the joints
// of the cut plane z = 0.1 open uniformly, the others not at all, and the pull
// on the upper half is 0.75 f_t times the cross-section (the hardening branch
// at x = 1/2), whichever side of a joint is its triangle a.
TEST(JointMesh, CutPlaneOpensUniformly) {
  const SplitMesh s = SplitForJoints(MakeBoxMesh({0, 0, 0}, {0.1, 0.1, 0.2}, 3, 3, 4), {1});
  const JointMaterial mat = Mortar();
  const JointLaw law = MakeJointLaw(mat, 0.05);
  const double lift = 0.5 * law.dn_peak;
  std::vector<Vec3> x = s.mesh.nodes;
  std::vector<char> upper(s.mesh.tets.size());
  for (std::size_t t = 0; t < s.mesh.tets.size(); ++t) {
    upper[t] = Centroid(s.mesh, static_cast<int>(t)).z > 0.1;
    if (upper[t])
      for (int n : s.mesh.tets[t]) x[n].z += lift;
  }
  Vec3 pull{};
  int cut = 0;
  for (const JointFace &j : s.joints) {
    double xa[3][3], xb[3][3], fa[3][3] = {}, fb[3][3] = {};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) xa[i][k] = x[j.a[i]][k], xb[i][k] = x[j.b[i]][k];
    JointState st[3];
    JointElementForces(law, xa, xb, st, fa, fb);
    if (upper[j.tet_a] == upper[j.tet_b]) {
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(fa[i][k], 0.0);
      continue;
    }
    ++cut;
    for (int i = 0; i < 3; ++i) pull += upper[j.tet_a] ? Vec3{fa[i][0], fa[i][1], fa[i][2]} : Vec3{fb[i][0], fb[i][1], fb[i][2]};
  }
  EXPECT_EQ(cut, 2 * 3 * 3); // two triangles per square of the cut
  EXPECT_NEAR(pull.z, -0.75 * mat.tensile_strength * 0.01, 1e-9 * mat.tensile_strength * 0.01);
  EXPECT_NEAR(pull.x, 0.0, 1e-9 * mat.tensile_strength * 0.01);
  EXPECT_NEAR(pull.y, 0.0, 1e-9 * mat.tensile_strength * 0.01);
}

// A fracturable body's mesh must be conforming; each kind of non-conformity is named.
namespace {
// Two boxes side by side at x = 1 in one body; nodes at the same place merged when merge.
TetMesh Glued(int n_right, bool merge) {
  TetMesh a = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 1, 1, 1);
  const TetMesh b = MakeBoxMesh({1, 0, 0}, {2, 1, 1}, n_right, n_right, n_right);
  std::vector<int> id(b.nodes.size());
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    id[i] = -1;
    for (std::size_t k = 0; merge && k < a.nodes.size() && id[i] < 0; ++k)
      if (norm(a.nodes[k] - b.nodes[i]) < 1e-12) id[i] = static_cast<int>(k);
    if (id[i] < 0) {
      id[i] = static_cast<int>(a.nodes.size());
      a.nodes.push_back(b.nodes[i]);
    }
  }
  for (auto t : b.tets) {
    for (int &n : t) n = id[n];
    a.tets.push_back(t);
  }
  a.body.assign(a.tets.size(), 0);
  a.body_names = {"wall"};
  return a;
}
void ExpectSplitError(const TetMesh &m, const std::string &text) {
  try {
    SplitForJoints(m, {1});
    ADD_FAILURE() << "no error, expected: " << text;
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}
} // namespace

TEST(JointMesh, NonConformingMeshesAreNamed) {
  // conforming: the two boxes share the nodes of their common face -> joints across it
  const SplitMesh ok = SplitForJoints(Glued(1, true), {1});
  EXPECT_EQ(ok.joints.size(), 6u + 6u + 2u) << "each cube has 6 inner faces, and the shared face is 2 triangles";
  // the same boxes with their own nodes on the common face: nothing would hold them together
  ExpectSplitError(Glued(1, false), "touch across a face whose nodes they do not share");
  // hanging nodes: a 2 x 2 x 2 box against one cube, the cube's face corners shared
  ExpectSplitError(Glued(2, true), "fracturable body 'wall': element ");
  // three tetrahedra on one face
  TetMesh fan;
  fan.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}};
  fan.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  fan.body = {0, 0, 0};
  fan.body_names = {"fan"};
  ExpectSplitError(fan, "is held by 3 tetrahedra (element 0, element 1, element 2)");
  // the same meshes in a body that is not fracturable: nothing is checked (no joints to make)
  EXPECT_NO_THROW(SplitForJoints(Glued(2, true), {0}));
}
