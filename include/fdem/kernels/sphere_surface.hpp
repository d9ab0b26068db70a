// A sphere against a triangulated surface (doc/spheres.md, "A sphere against a
// surface"): the closest point of a triangle, and the contacts of one sphere with
// the triangles of one body, one per touched feature (face, edge or vertex), so that
// a sphere rolling over an edge or a vertex feels one force that turns continuously,
// and a sphere in a concave corner feels each face. The surface of a rigid body's
// skin or of a deformable body's boundary; the force law is GranularForce
// (granular.hpp). Pure functions on doubles; no PETSc, no MPI.
#pragma once
#include <array>
#include <vector>

#include "fdem/kernels/vec3.hpp"

namespace fdem::kernels {

// The feature of a triangle (a, b, c) that holds a closest point.
enum class TriFeature { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

struct TriangleClosest {
  Vec3       p;       // the closest point of the triangle to x
  TriFeature feature; // where it lies: the open face, an open edge, or a vertex
};

// The point of the triangle (a, b, c) closest to x (barycentric regions; a degenerate
// triangle gives the closest point of its longest edge).
TriangleClosest ClosestPointOnTriangle(const Vec3 &x, const Vec3 &a, const Vec3 &b, const Vec3 &c);

struct SurfaceContact {
  int    tri;     // the triangle that holds the contact point (the first, for a shared edge or vertex)
  Vec3   point;   // the contact point on the surface
  Vec3   n;       // unit normal, from the surface towards the sphere's centre
  double overlap; // r - |x - point| > 0
  TriFeature feature;
};

// The contacts of the sphere (centre x, radius r > 0) with the triangles `candidates`
// (indices into tris, e.g. from a search) of one surface: triangles of node indices
// into nodes. One contact per touched feature: a point on an edge or a vertex shared by
// several triangles counts once, and it counts only if it is the closest point of every
// touched triangle that holds that edge or vertex (when one of them touches the sphere at
// a point of its own, inside its face or on another edge or vertex, the sphere is over
// that part: a face the sphere is over, or a neighbouring triangle of a flat face cut
// finer, hides the edge). Where the surface is concave each face touched counts, unless two
// neighbouring features (sharing a node) are touched at points closer than the contact
// radius sqrt(r overlap) (a nearly flat fold, e.g. of a deformed mesh): their patches
// overlap, and the deeper one alone counts.
// Deterministic: contacts in the order of the candidates.
std::vector<SurfaceContact> SphereSurfaceContacts(const Vec3 &x, double r, const std::vector<Vec3> &nodes, const std::vector<std::array<int, 3>> &tris, const std::vector<int> &candidates);
// The same into out (cleared first), for a caller that keeps the vector from call to call.
// group (may be null: every node its own): per node, the point it is a copy of, for a surface
// whose cells have nodes of their own (a fracturable body's split cells). Each copy of a
// vertex or an edge is then a feature of its own, counted once, and the rules above that
// compare features by their nodes compare them by their groups: a touch of one copy neither
// hides nor is merged with a touch of another copy of the same vertex (edge), a touch
// elsewhere that holds the group hides it as it would hide a shared node, and of the nearly
// flat fold's neighbouring features only two faces are merged (a copy's contact has a weight
// of its own: merging it with a feature of another weight would make the force jump where
// their depths cross).
void SphereSurfaceContacts(const Vec3 &x, double r, const std::vector<Vec3> &nodes, const std::vector<std::array<int, 3>> &tris, const std::vector<int> &candidates, std::vector<SurfaceContact> &out, const std::vector<int> *group = nullptr);

} // namespace fdem::kernels
