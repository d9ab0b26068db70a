// Mass properties of tetrahedral bodies and small mesh generators
// (see include/fdem/kernels/massprops.hpp).
#include <fdem/kernels/massprops.hpp>

#include <fdem/kernels/error.hpp>
#include <fdem/kernels/tetmesh.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

namespace fdem::kernels {
namespace {

using Tet = std::array<int, 4>;
using Tri = std::array<int, 3>;

[[noreturn]] void Fail(const std::string &body, const std::string &what) {
  throw InputError("body '" + body + "': " + what);
}

std::string TetString(const std::vector<Vec3> &nodes, const Tet &t, std::size_t e) {
  std::ostringstream os;
  os << "tetrahedron " << e << " (nodes " << t[0] << ", " << t[1] << ", " << t[2] << ", " << t[3] << ")";
  (void)nodes;
  return os.str();
}

double LongestEdge(const Vec3 p[4]) {
  double l = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) l = std::max(l, norm(p[b] - p[a]));
  return l;
}

// Faces of a positively oriented tetrahedron, each with outward normal.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

Tri SortedTri(Tri f) {
  std::sort(f.begin(), f.end());
  return f;
}

// (v1 - v0) . ((v2 - v0) x (v3 - v0)) / 6 (kept local: tetmesh.cpp exports
// the public TetSignedVolume with the same convention).
double SignedVolume(const Vec3 &v0, const Vec3 &v1, const Vec3 &v2, const Vec3 &v3) {
  return dot(v1 - v0, cross(v2 - v0, v3 - v0)) / 6.0;
}

} // namespace

int OrientTetsPositive(const std::vector<Vec3> &nodes, std::vector<std::array<int, 4>> &tets) {
  int flipped = 0;
  for (auto &t : tets) {
    if (SignedVolume(nodes.at(t[0]), nodes.at(t[1]), nodes.at(t[2]), nodes.at(t[3])) < 0.0) {
      std::swap(t[2], t[3]);
      ++flipped;
    }
  }
  return flipped;
}

std::vector<std::array<int, 3>> BoundaryFaces(const std::vector<std::array<int, 4>> &tets) {
  std::map<Tri, std::pair<int, Tri>> count; // sorted face -> (uses, oriented face of first use)
  for (const auto &t : tets)
    for (const auto &f : kFace) {
      const Tri tri{t[f[0]], t[f[1]], t[f[2]]};
      auto [it, inserted] = count.try_emplace(SortedTri(tri), 0, tri);
      ++it->second.first;
    }
  std::vector<Tri> out;
  for (const auto &kv : count)
    if (kv.second.first == 1) out.push_back(kv.second.second);
  return out;
}

void SymmetricEigen(const Mat3 &A, Vec3 &values, Mat3 &vectors) {
  Mat3 a = A;
  // Symmetrise against round-off in the input.
  for (int r = 0; r < 3; ++r)
    for (int c = r + 1; c < 3; ++c) a.m[r][c] = a.m[c][r] = 0.5 * (A.m[r][c] + A.m[c][r]);
  Mat3 v = Mat3::identity();
  double scale = 0;
  for (auto &row : a.m)
    for (double x : row) scale = std::max(scale, std::fabs(x));
  for (int sweep = 0; sweep < 64 && scale > 0; ++sweep) {
    const double off = std::fabs(a.m[0][1]) + std::fabs(a.m[0][2]) + std::fabs(a.m[1][2]);
    if (off <= 1e-18 * scale) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const double apq = a.m[p][q];
        if (std::fabs(apq) <= 1e-300) continue;
        const double theta = (a.m[q][q] - a.m[p][p]) / (2.0 * apq);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        Mat3 J = Mat3::identity();
        J.m[p][p] = c;
        J.m[q][q] = c;
        J.m[p][q] = s;
        J.m[q][p] = -s;
        a = transpose(J) * a * J;
        a.m[p][q] = a.m[q][p] = 0.0;
        v = v * J;
      }
  }
  int idx[3] = {0, 1, 2};
  std::sort(idx, idx + 3, [&](int x, int y) { return a.m[x][x] < a.m[y][y]; });
  Vec3 col[3];
  for (int k = 0; k < 3; ++k) {
    values[k] = a.m[idx[k]][idx[k]];
    col[k] = v.col(idx[k]);
  }
  for (int k = 0; k < 2; ++k) {
    int big = 0;
    for (int r = 1; r < 3; ++r)
      if (std::fabs(col[k][r]) > std::fabs(col[k][big])) big = r;
    if (col[k][big] < 0) col[k] = -col[k];
  }
  col[2] = cross(col[0], col[1]);
  vectors = Mat3::columns(col[0], col[1], col[2]);
}

