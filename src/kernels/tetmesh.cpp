// Tetrahedral mesh utilities; see tetmesh.hpp.
#include <fdem/kernels/tetmesh.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <map>
#include <numeric>
#include <unordered_map>

#include <fdem/kernels/error.hpp>

namespace fdem::kernels {

double TetSignedVolume(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &d) {
  return dot(b - a, cross(c - a, d - a)) / 6.0;
}

double TetSignedVolume(const TetMesh &mesh, int t) {
  const auto &n = mesh.tets[t];
  return TetSignedVolume(mesh.nodes[n[0]], mesh.nodes[n[1]], mesh.nodes[n[2]], mesh.nodes[n[3]]);
}

double TotalVolume(const TetMesh &mesh) {
  double v = 0;
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t) v += TetSignedVolume(mesh, t);
  return v;
}

namespace {
double LongestEdge(const std::vector<Vec3> &X, const std::array<int, 4> &n) {
  double h = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) h = std::max(h, norm(X[n[a]] - X[n[b]]));
  return h;
}
bool Degenerate(double six_v, double h) { return std::fabs(six_v) <= 1e-12 * h * h * h; }
} // namespace

int OrientTets(const std::vector<Vec3> &X, std::vector<std::array<int, 4>> &tets, const std::vector<int> &body) {
  int flipped = 0;
  for (std::size_t t = 0; t < tets.size(); ++t) {
    auto &n = tets[t];
    for (int a = 0; a < 4; ++a)
      if (n[a] < 0 || n[a] >= static_cast<int>(X.size()))
        throw InputError("body " + std::to_string(body.empty() ? 0 : body[t]) + ", element " + std::to_string(t) +
                         ": node index " + std::to_string(n[a]) + " out of range [0, " + std::to_string(X.size()) + ")");
    const double v6 = 6.0 * TetSignedVolume(X[n[0]], X[n[1]], X[n[2]], X[n[3]]);
    if (Degenerate(v6, LongestEdge(X, n)))
      throw InputError("body " + std::to_string(body.empty() ? 0 : body[t]) + ", element " + std::to_string(t) +
                       ": degenerate tetrahedron (zero volume)");
    if (v6 < 0) {
      std::swap(n[1], n[2]);
      ++flipped;
    }
  }
  return flipped;
}

int OrientTets(TetMesh &mesh) { return OrientTets(mesh.nodes, mesh.tets, mesh.body); }

