// The scene as data: what a scene file (YAML, doc/scenes.md) describes, read
// and checked by ReadScene. Pure C++ (yaml-cpp, no PETSc): every rank reads
// the same file and reaches the same result, so an error is collective.
#pragma once
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <fdem/kernels/vec3.hpp>

namespace fdem::driver {

using kernels::Mat3;
using kernels::Vec3;

// A user error in the scene: the message starts with "file:line:col: ".
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Where a value was written: "file:line:col" (1-based), for messages.
using Where = std::string;

// A fracturable material's joints (materials.NAME.fracture; doc/fracture.md).
struct Fracture {
  bool   present = false;
  double tensile_strength = 0, cohesion = 0, friction_angle = 0, GI = 0, GII = 0, joint_penalty = 0;
  double insert_at = 0; // > 0: joints inserted during the run where the stress reaches this fraction of the strength
  Where  where;
};

struct Material {
  std::string name, model = "munjiza_cst";
  double      density = 0, young = 0, poisson = 0, damping = 0;
  Fracture    fracture;
  // granular contact of spheres (doc/spheres.md); < 0: not given
  std::string contact_law; // "hertz" | "hooke" | "" (not given)
  double      restitution = -1, friction = -1, rolling_friction = -1, kn = -1, kt = -1, gamma_n = -1, gamma_t = -1;
  Where       where;
};

enum class ShapeKind { Box, Sphere, Ellipsoid, Cylinder, ConvexHull, Pebble, Mesh, Spheres };

struct Shape {
  ShapeKind         kind = ShapeKind::Box;
  Vec3              size;             // box: full lengths; ellipsoid: semi-axes
  double            radius = 0, height = 0; // sphere, cylinder; pebble: radius = mean long semi-axis
  long              seed = 1;         // pebble
  std::vector<Vec3> points;           // convex_hull; spheres: the centres
  std::vector<double> radii;         // spheres (a clump)
  std::string       file, group;      // mesh (file resolved against the scene's folder)
  Where             where;
};

// A node set of a deformable body, by region of the reference positions or by Gmsh physical group.
struct NodeSet {
  enum Kind { None, Below, Above, Group } kind = None;
  int         axis  = 2;
  double      value = 0;
  std::string group;
  Where       where;
};

// An initial velocity field of a deformable body (velocity_field:): amplitude * f(xi) along
// `direction` (a unit vector), xi = (X[axis] - from) / (to - from) over the placed reference
// positions; f: cantilever (first bending mode of a beam clamped at xi = 0, 1 at xi = 1),
// sine (sin(pi xi)), gaussian (exp(-((xi - centre) / width)^2)).
struct VelocityField {
  enum Kind { None, Cantilever, Sine, Gaussian } kind = None;
  int    axis = 0;
  double from = 0, to = 1, amplitude = 0, centre = 0.5, width = 0.1;
  Vec3   direction;
  Where  where;
  double Profile(double xi) const; // f(xi)
};

// A fracture zone of a deformable body (fracture_zone:): the box [lo, hi] in world coordinates
// (the placed body). A body with zones is split for fracture only at the tetrahedra whose
// centroids lie in one of them (FDEMDeformableAddFractureZone).
struct FractureZone {
  Vec3  lo, hi;
  Where where;
};

struct Body {
  std::string name, model, material; // model: rigid | deformable | sphere
  Shape       shape;
  double      resolution = -1;      // element size (< 0: default, see shapes.cpp)
  Vec3        position, velocity, angular_velocity;
  Mat3        rotation = Mat3::identity();
  bool        fixed    = false;     // rigid
  NodeSet     fix;                  // deformable
  bool        moved    = false;     // move: a rigid body (platen) or a node set moved at move_velocity
  NodeSet     move;                 // deformable: the moved nodes
  Vec3        move_velocity;
  Where       move_where;
  VelocityField velocity_field;      // deformable: added to velocity + angular_velocity x (X - centroid)
  std::vector<FractureZone> fracture_zones; // deformable, fracturable material: the split limited to these boxes (none: everywhere)
  Where       where;
  // a sphere or a clump: its contacts take the granular laws (and keep tangential springs)
  bool Granular() const { return model == "sphere" || shape.kind == ShapeKind::Spheres; }
};

struct Pack {
  long        count = 0, seed = 1;
  std::string like;
  Vec3        lo, hi;
  double      scale[2] = {1, 1};
  Where       where;
};

struct Contact {
  bool   present = false;
  double penalty = 0, friction = 0, normal_damping = 0, tangential_viscosity = 0, buffer = -1; // buffer < 0: auto
  Where  where;
};

// Periodic boundaries (rigid bodies and spheres): the cell [lo, hi) along the axes listed.
struct Periodic {
  bool  axis[3] = {false, false, false};
  Vec3  lo, hi;
  Where where;
  bool  Any() const { return axis[0] || axis[1] || axis[2]; }
};

struct Scene {
  std::string           file, dir; // the scene file and its folder
  std::string           title;
  Vec3                  gravity;
  double                end = 0, dt = -1, safety = 0.5; // dt < 0: auto
  std::string           scheme = "cd";
  Where                 time_where, scheme_where;
  Where                 dt_where; // time.dt's place (time:'s when the step is auto)
  std::vector<Material> materials;
  Contact               contact;
  Periodic              periodic;
  std::vector<Body>     bodies; // after ReadScene: the listed bodies, then the generated ones
  std::vector<Pack>     packs;
  std::string           output_dir = "out";
  double                output_every = -1; // HDF5 frames; < 0: 50 frames over the run
  double                output_balance = -1; // balance.csv rows; < 0: 10 per frame
  double                checkpoint_every = -1; // < 0: no checkpoints
  long                  checkpoint_keep  = 2;
  std::string           petsc;
  Where                 petsc_where; // of the petsc: key (an option of it may be what fails)

  const Material *FindMaterial(const std::string &name) const;
  const Body     *FindBody(const std::string &name) const;
  bool            Has(const char *model) const;
};

// Reads and checks a scene. `text` (if not null) is the file's content and
// `file` only names it (the embedded default scene). Throws SceneError.
Scene ReadScene(const std::string &file, const char *text = nullptr);

// The scene keys with a one-line description each, for --help.
const char *SceneKeysHelp();

// The embedded default scene (default_scene.yaml).
const char *DefaultSceneText();

} // namespace fdem::driver
