// Tests of the tetrahedral mesh utilities: generators, Gmsh reader, topology.
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

using namespace fdem::kernels;

namespace {

const double kPi = std::acos(-1.0);

// Checks that the mesh is conforming (every face in one or two tetrahedra,
// shared faces with opposite orientations) and that its boundary is closed
// (every boundary edge used once in each direction). Returns the volume by the
// divergence theorem over the boundary, (1/3) sum centroid . area vector.
double CheckConformingClosed(const TetMesh &m) {
  static const int F[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, std::vector<std::array<int, 3>>> faces;
  for (const auto &t : m.tets)
    for (const auto &f : F) {
      std::array<int, 3> o{t[f[0]], t[f[1]], t[f[2]]}, k = o;
      std::sort(k.begin(), k.end());
      faces[k].push_back(o);
    }
  auto cyclic_equal = [](const std::array<int, 3> &a, const std::array<int, 3> &b) {
    for (int s = 0; s < 3; ++s)
      if (a[0] == b[s] && a[1] == b[(s + 1) % 3] && a[2] == b[(s + 2) % 3]) return true;
    return false;
  };
  std::map<std::pair<int, int>, int> edges;  // directed boundary edges
  for (const auto &kv : faces) {
    EXPECT_LE(kv.second.size(), 2u) << "face shared by more than two tetrahedra";
    if (kv.second.size() == 2) {
      const auto &a = kv.second[0], &b = kv.second[1];
      EXPECT_TRUE(cyclic_equal(a, {b[0], b[2], b[1]})) << "shared face with equal orientations";
    }
  }
  const SurfaceInfo s = SurfaceTets(m);
  Vec3 sum_area{};
  double vol = 0;
  for (const auto &f : s.faces) {
    for (int e = 0; e < 3; ++e) edges[{f[e], f[(e + 1) % 3]}]++;
    const Vec3 a = 0.5 * cross(m.nodes[f[1]] - m.nodes[f[0]], m.nodes[f[2]] - m.nodes[f[0]]);
    sum_area += a;
    vol += dot((m.nodes[f[0]] + m.nodes[f[1]] + m.nodes[f[2]]) / 3.0, a) / 3.0;
  }
  for (const auto &kv : edges) {
    EXPECT_EQ(kv.second, 1) << "boundary edge used twice in one direction";
    auto it = edges.find({kv.first.second, kv.first.first});
    EXPECT_TRUE(it != edges.end() && it->second == 1) << "open boundary edge";
  }
  EXPECT_LT(norm(sum_area), 1e-12);
  return vol;
}

double MinVolume(const TetMesh &m) {
  double v = 1e300;
  for (int t = 0; t < static_cast<int>(m.tets.size()); ++t) v = std::min(v, TetSignedVolume(m, t));
  return v;
}

} // namespace

TEST(TetMesh, BoxMeshIsPositiveConformingClosedAndExact) {
  const TetMesh m = MakeBoxMesh({-1, 0.5, 2}, {2, 1.5, 4.5}, 3, 4, 5);
  EXPECT_EQ(m.nodes.size(), 4u * 5u * 6u);
  EXPECT_EQ(m.tets.size(), 6u * 3 * 4 * 5);
  EXPECT_EQ(m.body.size(), m.tets.size());
  EXPECT_EQ(m.NumBodies(), 1);
  EXPECT_GT(MinVolume(m), 0.0);
  const double V = 3.0 * 1.0 * 2.5;
  EXPECT_NEAR(TotalVolume(m), V, 1e-13 * V);
  EXPECT_NEAR(CheckConformingClosed(m), V, 1e-12 * V);
  // Boundary: each of the 2(nx ny + ny nz + nx nz) square cells is cut into 2 triangles.
  EXPECT_EQ(SurfaceTets(m).faces.size(), 2u * 2 * (3 * 4 + 4 * 5 + 3 * 5));
  // All Kuhn tetrahedra have the same volume h^3/6.
  EXPECT_NEAR(MinVolume(m), V / m.tets.size(), 1e-14);
}

TEST(TetMesh, BeamMeshHasProportionalCounts) {
  const TetMesh m = MakeBeamMesh(10.0, 1.0, 2.0, 3);  // h = 1/3: 30 x 3 x 6 cells
  EXPECT_EQ(m.tets.size(), 6u * 30 * 3 * 6);
  EXPECT_NEAR(TotalVolume(m), 20.0, 1e-12);
  EXPECT_GT(MinVolume(m), 0.0);
  EXPECT_EQ(m.body_names[0], "beam");
}

TEST(TetMesh, CylinderMeshVolumeIsThePolygonPrism) {
  for (int nr : {1, 2, 5}) {
    const double R = 0.7, H = 2.0;
    const TetMesh m = MakeCylinderMesh(R, H, nr, 4);
    const int n = 6 * nr;
    const double V = H * 0.5 * n * R * R * std::sin(2 * kPi / n);
    EXPECT_GT(MinVolume(m), 0.0) << "n_radial " << nr;
    EXPECT_NEAR(TotalVolume(m), V, 1e-13 * V) << "n_radial " << nr;
    EXPECT_NEAR(CheckConformingClosed(m), V, 1e-12 * V) << "n_radial " << nr;
    EXPECT_EQ(m.tets.size(), 3u * 4 * (6u * nr * nr));  // 6 nr^2 triangles per layer
    for (const auto &p : m.nodes) EXPECT_LE(std::hypot(p.x, p.y), R * (1 + 1e-14));
  }
  // Converges to pi R^2 H (polygon area error ~ (2 pi / n)^2 / 6).
  const TetMesh fine = MakeCylinderMesh(1.0, 1.0, 20, 1);
  EXPECT_NEAR(TotalVolume(fine), kPi, 2e-3);
}

TEST(TetMesh, GeneratorsRejectBadArguments) {
  EXPECT_THROW(MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 0, 1, 1), InputError);
  EXPECT_THROW(MakeBoxMesh({0, 0, 0}, {1, -1, 1}, 1, 1, 1), InputError);
  EXPECT_THROW(MakeCylinderMesh(-1, 1, 2, 2), InputError);
  EXPECT_THROW(MakeBeamMesh(1, 1, 1, 0), InputError);
}

