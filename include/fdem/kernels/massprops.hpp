// Mass properties of a closed rigid body given as a tetrahedral mesh, a
// symmetric 3x3 eigen-solver, and small tetrahedral mesh generators (box,
// ellipsoid, convex polyhedron). Pure numerics, C++ standard library only.
//
// Orientation convention: a tetrahedron (v0, v1, v2, v3) is accepted when its
// signed volume (v1 - v0) . ((v2 - v0) x (v3 - v0)) / 6 is positive.
// (PETSc's DMPlex wants the opposite sign; the model layer converts.)
// OrientTetsPositive() fixes a mesh given with mixed or negative orientation.
// (Same convention as tetmesh.hpp, whose TetSignedVolume gives the volume.)
#pragma once
#include <fdem/kernels/vec3.hpp>

#include <array>
#include <string>
#include <vector>

namespace fdem::kernels {

struct MassProperties {
  double volume = 0, mass = 0;
  Vec3 com;
  Mat3 inertia_com;        // inertia tensor about the COM, space frame
  Vec3 principal_moments;  // ascending
  Mat3 principal_axes;     // columns = unit principal axes (same order), right-handed (det +1)
};

// Exact mass, centre of mass and inertia of a homogeneous body (canonical
// tetrahedron second moments, int x_i x_j dV = V/20 (sum_a p_ai p_aj + S_i S_j)
// with S = sum of the four vertices). Throws InputError naming body_name and,
// where relevant, the element (tetrahedron index) for: non-positive or
// non-finite density; no tetrahedra; a node index out of range or repeated
// within a tetrahedron; a degenerate tetrahedron (|6V| <= 1e-14 * longest
// edge^3); a tetrahedron with negative signed volume; a boundary that is not a
// closed 2-manifold (a face shared by more than two tetrahedra, or a boundary
// edge not shared by exactly two boundary faces); zero total volume;
// degenerate inertia (smallest principal moment <= 1e-12 x largest).
MassProperties ComputeMassProperties(const std::vector<Vec3> &nodes, const std::vector<std::array<int, 4>> &tets,
                                     double density, const std::string &body_name);

// A ball: centre and radius.
struct Ball {
  Vec3   c;
  double r = 0;
};

// Mass properties of a homogeneous body that is the union of balls (a clump of spheres,
// overlapping or not). Moments of each line parallel to z through a grid of cells over the
// union's shadow (cell size about the smallest radius / 64, at most 1024 x 1024 cells and
// about 1e8 sphere tests: a clump of many spheres gets a coarser grid) are
// exact in z; across the lines a midpoint rule, corrected by each ball's exact moments minus
// its own grid estimate, so that one ball or balls that do not overlap are exact to
// round-off. Throws InputError naming body_name (and the sphere) for no balls, a radius not
// positive, a centre not finite, or a density not positive. Principal moments within 1e-4 of
// the largest of each other (below the integration's resolution) are made equal (their mean),
// so that a clump with an axis of symmetry, or with cubic or tetrahedral symmetry, is a
// symmetric or spherical top.
MassProperties BallUnionMassProperties(const std::vector<Ball> &balls, double density, const std::string &body_name);

// Swap the last two nodes of every tetrahedron with negative signed volume.
// Returns the number of tetrahedra flipped. Degenerate ones are left alone.
int OrientTetsPositive(const std::vector<Vec3> &nodes, std::vector<std::array<int, 4>> &tets);

// Boundary triangles (faces used by exactly one tetrahedron), oriented so that
// their normal (b - a) x (c - a) points out of a positively oriented mesh.
std::vector<std::array<int, 3>> BoundaryFaces(const std::vector<std::array<int, 4>> &tets);

// Symmetric 3x3 eigen-decomposition by cyclic Jacobi rotations: A = V diag(values) V^T,
// values ascending, columns of V unit, right-handed (det V = +1); each of the
// first two columns has its largest-magnitude component positive.
void SymmetricEigen(const Mat3 &A, Vec3 &values, Mat3 &vectors);

// Box [lo, hi] split into nx x ny x nz hexahedra, each into 6 tetrahedra along
// its lo-hi diagonal (Kuhn subdivision, conforming). Positive orientation.
void MakeBoxTets(const Vec3 &lo, const Vec3 &hi, int nx, int ny, int nz, std::vector<Vec3> &nodes,
                 std::vector<std::array<int, 4>> &tets);

// Ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 <= 1 centred at the origin: an
// octahedron whose faces are split into 4^refinement triangles projected onto
// the unit sphere and scaled by the semi-axes; tetrahedra join each surface
// triangle to the centre. Inscribed, so volume and inertia converge from below
// at second order in the edge length (~2^-refinement). refinement in [0, 9].
void MakeEllipsoidTets(const Vec3 &semi_axes, int refinement, std::vector<Vec3> &nodes,
                       std::vector<std::array<int, 4>> &tets);

// Convex hull of the points (incremental hull, O(n^2)), then one tetrahedron
// from the centroid of the hull vertices to each hull triangle. Nodes are the
// hull vertices followed by the centroid. Throws InputError if fewer than 4
// points or all points (nearly) coplanar.
void MakeConvexPolyhedronTets(const std::vector<Vec3> &points, std::vector<Vec3> &nodes,
                              std::vector<std::array<int, 4>> &tets);

} // namespace fdem::kernels
