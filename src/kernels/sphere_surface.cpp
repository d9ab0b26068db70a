// A sphere against a triangulated surface; see fdem/kernels/sphere_surface.hpp and
// doc/spheres.md.
#include <fdem/kernels/sphere_surface.hpp>

#include <algorithm>
#include <cmath>

namespace fdem::kernels {

namespace {
// The closest point of segment (p, q) to x, and whether it is an end (0: p, 1: q) or inside (-1).
Vec3 OnSegment(const Vec3 &x, const Vec3 &p, const Vec3 &q, int *end) {
  const Vec3   d  = q - p;
  const double dd = dot(d, d);
  const double t  = dd > 0 ? dot(x - p, d) / dd : 0.0;
  if (t <= 0) {
    *end = 0;
    return p;
  }
  if (t >= 1) {
    *end = 1;
    return q;
  }
  *end = -1;
  return p + t * d;
}
} // namespace

TriangleClosest ClosestPointOnTriangle(const Vec3 &x, const Vec3 &a, const Vec3 &b, const Vec3 &c) {
  const Vec3 ab = b - a, ac = c - a, ax = x - a;
  const Vec3 nrm = cross(ab, ac);
  if (!(dot(nrm, nrm) > 1e-28 * std::pow(std::max({dot(ab, ab), dot(ac, ac), dot(c - b, c - b)}), 2))) {
    // degenerate: the closest point of the longest edge
    const double lab = dot(ab, ab), lbc = dot(c - b, c - b), lca = dot(ac, ac);
    int          end;
    if (lab >= lbc && lab >= lca) {
      const Vec3 p = OnSegment(x, a, b, &end);
      return {p, end < 0 ? TriFeature::EdgeAB : end == 0 ? TriFeature::VertexA : TriFeature::VertexB};
    }
    if (lbc >= lca) {
      const Vec3 p = OnSegment(x, b, c, &end);
      return {p, end < 0 ? TriFeature::EdgeBC : end == 0 ? TriFeature::VertexB : TriFeature::VertexC};
    }
    const Vec3 p = OnSegment(x, c, a, &end);
    return {p, end < 0 ? TriFeature::EdgeCA : end == 0 ? TriFeature::VertexC : TriFeature::VertexA};
  }
  // the Voronoi regions of the vertices, the edges and the face, from the dot products
  const double d1 = dot(ab, ax), d2 = dot(ac, ax);
  if (d1 <= 0 && d2 <= 0) return {a, TriFeature::VertexA};
  const Vec3   bx = x - b;
  const double d3 = dot(ab, bx), d4 = dot(ac, bx);
  if (d3 >= 0 && d4 <= d3) return {b, TriFeature::VertexB};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + (d1 / (d1 - d3)) * ab, TriFeature::EdgeAB};
  const Vec3   cx = x - c;
  const double d5 = dot(ab, cx), d6 = dot(ac, cx);
  if (d6 >= 0 && d5 <= d6) return {c, TriFeature::VertexC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + (d2 / (d2 - d6)) * ac, TriFeature::EdgeCA};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), TriFeature::EdgeBC};
  const double s = 1.0 / (va + vb + vc);
  return {a + (vb * s) * ab + (vc * s) * ac, TriFeature::Face};
}

std::vector<SurfaceContact> SphereSurfaceContacts(const Vec3 &x, double r, const std::vector<Vec3> &nodes, const std::vector<std::array<int, 3>> &tris, const std::vector<int> &candidates) {
  std::vector<SurfaceContact> out;
  SphereSurfaceContacts(x, r, nodes, tris, candidates, out);
  return out;
}

