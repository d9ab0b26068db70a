// Geometry of a scene: the tetrahedral mesh of every body's shape (generated
// at the body's resolution, or read from Gmsh) and the bodies of
// `generate: pack`. Pure C++ on the library's kernels; every rank computes the
// same result.
#pragma once
#include "scene.hpp"

#include <fdem/kernels/tetmesh.hpp>

namespace fdem::driver {

// The mesh of a body's shape in the shape's own frame: generated shapes are
// centred on the origin, a Gmsh mesh keeps its file's coordinates (only the
// tetrahedra of shape.group when given). Throws SceneError naming the body.
kernels::TetMesh ShapeMesh(const Body &b);

// Appends the bodies of every pack: `count` copies of the body `like`, scaled
// by a factor uniform in [scale], turned by a random rotation, their centres
// drawn in the region so that no two bounding spheres of packed bodies meet (of one
// pack or of two).
// A pebble shape gets a new seed per copy. Copies are named LIKE_<i>.
void ExpandPacks(Scene &sc);

// The radius of a body's bounding sphere about its centre: a sphere's radius; a clump's
// largest |c - p| + r over its spheres, p their centres weighted by r^3 (its centre of mass
// when they do not overlap); otherwise BoundingRadius of its mesh.
double ShapeRadius(const Body &b);

// Bounding radius of the mesh about the origin.
double BoundingRadius(const kernels::TetMesh &m);

} // namespace fdem::driver