// ---------------------------------------------------------------- generators
TetMesh MakeBoxMesh(const Vec3 &lo, const Vec3 &hi, int nx, int ny, int nz) {
  if (nx < 1 || ny < 1 || nz < 1)
    throw InputError("MakeBoxMesh: cell counts must be >= 1 (got " + std::to_string(nx) + ", " + std::to_string(ny) +
                     ", " + std::to_string(nz) + ")");
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw InputError("MakeBoxMesh: need hi > lo in every direction");
  TetMesh m;
  const int NX = nx + 1, NY = ny + 1, NZ = nz + 1;
  m.nodes.resize(static_cast<std::size_t>(NX) * NY * NZ);
  for (int k = 0; k < NZ; ++k)
    for (int j = 0; j < NY; ++j)
      for (int i = 0; i < NX; ++i)
        m.nodes[i + NX * (j + NY * k)] = {lo.x + (hi.x - lo.x) * i / nx, lo.y + (hi.y - lo.y) * j / ny,
                                          lo.z + (hi.z - lo.z) * k / nz};
  // Kuhn subdivision: one tetrahedron per path 000 -> 111 along unit steps.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  static const int parity[6] = {+1, -1, -1, +1, +1, -1};
  const int step[3] = {1, NX, NX * NY};
  m.tets.reserve(static_cast<std::size_t>(6) * nx * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int v0 = i + NX * (j + NY * k);
        for (int p = 0; p < 6; ++p) {
          std::array<int, 4> t;
          t[0] = v0;
          t[1] = t[0] + step[perms[p][0]];
          t[2] = t[1] + step[perms[p][1]];
          t[3] = t[2] + step[perms[p][2]];
          if (parity[p] < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
      }
  m.body.assign(m.tets.size(), 0);
  m.body_names = {"box"};
  return m;
}

TetMesh MakeBeamMesh(double L, double W, double H, int n) {
  if (!(L > 0 && W > 0 && H > 0) || n < 1) throw InputError("MakeBeamMesh: need L, W, H > 0 and n >= 1");
  const double h = std::min({L, W, H}) / n;
  auto cells = [h](double s) { return std::max(1, static_cast<int>(std::lround(s / h))); };
  TetMesh m = MakeBoxMesh({0, 0, 0}, {L, W, H}, cells(L), cells(W), cells(H));
  m.body_names = {"beam"};
  return m;
}

TetMesh MakeCylinderMesh(double radius, double height, int n_radial, int n_axial) {
  if (!(radius > 0 && height > 0) || n_radial < 1 || n_axial < 1)
    throw InputError("MakeCylinderMesh: need radius, height > 0 and n_radial, n_axial >= 1");
  const double pi = std::acos(-1.0);
  // Disk: centre + rings; ring k (1..n_radial) has 6k nodes.
  std::vector<std::array<double, 2>> disk{{0.0, 0.0}};
  std::vector<int> ring_start{0, 1};
  for (int k = 1; k <= n_radial; ++k) {
    const int m = 6 * k;
    const double r = radius * k / n_radial;
    for (int j = 0; j < m; ++j) disk.push_back({r * std::cos(2 * pi * j / m), r * std::sin(2 * pi * j / m)});
    ring_start.push_back(static_cast<int>(disk.size()));
  }
  std::vector<std::array<int, 3>> tris;
  for (int k = 1; k <= n_radial; ++k) {
    const int m_in = k == 1 ? 1 : 6 * (k - 1), m_out = 6 * k;
    const int in0 = ring_start[k - 1], out0 = ring_start[k];
    if (k == 1) {
      for (int j = 0; j < m_out; ++j) tris.push_back({0, out0 + j, out0 + (j + 1) % m_out});
      continue;
    }
    // Merge-walk the two rings by angle.
    int i = 0, j = 0;
    while (i < m_in || j < m_out) {
      const double a_in = static_cast<double>(i + 1) / m_in, a_out = static_cast<double>(j + 1) / m_out;
      if (j < m_out && (i == m_in || a_out <= a_in)) {
        tris.push_back({in0 + i % m_in, out0 + j, out0 + (j + 1) % m_out});
        ++j;
      } else {
        tris.push_back({in0 + i, out0 + j % m_out, in0 + (i + 1) % m_in});
        ++i;
      }
    }
  }
  TetMesh mesh;
  const int nd = static_cast<int>(disk.size());
  for (int l = 0; l <= n_axial; ++l)
    for (const auto &p : disk) mesh.nodes.push_back({p[0], p[1], height * l / n_axial});
  for (int l = 0; l < n_axial; ++l)
    for (auto t : tris) {
      std::sort(t.begin(), t.end());  // diagonals from the lowest-numbered node: conforming
      const int a0 = t[0] + l * nd, b0 = t[1] + l * nd, c0 = t[2] + l * nd;
      const int a1 = a0 + nd, b1 = b0 + nd, c1 = c0 + nd;
      mesh.tets.push_back({a0, b0, c0, c1});
      mesh.tets.push_back({a0, b0, b1, c1});
      mesh.tets.push_back({a0, a1, b1, c1});
    }
  mesh.body.assign(mesh.tets.size(), 0);
  mesh.body_names = {"cylinder"};
  OrientTets(mesh);
  return mesh;
}

// ---------------------------------------------------------------- topology
std::vector<double> LumpedMasses(const TetMesh &mesh, const std::vector<double> &rho) {
  std::vector<double> m(mesh.nodes.size(), 0.0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int b = mesh.body.empty() ? 0 : mesh.body[t];
    if (b < 0 || b >= static_cast<int>(rho.size()))
      throw InputError("LumpedMasses: element " + std::to_string(t) + " has body " + std::to_string(b) +
                       " but only " + std::to_string(rho.size()) + " densities were given");
    const double q = rho[b] * TetSignedVolume(mesh, static_cast<int>(t)) / 4.0;
    for (int n : mesh.tets[t]) m[n] += q;
  }
  return m;
}

SurfaceInfo SurfaceTets(const TetMesh &mesh) {
  // Faces opposite node i, ordered so that (b-a)x(c-a) points out of a
  // positively oriented tetrahedron.
  static const int F[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  struct Face {
    std::array<int, 3> key;
    int tet, local;
  };
  std::vector<Face> faces;
  faces.reserve(4 * mesh.tets.size());
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k{mesh.tets[t][F[f][0]], mesh.tets[t][F[f][1]], mesh.tets[t][F[f][2]]};
      std::sort(k.begin(), k.end());
      faces.push_back({k, t, f});
    }
  std::sort(faces.begin(), faces.end(), [](const Face &a, const Face &b) { return a.key < b.key; });
  SurfaceInfo s;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) {
      const auto &n = mesh.tets[faces[i].tet];
      const int *l = F[faces[i].local];
      s.faces.push_back({n[l[0]], n[l[1]], n[l[2]]});
      s.face_tet.push_back(faces[i].tet);
      s.tets.push_back(faces[i].tet);
    }
    i = j;
  }
  std::sort(s.tets.begin(), s.tets.end());
  s.tets.erase(std::unique(s.tets.begin(), s.tets.end()), s.tets.end());
  return s;
}