void SphereSurfaceContacts(const Vec3 &x, double r, const std::vector<Vec3> &nodes, const std::vector<std::array<int, 3>> &tris, const std::vector<int> &candidates, std::vector<SurfaceContact> &out, const std::vector<int> *group) {
  // Each touch with its feature: a face (its triangle), an edge (its two nodes, sorted) or a vertex (its node).
  struct Touch {
    SurfaceContact c;
    int            kind; // 0 face, 1 edge, 2 vertex
    int            na, nb; // the feature's nodes (nb = -1 for a vertex; both -1 for a face)
  };
  thread_local std::vector<Touch> touches, kept; // scratch kept from call to call (no allocation per sphere)
  touches.clear();
  kept.clear();
  out.clear();
  for (int t : candidates) {
    const auto           &T = tris[t];
    const TriangleClosest q = ClosestPointOnTriangle(x, nodes[T[0]], nodes[T[1]], nodes[T[2]]);
    const Vec3            d = x - q.p;
    const double          dist = norm(d);
    if (!(dist < r) || !(dist > 0)) continue; // apart, or the centre on the surface (no normal)
    Touch h;
    h.c = {t, q.p, (1.0 / dist) * d, r - dist, q.feature};
    switch (q.feature) {
    case TriFeature::Face: h.kind = 0, h.na = h.nb = -1; break;
    case TriFeature::EdgeAB: h.kind = 1, h.na = T[0], h.nb = T[1]; break;
    case TriFeature::EdgeBC: h.kind = 1, h.na = T[1], h.nb = T[2]; break;
    case TriFeature::EdgeCA: h.kind = 1, h.na = T[2], h.nb = T[0]; break;
    case TriFeature::VertexA: h.kind = 2, h.na = T[0], h.nb = -1; break;
    case TriFeature::VertexB: h.kind = 2, h.na = T[1], h.nb = -1; break;
    case TriFeature::VertexC: h.kind = 2, h.na = T[2], h.nb = -1; break;
    }
    if (h.kind == 1 && h.na > h.nb) std::swap(h.na, h.nb);
    touches.push_back(h);
  }
  // the point a node stands for: its group (copies of one vertex), else the node
  auto g     = [&](int node) { return group ? (*group)[node] : node; };
  auto holds = [&](int t, int node) { return g(tris[t][0]) == g(node) || g(tris[t][1]) == g(node) || g(tris[t][2]) == g(node); };
  // two touches of one feature in copies (the same group's vertex, or edge)
  auto copies = [&](const Touch &a, const Touch &b) {
    if (a.kind == 0 || a.kind != b.kind || g(a.na) != g(b.na)) return false;
    return a.kind == 2 || g(a.nb) == g(b.nb) || (g(a.nb) == g(b.na) && g(a.na) == g(b.nb));
  };
  auto nodes_of = [&](const Touch &h, int out[3]) {
    if (h.kind == 0) {
      for (int k = 0; k < 3; ++k) out[k] = tris[h.c.tri][k];
      return 3;
    }
    out[0] = h.na, out[1] = h.nb;
    return h.kind == 1 ? 2 : 1;
  };
  auto SharesNode = [&](const Touch &a, const Touch &b) {
    int na[3], nb[3];
    const int ka = nodes_of(a, na), kb = nodes_of(b, nb);
    for (int x = 0; x < ka; ++x)
      for (int y = 0; y < kb; ++y)
        if (g(na[x]) == g(nb[y])) return true;
    return false;
  };
  for (std::size_t i = 0; i < touches.size(); ++i) {
    const Touch &h    = touches[i];
    bool         keep = true;
    for (std::size_t j = 0; j < touches.size() && keep; ++j) {
      if (j == i) continue;
      const Touch &o = touches[j];
      const bool same = o.kind == h.kind && o.na == h.na && o.nb == h.nb;
      if (h.kind > 0 && same && j < i) keep = false; // the same edge or vertex, counted by an earlier triangle
      // an edge or vertex is a closest point of the surface only if it is the closest point of
      // every triangle that holds it: another triangle holding it with a nearer point of its own
      // (its face, another edge or vertex) means the sphere is over that part, not this one
      else if (h.kind > 0 && !same && !copies(h, o) && holds(o.c.tri, h.na) && (h.kind == 2 || holds(o.c.tri, h.nb))) keep = false;
    }
    if (keep) kept.push_back(h);
  }
  // two neighbouring features of a nearly flat fold touched at nearly one point: their contact
  // patches overlap, one contact (the deeper; of equal ones the first). With copies (group),
  // only two faces: a copy of an edge or a vertex carries a weight of its own (the caller's),
  // and keeping the deeper of two features of different weights would switch the weight
  // where their depths cross
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const Touch &h    = kept[i];
    bool         keep = true;
    for (std::size_t j = 0; j < kept.size() && keep; ++j) {
      const Touch &o = kept[j];
      if (j != i && (!group || (h.kind == 0 && o.kind == 0)) && SharesNode(h, o) && norm(h.c.point - o.c.point) < std::sqrt(r * std::max(h.c.overlap, o.c.overlap)) && (o.c.overlap > h.c.overlap || (o.c.overlap == h.c.overlap && j < i))) keep = false;
    }
    if (keep) out.push_back(h.c);
  }
}

} // namespace fdem::kernels
