// Tetrahedral mesh utilities: generators (box, beam, cylinder), a Gmsh .msh
// reader (ASCII 2.2 and 4.1), orientation fixing, lumped masses, surface
// extraction and connected components. Pure C++; no PETSc.
//
// Orientation convention (used by every fdem kernel): a tetrahedron
// (n0, n1, n2, n3) is valid when det[x1-x0, x2-x0, x3-x0] > 0, i.e. its signed
// volume V = det/6 is positive. (PETSc's DMPlexCreateFromCellListPetsc wants
// the opposite sign: swap n1 and n2 when handing cells to DMPlex.)
#pragma once
#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <fdem/kernels/vec3.hpp>

namespace fdem::kernels {

// The six edges of a tetrahedron (n0, n1, n2, n3) as vertex pairs, in the order every fdem
// table of edges uses, and the slot of the edge (a, b) in it.
constexpr int kTetEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
constexpr int TetEdgeSlot(int a, int b) { return a > b ? TetEdgeSlot(b, a) : a == 0 ? b - 1 : a + b; }

struct TetMesh {
  std::vector<Vec3> nodes;
  std::vector<std::array<int, 4>> tets;
  std::vector<int> body;                // body id per tetrahedron, 0..n_bodies-1
  std::vector<std::string> body_names;  // per body id (physical name, or "component_<i>")
  std::vector<long> tet_line;           // reader: the file line of each tetrahedron (else empty)
  std::vector<std::string> warnings;    // reader: legitimate but unusual input, "file:line: what"
  int NumBodies() const { return static_cast<int>(body_names.size()); }
};

// The earliest repeated tetrahedron (the same four nodes in any order), in the
// order given: {first, second} with first < second the positions of the two
// copies, or {n, n} (n = tets.size()) when no tetrahedron repeats. O(n log n).
template <class Index>
std::array<std::size_t, 2> FirstRepeatedTet(const std::vector<std::array<Index, 4>> &tets);

// Signed volume det[b-a, c-a, d-a] / 6.
double TetSignedVolume(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &d);
double TetSignedVolume(const TetMesh &mesh, int tet);
double TotalVolume(const TetMesh &mesh);

// Swap nodes 1 and 2 of every tetrahedron with negative signed volume so that
// all volumes become positive. Throws InputError naming the body and element
// for a degenerate tetrahedron (|6V| <= 1e-12 * (longest edge)^3). Returns the
// number of tetrahedra flipped.
int OrientTets(TetMesh &mesh);
int OrientTets(const std::vector<Vec3> &nodes, std::vector<std::array<int, 4>> &tets,
               const std::vector<int> &body = {});

// Index along a Hilbert curve through a cube of 2^bits cells per side (bits
// 1..21) of the cell (X[0], X[1], X[2]), each < 2^bits: a bijection onto
// 0 .. 2^(3 bits) - 1 in which cells of consecutive indices share a face.
std::uint64_t HilbertIndex(const std::uint32_t X[3], int bits);
// HilbertIndex of point x in the box [lo, hi] cut into 2^21 cells per side
// (points outside are clamped to it; a flat side counts as one cell). Sorting
// elements by the key of their centroids puts neighbours in space next to
// each other in memory.
std::uint64_t HilbertKey(const Vec3 &x, const Vec3 &lo, const Vec3 &hi);

// Structured box [lo, hi] with nx*ny*nz cells, each cut into 6 tetrahedra
// around its main diagonal (Kuhn subdivision, conforming across cells).
// Nodes are numbered i + (nx+1)*(j + (ny+1)*k). One body ("box").
TetMesh MakeBoxMesh(const Vec3 &lo, const Vec3 &hi, int nx, int ny, int nz);
// Box [0,L]x[0,W]x[0,H] with n cells across the smallest side and the other
// counts proportional (rounded, at least 1). One body ("beam").
TetMesh MakeBeamMesh(double L, double W, double H, int n);
// Cylinder of axis z, base centred at the origin, 0 <= z <= height. The
// cross-section is the polygon of 6*n_radial vertices at the given radius,
// triangulated in n_radial rings (ring k has 6k nodes), extruded in n_axial
// layers, each prism cut into 3 tetrahedra conformingly (diagonals from the
// lower-numbered node). Volume = height * 3 n_radial radius^2 sin(pi/(3 n_radial)).
TetMesh MakeCylinderMesh(double radius, double height, int n_radial, int n_axial);

// Gmsh .msh reader, ASCII formats 2.2 and 4.1. Keeps 4-node tetrahedra (type
// 4); ignores points, lines and surface elements; rejects any other volume
// element type. Physical volume groups become bodies (sorted by tag, named via
// $PhysicalNames, else "physical_<tag>"); without physical groups each
// node-connected component is a body. Only nodes used by tetrahedra are kept
// (in the order of their tags). Tetrahedra are re-oriented to positive volume.
// Hostile input is rejected, never trusted: every count is checked against
// the bytes left in the input before anything is sized by it; coordinates
// must be finite; a tetrahedron given twice is an error naming both elements;
// so is a face in three tetrahedra or in two on the same side of it (overlap);
// two nodes at exactly the same coordinates in one body are an error (an
// unjoined seam), in two different bodies a warning in mesh.warnings (bodies
// meshed separately that touch). Errors: InputError "file:line: what".
TetMesh ReadGmsh(const std::string &path);
TetMesh ParseGmsh(std::istream &in, const std::string &filename);

// Lumped nodal masses: each tetrahedron gives rho_body * V / 4 to each node.
std::vector<double> LumpedMasses(const TetMesh &mesh, const std::vector<double> &density_per_body);

struct SurfaceInfo {
  std::vector<int> tets;                    // tetrahedra with >= 1 boundary face (ascending)
  std::vector<std::array<int, 3>> faces;    // boundary faces, normal (b-a)x(c-a) outward
  std::vector<int> face_tet;                // owning tetrahedron of each face
};
// Boundary faces are faces that belong to exactly one tetrahedron.
SurfaceInfo SurfaceTets(const TetMesh &mesh);

// Connected components of tetrahedra sharing at least one node. Returns the
// component of each tetrahedron, numbered in order of first appearance;
// *n_components receives the count.
std::vector<int> ConnectedComponents(const TetMesh &mesh, int *n_components = nullptr);

} // namespace fdem::kernels