TEST(TetMesh, OrientTetsFlipsNegativeAndRejectsDegenerate) {
  TetMesh m = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  int expected = 0;
  for (std::size_t t = 0; t < m.tets.size(); t += 3, ++expected) std::swap(m.tets[t][0], m.tets[t][3]);
  EXPECT_EQ(OrientTets(m), expected);
  EXPECT_GT(MinVolume(m), 0.0);
  EXPECT_EQ(OrientTets(m), 0);
  m.body.assign(m.tets.size(), 0);
  m.body[7] = 3;
  m.nodes.push_back({0.5, 0.5, 0.5});  // nodes 0..26 exist; make tet 7 flat
  m.tets[7] = {0, 1, 2, static_cast<int>(m.nodes.size()) - 1};
  m.nodes[m.tets[7][3]] = 0.5 * (m.nodes[0] + m.nodes[1]);
  try {
    OrientTets(m);
    FAIL() << "degenerate tetrahedron accepted";
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find("body 3, element 7"), std::string::npos) << e.what();
  }
}

TEST(TetMesh, LumpedMassesSumToRhoVolumePerBody) {
  TetMesh a = MakeBoxMesh({0, 0, 0}, {1, 2, 3}, 2, 3, 2);
  const TetMesh b = MakeCylinderMesh(0.5, 1.0, 3, 2);
  // Merge b (shifted) as body 1.
  const int off = static_cast<int>(a.nodes.size());
  for (auto p : b.nodes) a.nodes.push_back(p + Vec3{5, 0, 0});
  for (auto t : b.tets) {
    for (int &n : t) n += off;
    a.tets.push_back(t);
    a.body.push_back(1);
  }
  a.body_names.push_back("cyl");
  const std::vector<double> m = LumpedMasses(a, {2.0, 7.0});
  double m0 = 0, m1 = 0;
  for (int i = 0; i < off; ++i) m0 += m[i];
  for (std::size_t i = off; i < m.size(); ++i) m1 += m[i];
  EXPECT_NEAR(m0, 2.0 * 6.0, 1e-12);
  EXPECT_NEAR(m1, 7.0 * TotalVolume(b), 1e-12);
  for (double q : m) EXPECT_GT(q, 0.0);
  EXPECT_THROW(LumpedMasses(a, {1.0}), InputError);

  int nc = 0;
  const std::vector<int> comp = ConnectedComponents(a, &nc);
  EXPECT_EQ(nc, 2);
  for (std::size_t t = 0; t < comp.size(); ++t) EXPECT_EQ(comp[t], a.body[t]);
}