// Mass properties from the moments of the volume about the point o: vol = int dV, first =
// int (x - o) dV, second = int (x - o)_i (x - o)_j dV.
static MassProperties FromMoments(double vol, const Vec3 &first, const Mat3 &second, const Vec3 &o, double density, const std::string &body_name) {
  MassProperties mp;
  mp.volume = vol;
  mp.mass = density * vol;
  const Vec3 d = first / vol; // COM relative to o
  mp.com = o + d;
  // Second moment about the COM (parallel axis), then the inertia tensor.
  Mat3 C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C.m[i][j] = density * (second.m[i][j] - vol * d[i] * d[j]);
  const double tr = trace(C);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) mp.inertia_com.m[i][j] = (i == j ? tr : 0.0) - C.m[i][j];
  SymmetricEigen(mp.inertia_com, mp.principal_moments, mp.principal_axes);
  if (mp.principal_moments[0] <= 1e-12 * mp.principal_moments[2]) {
    std::ostringstream os;
    os << "degenerate inertia: principal moments " << mp.principal_moments[0] << ", " << mp.principal_moments[1] << ", "
       << mp.principal_moments[2] << " (smallest <= 1e-12 x largest)";
    Fail(body_name, os.str());
  }
  return mp;
}

MassProperties ComputeMassProperties(const std::vector<Vec3> &nodes, const std::vector<std::array<int, 4>> &tets,
                                     double density, const std::string &body_name) {
  if (!(density > 0.0) || !std::isfinite(density)) {
    std::ostringstream os;
    os << "density " << density << " must be positive and finite";
    Fail(body_name, os.str());
  }
  if (tets.empty()) Fail(body_name, "has no tetrahedra (zero total volume)");
  const int nn = static_cast<int>(nodes.size());
  // Reference origin: mean of the nodes (reduces cancellation in the moments).
  Vec3 o;
  for (const auto &p : nodes) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) Fail(body_name, "a node coordinate is not finite");
    o += p;
  }
  o = o / static_cast<double>(std::max(nn, 1));

  double vol = 0;
  Vec3 first;   // int x dV about o
  Mat3 second;  // int x x^T dV about o
  for (std::size_t e = 0; e < tets.size(); ++e) {
    const Tet &t = tets[e];
    for (int a = 0; a < 4; ++a) {
      if (t[a] < 0 || t[a] >= nn) {
        std::ostringstream os;
        os << TetString(nodes, t, e) << " refers to node " << t[a] << " outside [0, " << nn << ")";
        Fail(body_name, os.str());
      }
      for (int b = 0; b < a; ++b)
        if (t[a] == t[b]) Fail(body_name, TetString(nodes, t, e) + " repeats a node");
    }
    Vec3 p[4];
    for (int a = 0; a < 4; ++a) p[a] = nodes[t[a]] - o;
    const double V = SignedVolume(p[0], p[1], p[2], p[3]);
    const double L = LongestEdge(p);
    if (std::fabs(6.0 * V) <= 1e-14 * L * L * L) {
      std::ostringstream os;
      os << TetString(nodes, t, e) << " is degenerate (signed volume " << V << ", longest edge " << L << ")";
      Fail(body_name, os.str());
    }
    if (V < 0.0) {
      std::ostringstream os;
      os << TetString(nodes, t, e) << " has negative signed volume " << V
         << " (expected (v1-v0).((v2-v0)x(v3-v0)) > 0; call OrientTetsPositive)";
      Fail(body_name, os.str());
    }
    const Vec3 S = p[0] + p[1] + p[2] + p[3];
    vol += V;
    first += (V / 4.0) * S;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double sum = S[i] * S[j];
        for (int a = 0; a < 4; ++a) sum += p[a][i] * p[a][j];
        second.m[i][j] += V / 20.0 * sum;
      }
  }

  // The same tetrahedron twice: named as such (a lone one's faces would pair
  // up with its copy's and pass the boundary check below with twice the mass).
  {
    const auto rep = FirstRepeatedTet(tets);
    if (rep[1] < tets.size()) Fail(body_name, TetString(nodes, tets[rep[1]], rep[1]) + " repeats tetrahedron " + std::to_string(rep[0]));
  }
  // Closed 2-manifold boundary.
  {
    std::map<Tri, std::pair<int, std::size_t>> faces; // sorted face -> (uses, first tet)
    for (std::size_t e = 0; e < tets.size(); ++e)
      for (const auto &f : kFace) {
        const Tri key = SortedTri({tets[e][f[0]], tets[e][f[1]], tets[e][f[2]]});
        auto [it, inserted] = faces.try_emplace(key, 0, e);
        if (++it->second.first > 2) {
          std::ostringstream os;
          os << "boundary is not a closed 2-manifold: face (" << key[0] << ", " << key[1] << ", " << key[2]
             << ") of " << TetString(nodes, tets[e], e) << " is shared by more than two tetrahedra (first: tetrahedron "
             << it->second.second << ")";
          Fail(body_name, os.str());
        }
      }
    std::map<std::pair<int, int>, std::pair<int, std::size_t>> edges; // boundary edge -> (faces, a tet)
    for (const auto &kv : faces) {
      if (kv.second.first != 1) continue;
      const Tri &f = kv.first;
      for (int k = 0; k < 3; ++k) {
        const int a = f[k], b = f[(k + 1) % 3];
        auto [it, inserted] = edges.try_emplace(std::make_pair(std::min(a, b), std::max(a, b)), 0, kv.second.second);
        ++it->second.first;
      }
    }
    for (const auto &kv : edges)
      if (kv.second.first != 2) {
        std::ostringstream os;
        os << "boundary is not a closed 2-manifold: boundary edge (" << kv.first.first << ", " << kv.first.second
           << ") next to " << TetString(nodes, tets[kv.second.second], kv.second.second) << " is shared by "
           << kv.second.first << " boundary faces instead of 2";
        Fail(body_name, os.str());
      }
  }

  if (!(vol > 0.0)) Fail(body_name, "total volume is zero");
  return FromMoments(vol, first, second, o, density, body_name);
}

