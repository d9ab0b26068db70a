// Tetrahedral mesh utilities; see tetmesh.hpp.
#include <fdem/kernels/tetmesh.hpp>
#include <fdem/kernels/joint_mesh.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <map>
#include <numeric>
#include <sstream>
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

// ---------------------------------------------------------------- ordering
// Skilling's transform (J. Skilling, "Programming the Hilbert curve", AIP
// Conf. Proc. 707, 381, 2004): undo the curve's rotations and reflections
// level by level, Gray-code the result, then interleave the bits.
std::uint64_t HilbertIndex(const std::uint32_t X_in[3], int bits) {
  std::uint32_t X[3] = {X_in[0], X_in[1], X_in[2]};
  // (without branches: the bits of a centroid are as good as random, and mispredicted branches
  // were most of a key's cost)
  for (std::uint32_t q = 1u << (bits - 1); q > 1; q >>= 1) {
    const std::uint32_t p = q - 1;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t set = 0u - (std::uint32_t)((X[i] & q) != 0); // all ones where bit q of X[i] is set
      const std::uint32_t t   = (X[0] ^ X[i]) & p & ~set;               // else X[0] and X[i] swap their low bits
      X[0] ^= (p & set) | t;                                            // where set, X[0]'s low bits are inverted
      X[i] ^= t;
    }
  }
  for (int i = 1; i < 3; ++i) X[i] ^= X[i - 1];
  std::uint32_t t = 0;
  for (std::uint32_t q = 1u << (bits - 1); q > 1; q >>= 1) t ^= (q - 1) & (0u - (std::uint32_t)((X[2] & q) != 0));
  for (int i = 0; i < 3; ++i) X[i] ^= t;
  // interleave: bit b of X[0], X[1], X[2] goes to bit 3b + 2, 3b + 1, 3b of the key
  const auto spread = [bits](std::uint32_t x) {
    std::uint64_t v = x & ((1u << bits) - 1); // (bits <= 21)
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(X[0]) << 2 | spread(X[1]) << 1 | spread(X[2]);
}

