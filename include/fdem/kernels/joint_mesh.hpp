// Fracturable meshes (doc/fracture.md): every tetrahedron of a fracturable
// body gets its own four nodes, and every face that two of its tetrahedra
// shared becomes a joint, the pair of coincident triangles that the cohesive
// law (joint.hpp) holds together. Pure C++; no PETSc.
#pragma once
#include <array>
#include <vector>

#include <fdem/kernels/tetmesh.hpp>

namespace fdem::kernels {

// One joint: triangle a of tetrahedron tet_a, ordered so that its right-hand
// normal (a1-a0)x(a2-a0) points out of tet_a (towards tet_b), and triangle b
// of tet_b with node b[i] at the position of a[i] (the argument order of
// JointElementForces). Node ids are those of the split mesh.
struct JointFace {
  int tet_a = -1, tet_b = -1;
  std::array<int, 3> a{}, b{};
};

struct SplitMesh {
  TetMesh mesh;                 // the split mesh: same tetrahedra in the same order, bodies and names
  std::vector<int> parent;      // per split node: the node of the input mesh it was copied from
  std::vector<JointFace> joints; // in the order of the sorted face keys (deterministic)
  std::vector<char> split;      // per tetrahedron: 1 when it got nodes of its own
  std::vector<char> boundary;   // per tetrahedron, bit k: its face k (opposite node k) belongs to no
                                // other tetrahedron of the split mesh (the input's boundary faces,
                                // and both sides of every face where a tetrahedron was split)
};

// Splits the tetrahedra of the bodies with split_body[b] != 0 (one entry per
// body of the mesh): each gets four new nodes, copies of its own; every face
// shared by two of them (same body) becomes a joint. Nodes of other bodies
// are kept, renumbered in order of first use, and their tetrahedra are
// unchanged. The input must be a valid oriented mesh (ParseGmsh or
// OrientTets); throws InputError when split_body has the wrong size, and, naming
// the body and the elements (with their file lines when the mesh has them), when a
// split body's mesh is not conforming: a face held by more than two tetrahedra, or
// two tetrahedra that touch across a face without sharing its nodes (hanging or
// duplicated nodes: found from the boundary faces, one lying on another with the
// opposite normal; a grid keeps it linear).
//
// split_tet (one entry per tetrahedron; empty: all) limits the split to the
// tetrahedra of those bodies with split_tet[t] != 0 (a fracture zone): the
// others keep shared nodes, and a face between a split and an unsplit
// tetrahedron of the body is a joint too, triangle a on the split side and
// triangle b made of the unsplit tetrahedron's (shared) nodes.
SplitMesh SplitForJoints(const TetMesh &mesh, const std::vector<char> &split_body, const std::vector<char> &split_tet = {});

// The faces of a mesh, each once with the tetrahedra that hold it: for the
// face k of tetrahedron t (the face opposite node k, ordered so that its
// right-hand normal points out of t), FaceTets lists (t, k) pairs grouped by
// face. Used by SurfaceTets (faces with one tetrahedron) and SplitForJoints
// (faces with two).
struct TetFace {
  std::array<int, 3> key; // the sorted node ids
  int tet, local;         // the tetrahedron and the node opposite the face
};
// All 4 n faces sorted by key, so that the copies of a face are adjacent.
std::vector<TetFace> SortedFaces(const std::vector<std::array<int, 4>> &tets);

// SplitForJoints for many splits of one mesh (fracture zones, joints inserted during a run):
// the faces are sorted and the split bodies checked conforming once, at construction
// (the same errors); Split(split_tet) is then SplitForJoints(mesh, split_body, split_tet).
// The mesh must outlive the splitter.
class JointSplitter {
public:
  JointSplitter(const TetMesh &mesh, std::vector<char> split_body);
  SplitMesh Split(const std::vector<char> &split_tet = {}) const;

private:
  const TetMesh *mesh_;
  std::vector<char> split_body_;
  std::vector<TetFace> faces_;
};
// The face opposite node k of a tetrahedron, outward for a positively oriented one.
inline constexpr int kTetFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

} // namespace fdem::kernels