void MakeBoxTets(const Vec3 &lo, const Vec3 &hi, int nx, int ny, int nz, std::vector<Vec3> &nodes,
                 std::vector<std::array<int, 4>> &tets) {
  if (nx < 1 || ny < 1 || nz < 1) throw InputError("MakeBoxTets: cell counts must be at least 1");
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw InputError("MakeBoxTets: hi must exceed lo in x, y and z");
  nodes.clear();
  tets.clear();
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        nodes.push_back({lo.x + (hi.x - lo.x) * i / nx, lo.y + (hi.y - lo.y) * j / ny, lo.z + (hi.z - lo.z) * k / nz});
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto &pm : perms) {
          int c[3] = {i, j, k};
          Tet t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[pm[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          tets.push_back(t);
        }
  OrientTetsPositive(nodes, tets);
}

void MakeEllipsoidTets(const Vec3 &semi_axes, int refinement, std::vector<Vec3> &nodes,
                       std::vector<std::array<int, 4>> &tets) {
  if (!(semi_axes.x > 0 && semi_axes.y > 0 && semi_axes.z > 0))
    throw InputError("MakeEllipsoidTets: semi-axes must be positive");
  if (refinement < 0 || refinement > 9) throw InputError("MakeEllipsoidTets: refinement must be in [0, 9]");
  std::vector<Vec3> sph = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Octahedron faces, outward.
  std::vector<Tri> tris = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int r = 0; r < refinement; ++r) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const Vec3 m = sph[a] + sph[b];
      sph.push_back(m / norm(m));
      const int id = static_cast<int>(sph.size()) - 1;
      mid.emplace(key, id);
      return id;
    };
    std::vector<Tri> next;
    next.reserve(4 * tris.size());
    for (const auto &t : tris) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    tris.swap(next);
  }
  nodes.clear();
  tets.clear();
  for (const auto &p : sph) nodes.push_back({semi_axes.x * p.x, semi_axes.y * p.y, semi_axes.z * p.z});
  const int centre = static_cast<int>(nodes.size());
  nodes.push_back({0, 0, 0});
  // Outward triangle (a, b, c) with the centre first gives positive volume.
  for (const auto &t : tris) tets.push_back({centre, t[0], t[1], t[2]});
  OrientTetsPositive(nodes, tets);
}