TEST(TetMesh, SurfaceTetsFacesBelongToTheirTets) {
  const TetMesh m = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  const SurfaceInfo s = SurfaceTets(m);
  ASSERT_EQ(s.faces.size(), s.face_tet.size());
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    const auto &t = m.tets[s.face_tet[f]];
    for (int n : s.faces[f]) EXPECT_NE(std::find(t.begin(), t.end(), n), t.end());
    EXPECT_TRUE(std::binary_search(s.tets.begin(), s.tets.end(), s.face_tet[f]));
    // Outward: the face normal points away from the opposite node.
    int opp = -1;
    for (int n : t)
      if (std::find(s.faces[f].begin(), s.faces[f].end(), n) == s.faces[f].end()) opp = n;
    const auto &X = m.nodes;
    const Vec3 nrm = cross(X[s.faces[f][1]] - X[s.faces[f][0]], X[s.faces[f][2]] - X[s.faces[f][0]]);
    EXPECT_LT(dot(nrm, X[opp] - X[s.faces[f][0]]), 0.0);
  }
  // The centre cell's 6 tetrahedra touch no boundary: 27*6 - 6 surface tets at most.
  EXPECT_LT(s.tets.size(), m.tets.size());
  EXPECT_EQ(s.faces.size(), 2u * 6 * 9);
}

// ------------------------------------------------------------- Gmsh reader
namespace {

// Node tags are 10 + 3i (non-contiguous); elements include a point and a
// triangle that must be ignored.
std::string WriteMsh22(const TetMesh &m, bool physical) {
  std::ostringstream o;
  o.precision(17);
  o << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  if (physical) {
    o << "$PhysicalNames\n" << m.NumBodies() + 1 << "\n2 99 \"skin\"\n";
    for (int b = 0; b < m.NumBodies(); ++b) o << "3 " << 100 + b << " \"" << m.body_names[b] << "\"\n";
    o << "$EndPhysicalNames\n";
  }
  o << "$Nodes\n" << m.nodes.size() << "\n";
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    o << 10 + 3 * i << " " << m.nodes[i].x << " " << m.nodes[i].y << " " << m.nodes[i].z << "\n";
  o << "$EndNodes\n$Elements\n" << m.tets.size() + 2 << "\n";
  o << "1 15 2 0 1 10\n";
  o << "2 2 2 99 1 10 13 16\n";
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    o << 3 + t << " 4 2 " << (physical ? 100 + m.body[t] : 0) << " " << 1 + m.body[t];
    for (int n : m.tets[t]) o << " " << 10 + 3 * n;
    o << "\n";
  }
  o << "$EndElements\n";
  return o.str();
}

