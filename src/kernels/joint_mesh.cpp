// Splitting a tetrahedral mesh into joints (include/fdem/kernels/joint_mesh.hpp).
#include <fdem/kernels/joint_mesh.hpp>

#include <algorithm>
#include <string>

#include <fdem/kernels/error.hpp>

namespace fdem::kernels {

std::vector<TetFace> SortedFaces(const std::vector<std::array<int, 4>> &tets) {
  std::vector<TetFace> faces;
  faces.reserve(4 * tets.size());
  for (int t = 0; t < static_cast<int>(tets.size()); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k{tets[t][kTetFace[f][0]], tets[t][kTetFace[f][1]], tets[t][kTetFace[f][2]]};
      std::sort(k.begin(), k.end());
      faces.push_back({k, t, f});
    }
  std::sort(faces.begin(), faces.end(), [](const TetFace &a, const TetFace &b) { return a.key < b.key || (a.key == b.key && a.tet < b.tet); });
  return faces;
}

SplitMesh SplitForJoints(const TetMesh &mesh, const std::vector<char> &split_body) {
  if (static_cast<int>(split_body.size()) != mesh.NumBodies())
    throw InputError("SplitForJoints: " + std::to_string(split_body.size()) + " split flags for " +
                     std::to_string(mesh.NumBodies()) + " bodies");
  const int nt = static_cast<int>(mesh.tets.size());
  auto split = [&](int t) { return split_body[mesh.body[t]] != 0; };
  SplitMesh s;
  s.mesh.body = mesh.body;
  s.mesh.body_names = mesh.body_names;
  s.mesh.tet_line = mesh.tet_line;
  s.mesh.warnings = mesh.warnings;
  s.mesh.tets.resize(nt);
  std::vector<int> kept(mesh.nodes.size(), -1); // new id of a node of an unsplit body
  auto add = [&](int old) {
    s.mesh.nodes.push_back(mesh.nodes[old]);
    s.parent.push_back(old);
    return static_cast<int>(s.mesh.nodes.size()) - 1;
  };
  for (int t = 0; t < nt; ++t)
    for (int j = 0; j < 4; ++j) {
      const int old = mesh.tets[t][j];
      if (split(t)) s.mesh.tets[t][j] = add(old);
      else {
        if (kept[old] < 0) kept[old] = add(old);
        s.mesh.tets[t][j] = kept[old];
      }
    }
  // joints: faces held by exactly two split tetrahedra of one body
  const std::vector<TetFace> faces = SortedFaces(mesh.tets);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    const TetFace &A = faces[i];
    if (j - i == 2 && split(A.tet) && split(faces[i + 1].tet) && mesh.body[A.tet] == mesh.body[faces[i + 1].tet]) {
      const TetFace &B = faces[i + 1];
      JointFace jf;
      jf.tet_a = A.tet;
      jf.tet_b = B.tet;
      for (int m = 0; m < 3; ++m) {
        const int la = kTetFace[A.local][m]; // local node of tet_a, in outward order
        const int old = mesh.tets[A.tet][la];
        jf.a[m] = s.mesh.tets[A.tet][la];
        for (int lb = 0; lb < 4; ++lb)
          if (mesh.tets[B.tet][lb] == old) jf.b[m] = s.mesh.tets[B.tet][lb];
      }
      s.joints.push_back(jf);
    }
    i = j;
  }
  return s;
}

} // namespace fdem::kernels