void MakeConvexPolyhedronTets(const std::vector<Vec3> &points, std::vector<Vec3> &nodes,
                              std::vector<std::array<int, 4>> &tets) {
  const int n = static_cast<int>(points.size());
  if (n < 4) throw InputError("MakeConvexPolyhedronTets: need at least 4 points, got " + std::to_string(n));
  Vec3 lo = points[0], hi = points[0];
  for (const auto &p : points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  const double diag = norm(hi - lo);
  const double eps = 1e-12 * diag;
  if (!(diag > 0)) throw InputError("MakeConvexPolyhedronTets: all points coincide");
  // Initial tetrahedron: two farthest-apart extreme points, then the farthest
  // from their line, then the farthest from their plane.
  int i0 = 0, i1 = 0;
  {
    double best = -1;
    for (int a = 0; a < n; ++a) {
      const double d = norm(points[a] - points[0]);
      if (d > best) { best = d; i1 = a; }
    }
    best = -1;
    for (int a = 0; a < n; ++a) {
      const double d = norm(points[a] - points[i1]);
      if (d > best) { best = d; i0 = a; }
    }
  }
  const Vec3 dir = (points[i1] - points[i0]) / norm(points[i1] - points[i0]);
  int i2 = -1;
  double best = eps;
  for (int a = 0; a < n; ++a) {
    const Vec3 w = points[a] - points[i0];
    const double d = norm(w - dot(w, dir) * dir);
    if (d > best) { best = d; i2 = a; }
  }
  if (i2 < 0) throw InputError("MakeConvexPolyhedronTets: all points are collinear");
  const Vec3 nrm0 = cross(points[i1] - points[i0], points[i2] - points[i0]);
  const Vec3 nrm = nrm0 / norm(nrm0);
  int i3 = -1;
  best = eps;
  for (int a = 0; a < n; ++a) {
    const double d = std::fabs(dot(points[a] - points[i0], nrm));
    if (d > best) { best = d; i3 = a; }
  }
  if (i3 < 0) throw InputError("MakeConvexPolyhedronTets: all points are coplanar (no volume)");
  if (dot(points[i3] - points[i0], nrm) > 0) std::swap(i1, i2); // make (i0,i1,i2) face away from i3

  std::vector<Tri> faces = {{i0, i1, i2}, {i0, i3, i1}, {i1, i3, i2}, {i2, i3, i0}};
  auto dist = [&](const Tri &f, const Vec3 &p) {
    const Vec3 nf = cross(points[f[1]] - points[f[0]], points[f[2]] - points[f[0]]);
    return dot(p - points[f[0]], nf) / norm(nf);
  };
  for (int a = 0; a < n; ++a) {
    if (a == i0 || a == i1 || a == i2 || a == i3) continue;
    std::vector<char> visible(faces.size(), 0);
    bool any = false;
    for (std::size_t f = 0; f < faces.size(); ++f)
      if (dist(faces[f], points[a]) > eps) visible[f] = any = true;
    if (!any) continue; // inside (or on) the current hull
    std::map<std::pair<int, int>, std::size_t> owner; // directed edge -> face
    for (std::size_t f = 0; f < faces.size(); ++f)
      for (int k = 0; k < 3; ++k) owner[{faces[f][k], faces[f][(k + 1) % 3]}] = f;
    std::vector<Tri> next;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      if (!visible[f]) {
        next.push_back(faces[f]);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const int u = faces[f][k], w = faces[f][(k + 1) % 3];
        const auto it = owner.find({w, u});
        if (it != owner.end() && !visible[it->second]) next.push_back({u, w, a}); // horizon edge
      }
    }
    faces.swap(next);
  }
  // Renumber the hull vertices; centroid as the apex of every tetrahedron.
  std::map<int, int> renum;
  nodes.clear();
  tets.clear();
  for (const auto &f : faces)
    for (int v : f)
      if (renum.emplace(v, static_cast<int>(nodes.size())).second) nodes.push_back(points[v]);
  Vec3 c;
  for (const auto &p : nodes) c += p;
  c = c / static_cast<double>(nodes.size());
  const int centre = static_cast<int>(nodes.size());
  nodes.push_back(c);
  for (const auto &f : faces) tets.push_back({centre, renum[f[0]], renum[f[1]], renum[f[2]]});
  OrientTetsPositive(nodes, tets);
}

