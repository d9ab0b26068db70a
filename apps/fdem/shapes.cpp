#include "shapes.hpp"

#include <fdem/kernels/error.hpp>
#include <fdem/kernels/massprops.hpp>
#include <fdem/kernels/pebble.hpp>
#include <fdem/kernels/rotation.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace fdem::driver {
namespace {

kernels::TetMesh FromTets(std::vector<Vec3> X, std::vector<std::array<int, 4>> T) {
  kernels::TetMesh m;
  m.nodes = std::move(X);
  m.tets  = std::move(T);
  m.body.assign(m.tets.size(), 0);
  m.body_names = {"body"};
  return m;
}

int Cells(double length, double h) { return std::max(1, (int)std::lround(length / h)); }

// A generated mesh of more tetrahedra than this is refused at input (each takes ~1 kB with its
// nodes, the TS's vectors and contact): a resolution far below the body's size is a typo, and its
// cell counts would leave the range of int
constexpr double kMaxGeneratedTets = 1e8;
void CheckGeneratedTets(double tets, double h) {
  if (tets <= kMaxGeneratedTets) return;
  char msg[200];
  std::snprintf(msg, sizeof msg, "resolution %.3g m would give about %.3g tetrahedra (at most %.0e are generated): give a larger resolution", h, tets, kMaxGeneratedTets);
  throw kernels::InputError(msg);
}

// Refinement level of the ellipsoid generator whose edges are about h on the largest semi-axis a.
int Refinement(double a, double h) { return std::clamp((int)std::ceil(std::log2(M_PI * a / (2 * h))), 1, 6); }

} // namespace

kernels::TetMesh ShapeMesh(const Body &b) {
  const Shape &s   = b.shape;
  const bool   def = b.model == "deformable";
  try {
    std::vector<Vec3>               X;
    std::vector<std::array<int, 4>> T;
    switch (s.kind) {
    case ShapeKind::Box: {
      const double smallest = std::min({s.size.x, s.size.y, s.size.z});
      const double h        = b.resolution > 0 ? b.resolution : (def ? smallest / 4 : smallest);
      CheckGeneratedTets(6 * std::max(1.0, s.size.x / h) * std::max(1.0, s.size.y / h) * std::max(1.0, s.size.z / h), h);
      return kernels::MakeBoxMesh(-0.5 * s.size, 0.5 * s.size, Cells(s.size.x, h), Cells(s.size.y, h), Cells(s.size.z, h));
    }
    case ShapeKind::Sphere:
    case ShapeKind::Ellipsoid: {
      const Vec3   axes = s.kind == ShapeKind::Sphere ? Vec3(s.radius, s.radius, s.radius) : s.size;
      const double a    = std::max({axes.x, axes.y, axes.z});
      kernels::MakeEllipsoidTets(axes, b.resolution > 0 ? Refinement(a, b.resolution) : (def ? 3 : 2), X, T);
      return FromTets(X, T);
    }
    case ShapeKind::Cylinder: {
      const double     h = b.resolution > 0 ? b.resolution : s.radius / (def ? 3 : 2);
      CheckGeneratedTets(12 * std::max(1.0, s.radius / h) * std::max(1.0, s.radius / h) * std::max(1.0, s.height / h), h); // rings of ~2 pi r / h cells
      kernels::TetMesh m = kernels::MakeCylinderMesh(s.radius, s.height, Cells(s.radius, h), Cells(s.height, h));
      for (auto &p : m.nodes) p.z -= 0.5 * s.height;
      return m;
    }
    case ShapeKind::ConvexHull:
      kernels::MakeConvexPolyhedronTets(s.points, X, T);
      return FromTets(X, T);
    case ShapeKind::Spheres: // a clump: each sphere's octahedron (its bounding box, for the scene's extent and the packing)
      for (size_t k = 0; k < s.points.size(); ++k) {
        std::vector<Vec3>               Xk;
        std::vector<std::array<int, 4>> Tk;
        kernels::MakeEllipsoidTets(Vec3(s.radii[k], s.radii[k], s.radii[k]), 0, Xk, Tk);
        const int base = (int)X.size();
        for (const Vec3 &p : Xk) X.push_back(s.points[k] + p);
        for (const auto &t : Tk) T.push_back({base + t[0], base + t[1], base + t[2], base + t[3]});
      }
      return FromTets(X, T);
    case ShapeKind::Pebble:
      {
      kernels::PebbleRandom random((unsigned long)s.seed);
      kernels::MakeConvexPolyhedronTets(kernels::RandomPebble(s.radius, random).points, X, T);
    }
      return FromTets(X, T);
    case ShapeKind::Mesh: {
      kernels::TetMesh m = kernels::ReadGmsh(s.file);
      if (s.group.empty()) return m;
      const auto it = std::find(m.body_names.begin(), m.body_names.end(), s.group);
      if (it == m.body_names.end()) {
        std::string known;
        for (const auto &n : m.body_names) known += (known.empty() ? "" : ", ") + n;
        throw SceneError(s.where + ": body '" + b.name + "': the mesh " + s.file + " has no physical volume '" + s.group + "' (it has: " + known + ")");
      }
      const int                       g = (int)(it - m.body_names.begin());
      std::vector<int>                map(m.nodes.size(), -1);
      kernels::TetMesh                out;
      for (size_t e = 0; e < m.tets.size(); ++e) {
        if (m.body[e] != g) continue;
        std::array<int, 4> t;
        for (int k = 0; k < 4; ++k) {
          int &id = map[m.tets[e][k]];
          if (id < 0) id = (int)out.nodes.size(), out.nodes.push_back(m.nodes[m.tets[e][k]]);
          t[k] = id;
        }
        out.tets.push_back(t);
      }
      out.body.assign(out.tets.size(), 0);
      out.body_names = {s.group};
      return out;
    }
    }
  } catch (const kernels::InputError &e) {
    throw SceneError(s.where + ": body '" + b.name + "': " + e.what());
  }
  return {};
}