std::vector<int> ConnectedComponents(const TetMesh &mesh, int *n_components) {
  std::vector<int> parent(mesh.nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto &t : mesh.tets)
    for (int a = 1; a < 4; ++a) {
      const int r0 = find(t[0]), r1 = find(t[a]);
      if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
    }
  std::unordered_map<int, int> id;
  std::vector<int> comp(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int r = find(mesh.tets[t][0]);
    auto it = id.find(r);
    if (it == id.end()) it = id.emplace(r, static_cast<int>(id.size())).first;
    comp[t] = it->second;
  }
  if (n_components) *n_components = static_cast<int>(id.size());
  return comp;
}

// ---------------------------------------------------------------- Gmsh reader
namespace {

// Dimension of Gmsh element types (-1: unknown).
int GmshTypeDim(long type) {
  switch (type) {
  case 15: return 0;
  case 1: case 8: case 26: case 27: case 28: return 1;
  case 2: case 3: case 9: case 10: case 16: case 20: case 21: case 22: case 23: case 24: case 25: return 2;
  case 4: case 5: case 6: case 7: case 11: case 12: case 13: case 14: case 17: case 18: case 19: case 29: case 30:
  case 31: case 92: case 93: return 3;
  default: return -1;
  }
}

const char *GmshTypeName(long type) {
  switch (type) {
  case 4: return "4-node tetrahedron";
  case 5: return "8-node hexahedron";
  case 6: return "6-node prism";
  case 7: return "5-node pyramid";
  case 11: return "10-node tetrahedron";
  case 12: return "27-node hexahedron";
  case 13: return "18-node prism";
  case 14: return "14-node pyramid";
  case 17: return "20-node hexahedron";
  case 18: return "15-node prism";
  case 19: return "13-node pyramid";
  default: return "higher-order volume element";
  }
}

class MshReader {
public:
  MshReader(std::istream &in, std::string file) : in_(in), file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string &what) const {
    throw InputError(file_ + ":" + std::to_string(line_) + ": " + what);
  }
  [[noreturn]] void FailAt(long line, const std::string &what) const {
    throw InputError(file_ + ":" + std::to_string(line) + ": " + what);
  }
  bool Next(std::string &s) {
    if (!std::getline(in_, s)) return false;
    ++line_;
    if (!s.empty() && s.back() == '\r') s.pop_back();
    return true;
  }
  // Next line inside section `sec`; EOF or a '$' line is an error.
  void Line(const std::string &sec, std::string &s) {
    if (!Next(s)) Fail("unexpected end of file inside " + sec + " (missing $End" + sec.substr(1) + "?)");
    if (!s.empty() && s[0] == '$') Fail("unexpected '" + s + "' inside " + sec + " (section too short?)");
  }
  void End(const std::string &sec) {
    std::string s;
    if (!Next(s)) Fail("unexpected end of file: missing $End" + sec.substr(1));
    if (Trim(s) != "$End" + sec.substr(1)) Fail("expected $End" + sec.substr(1) + ", found '" + s + "'");
  }
  static std::string Trim(const std::string &s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  }
  // Integers on a line; at least `min_count` of them, else an error.
  void Ints(const std::string &s, std::vector<long> &out, std::size_t min_count, const char *what) {
    out.clear();
    const char *p = s.c_str();
    char *end;
    for (;;) {
      while (*p == ' ' || *p == '\t') ++p;
      if (!*p) break;
      errno = 0;
      const long v = std::strtol(p, &end, 10);
      if (end == p || (*end && *end != ' ' && *end != '\t') || errno) Fail(std::string("malformed ") + what + ": '" + s + "'");
      out.push_back(v);
      p = end;
    }
    if (out.size() < min_count)
      Fail(std::string("malformed ") + what + ": expected at least " + std::to_string(min_count) + " integers, got '" + s + "'");
  }
  void Reals(const std::string &s, double *out, int count, const char *what) {
    const char *p = s.c_str();
    char *end;
    for (int i = 0; i < count; ++i) {
      out[i] = std::strtod(p, &end);
      if (end == p || (*end && *end != ' ' && *end != '\t')) Fail(std::string("malformed ") + what + ": '" + s + "'");
      p = end;
    }
  }
  long line() const { return line_; }
  const std::string &file() const { return file_; }

private:
  std::istream &in_;
  std::string file_;
  long line_ = 0;
};