std::string WriteMsh41(const TetMesh &m, bool physical) {
  std::ostringstream o;
  o.precision(17);
  const int nb = m.NumBodies();
  o << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  if (physical) {
    o << "$PhysicalNames\n" << nb << "\n";
    for (int b = 0; b < nb; ++b) o << "3 " << 100 + b << " \"" << m.body_names[b] << "\"\n";
    o << "$EndPhysicalNames\n";
  }
  o << "$Entities\n1 0 1 " << nb << "\n";
  o << "1 0 0 0 0\n";
  o << "1 0 0 0 1 1 1 0 0\n";
  for (int b = 0; b < nb; ++b) {
    o << 1 + b << " -1 -1 -1 9 9 9 ";
    if (physical) o << "1 " << 100 + b;
    else o << "0";
    o << " 1 1\n";
  }
  o << "$EndEntities\n";
  // One node block per body would need shared-node handling; one block in volume 1.
  o << "$Nodes\n1 " << m.nodes.size() << " 10 " << 10 + 3 * (m.nodes.size() - 1) << "\n";
  o << "3 1 0 " << m.nodes.size() << "\n";
  for (std::size_t i = 0; i < m.nodes.size(); ++i) o << 10 + 3 * i << "\n";
  for (const auto &p : m.nodes) o << p.x << " " << p.y << " " << p.z << "\n";
  o << "$EndNodes\n";
  o << "$Elements\n" << nb + 1 << " " << m.tets.size() + 1 << " 1 " << m.tets.size() + 1 << "\n";
  o << "2 1 2 1\n1 10 13 16\n";
  std::size_t tag = 2;
  for (int b = 0; b < nb; ++b) {
    std::size_t cnt = std::count(m.body.begin(), m.body.end(), b);
    o << "3 " << 1 + b << " 4 " << cnt << "\n";
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      if (m.body[t] == b) {
        o << tag++;
        for (int n : m.tets[t]) o << " " << 10 + 3 * n;
        o << "\n";
      }
  }
  o << "$EndElements\n";
  return o.str();
}

// Two boxes side by side (not sharing nodes), body 0 "left", body 1 "right".
TetMesh TwoBodies() {
  TetMesh a = MakeBoxMesh({0, 0, 0}, {1, 1, 1}, 2, 1, 1);
  const TetMesh b = MakeBoxMesh({2, 0, 0}, {3, 1, 2}, 1, 1, 2);
  const int off = static_cast<int>(a.nodes.size());
  a.nodes.insert(a.nodes.end(), b.nodes.begin(), b.nodes.end());
  for (auto t : b.tets) {
    for (int &n : t) n += off;
    a.tets.push_back(t);
    a.body.push_back(1);
  }
  a.body_names = {"left", "right"};
  return a;
}

TetMesh Parse(const std::string &text, const std::string &name = "test.msh") {
  std::istringstream in(text);
  return ParseGmsh(in, name);
}

void ExpectSameMesh(const TetMesh &a, const TetMesh &b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) EXPECT_EQ(norm(a.nodes[i] - b.nodes[i]), 0.0);
  ASSERT_EQ(a.tets.size(), b.tets.size());
  for (std::size_t t = 0; t < a.tets.size(); ++t) EXPECT_EQ(a.tets[t], b.tets[t]);
  EXPECT_EQ(a.body, b.body);
  EXPECT_EQ(a.body_names, b.body_names);
}