std::uint64_t HilbertKey(const Vec3 &x, const Vec3 &lo, const Vec3 &hi) {
  constexpr int    kBits = 21;
  constexpr double kTop  = (1u << kBits) - 1;
  std::uint32_t    X[3];
  for (int k = 0; k < 3; ++k) {
    const double w = hi[k] > lo[k] ? (x[k] - lo[k]) / (hi[k] - lo[k]) : 0.0;
    X[k]           = (std::uint32_t)(w >= 0 ? (w <= 1 ? w * kTop : kTop) : 0.0); // NaN to 0
  }
  return HilbertIndex(X, kBits);
}

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
  const std::vector<TetFace> faces = SortedFaces(mesh.tets);
  SurfaceInfo s;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) {
      const auto &n = mesh.tets[faces[i].tet];
      const int *l = kTetFace[faces[i].local];
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

std::string CoordString(const Vec3 &x) {
  std::ostringstream o;
  o.precision(17);
  o << "(" << x.x << ", " << x.y << ", " << x.z << ")";
  return o.str();
}

// Line-oriented reader that knows where it is (file:line for every error) and
// how many bytes of the input are left (a count read from the file is checked
// against that before anything is sized by it: a line takes at least 1 byte).
class MshReader {
public:
  MshReader(std::istream &in, std::string file) : in_(in), file_(std::move(file)) {
    const std::istream::pos_type here = in_.tellg();
    if (here != std::istream::pos_type(-1) && in_.seekg(0, std::ios::end)) {
      const std::istream::pos_type end = in_.tellg();
      if (end != std::istream::pos_type(-1) && end >= here) size_ = static_cast<long long>(end - here);
    }
    in_.clear();
    if (here != std::istream::pos_type(-1)) in_.seekg(here);
  }

  std::string At(long line) const { return file_ + ":" + std::to_string(line); }
  [[noreturn]] void Fail(const std::string &what) const { FailAt(line_, what); }
  [[noreturn]] void FailAt(long line, const std::string &what) const { throw InputError(At(line) + ": " + what); }
  bool Next(std::string &s) {
    if (!std::getline(in_, s)) return false;
    ++line_;
    read_ += static_cast<long long>(s.size()) + 1;
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
  // A count of items read from the current line, each taking `lines_per_item`
  // lines of what follows: must be >= 0 and fit in the rest of the input.
  long Count(long n, long lines_per_item, const std::string &what) const {
    if (n < 0) Fail(what + " " + std::to_string(n) + " is negative");
    if (size_ >= 0) {
      const long long left = size_ - read_;
      if (n > left / lines_per_item)
        Fail(what + " " + std::to_string(n) + " is more than the rest of the file can hold (" + std::to_string(left) +
             " bytes left, at least " + std::to_string(lines_per_item) + " line(s) each)");
    }
    return n;
  }
  // Integers on a line; at least `min_count` of them, else an error.
  void Ints(const std::string &s, std::vector<long> &out, std::size_t min_count, const char *what) const {
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
  // `count` finite reals from `from` on (a position in `line`; a number out of
  // the double range, nan or inf is an error). Returns the rest of the line.
  const char *Reals(const std::string &line, const char *from, double *out, int count, const char *what) const {
    const char *p = from;
    char *end;
    for (int i = 0; i < count; ++i) {
      out[i] = std::strtod(p, &end);
      if (end == p || (*end && *end != ' ' && *end != '\t')) Fail(std::string("malformed ") + what + ": '" + line + "'");
      if (!std::isfinite(out[i]))
        Fail(std::string(what) + ": value '" + MshReader::Trim(std::string(p, static_cast<const char *>(end))) + "' is not a finite number");
      p = end;
    }
    return p;
  }
  long line() const { return line_; }

private:
  std::istream &in_;
  std::string file_;
  long line_ = 0;
  long long read_ = 0;   // bytes consumed
  long long size_ = -1;  // bytes in the input from the start (-1: unknown, e.g. a pipe)
};

struct RawNode {
  long tag, line;
  Vec3 x;
};

struct RawTet {
  std::array<long, 4> nodes;
  long tag;     // element tag
  long phys;    // physical tag (2.2) or 0
  long entity;  // entity tag (4.1) or -1
  long line;
};

// The earliest repeated tetrahedron in file order (same four nodes in any
// order) is an error naming both elements and their lines.
void CheckRepeatedTets(const MshReader &r, const std::vector<RawTet> &raw) {
  std::vector<std::array<long, 4>> nodes(raw.size());
  for (std::size_t t = 0; t < raw.size(); ++t) nodes[t] = raw[t].nodes;
  const auto [first, second] = FirstRepeatedTet(nodes);
  if (second == raw.size()) return;
  const RawTet &a = raw[first], &b = raw[second];
  r.FailAt(b.line, "element " + std::to_string(b.tag) + " repeats element " + std::to_string(a.tag) + " (line " +
                       std::to_string(a.line) + "): the same tetrahedron (nodes " + std::to_string(b.nodes[0]) + " " +
                       std::to_string(b.nodes[1]) + " " + std::to_string(b.nodes[2]) + " " + std::to_string(b.nodes[3]) +
                       ") given twice");
}

// Faces of the (positively oriented) tetrahedra: a face in more than two
// tetrahedra, or in two that lie on the same side of it (they overlap), is an
// error naming the elements, their lines and the face's nodes (first in file order).
void CheckSharedFaces(const MshReader &r, const std::vector<RawTet> &raw, const TetMesh &mesh,
                      const std::vector<const RawNode *> &src) {
  static const int F[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};  // outward
  struct Face {
    std::array<int, 3> key;  // sorted mesh nodes
    int tet, parity;         // parity of the outward orientation relative to key
  };
  std::vector<Face> faces;
  faces.reserve(4 * mesh.tets.size());
  for (int t = 0; t < static_cast<int>(mesh.tets.size()); ++t)
    for (const auto &f : F) {
      const auto &n = mesh.tets[t];
      const std::array<int, 3> o{n[f[0]], n[f[1]], n[f[2]]};
      std::array<int, 3> k = o;
      std::sort(k.begin(), k.end());
      faces.push_back({k, t, ((o[0] > o[1]) + (o[0] > o[2]) + (o[1] > o[2])) % 2});
    }
  std::sort(faces.begin(), faces.end(), [](const Face &a, const Face &b) { return a.key < b.key || (a.key == b.key && a.tet < b.tet); });
  long worst = -1;
  std::string what;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    const bool too_many = j - i > 2, same_side = j - i == 2 && faces[i].parity == faces[i + 1].parity;
    if (too_many || same_side) {
      const RawTet &a = raw[faces[i].tet], &b = raw[faces[i + 1].tet];
      const RawTet &last = raw[faces[too_many ? i + 2 : i + 1].tet];
      if (worst < 0 || last.line < worst) {
        worst = last.line;
        std::string face = "face (nodes";
        for (int m : faces[i].key) face += " " + std::to_string(src[m]->tag);
        face += ")";
        what = too_many ? "element " + std::to_string(last.tag) + " has a " + face + " that elements " + std::to_string(a.tag) +
                              " (line " + std::to_string(a.line) + ") and " + std::to_string(b.tag) + " (line " +
                              std::to_string(b.line) + ") already share: a face belongs to at most two tetrahedra (overlapping elements)"
                        : "element " + std::to_string(b.tag) + " and element " + std::to_string(a.tag) + " (line " +
                              std::to_string(a.line) + ") lie on the same side of their shared " + face + ": they overlap";
      }
    }
    i = j;
  }
  if (worst >= 0) r.FailAt(worst, what);
}

// Distinct nodes at exactly the same coordinates. Within one body that is a
// seam the mesh falls apart at (an error); between two bodies it is legitimate
// (bodies meshed separately that touch) and gives one warning for the file.
void CheckCoincidentNodes(const MshReader &r, const TetMesh &mesh, const std::vector<const RawNode *> &src,
                          std::vector<std::string> &warnings) {
  std::vector<std::pair<int, int>> node_body;  // (node, body), sorted, unique
  node_body.reserve(4 * mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int a : mesh.tets[t]) node_body.emplace_back(a, mesh.body[t]);
  std::sort(node_body.begin(), node_body.end());
  node_body.erase(std::unique(node_body.begin(), node_body.end()), node_body.end());
  std::vector<std::size_t> first_body(mesh.nodes.size() + 1, 0);  // node i's bodies: [first_body[i], first_body[i+1])
  for (const auto &nb : node_body) ++first_body[nb.first + 1];
  std::partial_sum(first_body.begin(), first_body.end(), first_body.begin());

  const int n = static_cast<int>(mesh.nodes.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    const Vec3 &p = mesh.nodes[a], &q = mesh.nodes[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return p.z < q.z;
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return less(a, b) || (!less(b, a) && src[a]->line < src[b]->line); });
  long extra = 0;
  std::string warning;
  std::map<int, int> holder;  // body -> the first node of the group in it
  const RawNode *seam_a = nullptr, *seam_b = nullptr;  // two coincident nodes in one body
  int seam_body = -1;
  for (int i = 0; i < n;) {
    int j = i + 1;
    while (j < n && !less(order[i], order[j])) ++j;
    if (j - i > 1) {
      holder.clear();
      for (int k = i; k < j; ++k)
        for (std::size_t q = first_body[order[k]]; q < first_body[order[k] + 1]; ++q) {
          const auto ins = holder.emplace(node_body[q].second, order[k]);
          if (ins.second) continue;
          if (!seam_a || src[order[k]]->line < seam_b->line) {
            seam_a = src[ins.first->second];
            seam_b = src[order[k]];
            seam_body = node_body[q].second;
          }
        }
      if (warning.empty()) {
        const RawNode &a = *src[order[i]], &b = *src[order[i + 1]];
        warning = r.At(b.line) + ": node " + std::to_string(b.tag) + " has the same coordinates " + CoordString(b.x) +
                  " as node " + std::to_string(a.tag) + " (line " + std::to_string(a.line) + ") of another body ('" +
                  mesh.body_names[node_body[first_body[order[i]]].second] + "' and '" +
                  mesh.body_names[node_body[first_body[order[i + 1]]].second] + "' touch there)";
      }
      extra += j - i - 1;
    }
    i = j;
  }
  if (seam_a)  // the first one in file order
    r.FailAt(seam_b->line, "node " + std::to_string(seam_b->tag) + " has the same coordinates " + CoordString(seam_b->x) +
                               " as node " + std::to_string(seam_a->tag) + " (line " + std::to_string(seam_a->line) +
                               ") and both are in body '" + mesh.body_names[seam_body] +
                               "': its tetrahedra are not joined there (merge the nodes, e.g. Gmsh's Coherence Mesh)");
  if (extra > 1) warning += "; " + std::to_string(extra - 1) + " more node(s) coincide with a node of another body";
  if (!warning.empty()) warnings.push_back(warning);
}

TetMesh Parse(MshReader &r) {
  std::string s;
  double version = 0;
  bool have_format = false, have_nodes = false, have_elements = false;
  std::map<long, std::string> names3;                    // physical tag -> name (dim 3)
  std::unordered_map<long, std::vector<long>> vol_phys;  // 4.1 volume entity -> physical tags
  std::unordered_map<long, std::size_t> node_index;      // node tag -> index in raw_nodes
  std::vector<RawNode> raw_nodes;
  std::vector<RawTet> raw;
  std::vector<long> ints;

  while (r.Next(s)) {
    const std::string sec = MshReader::Trim(s);
    if (sec.empty()) continue;
    if (sec[0] != '$') r.Fail("expected a section header ($Name), found '" + s + "'");
    if (sec == "$MeshFormat") {
      r.Line(sec, s);
      char *e;
      const char *p = s.c_str();
      const double v = std::strtod(p, &e);
      if (e == p) r.Fail("malformed $MeshFormat line '" + s + "'");
      p = e;
      const long ft = std::strtol(p, &e, 10);
      if (e == p) r.Fail("malformed $MeshFormat line '" + s + "'");
      if (v != 2.2 && v != 4.1)
        r.Fail("unsupported .msh version " + MshReader::Trim(s.substr(0, s.find(' '))) + " (supported: 2.2, 4.1)");
      if (ft != 0) r.Fail("binary .msh files are not supported (save as ASCII)");
      version = v;
      have_format = true;
      r.End(sec);
    } else if (sec == "$PhysicalNames") {
      r.Line(sec, s);
      r.Ints(s, ints, 1, "$PhysicalNames count");
      const long n = r.Count(ints[0], 1, "$PhysicalNames count");
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
      const char *kind[4] = {"$Entities point count", "$Entities curve count", "$Entities surface count",
                             "$Entities volume count"};
      long count[4];
      for (int k = 0; k < 4; ++k) count[k] = r.Count(ints[k], 1, kind[k]);
      for (int k = 0; k < 3; ++k)
        for (long i = 0; i < count[k]; ++i) r.Line(sec, s);
      for (long i = 0; i < count[3]; ++i) {
        r.Line(sec, s);
        // tag minX minY minZ maxX maxY maxZ numPhysicalTags tags... : parse tag, skip 6 reals.
        const char *p = s.c_str();
        char *e;
        errno = 0;
        const long tag = std::strtol(p, &e, 10);
        if (e == p || errno) r.Fail("malformed volume entity line '" + s + "'");
        double box[6];
        p = r.Reals(s, e, box, 6, "volume entity line (expected: tag minX minY minZ maxX maxY maxZ numPhysicalTags tags...)");
        r.Ints(p, ints, 1, "volume entity line");
        const long nphys = ints[0];
        if (nphys < 0 || nphys > static_cast<long>(ints.size()) - 1)
          r.Fail("volume entity line: numPhysicalTags " + std::to_string(nphys) + " does not match the " +
                 std::to_string(ints.size() - 1) + " integers after it: '" + s + "'");
        vol_phys[tag].assign(ints.begin() + 1, ints.begin() + 1 + nphys);
      }
      r.End(sec);
    } else if (sec == "$Nodes") {
      if (!have_format) r.Fail("$Nodes before $MeshFormat");
      have_nodes = true;
      auto add = [&](long tag, long line, const double x[3]) {
        if (!node_index.emplace(tag, raw_nodes.size()).second)
          r.FailAt(line, "duplicate node tag " + std::to_string(tag) + " (first on line " +
                             std::to_string(raw_nodes[node_index[tag]].line) + ")");
        raw_nodes.push_back({tag, line, {x[0], x[1], x[2]}});
      };
      r.Line(sec, s);
      if (version == 2.2) {
        r.Ints(s, ints, 1, "$Nodes count");
        const long n = r.Count(ints[0], 1, "$Nodes count");
        for (long i = 0; i < n; ++i) {
          r.Line(sec, s);
          const char *p = s.c_str();
          char *e;
          errno = 0;
          const long tag = std::strtol(p, &e, 10);
          if (e == p || errno) r.Fail("malformed node line '" + s + "' (expected: tag x y z)");
          double x[3];
          r.Reals(s, e, x, 3, "node line (expected: tag x y z)");
          add(tag, r.line(), x);
        }
      } else {
        r.Ints(s, ints, 4, "$Nodes header (numEntityBlocks numNodes minTag maxTag)");
        const long nblocks = r.Count(ints[0], 1, "$Nodes numEntityBlocks");
        std::vector<std::pair<long, long>> tags;  // (tag, line)
        for (long b = 0; b < nblocks; ++b) {
          r.Line(sec, s);
          r.Ints(s, ints, 4, "node block header (entityDim entityTag parametric numNodes)");
          const long nb = r.Count(ints[3], 2, "node block numNodes");
          tags.clear();  // grows with the lines actually read (the count may be unchecked: input of unknown size)
          for (long i = 0; i < nb; ++i) {
            r.Line(sec, s);
            r.Ints(s, ints, 1, "node tag");
            if (ints.size() != 1) r.Fail("malformed node tag line '" + s + "' (expected one tag)");
            tags.emplace_back(ints[0], r.line());
          }
          for (long i = 0; i < nb; ++i) {
            r.Line(sec, s);
            double x[3];
            r.Reals(s, s.c_str(), x, 3, "node coordinates");
            add(tags[i].first, r.line(), x);
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
        const long n = r.Count(ints[0], 1, "$Elements count");
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
          // 3 + ntags + 4 integers, compared without overflow.
          if (ntags < 0 || static_cast<long>(ints.size()) - 7 != ntags)
            r.Fail("tetrahedron line must have 3 + ntags + 4 integers (ntags = " + std::to_string(ntags) + "): '" + s + "'");
          RawTet t;
          for (int a = 0; a < 4; ++a) t.nodes[a] = ints[3 + ntags + a];
          t.tag = ints[0];
          t.phys = ntags > 0 ? ints[3] : 0;
          t.entity = -1;
          t.line = r.line();
          raw.push_back(t);
        }
      } else {
        r.Ints(s, ints, 4, "$Elements header (numEntityBlocks numElements minTag maxTag)");
        const long nblocks = r.Count(ints[0], 1, "$Elements numEntityBlocks");
        for (long b = 0; b < nblocks; ++b) {
          r.Line(sec, s);
          r.Ints(s, ints, 4, "element block header (entityDim entityTag elementType numElements)");
          const long dim = ints[0], entity = ints[1], type = ints[2];
          const long nb = r.Count(ints[3], 1, "element block numElements");
          if (GmshTypeDim(type) < 0) r.Fail("unknown element type " + std::to_string(type));
          if (GmshTypeDim(type) != dim)
            r.Fail("element block of dimension " + std::to_string(dim) + " holds element type " + std::to_string(type) +
                   " of dimension " + std::to_string(GmshTypeDim(type)));
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
            t.tag = ints[0];
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
  if (r.line() == 0) r.Fail("empty file (expected a $MeshFormat section)");
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
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return raw_nodes[a].tag < raw_nodes[b].tag; });
  std::vector<int> new_id(raw_nodes.size(), -1);
  std::vector<const RawNode *> src;  // file node of each mesh node
  TetMesh mesh;
  for (std::size_t i : order) {
    new_id[i] = static_cast<int>(mesh.nodes.size());
    mesh.nodes.push_back(raw_nodes[i].x);
    src.push_back(&raw_nodes[i]);
  }
  for (const auto &t : raw) {
    std::array<int, 4> n;
    for (int a = 0; a < 4; ++a) n[a] = new_id[node_index[t.nodes[a]]];
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (n[a] == n[b]) r.FailAt(t.line, "tetrahedron has a repeated node " + std::to_string(t.nodes[a]));
    const double v6 = 6.0 * TetSignedVolume(mesh.nodes[n[0]], mesh.nodes[n[1]], mesh.nodes[n[2]], mesh.nodes[n[3]]);
    const double h = LongestEdge(mesh.nodes, n);
    if (!std::isfinite(v6) || !std::isfinite(h))
      r.FailAt(t.line, "tetrahedron volume is not a finite number (coordinates too large)");
    if (Degenerate(v6, h)) r.FailAt(t.line, "degenerate tetrahedron (zero volume)");
    if (v6 < 0) std::swap(n[1], n[2]);
    mesh.tets.push_back(n);
    mesh.tet_line.push_back(t.line);
  }
  CheckRepeatedTets(r, raw);
  CheckSharedFaces(r, raw, mesh, src);

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
  CheckCoincidentNodes(r, mesh, src, mesh.warnings);
  return mesh;
}

} // namespace

TetMesh ParseGmsh(std::istream &in, const std::string &filename) {
  MshReader r(in, filename);
  try {
    return Parse(r);
  } catch (const InputError &) {
    throw;
  } catch (const std::exception &e) {  // e.g. std::bad_alloc: still say where
    r.Fail(std::string("cannot read the mesh: ") + e.what());
  }
}

TetMesh ReadGmsh(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot open file");
  return ParseGmsh(f, path);
}

template <class Index>
std::array<std::size_t, 2> FirstRepeatedTet(const std::vector<std::array<Index, 4>> &tets) {
  const std::size_t n = tets.size();
  std::vector<std::pair<std::array<Index, 4>, std::size_t>> key(n);
  for (std::size_t t = 0; t < n; ++t) {
    key[t] = {tets[t], t};
    std::sort(key[t].first.begin(), key[t].first.end());
  }
  std::sort(key.begin(), key.end());
  std::array<std::size_t, 2> best{n, n};  // earliest second copy wins
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    if (key[i].first != key[j].first) { j = i; continue; }  // j: first copy of this run (smallest position)
    if (key[i].second < best[1]) best = {key[j].second, key[i].second};
  }
  return best;
}
template std::array<std::size_t, 2> FirstRepeatedTet(const std::vector<std::array<int, 4>> &);
template std::array<std::size_t, 2> FirstRepeatedTet(const std::vector<std::array<long, 4>> &);

} // namespace fdem::kernels