double ShapeRadius(const Body &b) {
  if (b.model == "sphere") return b.shape.radius;
  if (b.shape.kind == ShapeKind::Spheres) {
    Vec3   p;
    double w = 0, r = 0;
    for (size_t k = 0; k < b.shape.points.size(); ++k) {
      const double v = b.shape.radii[k] * b.shape.radii[k] * b.shape.radii[k];
      p += v * b.shape.points[k];
      w += v;
    }
    p = (1 / w) * p;
    for (size_t k = 0; k < b.shape.points.size(); ++k) r = std::max(r, norm(b.shape.points[k] - p) + b.shape.radii[k]);
    return r;
  }
  return BoundingRadius(ShapeMesh(b));
}

double BoundingRadius(const kernels::TetMesh &m) {
  double r = 0;
  for (const auto &p : m.nodes) r = std::max(r, norm(p));
  return r;
}

void ExpandPacks(Scene &sc) {
  std::vector<std::pair<Vec3, double>> placed; // the bounding spheres of every pack's bodies so far
  for (const Pack &p : sc.packs) {
    const Body                             like = *sc.FindBody(p.like);
    std::mt19937_64                        rng((unsigned long)p.seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::normal_distribution<double>       N(0.0, 1.0);
    for (long i = 0; i < p.count; ++i) {
      Body b = like;
      b.name = like.name + "_" + std::to_string(i);
      if (sc.FindBody(b.name)) throw SceneError(p.where + ": pack of '" + like.name + "': the generated name '" + b.name + "' is already a body's name");
      if (b.shape.kind == ShapeKind::Pebble) b.shape.seed = (long)(rng() % 1000000007UL);
      const double s = p.scale[0] + (p.scale[1] - p.scale[0]) * U(rng);
      if (s != 1) {
        b.shape.radius *= s;
        b.shape.height *= s;
        b.shape.size = s * b.shape.size;
        for (auto &q : b.shape.points) q = s * q;
        for (double &q : b.shape.radii) q *= s;
        if (b.resolution > 0) b.resolution *= s;
        if (b.shape.kind == ShapeKind::Mesh) throw SceneError(p.where + ": pack: scale other than [1, 1] is not available for mesh shapes ('" + like.name + "')");
      }
      const double r = ShapeRadius(b);
      Vec3         axis(N(rng), N(rng), N(rng));
      b.rotation = kernels::RotationMatrix(axis * (M_PI * U(rng) / std::max(norm(axis), 1e-12)));
      bool ok    = false;
      for (int tries = 0; tries < 10000 && !ok; ++tries) {
        for (int k = 0; k < 3; ++k) {
          const double lo = p.lo[k] + std::min(r, 0.5 * (p.hi[k] - p.lo[k])), hi = p.hi[k] - std::min(r, 0.5 * (p.hi[k] - p.lo[k]));
          b.position[k]   = lo + (hi - lo) * U(rng);
        }
        ok = true;
        for (const auto &q : placed)
          if (norm(q.first - b.position) < q.second + r) {
            ok = false;
            break;
          }
      }
      if (!ok) throw SceneError(p.where + ": pack of '" + like.name + "': found room for only " + std::to_string(i) + " of " + std::to_string(p.count) + " bodies in the region (enlarge it or lower count or scale)");
      placed.push_back({b.position, r});
      b.where = p.where;
      sc.bodies.push_back(std::move(b));
    }
  }
}

} // namespace fdem::driver