// Expects ParseGmsh to throw with "file:line:" followed by text containing `what`.
void ExpectParseError(const std::string &text, int line, const std::string &what) {
  try {
    Parse(text, "bad.msh");
    ADD_FAILURE() << "accepted malformed input; expected line " << line << ": " << what;
  } catch (const InputError &e) {
    const std::string msg = e.what();
    const std::string where = line > 0 ? "bad.msh:" + std::to_string(line) + ":" : "bad.msh:";
    EXPECT_EQ(msg.rfind(where, 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

} // namespace

TEST(Gmsh, RoundTrip22WithPhysicalGroups) {
  const TetMesh m = TwoBodies();
  ExpectSameMesh(Parse(WriteMsh22(m, true)), m);
}

TEST(Gmsh, RoundTrip41WithPhysicalGroups) {
  const TetMesh m = TwoBodies();
  ExpectSameMesh(Parse(WriteMsh41(m, true)), m);
}

TEST(Gmsh, NoPhysicalGroupsGiveConnectedComponents) {
  TetMesh m = TwoBodies();
  m.body_names = {"component_0", "component_1"};
  ExpectSameMesh(Parse(WriteMsh22(m, false)), m);
  ExpectSameMesh(Parse(WriteMsh41(m, false)), m);
}

TEST(Gmsh, ReaderOrientsTetsAndDropsUnusedNodes) {
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n7 5 5 5\n$EndNodes\n"
      "$Elements\n1\n1 4 0 1 3 2 4\n$EndElements\n";
  const TetMesh m = Parse(text);
  ASSERT_EQ(m.nodes.size(), 4u);
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_NEAR(TetSignedVolume(m, 0), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(m.body_names, std::vector<std::string>{"component_0"});
}

TEST(Gmsh, ReadsFileAndNamesItInErrors) {
  const std::string path = ::testing::TempDir() + "fdem_test_tetmesh.msh";
  {
    std::ofstream f(path);
    f << WriteMsh41(TwoBodies(), true);
  }
  EXPECT_EQ(ReadGmsh(path).tets.size(), TwoBodies().tets.size());
  {
    std::ofstream f(path);
    f << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 zero\n$EndNodes\n";
  }
  try {
    ReadGmsh(path);
    ADD_FAILURE() << "accepted a bad coordinate";
  } catch (const InputError &e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":8:", 0), 0u) << e.what();
  }
  std::remove(path.c_str());
  try {
    ReadGmsh(path);
    ADD_FAILURE();
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST(Gmsh, RejectsMalformedInputWithFileAndLine) {
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  const std::string nodes22 = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";  // lines 4-10
  // Hexahedron in the volume (2.2): line 13.
  ExpectParseError(fmt22 + nodes22 + "$Elements\n2\n1 4 0 1 2 3 4\n2 5 0 1 2 3 4 1 2 3 4\n$EndElements\n", 14,
                   "unsupported volume element type 5 (8-node hexahedron)");
  // Hexahedron block (4.1): the block header line.
  const std::string fmt41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string nodes41 = "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";  // 4-15
  ExpectParseError(fmt41 + nodes41 + "$Elements\n1 1 1 1\n3 1 5 1\n1 1 2 3 4 1 2 3 4\n$EndElements\n", 18,
                   "unsupported volume element type 5");
  ExpectParseError(fmt41 + nodes41 + "$Elements\n1 1 1 1\n3 1 6 1\n1 1 2 3 4 1 2\n$EndElements\n", 18,
                   "6-node prism");
  // Missing sections.
  ExpectParseError(fmt22 + "$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n", 0, "missing $Nodes section");
  ExpectParseError(fmt22 + nodes22, 0, "missing $Elements section");
  ExpectParseError(nodes22, 1, "$Nodes before $MeshFormat");
  // Bad numbers and references.
  ExpectParseError(fmt22 + "$Nodes\n2\n1 0 0 0\n2 1 x 0\n$EndNodes\n", 7, "malformed node line");
  ExpectParseError(fmt22 + nodes22 + "$Elements\n1\n1 4 0 1 2 3 9\n$EndElements\n", 13, "undefined node 9");
  ExpectParseError(fmt22 + nodes22 + "$Elements\n1\n1 4 0 1 2 3\n$EndElements\n", 13, "3 + ntags + 4");
  ExpectParseError(fmt41 + nodes41 + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3\n$EndElements\n", 19, "tetrahedron line");
  // Section too short / truncated file.
  ExpectParseError(fmt22 + "$Nodes\n3\n1 0 0 0\n$EndNodes\n", 7, "inside $Nodes");
  ExpectParseError(fmt22 + nodes22 + "$Elements\n1\n1 4 0 1 2 3 4\n", 13, "missing $EndElements");
  // Degenerate tetrahedron, unsupported format variants, a stray line.
  ExpectParseError(fmt22 + "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
                   13, "degenerate");
  ExpectParseError("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", 2, "unsupported .msh version 3.0");
  ExpectParseError("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", 2, "binary");
  ExpectParseError(fmt22 + "hello\n", 4, "expected a section header");
  const std::string nodes22_5 = "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$EndNodes\n";  // lines 4-11
  ExpectParseError(fmt22 + nodes22_5 + "$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n$Elements\n1\n1 4 2 5 1 2 3 4 5\n$EndElements\n",
                   14, "no physical group");
}

// Counts are checked against the bytes left before anything is sized by them,
// with overflow-safe arithmetic; each error names file:line.
TEST(Gmsh, RejectsCountsTheFileCannotHold) {
  const std::string fmt41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  // np + nc + ns overflowed to a negative sum and the section was accepted.
  ExpectParseError(fmt41 + "$Entities\n9223372036854775807 1 0 0\n$EndEntities\n", 5,
                   "$Entities point count 9223372036854775807 is more than the rest of the file can hold");
  ExpectParseError(fmt41 + "$Entities\n0 0 -1 0\n$EndEntities\n", 5, "$Entities surface count -1 is negative");
  // A node block's count was used to size a vector: 1e12 -> std::bad_alloc, 2^31-1 -> 16 GiB, -1 -> length_error.
  for (const char *n : {"1000000000000", "2147483647", "9223372036854775807"})
    ExpectParseError(fmt41 + "$Nodes\n1 1 1 1\n3 1 0 " + n + "\n1\n0 0 0\n$EndNodes\n", 6,
                     std::string("node block numNodes ") + n + " is more than the rest of the file can hold");
  ExpectParseError(fmt41 + "$Nodes\n1 1 1 1\n3 1 0 -1\n$EndNodes\n", 6, "node block numNodes -1 is negative");
  ExpectParseError(fmt41 + "$Nodes\n-2 1 1 1\n$EndNodes\n", 5, "$Nodes numEntityBlocks -2 is negative");
  ExpectParseError(fmt22 + "$Nodes\n1000000000000\n1 0 0 0\n$EndNodes\n", 5, "$Nodes count 1000000000000 is more than");
  ExpectParseError(fmt22 + "$PhysicalNames\n-3\n$EndPhysicalNames\n", 5, "$PhysicalNames count -3 is negative");
  // 3 + ntags + 4 overflowed.
  const std::string nodes22 = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";
  ExpectParseError(fmt22 + nodes22 + "$Elements\n1\n1 4 9223372036854775805 1 2 3 4\n$EndElements\n", 13,
                   "3 + ntags + 4 integers (ntags = 9223372036854775805)");
  // numPhysicalTags of a volume entity: 1 + nphys overflowed.
  ExpectParseError(fmt41 + "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 9223372036854775807 5\n$EndEntities\n", 6,
                   "numPhysicalTags 9223372036854775807 does not match");
  // An integer out of range is malformed, not wrapped.
  ExpectParseError(fmt22 + "$Nodes\n99999999999999999999\n$EndNodes\n", 5, "malformed $Nodes count");
}

namespace {
// A stream that cannot seek (a pipe): its size is unknown.
struct PipeBuf : std::stringbuf {
  using std::stringbuf::stringbuf;
  pos_type seekoff(off_type, std::ios_base::seekdir, std::ios_base::openmode) override { return pos_type(-1); }
  pos_type seekpos(pos_type, std::ios_base::openmode) override { return pos_type(-1); }
};
} // namespace

TEST(Gmsh, UnknownSizeStillAllocatesOnlyWhatItReads) {
  PipeBuf buf("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1000000000000\n1\n2\n$EndNodes\n");
  std::istream in(&buf);
  try {
    ParseGmsh(in, "pipe");
    ADD_FAILURE() << "accepted a truncated node block";
  } catch (const InputError &e) {
    EXPECT_EQ(std::string(e.what()), "pipe:9: unexpected '$EndNodes' inside $Nodes (section too short?)");
  }
}

TEST(Gmsh, RejectsNonFiniteCoordinates) {
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  for (const char *bad : {"nan", "inf", "-inf", "1e999", "NAN"})
    ExpectParseError(fmt22 + "$Nodes\n2\n1 0 0 0\n2 1 " + bad + " 0\n$EndNodes\n", 7,
                     std::string("node line (expected: tag x y z): value '") + bad + "' is not a finite number");
  ExpectParseError("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 nan\n$EndNodes\n", 8,
                   "node coordinates: value 'nan' is not a finite number");
  // Finite but too large: the volume overflows (nan); the tetrahedron's line is named.
  ExpectParseError(fmt22 + "$Nodes\n4\n1 0 0 0\n2 1e300 0 0\n3 0 1e300 0\n4 0 0 1e300\n$EndNodes\n$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n",
                   13, "tetrahedron volume is not a finite number");
}

TEST(Gmsh, RejectsATetrahedronGivenTwice) {
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  const std::string nodes = "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$EndNodes\n";  // lines 4-11
  // Was accepted: mass doubled, no boundary faces between the two copies.
  ExpectParseError(fmt22 + nodes + "$Elements\n3\n7 4 2 1 1 1 2 3 4\n8 4 2 1 1 2 3 4 5\n9 4 2 1 1 4 3 2 1\n$EndElements\n", 16,
                   "element 9 repeats element 7 (line 14): the same tetrahedron (nodes 4 3 2 1) given twice");
  // In two physical volumes (4.1: two blocks): still one tetrahedron twice.
  ExpectParseError("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
                   "$Elements\n2 2 1 2\n3 1 4 1\n1 1 2 3 4\n3 2 4 1\n2 2 1 3 4\n$EndElements\n",
                   21, "element 2 repeats element 1 (line 19)");
}

TEST(Gmsh, CoincidentNodesAreAnErrorInOneBodyAndAWarningBetweenTwo) {
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  // Two tetrahedra touching at a face, with the face's nodes given twice (tags 5-7 = 2-4).
  const std::string nodes = "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 0 0\n6 0 1 0\n7 0 0 1\n8 1 1 1\n$EndNodes\n";  // 4-14
  const std::string one_body = "$Elements\n2\n1 4 2 1 1 1 2 3 4\n2 4 2 1 1 5 6 7 8\n$EndElements\n";
  ExpectParseError(fmt22 + nodes + one_body, 10,
                   "node 5 has the same coordinates (1, 0, 0) as node 2 (line 7) and both are in body 'physical_1'");
  const std::string two_bodies = "$Elements\n2\n1 4 2 1 1 1 2 3 4\n2 4 2 2 1 5 6 7 8\n$EndElements\n";
  const TetMesh m = Parse(fmt22 + nodes + two_bodies, "touch.msh");
  EXPECT_EQ(m.NumBodies(), 2);
  ASSERT_EQ(m.warnings.size(), 1u);
  EXPECT_EQ(m.warnings[0], "touch.msh:12: node 7 has the same coordinates (0, 0, 1) as node 4 (line 9) of another body "
                           "('physical_1' and 'physical_2' touch there); 2 more node(s) coincide with a node of another body");
  // Without physical groups the two components are the bodies: same warning.
  const std::string no_phys = "$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 5 6 7 8\n$EndElements\n";
  const TetMesh c = Parse(fmt22 + nodes + no_phys, "touch.msh");
  EXPECT_EQ(c.NumBodies(), 2);
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("('component_0' and 'component_1' touch there)"), std::string::npos) << c.warnings[0];
  // A valid mesh has no warnings.
  EXPECT_TRUE(Parse(WriteMsh41(TwoBodies(), true)).warnings.empty());
}

TEST(Gmsh, RejectsOverlappingTetrahedra) {
  const std::string fmt22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  // Nodes 5 and 6 on the same side of face 1-2-3 (z > 0); node 7 below it.
  const std::string nodes =
      "$Nodes\n7\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0.2 0.2 0.5\n6 0.1 0.1 2\n7 0.2 0.2 -1\n$EndNodes\n";  // 4-13
  // Two tetrahedra on the same side of their shared face: accepted before (volume counted twice).
  ExpectParseError(fmt22 + nodes + "$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 1 3 2 5\n$EndElements\n", 17,
                   "element 2 and element 1 (line 16) lie on the same side of their shared face (nodes 1 2 3): they overlap");
  // Three tetrahedra on one face.
  ExpectParseError(fmt22 + nodes + "$Elements\n3\n1 4 0 1 2 3 4\n2 4 0 1 2 3 7\n3 4 0 1 2 3 6\n$EndElements\n", 18,
                   "element 3 has a face (nodes 1 2 3) that elements 1 (line 16) and 2 (line 17) already share");
  // One on each side is a valid mesh; tet_line gives each tetrahedron's line.
  const TetMesh m = Parse(fmt22 + nodes + "$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 1 2 3 7\n$EndElements\n");
  EXPECT_EQ(m.tet_line, (std::vector<long>{16, 17}));
}

// The Hilbert index is a bijection of the 2^(3 bits) cells of a cube onto
// 0 .. 2^(3 bits) - 1, and cells of consecutive indices share a face.
TEST(Ordering, HilbertIndexWalksFaceNeighbours) {
  for (int bits = 1; bits <= 5; ++bits) {
    const std::uint32_t          n = 1u << bits;
    std::vector<std::array<int, 3>> at(std::size_t(n) * n * n, {-1, -1, -1});
    for (std::uint32_t x = 0; x < n; ++x)
      for (std::uint32_t y = 0; y < n; ++y)
        for (std::uint32_t z = 0; z < n; ++z) {
          const std::uint32_t X[3] = {x, y, z};
          const std::uint64_t h    = HilbertIndex(X, bits);
          ASSERT_LT(h, at.size()) << "bits " << bits;
          ASSERT_EQ(at[h][0], -1) << "bits " << bits << ": index " << h << " given twice";
          at[h] = {(int)x, (int)y, (int)z};
        }
    for (std::size_t h = 1; h < at.size(); ++h) {
      const int d = std::abs(at[h][0] - at[h - 1][0]) + std::abs(at[h][1] - at[h - 1][1]) + std::abs(at[h][2] - at[h - 1][2]);
      ASSERT_EQ(d, 1) << "bits " << bits << ": indices " << h - 1 << " and " << h << " are not face neighbours";
    }
  }
  // HilbertKey scales a box onto 2^21 cells per side: its corners and its
  // centre land where HilbertIndex puts those cells; outside points are clamped
  const Vec3          lo(-1, 2, 0), hi(3, 4, 1e-9);
  const std::uint32_t top = (1u << 21) - 1, c0[3] = {0, 0, 0}, c1[3] = {top, top, top};
  EXPECT_EQ(HilbertKey(lo, lo, hi), HilbertIndex(c0, 21));
  EXPECT_EQ(HilbertKey(hi, lo, hi), HilbertIndex(c1, 21));
  EXPECT_EQ(HilbertKey(Vec3(-5, 0, -1), lo, hi), HilbertIndex(c0, 21));
  EXPECT_EQ(HilbertKey(Vec3(std::nan(""), 0, -1), lo, hi), HilbertIndex(c0, 21));
}
