// Splitting a tetrahedral mesh into joints (include/fdem/kernels/joint_mesh.hpp).
#include <fdem/kernels/joint_mesh.hpp>
#include <fdem/kernels/bucket_sort.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

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
  // (the keys compared entry by entry: std::array's operators call memcmp here)
  const auto before = [](const TetFace &a, const TetFace &b) {
    if (a.key[0] != b.key[0]) return a.key[0] < b.key[0];
    if (a.key[1] != b.key[1]) return a.key[1] < b.key[1];
    if (a.key[2] != b.key[2]) return a.key[2] < b.key[2];
    return a.tet != b.tet ? a.tet < b.tet : a.local < b.local;
  };
  BucketSort(faces, [](const TetFace &f) { return f.key[0]; }, before); // linear: one bucket per smallest node id
  return faces;
}

namespace {
std::string Element(const TetMesh &mesh, int t) {
  std::string e = "element " + std::to_string(t);
  if (t < static_cast<int>(mesh.tet_line.size())) e += " (line " + std::to_string(mesh.tet_line[t]) + ")";
  return e;
}

// A fracturable body's mesh must be conforming: a face is held by at most two of its
// tetrahedra, and two of its tetrahedra that touch across a face share that face's
// nodes (else no joint can hold them: the body would carry a hidden crack). The
// second is found from the boundary faces (held by one tetrahedron): one whose centroid
// lies on another boundary face of the same body, in its plane, with the opposite
// normal, is an interface the mesh does not connect (hanging nodes, or duplicated
// nodes). A uniform grid of the boundary faces' boxes keeps it linear.
void CheckConforming(const TetMesh &mesh, const std::vector<TetFace> &faces, const std::vector<char> &split_body) {
  auto split = [&](int t) { return split_body[mesh.body[t]] != 0; };
  struct Face {
    int  tet;
    Vec3 v[3], n, c; // vertices, unit normal (outward), centroid
  };
  std::vector<Face> bnd;
  double            hsum = 0;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (split(faces[i].tet)) {
      if (j - i > 2) {
        std::string who;
        for (std::size_t k = i; k < j; ++k) who += (k > i ? ", " : "") + Element(mesh, faces[k].tet);
        throw InputError("fracturable body '" + mesh.body_names[mesh.body[faces[i].tet]] + "': the face of nodes " + std::to_string(faces[i].key[0]) + ", " + std::to_string(faces[i].key[1]) + ", " +
                         std::to_string(faces[i].key[2]) + " is held by " + std::to_string(j - i) + " tetrahedra (" + who + "); a fracturable mesh must be conforming, each face between at most two tetrahedra");
      }
      if (j - i == 1) {
        Face f;
        f.tet = faces[i].tet;
        for (int m = 0; m < 3; ++m) f.v[m] = mesh.nodes[mesh.tets[f.tet][kTetFace[faces[i].local][m]]];
        const Vec3 a = cross(f.v[1] - f.v[0], f.v[2] - f.v[0]);
        const double A = norm(a);
        if (A > 0) {
          f.n = (1.0 / A) * a;
          f.c = (1.0 / 3.0) * (f.v[0] + f.v[1] + f.v[2]);
          hsum += norm(f.v[1] - f.v[0]);
          bnd.push_back(f);
        }
      }
    }
    i = j;
  }
  if (bnd.empty()) return;
  const double h = 2 * hsum / bnd.size(); // the grid's cell: twice the mean edge
  auto cell = [&](double x) { return static_cast<long long>(std::floor(x / h)); };
  auto key = [](long long i, long long j, long long k) { return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL); };
  std::unordered_multimap<long long, int> grid;
  for (int f = 0; f < static_cast<int>(bnd.size()); ++f) {
    Vec3 lo = bnd[f].v[0], hi = bnd[f].v[0];
    for (int m = 1; m < 3; ++m) {
      lo = Vec3(std::fmin(lo.x, bnd[f].v[m].x), std::fmin(lo.y, bnd[f].v[m].y), std::fmin(lo.z, bnd[f].v[m].z));
      hi = Vec3(std::fmax(hi.x, bnd[f].v[m].x), std::fmax(hi.y, bnd[f].v[m].y), std::fmax(hi.z, bnd[f].v[m].z));
    }
    for (long long i = cell(lo.x); i <= cell(hi.x); ++i)
      for (long long j = cell(lo.y); j <= cell(hi.y); ++j)
        for (long long k = cell(lo.z); k <= cell(hi.z); ++k) grid.emplace(key(i, j, k), f);
  }
  for (const Face &f : bnd) {
    const auto range = grid.equal_range(key(cell(f.c.x), cell(f.c.y), cell(f.c.z)));
    for (auto it = range.first; it != range.second; ++it) {
      const Face &g = bnd[it->second];
      if (g.tet == f.tet || mesh.body[g.tet] != mesh.body[f.tet] || dot(f.n, g.n) > -0.99) continue;
      const double size = norm(g.v[1] - g.v[0]) + norm(g.v[2] - g.v[1]) + norm(g.v[0] - g.v[2]);
      if (std::fabs(dot(g.n, f.c - g.v[0])) > 1e-6 * size) continue; // not in g's plane
      // f's centroid inside g (barycentric coordinates, a small tolerance)
      bool inside = true;
      for (int m = 0; m < 3 && inside; ++m) inside = dot(cross(g.v[(m + 1) % 3] - g.v[m], f.c - g.v[m]), g.n) > -1e-9 * size * size;
      if (inside)
        throw InputError("fracturable body '" + mesh.body_names[mesh.body[f.tet]] + "': " + Element(mesh, f.tet) + " and " + Element(mesh, g.tet) +
                         " touch across a face whose nodes they do not share (a non-conforming mesh: hanging or duplicated nodes); no joint could hold them together. Mesh the body conformingly");
    }
  }
}
} // namespace