struct RawTet {
  std::array<long, 4> nodes;
  long phys;    // physical tag (2.2) or 0
  long entity;  // entity tag (4.1) or -1
  long line;
};

} // namespace

TetMesh ParseGmsh(std::istream &in, const std::string &filename) {
  MshReader r(in, filename);
  std::string s;
  double version = 0;
  bool have_format = false, have_nodes = false, have_elements = false;
  std::map<long, std::string> names3;             // physical tag -> name (dim 3)
  std::unordered_map<long, std::vector<long>> vol_phys;  // 4.1 volume entity -> physical tags
  std::unordered_map<long, std::size_t> node_index;      // node tag -> index in raw_nodes
  std::vector<std::pair<long, Vec3>> raw_nodes;
  std::vector<RawTet> raw;
  std::vector<long> ints;

  while (r.Next(s)) {
    const std::string sec = MshReader::Trim(s);
    if (sec.empty()) continue;
    if (sec[0] != '$') r.Fail("expected a section header ($Name), found '" + s + "'");
    if (sec == "$MeshFormat") {
      r.Line(sec, s);
      double v = 0;
      long ft = 0, ds = 0;
      char *e;
      const char *p = s.c_str();
      v = std::strtod(p, &e);
      if (e == p) r.Fail("malformed $MeshFormat line '" + s + "'");
      p = e;
      ft = std::strtol(p, &e, 10);
      if (e == p) r.Fail("malformed $MeshFormat line '" + s + "'");
      p = e;
      ds = std::strtol(p, &e, 10);
      (void)ds;
      if (v != 2.2 && v != 4.1)
        r.Fail("unsupported .msh version " + MshReader::Trim(s.substr(0, s.find(' '))) + " (supported: 2.2, 4.1)");
      if (ft != 0) r.Fail("binary .msh files are not supported (save as ASCII)");
      version = v;
      have_format = true;
      r.End(sec);
    } else if (sec == "$PhysicalNames") {
      r.Line(sec, s);
      r.Ints(s, ints, 1, "$PhysicalNames count");
      const long n = ints[0];
      for (long i = 0; i < n; ++i) {
        r.Line(sec, s);
        const auto q0 = s.find('"'), q1 = s.rfind('"');
        if (q0 == std::string::npos || q1 == q0) r.Fail("malformed physical name line '" + s + "' (expected: dim tag \"name\")");
        r.Ints(s.substr(0, q0), ints, 2, "physical name line");
        if (ints[0] == 3) names3[ints[1]] = s.substr(q0 + 1, q1 - q0 - 1);
      }
      r.End(sec);
    } else if (sec == "$Entities") {
      if (!have_format) r.Fail("$Entities before $MeshFormat");
      r.Line(sec, s);
      r.Ints(s, ints, 4, "$Entities counts");
      const long np = ints[0], nc = ints[1], ns = ints[2], nv = ints[3];
      for (long i = 0; i < np + nc + ns; ++i) r.Line(sec, s);
      for (long i = 0; i < nv; ++i) {
        r.Line(sec, s);
        // tag minX minY minZ maxX maxY maxZ numPhysicalTags tags... : parse tag, skip 6 reals.
        const char *p = s.c_str();
        char *e;
        const long tag = std::strtol(p, &e, 10);
        if (e == p) r.Fail("malformed volume entity line '" + s + "'");
        p = e;
        for (int k = 0; k < 6; ++k) {
          std::strtod(p, &e);
          if (e == p) r.Fail("malformed volume entity line '" + s + "'");
          p = e;
        }
        r.Ints(p, ints, 1, "volume entity line");
        const long nphys = ints[0];
        if (nphys < 0 || static_cast<long>(ints.size()) < 1 + nphys) r.Fail("malformed volume entity line '" + s + "'");
        vol_phys[tag].assign(ints.begin() + 1, ints.begin() + 1 + nphys);
      }
      r.End(sec);
    } else if (sec == "$Nodes") {
      if (!have_format) r.Fail("$Nodes before $MeshFormat");
      have_nodes = true;
      auto add = [&](long tag, const Vec3 &x) {
        if (!node_index.emplace(tag, raw_nodes.size()).second) r.Fail("duplicate node tag " + std::to_string(tag));
        raw_nodes.push_back({tag, x});
      };
      r.Line(sec, s);
      if (version == 2.2) {
        r.Ints(s, ints, 1, "$Nodes count");
        const long n = ints[0];
        for (long i = 0; i < n; ++i) {
          r.Line(sec, s);
          const char *p = s.c_str();
          char *e;
          const long tag = std::strtol(p, &e, 10);
          if (e == p) r.Fail("malformed node line '" + s + "' (expected: tag x y z)");
          double x[3];
          r.Reals(e, x, 3, "node line (expected: tag x y z)");
          add(tag, {x[0], x[1], x[2]});
        }
      } else {
        r.Ints(s, ints, 4, "$Nodes header (numEntityBlocks numNodes minTag maxTag)");
        const long nblocks = ints[0];
        for (long b = 0; b < nblocks; ++b) {
          r.Line(sec, s);
          r.Ints(s, ints, 4, "node block header (entityDim entityTag parametric numNodes)");
          const long parametric = ints[2], nb = ints[3];
          std::vector<long> tags(nb);
          for (long i = 0; i < nb; ++i) {
            r.Line(sec, s);
            r.Ints(s, ints, 1, "node tag");
            tags[i] = ints[0];
          }
          for (long i = 0; i < nb; ++i) {
            r.Line(sec, s);
            double x[3];
            r.Reals(s, x, 3, "node coordinates");
            (void)parametric;
            add(tags[i], {x[0], x[1], x[2]});
          }
        }
      }
      r.End(sec);
    } else if (sec == "$Elements") {
      if (!have_format) r.Fail("$Elements before $MeshFormat");
      have_elements = true;
      r.Line(sec, s);
      if (version == 2.2) {
        r.Ints(s, ints, 1, "$Elements count");
        const long n = ints[0];
        for (long i = 0; i < n; ++i) {
          r.Line(sec, s);
          r.Ints(s, ints, 3, "element line (expected: tag type ntags tags... nodes...)");
          const long type = ints[1], ntags = ints[2];
          const int dim = GmshTypeDim(type);
          if (dim < 0) r.Fail("unknown element type " + std::to_string(type));
          if (dim < 3) continue;
          if (type != 4)
            r.Fail("unsupported volume element type " + std::to_string(type) + " (" + GmshTypeName(type) +
                   "); only 4-node tetrahedra (type 4) are supported");
          if (ntags < 0 || static_cast<long>(ints.size()) != 3 + ntags + 4)
            r.Fail("tetrahedron line must have 3 + ntags + 4 integers: '" + s + "'");
          RawTet t;
          for (int a = 0; a < 4; ++a) t.nodes[a] = ints[3 + ntags + a];
          t.phys = ntags > 0 ? ints[3] : 0;
          t.entity = -1;
          t.line = r.line();
          raw.push_back(t);
        }
      } else {
        r.Ints(s, ints, 4, "$Elements header (numEntityBlocks numElements minTag maxTag)");
        const long nblocks = ints[0];
        for (long b = 0; b < nblocks; ++b) {
          r.Line(sec, s);
          r.Ints(s, ints, 4, "element block header (entityDim entityTag elementType numElements)");
          const long dim = ints[0], entity = ints[1], type = ints[2], nb = ints[3];
          if (GmshTypeDim(type) < 0) r.Fail("unknown element type " + std::to_string(type));
          const bool keep = dim == 3;
          if (keep && type != 4)
            r.Fail("unsupported volume element type " + std::to_string(type) + " (" + GmshTypeName(type) +
                   "); only 4-node tetrahedra (type 4) are supported");
          for (long i = 0; i < nb; ++i) {
            r.Line(sec, s);
            if (!keep) continue;
            r.Ints(s, ints, 5, "tetrahedron line (expected: tag n0 n1 n2 n3)");
            if (ints.size() != 5) r.Fail("tetrahedron line must have exactly 5 integers: '" + s + "'");
            RawTet t;
            for (int a = 0; a < 4; ++a) t.nodes[a] = ints[1 + a];
            t.phys = 0;
            t.entity = entity;
            t.line = r.line();
            raw.push_back(t);
          }
        }
      }
      r.End(sec);
    } else {
      // Unknown section: skip to its end.
      const std::string end = "$End" + sec.substr(1);
      bool found = false;
      while (r.Next(s))
        if (MshReader::Trim(s) == end) {
          found = true;
          break;
        }
      if (!found) r.Fail("unexpected end of file: missing " + end);
    }
  }
  if (!have_format) r.Fail("missing $MeshFormat section");
  if (!have_nodes) r.Fail("missing $Nodes section");
  if (!have_elements) r.Fail("missing $Elements section");
  if (raw.empty()) r.Fail("no 4-node tetrahedra (type 4) in $Elements");

  // Physical tag per tetrahedron.
  if (version == 4.1)
    for (auto &t : raw) {
      auto it = vol_phys.find(t.entity);
      t.phys = (it != vol_phys.end() && !it->second.empty()) ? it->second.front() : 0;
    }
  bool any_phys = false;
  for (const auto &t : raw) any_phys = any_phys || t.phys != 0;

  // Compact nodes: keep those used by tetrahedra, in tag order.
  std::vector<int> used(raw_nodes.size(), 0);
  for (const auto &t : raw)
    for (long n : t.nodes) {
      auto it = node_index.find(n);
      if (it == node_index.end()) r.FailAt(t.line, "tetrahedron references undefined node " + std::to_string(n));
      used[it->second] = 1;
    }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < raw_nodes.size(); ++i)
    if (used[i]) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return raw_nodes[a].first < raw_nodes[b].first; });
  std::vector<int> new_id(raw_nodes.size(), -1);
  TetMesh mesh;
  for (std::size_t i : order) {
    new_id[i] = static_cast<int>(mesh.nodes.size());
    mesh.nodes.push_back(raw_nodes[i].second);
  }
  for (const auto &t : raw) {
    std::array<int, 4> n;
    for (int a = 0; a < 4; ++a) n[a] = new_id[node_index[t.nodes[a]]];
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (n[a] == n[b]) r.FailAt(t.line, "tetrahedron has a repeated node " + std::to_string(t.nodes[a]));
    const double v6 = 6.0 * TetSignedVolume(mesh.nodes[n[0]], mesh.nodes[n[1]], mesh.nodes[n[2]], mesh.nodes[n[3]]);
    if (Degenerate(v6, LongestEdge(mesh.nodes, n))) r.FailAt(t.line, "degenerate tetrahedron (zero volume)");
    if (v6 < 0) std::swap(n[1], n[2]);
    mesh.tets.push_back(n);
  }

  if (any_phys) {
    std::map<long, int> body_of;
    for (const auto &t : raw) {
      if (t.phys == 0)
        r.FailAt(t.line, "tetrahedron belongs to no physical group while other tetrahedra do "
                         "(add it to a physical volume or remove all physical volumes)");
      body_of.emplace(t.phys, 0);
    }
    int b = 0;
    for (auto &kv : body_of) {
      kv.second = b++;
      auto it = names3.find(kv.first);
      mesh.body_names.push_back(it != names3.end() ? it->second : "physical_" + std::to_string(kv.first));
    }
    for (const auto &t : raw) mesh.body.push_back(body_of[t.phys]);
  } else {
    int nc = 0;
    mesh.body = ConnectedComponents(mesh, &nc);
    for (int c = 0; c < nc; ++c) mesh.body_names.push_back("component_" + std::to_string(c));
  }
  return mesh;
}

TetMesh ReadGmsh(const std::string &path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open file");
  return ParseGmsh(f, path);
}

} // namespace fdem::kernels