MassProperties BallUnionMassProperties(const std::vector<Ball> &balls, double density, const std::string &body_name) {
  if (balls.empty()) Fail(body_name, "has no spheres");
  if (!std::isfinite(density) || !(density > 0.0)) Fail(body_name, "density " + std::to_string(density) + " must be positive");
  for (std::size_t k = 0; k < balls.size(); ++k) {
    const Ball &b = balls[k];
    if (!std::isfinite(b.c.x) || !std::isfinite(b.c.y) || !std::isfinite(b.c.z)) Fail(body_name, "sphere " + std::to_string(k) + ": its centre is not finite");
    if (!std::isfinite(b.r) || !(b.r > 0.0)) Fail(body_name, "sphere " + std::to_string(k) + ": radius " + std::to_string(b.r) + " must be positive");
  }
  // Moments about o (the first centre) on lines parallel to z through the centres of an nx x ny
  // grid of cells over the union's shadow: along a line the union is a set of intervals, whose
  // moments in z are exact; across the cells the midpoint rule (with the cell's own spread hx^2/12
  // in the x^2 and y^2 moments). The same grid gives each ball alone; its exact moments minus
  // that are added (a control variate), which makes one ball, or balls that do not overlap,
  // exact to round-off and leaves the error of the shadow's edges hidden inside other balls.
  const Vec3 o = balls[0].c;
  double     lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL}, rmin = HUGE_VAL;
  for (const Ball &b : balls) {
    const Vec3 c = b.c - o;
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], c[a] - b.r), hi[a] = std::max(hi[a], c[a] + b.r);
    rmin = std::min(rmin, b.r);
  }
  // at most 1024 lines a side, and about 1e8 sphere tests in all (a clump of many spheres gets a
  // coarser grid, never fewer than 16 lines a side)
  const double most = std::max(16.0, std::min(1024.0, std::floor(std::sqrt(1e8 / (double)balls.size()))));
  int          n[2];
  double       h[2];
  for (int a = 0; a < 2; ++a) {
    if (!std::isfinite(hi[a] - lo[a])) Fail(body_name, "its spheres span a region too large to integrate");
    n[a] = (int)std::min(most, std::max(16.0, std::ceil((hi[a] - lo[a]) / (rmin / 64))));
    h[a] = (hi[a] - lo[a]) / n[a];
  }
  struct Moments {
    double vol = 0;
    Vec3   first;
    Mat3   second;
    void   Add(double A, double x, double y, double hx2, double hy2, double z0, double z1) {
      const double L = z1 - z0, Z1 = 0.5 * (z1 * z1 - z0 * z0), Z2 = (z1 * z1 * z1 - z0 * z0 * z0) / 3;
      vol += A * L;
      first += A * Vec3(x * L, y * L, Z1);
      second.m[0][0] += A * (x * x + hx2 / 12) * L;
      second.m[1][1] += A * (y * y + hy2 / 12) * L;
      second.m[2][2] += A * Z2;
      second.m[0][1] += A * x * y * L;
      second.m[0][2] += A * x * Z1;
      second.m[1][2] += A * y * Z1;
    }
  };
  Moments                                  uni;
  std::vector<Moments>                     single(balls.size());
  std::vector<std::pair<double, double>>   iv;
  const double                             A = h[0] * h[1];
  for (int i = 0; i < n[0]; ++i) {
    const double x = lo[0] + (i + 0.5) * h[0];
    for (int j = 0; j < n[1]; ++j) {
      const double y = lo[1] + (j + 0.5) * h[1];
      iv.clear();
      for (std::size_t k = 0; k < balls.size(); ++k) {
        const Vec3   c  = balls[k].c - o;
        const double d2 = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y), r2 = balls[k].r * balls[k].r;
        if (!(d2 < r2)) continue;
        const double s = std::sqrt(r2 - d2);
        iv.emplace_back(c.z - s, c.z + s);
        single[k].Add(A, x, y, h[0] * h[0], h[1] * h[1], c.z - s, c.z + s);
      }
      if (iv.empty()) continue;
      std::sort(iv.begin(), iv.end());
      double z0 = iv[0].first, z1 = iv[0].second;
      for (std::size_t m = 1; m < iv.size(); ++m) {
        if (iv[m].first > z1) {
          uni.Add(A, x, y, h[0] * h[0], h[1] * h[1], z0, z1);
          z0 = iv[m].first;
        }
        z1 = std::max(z1, iv[m].second);
      }
      uni.Add(A, x, y, h[0] * h[0], h[1] * h[1], z0, z1);
    }
  }
  for (std::size_t k = 0; k < balls.size(); ++k) {
    const Vec3   c = balls[k].c - o;
    const double r = balls[k].r, V = 4.0 / 3.0 * M_PI * r * r * r;
    uni.vol += V - single[k].vol;
    uni.first += V * c - single[k].first;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) uni.second.m[a][b] += V * (c[a] * c[b] + (a == b ? r * r / 5 : 0.0)) - single[k].second.m[a][b];
  }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < a; ++b) uni.second.m[a][b] = uni.second.m[b][a];
  if (!std::isfinite(uni.vol) || !(uni.vol > 0)) Fail(body_name, "the volume of its spheres is not a positive finite number (radii and centres too far apart in scale)");
  MassProperties mp = FromMoments(uni.vol, uni.first, uni.second, o, density, body_name);
  // Principal moments that differ by less than the integration resolves (1e-4 of the largest;
  // measured errors ~5e-5) are made equal, their mean: a clump symmetric about an axis (a
  // dumbbell) or with cubic or tetrahedral symmetry (isotropic) is then a symmetric or spherical
  // top, whose free rotation has a closed form (rotation.hpp), and its moments are exact to the
  // integration's accuracy either way.
  Vec3        &I   = mp.principal_moments; // ascending
  const double tol = 1e-4 * I[2];
  if (I[2] - I[0] <= tol) I[0] = I[1] = I[2] = (I[0] + I[1] + I[2]) / 3;
  else if (I[1] - I[0] <= tol) I[0] = I[1] = 0.5 * (I[0] + I[1]);
  else if (I[2] - I[1] <= tol) I[1] = I[2] = 0.5 * (I[1] + I[2]);
  Mat3 D;
  for (int k = 0; k < 3; ++k) D.m[k][k] = I[k];
  mp.inertia_com = mp.principal_axes * D * transpose(mp.principal_axes);
  return mp;
}

} // namespace fdem::kernels