JointSplitter::JointSplitter(const TetMesh &mesh, std::vector<char> split_body) : mesh_(&mesh), split_body_(std::move(split_body)) {
  if (static_cast<int>(split_body_.size()) != mesh.NumBodies())
    throw InputError("SplitForJoints: " + std::to_string(split_body_.size()) + " split flags for " +
                     std::to_string(mesh.NumBodies()) + " bodies");
  faces_ = SortedFaces(mesh.tets);
  CheckConforming(mesh, faces_, split_body_);
}

SplitMesh SplitForJoints(const TetMesh &mesh, const std::vector<char> &split_body, const std::vector<char> &split_tet) {
  return JointSplitter(mesh, split_body).Split(split_tet);
}

SplitMesh JointSplitter::Split(const std::vector<char> &split_tet) const {
  const TetMesh           &mesh       = *mesh_;
  const std::vector<char> &split_body = split_body_;
  const int nt = static_cast<int>(mesh.tets.size());
  if (!split_tet.empty() && static_cast<int>(split_tet.size()) != nt)
    throw InputError("SplitForJoints: " + std::to_string(split_tet.size()) + " tetrahedron flags for " + std::to_string(nt) + " tetrahedra");
  auto fracturable = [&](int t) { return split_body[mesh.body[t]] != 0; };
  auto split       = [&](int t) { return fracturable(t) && (split_tet.empty() || split_tet[t] != 0); };
  SplitMesh s;
  s.mesh.body = mesh.body;
  s.mesh.body_names = mesh.body_names;
  s.mesh.tet_line = mesh.tet_line;
  s.mesh.warnings = mesh.warnings;
  s.mesh.tets.resize(nt);
  s.split.resize(nt);
  std::size_t nsplit = 0;
  for (int t = 0; t < nt; ++t) nsplit += split(t) ? 1 : 0;
  s.mesh.nodes.reserve(4 * nsplit + mesh.nodes.size()); // (at most)
  s.parent.reserve(4 * nsplit + mesh.nodes.size());
  s.joints.reserve(std::min(4 * nsplit, 2 * static_cast<std::size_t>(nt)));
  std::vector<int> kept(mesh.nodes.size(), -1); // new id of a node of an unsplit tetrahedron
  auto add = [&](int old) {
    s.mesh.nodes.push_back(mesh.nodes[old]);
    s.parent.push_back(old);
    return static_cast<int>(s.mesh.nodes.size()) - 1;
  };
  for (int t = 0; t < nt; ++t) {
    s.split[t] = split(t);
    for (int j = 0; j < 4; ++j) {
      const int old = mesh.tets[t][j];
      if (s.split[t]) s.mesh.tets[t][j] = add(old);
      else {
        if (kept[old] < 0) kept[old] = add(old);
        s.mesh.tets[t][j] = kept[old];
      }
    }
  }
  // joints: faces held by exactly two tetrahedra of one fracturable body, one of them split
  // at least (triangle a on a split one, so that a joint's side a has nodes of its own)
  const std::vector<TetFace> &faces = faces_;
  s.boundary.assign(nt, 0);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    // the split mesh's boundary: a split tetrahedron's faces are its own; the unsplit holders
    // of a face keep its nodes, so they share it unless one of them holds it alone
    std::size_t unsplit = 0;
    for (std::size_t k = i; k < j; ++k) unsplit += s.split[faces[k].tet] ? 0 : 1;
    for (std::size_t k = i; k < j; ++k)
      if (s.split[faces[k].tet] || unsplit == 1) s.boundary[faces[k].tet] |= static_cast<char>(1 << faces[k].local);
    if (j - i == 2 && fracturable(faces[i].tet) && mesh.body[faces[i].tet] == mesh.body[faces[i + 1].tet] && (split(faces[i].tet) || split(faces[i + 1].tet))) {
      const bool     swap = !split(faces[i].tet);
      const TetFace &A = faces[i + (swap ? 1 : 0)], &B = faces[i + (swap ? 0 : 1)];
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
