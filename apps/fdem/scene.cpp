// Reading and checking a scene file with yaml-cpp. Every error names
// file:line:col (yaml-cpp's Mark, made 1-based) and what is wrong.
#include "scene.hpp"

#include <fdem/kernels/rotation.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

namespace fdem::driver {
namespace {

// Edit distance, for "did you mean".
size_t Distance(const std::string &a, const std::string &b) {
  std::vector<size_t> d(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t prev = d[0];
    d[0]        = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cur = d[j];
      d[j]             = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
      prev             = cur;
    }
  }
  return d[b.size()];
}

std::string Nearest(const std::string &word, const std::vector<std::string> &choices) {
  std::string best;
  size_t      bd = 1000;
  for (const auto &c : choices) {
    const size_t d = Distance(word, c);
    if (d < bd) bd = d, best = c;
  }
  return best;
}

std::string Join(const std::vector<std::string> &v) {
  std::string s;
  for (const auto &x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

class Reader {
public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  Where At(const YAML::Node &n) const { return At(n.Mark()); }
  Where At(const YAML::Mark &m) const {
    if (m.is_null()) return file_;
    return file_ + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
  }
  [[noreturn]] void Fail(const YAML::Node &n, const std::string &what) const { throw SceneError(At(n) + ": " + what); }
  [[noreturn]] void Fail(const Where &w, const std::string &what) const { throw SceneError(w + ": " + what); }

  // A map whose keys must be among `allowed`.
  void Keys(const YAML::Node &n, const std::string &where, const std::vector<std::string> &allowed) const {
    if (!n.IsMap()) Fail(n, where + ": expected a map of keys (" + Join(allowed) + ")" + Got(n));
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = it->first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
        Fail(it->first, where + ": unknown key '" + k + "' (did you mean '" + Nearest(k, allowed) + "'? valid keys: " + Join(allowed) + ")");
      Unique(n, it, where);
    }
  }
  // A map's key given twice (YAML forbids it; the parser keeps the first silently): an error at
  // the second, naming the first.
  template <class Map, class It> void Unique(Map &n, It at, const std::string &where) const {
    const std::string k = at->first.Scalar();
    for (auto it = n.begin(); it != at; ++it)
      if (it->first.Scalar() == k) Fail(at->first, where + ": key '" + k + "' given twice (first at " + At(it->first) + ")");
  }
  const YAML::Node Required(const YAML::Node &map, const std::string &key, const std::string &where) const {
    const YAML::Node v = map[key];
    if (!v) Fail(map, where + ": missing required key '" + key + "'");
    return v;
  }
  static std::string Got(const YAML::Node &n) {
    if (n.IsScalar()) return ", got '" + n.Scalar() + "'";
    if (n.IsSequence()) return ", got a list";
    if (n.IsMap()) return ", got a map";
    return ", got nothing";
  }
  double Real(const YAML::Node &n, const std::string &what) const {
    if (!n.IsScalar()) Fail(n, what + ": expected a number" + Got(n));
    double v;
    if (!YAML::convert<double>::decode(n, v) || !std::isfinite(v)) Fail(n, what + ": expected a number" + Got(n));
    return v;
  }
  long Int(const YAML::Node &n, const std::string &what) const {
    const double v = Real(n, what);
    if (v != std::floor(v) || std::fabs(v) > 1e15) Fail(n, what + ": expected an integer" + Got(n));
    return (long)v;
  }
  bool Bool(const YAML::Node &n, const std::string &what) const {
    bool b;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, b)) Fail(n, what + ": expected true or false" + Got(n));
    return b;
  }
  std::string String(const YAML::Node &n, const std::string &what) const {
    if (!n.IsScalar()) Fail(n, what + ": expected a string" + Got(n));
    return n.Scalar();
  }
  Vec3 Vector(const YAML::Node &n, const std::string &what) const {
    if (!n.IsSequence() || n.size() != 3) Fail(n, what + ": expected a list of 3 numbers [x, y, z]" + Got(n));
    return Vec3(Real(n[0], what + "[0]"), Real(n[1], what + "[1]"), Real(n[2], what + "[2]"));
  }
  double Positive(const YAML::Node &n, const std::string &what) const {
    const double v = Real(n, what);
    if (!(v > 0)) Fail(n, what + ": must be positive, got " + n.Scalar());
    return v;
  }
  double NonNegative(const YAML::Node &n, const std::string &what) const {
    const double v = Real(n, what);
    if (v < 0) Fail(n, what + ": must not be negative, got " + n.Scalar());
    return v;
  }
  int Axis(const YAML::Node &n, const std::string &what) const {
    const std::string a = String(n, what);
    if (a == "x") return 0;
    if (a == "y") return 1;
    if (a == "z") return 2;
    Fail(n, what + ": expected an axis x, y or z, got '" + a + "'");
  }
  std::string Choice(const YAML::Node &n, const std::string &what, const std::vector<std::string> &choices) const {
    const std::string s = String(n, what);
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) Fail(n, what + ": unknown " + what.substr(what.rfind('.') + 1) + " '" + s + "' (did you mean '" + Nearest(s, choices) + "'? choose one of " + Join(choices) + ")");
    return s;
  }

  const std::string &file() const { return file_; }

private:
  std::string file_;
};

const std::vector<std::string> kTop       = {"title", "gravity", "time", "materials", "contact", "periodic", "bodies", "generate", "output", "checkpoint", "petsc"};
const std::vector<std::string> kTime      = {"end", "dt", "safety", "scheme"};
const std::vector<std::string> kMaterial  = {"density", "young", "poisson", "model", "damping", "fracture", "restitution", "friction", "rolling_friction", "contact_law", "kn", "kt", "gamma_n", "gamma_t"};
const std::vector<std::string> kFracture  = {"tensile_strength", "cohesion", "friction_angle", "G_I", "G_II", "joint_penalty", "insert_at"};
const std::vector<std::string> kModels    = {"finite_strain", "munjiza_cst", "neo_hookean", "small_strain", "small_strain_linear"};
const std::vector<std::string> kContact   = {"penalty", "friction", "normal_damping", "tangential_viscosity", "buffer"};
const std::vector<std::string> kBody      = {"name", "model", "material", "shape", "resolution", "position", "rotation", "velocity", "angular_velocity", "fixed", "fix", "move", "velocity_field", "fracture_zone"};
const std::vector<std::string> kShapes    = {"box", "sphere", "ellipsoid", "cylinder", "convex_hull", "pebble", "spheres", "mesh"};
const std::vector<std::string> kBodyModel = {"rigid", "deformable", "sphere", "auto"};
const std::vector<std::string> kSchemes   = {"cd", "pv", "chin", "omf30", "omf32", "fr", "pefrl", "t112", "t16", "d112", "pc3", "pc4", "pc5"};

Material ReadMaterial(const Reader &r, const std::string &name, const YAML::Node &n) {
  const std::string w = "materials." + name;
  Material          m;
  m.name  = name;
  m.where = r.At(n);
  r.Keys(n, w, kMaterial);
  m.density = r.Real(r.Required(n, "density", w), w + ".density");
  if (!(m.density > 0)) r.Fail(n["density"], w + ".density: must be positive, got " + n["density"].Scalar());
  if (n["young"]) m.young = r.Positive(n["young"], w + ".young");
  if (n["poisson"]) {
    m.poisson = r.Real(n["poisson"], w + ".poisson");
    if (!(m.poisson > -1 && m.poisson < 0.5)) r.Fail(n["poisson"], w + ".poisson: must lie in (-1, 0.5), got " + n["poisson"].Scalar());
  }
  if (n["damping"]) m.damping = r.NonNegative(n["damping"], w + ".damping");
  if (n["restitution"]) {
    m.restitution = r.Positive(n["restitution"], w + ".restitution");
    if (!(m.restitution <= 1)) r.Fail(n["restitution"], w + ".restitution: must lie in (0, 1], got " + n["restitution"].Scalar());
  }
  if (n["friction"]) m.friction = r.NonNegative(n["friction"], w + ".friction");
  if (n["rolling_friction"]) m.rolling_friction = r.NonNegative(n["rolling_friction"], w + ".rolling_friction");
  if (n["contact_law"]) m.contact_law = r.Choice(n["contact_law"], w + ".contact_law", {"hertz", "hooke"});
  if (n["kn"]) m.kn = r.Positive(n["kn"], w + ".kn");
  if (n["kt"]) m.kt = r.NonNegative(n["kt"], w + ".kt");
  if (n["gamma_n"]) m.gamma_n = r.NonNegative(n["gamma_n"], w + ".gamma_n");
  if (n["gamma_t"]) m.gamma_t = r.NonNegative(n["gamma_t"], w + ".gamma_t");
  if ((n["gamma_n"] || n["gamma_t"]) && m.contact_law != "hooke") r.Fail(n["gamma_n"] ? n["gamma_n"] : n["gamma_t"], w + ": gamma_n and gamma_t (damping rates, 1/s) belong to contact_law: hooke; the Hertz law takes restitution");
  if (m.contact_law == "hooke" && !n["kn"]) r.Fail(n["contact_law"], w + ".contact_law: hooke needs kn (N/m), the normal stiffness");
  if (m.contact_law == "hertz" && !(n["young"] && n["poisson"])) r.Fail(n["contact_law"], w + ".contact_law: hertz needs young and poisson");
  if (n["fracture"]) {
    const YAML::Node  f  = n["fracture"];
    const std::string wf = w + ".fracture";
    r.Keys(f, wf, kFracture);
    Fracture &F = m.fracture;
    F.present          = true;
    F.where            = r.At(f);
    F.tensile_strength = r.Positive(r.Required(f, "tensile_strength", wf), wf + ".tensile_strength");
    F.cohesion         = r.Positive(r.Required(f, "cohesion", wf), wf + ".cohesion");
    F.friction_angle   = r.NonNegative(r.Required(f, "friction_angle", wf), wf + ".friction_angle");
    if (!(F.friction_angle < 90)) r.Fail(f["friction_angle"], wf + ".friction_angle: must lie in [0, 90) degrees, got " + f["friction_angle"].Scalar());
    F.GI            = r.Positive(r.Required(f, "G_I", wf), wf + ".G_I");
    F.GII           = r.Positive(r.Required(f, "G_II", wf), wf + ".G_II");
    F.joint_penalty = r.Positive(r.Required(f, "joint_penalty", wf), wf + ".joint_penalty");
    if (f["insert_at"]) {
      F.insert_at = r.Positive(f["insert_at"], wf + ".insert_at");
      if (!(F.insert_at <= 1)) r.Fail(f["insert_at"], wf + ".insert_at: the fraction of the strength at which a tetrahedron gets joints must lie in (0, 1], got " + f["insert_at"].Scalar());
    }
  }
  if (n["model"]) {
    m.model = r.Choice(n["model"], w + ".model", kModels);
    if (m.model == "finite_strain") m.model = "munjiza_cst";
    if (m.model == "small_strain") m.model = "small_strain_linear";
  }
  return m;
}

Shape ReadShape(const Reader &r, const std::string &w, const YAML::Node &n, const std::string &dir) {
  Shape s;
  s.where = r.At(n);
  if (!n.IsMap() || n.size() != 1) r.Fail(n, w + ": expected one shape as {kind: parameters}, kind one of " + Join(kShapes) + Reader::Got(n));
  const YAML::Node  key  = n.begin()->first, v = n.begin()->second;
  const std::string kind = r.Choice(key, w, kShapes);
  const std::string wk   = w + "." + kind;
  if (kind == "box") {
    s.kind = ShapeKind::Box;
    s.size = r.Vector(v, wk);
    for (int k = 0; k < 3; ++k)
      if (!(s.size[k] > 0)) r.Fail(v[k], wk + ": the sides must be positive, got " + v[k].Scalar());
  } else if (kind == "sphere") {
    s.kind   = ShapeKind::Sphere;
    s.radius = r.Positive(v, wk + " (radius)");
  } else if (kind == "ellipsoid") {
    s.kind = ShapeKind::Ellipsoid;
    s.size = r.Vector(v, wk);
    for (int k = 0; k < 3; ++k)
      if (!(s.size[k] > 0)) r.Fail(v[k], wk + ": the semi-axes must be positive, got " + v[k].Scalar());
  } else if (kind == "cylinder") {
    s.kind = ShapeKind::Cylinder;
    r.Keys(v, wk, {"radius", "height"});
    s.radius = r.Positive(r.Required(v, "radius", wk), wk + ".radius");
    s.height = r.Positive(r.Required(v, "height", wk), wk + ".height");
  } else if (kind == "convex_hull") {
    s.kind = ShapeKind::ConvexHull;
    if (!v.IsSequence() || v.size() < 4) r.Fail(v, wk + ": expected a list of at least 4 points [x, y, z]" + Reader::Got(v));
    for (size_t i = 0; i < v.size(); ++i) s.points.push_back(r.Vector(v[i], wk + "[" + std::to_string(i) + "]"));
  } else if (kind == "spheres") {
    s.kind = ShapeKind::Spheres;
    if (!v.IsSequence() || v.size() < 1) r.Fail(v, wk + ": expected a list of spheres [x, y, z, radius] (a clump, in its own frame)" + Reader::Got(v));
    for (size_t i = 0; i < v.size(); ++i) {
      const std::string wi = wk + "[" + std::to_string(i) + "]";
      if (!v[i].IsSequence() || v[i].size() != 4) r.Fail(v[i], wi + ": expected [x, y, z, radius]" + Reader::Got(v[i]));
      s.points.push_back(Vec3(r.Real(v[i][0], wi + "[0]"), r.Real(v[i][1], wi + "[1]"), r.Real(v[i][2], wi + "[2]")));
      s.radii.push_back(r.Positive(v[i][3], wi + " (radius)"));
    }
  } else if (kind == "pebble") {
    s.kind = ShapeKind::Pebble;
    r.Keys(v, wk, {"size", "seed"});
    s.radius = r.Positive(r.Required(v, "size", wk), wk + ".size");
    if (v["seed"]) s.seed = r.Int(v["seed"], wk + ".seed");
  } else {
    s.kind = ShapeKind::Mesh;
    if (v.IsMap()) {
      r.Keys(v, wk, {"file", "group"});
      if (v["group"]) s.group = r.String(v["group"], wk + ".group");
    }
    const YAML::Node f = v.IsMap() ? r.Required(v, "file", wk) : v; // (a YAML::Node assignment would write into the tree)
    s.file = r.String(f, wk + (v.IsMap() ? ".file" : ""));
    if (!s.file.empty() && s.file[0] != '/') s.file = dir + s.file;
    std::ifstream in(s.file);
    if (!in) r.Fail(f, wk + ": cannot read the mesh file '" + s.file + "'");
  }
  return s;
}

// fix: {below|above|group}; move: the same and velocity (moving = true).
NodeSet ReadNodeSet(const Reader &r, const std::string &w, const YAML::Node &n, bool moving = false) {
  NodeSet s;
  s.where = r.At(n);
  if (moving) r.Keys(n, w, {"below", "above", "group", "velocity"});
  else r.Keys(n, w, {"below", "above", "group"});
  if (n.size() != 1u + (moving ? 1u : 0u) || (moving && !n["velocity"]))
    r.Fail(n, w + (moving ? ": give the velocity: [vx, vy, vz] and exactly one of below: [axis, value], above: [axis, value] or group: name" : ": give exactly one of below: [axis, value], above: [axis, value] or group: name"));
  if (n["group"]) {
    s.kind  = NodeSet::Group;
    s.group = r.String(n["group"], w + ".group");
    return s;
  }
  const bool       below = (bool)n["below"];
  const YAML::Node v     = below ? n["below"] : n["above"];
  const std::string wk   = w + (below ? ".below" : ".above");
  if (!v.IsSequence() || v.size() != 2) r.Fail(v, wk + ": expected [axis, value], e.g. [z, 0.001]" + Reader::Got(v));
  s.kind  = below ? NodeSet::Below : NodeSet::Above;
  s.axis  = r.Axis(v[0], wk + "[0]");
  s.value = r.Real(v[1], wk + "[1]");
  return s;
}

VelocityField ReadVelocityField(const Reader &r, const std::string &w, const YAML::Node &n) {
  VelocityField f;
  f.where = r.At(n);
  r.Keys(n, w, {"shape", "along", "direction", "amplitude", "centre", "width"});
  const std::string k = r.Choice(r.Required(n, "shape", w), w + ".shape", {"cantilever", "sine", "gaussian"});
  f.kind              = k == "cantilever" ? VelocityField::Cantilever : k == "sine" ? VelocityField::Sine : VelocityField::Gaussian;
  const YAML::Node a  = r.Required(n, "along", w);
  if (!a.IsSequence() || a.size() != 3) r.Fail(a, w + ".along: expected [axis, from, to], e.g. [x, 0, 1]" + Reader::Got(a));
  f.axis = r.Axis(a[0], w + ".along[0]");
  f.from = r.Real(a[1], w + ".along[1]");
  f.to   = r.Real(a[2], w + ".along[2]");
  if (!(f.to != f.from)) r.Fail(a, w + ".along: from and to must differ");
  f.direction = r.Vector(r.Required(n, "direction", w), w + ".direction");
  if (!(norm(f.direction) > 0)) r.Fail(n["direction"], w + ".direction: must not be zero");
  f.direction = f.direction * (1 / norm(f.direction));
  f.amplitude = r.Real(r.Required(n, "amplitude", w), w + ".amplitude");
  if (f.kind == VelocityField::Gaussian) {
    f.centre = r.Real(r.Required(n, "centre", w), w + ".centre");
    f.width  = r.Positive(r.Required(n, "width", w), w + ".width");
  } else if (n["centre"] || n["width"]) r.Fail(n["centre"] ? n["centre"] : n["width"], w + ": centre and width belong to shape: gaussian");
  return f;
}

// fracture_zone: {min: [x, y, z], max: [x, y, z]} or a list of such boxes (world coordinates).
std::vector<FractureZone> ReadFractureZones(const Reader &r, const std::string &w, const YAML::Node &n) {
  const char *shape = ": expected a box {min: [x, y, z], max: [x, y, z]} or a list of them";
  if (!n.IsMap() && !(n.IsSequence() && n.size() > 0)) r.Fail(n, w + shape + (n.IsSequence() ? std::string(", got an empty list") : Reader::Got(n)));
  std::vector<FractureZone> zones;
  for (size_t i = 0; i < (n.IsMap() ? 1 : n.size()); ++i) {
    const YAML::Node  z  = n.IsMap() ? n : n[i];
    const std::string wz = n.IsMap() ? w : w + "[" + std::to_string(i) + "]";
    if (!z.IsMap()) r.Fail(z, wz + ": expected a box {min: [x, y, z], max: [x, y, z]}" + Reader::Got(z));
    r.Keys(z, wz, {"min", "max"});
    FractureZone Z;
    Z.where = r.At(z);
    Z.lo    = r.Vector(r.Required(z, "min", wz), wz + ".min");
    Z.hi    = r.Vector(r.Required(z, "max", wz), wz + ".max");
    for (int k = 0; k < 3; ++k)
      if (!(Z.lo[k] <= Z.hi[k])) r.Fail(z["min"], wz + ": min exceeds max in " + std::string(1, "xyz"[k]) + " (min " + z["min"][k].Scalar() + ", max " + z["max"][k].Scalar() + ")");
    zones.push_back(Z);
  }
  return zones;
}

Body ReadBody(const Reader &r, size_t i, const YAML::Node &n, const std::string &dir) {
  std::string w = "bodies[" + std::to_string(i) + "]";
  r.Keys(n, w, kBody);
  Body b;
  b.where = r.At(n);
  b.name  = r.String(r.Required(n, "name", w), w + ".name");
  if (b.name.empty()) r.Fail(n["name"], w + ".name: must not be empty");
  w       = "body '" + b.name + "'";
  b.model = r.Choice(r.Required(n, "model", w), w + ".model", kBodyModel);
  b.shape = ReadShape(r, w + ".shape", r.Required(n, "shape", w), dir);
  if (b.model == "sphere" && b.shape.kind != ShapeKind::Sphere) r.Fail(n["shape"], w + ".shape: a body of model sphere has shape {sphere: radius}");
  if (b.shape.kind == ShapeKind::Spheres && b.model != "rigid" && b.model != "auto") r.Fail(n["model"], w + ".model: a clump (shape {spheres: ...}) is a rigid body: give model: rigid");
  if (n["fixed"]) {
    b.fixed = r.Bool(n["fixed"], w + ".fixed");
    if (b.model == "deformable") r.Fail(n["fixed"], w + ".fixed: only rigid bodies are fixed as a whole; fix the nodes of a deformable body with fix: {below: [axis, value]}, {above: ...} or {group: name}");
  }
  if (n["material"]) b.material = r.String(n["material"], w + ".material");
  else if (!b.fixed && !(b.model != "deformable" && n["move"])) r.Fail(n, w + ": missing required key 'material' (only a fixed or moved rigid body may omit it)");
  if (n["resolution"]) b.resolution = r.Positive(n["resolution"], w + ".resolution");
  if (n["position"]) b.position = r.Vector(n["position"], w + ".position");
  if (n["velocity"]) b.velocity = r.Vector(n["velocity"], w + ".velocity");
  if (n["angular_velocity"]) b.angular_velocity = r.Vector(n["angular_velocity"], w + ".angular_velocity");
  if (n["rotation"]) {
    const YAML::Node rot = n["rotation"];
    r.Keys(rot, w + ".rotation", {"axis", "degrees"});
    const Vec3   axis = r.Vector(r.Required(rot, "axis", w + ".rotation"), w + ".rotation.axis");
    const double deg  = r.Real(r.Required(rot, "degrees", w + ".rotation"), w + ".rotation.degrees");
    if (!(norm(axis) > 0)) r.Fail(rot["axis"], w + ".rotation.axis: must not be zero");
    b.rotation = kernels::RotationMatrix(axis * (deg * M_PI / 180 / norm(axis)));
  }
  if (n["fix"]) {
    if (b.model != "deformable" && b.model != "auto") r.Fail(n["fix"], w + ".fix: node sets belong to deformable bodies; a rigid body is held with fixed: true");
    b.fix = ReadNodeSet(r, w + ".fix", n["fix"]);
    if (b.fix.kind == NodeSet::Group && b.shape.kind != ShapeKind::Mesh) r.Fail(n["fix"], w + ".fix.group: physical groups exist only for shape {mesh: ...}");
  }
  if (n["move"]) {
    const YAML::Node m = n["move"];
    b.moved            = true;
    b.move_where       = r.At(m);
    if (b.model == "rigid" || b.model == "sphere" || (b.model == "auto" && !m["below"] && !m["above"] && !m["group"])) {
      r.Keys(m, w + ".move", {"velocity"});
      if (b.fixed) r.Fail(m, w + ".move: a body is either fixed: true or moved, not both");
      if (n["velocity"] || n["angular_velocity"]) r.Fail(n["velocity"] ? n["velocity"] : n["angular_velocity"], w + ": a moved body's velocity is move.velocity (it moves without turning); remove velocity/angular_velocity");
    } else {
      b.move = ReadNodeSet(r, w + ".move", m, true);
      if (b.move.kind == NodeSet::Group && b.shape.kind != ShapeKind::Mesh) r.Fail(m, w + ".move.group: physical groups exist only for shape {mesh: ...}");
    }
    b.move_velocity = r.Vector(r.Required(m, "velocity", w + ".move"), w + ".move.velocity");
  }
  if (n["velocity_field"]) {
    if (b.model != "deformable" && b.model != "auto") r.Fail(n["velocity_field"], w + ".velocity_field: only a deformable body has a velocity field; a rigid body has velocity and angular_velocity");
    b.velocity_field = ReadVelocityField(r, w + ".velocity_field", n["velocity_field"]);
  }
  if (n["fracture_zone"]) {
    if ((b.model != "deformable" && b.model != "auto") || b.shape.kind == ShapeKind::Spheres)
      r.Fail(n["fracture_zone"], w + ".fracture_zone: only deformable bodies fracture (this one is " + (b.shape.kind == ShapeKind::Spheres ? std::string("a clump, a rigid body") : "of model " + b.model) + "); give the body model: deformable and a material with fracture:");
    b.fracture_zones = ReadFractureZones(r, w + ".fracture_zone", n["fracture_zone"]);
  }
  return b;
}

Pack ReadPack(const Reader &r, size_t i, const YAML::Node &item) {
  const std::string w0 = "generate[" + std::to_string(i) + "]";
  r.Keys(item, w0, {"pack"});
  const YAML::Node  n = r.Required(item, "pack", w0);
  const std::string w = w0 + ".pack";
  r.Keys(n, w, {"count", "like", "region", "scale", "seed"});
  Pack p;
  p.where = r.At(n);
  p.count = r.Int(r.Required(n, "count", w), w + ".count");
  if (p.count < 1) r.Fail(n["count"], w + ".count: must be at least 1, got " + n["count"].Scalar());
  p.like                 = r.String(r.Required(n, "like", w), w + ".like");
  const YAML::Node region = r.Required(n, "region", w);
  r.Keys(region, w + ".region", {"lo", "hi"});
  p.lo = r.Vector(r.Required(region, "lo", w + ".region"), w + ".region.lo");
  p.hi = r.Vector(r.Required(region, "hi", w + ".region"), w + ".region.hi");
  for (int k = 0; k < 3; ++k)
    if (!(p.hi[k] > p.lo[k])) r.Fail(region, w + ".region: hi must exceed lo in every direction");
  if (n["scale"]) {
    const YAML::Node s = n["scale"];
    if (!s.IsSequence() || s.size() != 2) r.Fail(s, w + ".scale: expected [min, max]" + Reader::Got(s));
    p.scale[0] = r.Positive(s[0], w + ".scale[0]");
    p.scale[1] = r.Positive(s[1], w + ".scale[1]");
    if (p.scale[1] < p.scale[0]) r.Fail(s, w + ".scale: max is below min");
  }
  if (n["seed"]) p.seed = r.Int(n["seed"], w + ".seed");
  return p;
}

} // namespace

const Material *Scene::FindMaterial(const std::string &name) const {
  for (const auto &m : materials)
    if (m.name == name) return &m;
  return nullptr;
}
const Body *Scene::FindBody(const std::string &name) const {
  for (const auto &b : bodies)
    if (b.name == name) return &b;
  return nullptr;
}
bool Scene::Has(const char *model) const {
  for (const auto &b : bodies)
    if (b.model == model) return true;
  return false;
}

Scene ReadScene(const std::string &file, const char *text) {
  Scene sc;
  sc.file             = file;
  const size_t slash  = file.rfind('/');
  sc.dir              = slash == std::string::npos ? std::string() : file.substr(0, slash + 1);
  const Reader r(file);
  YAML::Node   root;
  try {
    if (text) root = YAML::Load(text);
    else {
      std::ifstream in(file);
      if (!in) throw SceneError(file + ": cannot open the scene file");
      root = YAML::Load(in);
    }
  } catch (const YAML::Exception &e) {
    throw SceneError(r.At(e.mark) + ": not valid YAML: " + e.msg);
  }
  if (!root || root.IsNull()) throw SceneError(file + ": the scene file is empty");
  r.Keys(root, "scene", kTop);
  if (root["title"]) sc.title = r.String(root["title"], "title");
  if (root["gravity"]) sc.gravity = r.Vector(root["gravity"], "gravity");

  const YAML::Node time = r.Required(root, "time", "scene");
  r.Keys(time, "time", kTime);
  sc.time_where = r.At(time);
  sc.dt_where   = time["dt"] ? r.At(time["dt"]) : sc.time_where;
  sc.end        = r.Real(r.Required(time, "end", "time"), "time.end");
  if (!(sc.end > 0)) r.Fail(time["end"], "time.end: must be positive, got " + time["end"].Scalar());
  if (time["dt"]) {
    if (!(time["dt"].IsScalar() && time["dt"].Scalar() == "auto")) {
      sc.dt = r.Real(time["dt"], "time.dt (a number or auto)");
      if (!(sc.dt > 0)) r.Fail(time["dt"], "time.dt: must be positive (or auto), got " + time["dt"].Scalar());
    }
  }
  if (time["safety"]) {
    sc.safety = r.Positive(time["safety"], "time.safety");
    if (sc.safety > 1) r.Fail(time["safety"], "time.safety: must lie in (0, 1], got " + time["safety"].Scalar());
  }
  if (time["scheme"]) {
    sc.scheme_where = r.At(time["scheme"]);
    sc.scheme       = r.Choice(time["scheme"], "time.scheme", kSchemes);
  }

  if (root["materials"]) {
    const YAML::Node ms = root["materials"];
    if (!ms.IsMap()) r.Fail(ms, "materials: expected a map name: {density: ..., young: ..., poisson: ...}" + Reader::Got(ms));
    for (auto it = ms.begin(); it != ms.end(); ++it) {
      r.Unique(ms, it, "materials");
      sc.materials.push_back(ReadMaterial(r, it->first.Scalar(), it->second));
    }
  }
  if (root["contact"]) {
    const YAML::Node c = root["contact"];
    r.Keys(c, "contact", kContact);
    sc.contact.present = true;
    sc.contact.where   = r.At(c);
    sc.contact.penalty = r.Positive(r.Required(c, "penalty", "contact"), "contact.penalty");
    if (c["friction"]) sc.contact.friction = r.NonNegative(c["friction"], "contact.friction");
    if (c["normal_damping"]) sc.contact.normal_damping = r.NonNegative(c["normal_damping"], "contact.normal_damping");
    if (c["tangential_viscosity"]) sc.contact.tangential_viscosity = r.NonNegative(c["tangential_viscosity"], "contact.tangential_viscosity");
    if (c["buffer"] && !(c["buffer"].IsScalar() && c["buffer"].Scalar() == "auto")) sc.contact.buffer = r.Positive(c["buffer"], "contact.buffer (a length or auto)");
    if (sc.contact.friction > 0 && !(sc.contact.tangential_viscosity > 0))
      r.Fail(c["friction"], "contact.friction: friction between tetrahedra is regularised, F_t = -min(friction |F_n|, tangential_viscosity A |v_t|), so it needs contact.tangential_viscosity > 0 (Pa s/m; doc/contact.md); without it there is no friction");
  }

  if (root["periodic"]) {
    const YAML::Node p = root["periodic"];
    r.Keys(p, "periodic", {"axes", "lo", "hi"});
    sc.periodic.where     = r.At(p);
    const YAML::Node axes = r.Required(p, "axes", "periodic");
    if (!axes.IsSequence() || axes.size() == 0) r.Fail(axes, "periodic.axes: expected a list of axes, e.g. [x, y]" + Reader::Got(axes));
    for (size_t i = 0; i < axes.size(); ++i) {
      const int k = r.Axis(axes[i], "periodic.axes[" + std::to_string(i) + "]");
      if (sc.periodic.axis[k]) r.Fail(axes[i], "periodic.axes: axis " + std::string(1, "xyz"[k]) + " is listed twice");
      sc.periodic.axis[k] = true;
    }
    sc.periodic.lo = r.Vector(r.Required(p, "lo", "periodic"), "periodic.lo");
    sc.periodic.hi = r.Vector(r.Required(p, "hi", "periodic"), "periodic.hi");
    for (int k = 0; k < 3; ++k)
      if (sc.periodic.axis[k] && !(sc.periodic.hi[k] > sc.periodic.lo[k])) r.Fail(p["hi"], "periodic: the cell is empty along the periodic axis " + std::string(1, "xyz"[k]) + " (lo " + std::to_string(sc.periodic.lo[k]) + ", hi " + std::to_string(sc.periodic.hi[k]) + ")");
  }

  const YAML::Node bodies = r.Required(root, "bodies", "scene");
  if (!bodies.IsSequence() || bodies.size() == 0) r.Fail(bodies, "bodies: expected a list of bodies" + Reader::Got(bodies));
  std::set<std::string> names;
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body b = ReadBody(r, i, bodies[i], sc.dir);
    if (!names.insert(b.name).second) r.Fail(bodies[i]["name"], "bodies[" + std::to_string(i) + "].name: duplicated body name '" + b.name + "' (first at " + sc.FindBody(b.name)->where + ")");
    if (!b.material.empty() && !sc.FindMaterial(b.material)) {
      std::vector<std::string> known;
      for (const auto &m : sc.materials) known.push_back(m.name);
      r.Fail(bodies[i]["material"], "body '" + b.name + "'.material: unknown material '" + b.material + "'" + (known.empty() ? std::string(" (the scene has no materials:)") : " (did you mean '" + Nearest(b.material, known) + "'? materials: " + Join(known) + ")"));
    }
    if (b.model != "deformable" && b.model != "auto" && !b.material.empty() && sc.FindMaterial(b.material)->fracture.present)
      r.Fail(bodies[i]["material"], "body '" + b.name + "': material '" + b.material + "' is fracturable (fracture: at " + sc.FindMaterial(b.material)->fracture.where + "), and only deformable bodies fracture; give the body model: deformable, or a material without fracture:");
    if (!b.fracture_zones.empty()) {
      const Material *m = b.material.empty() ? nullptr : sc.FindMaterial(b.material);
      if (!(m && m->fracture.present)) {
        const std::string why = m ? "material '" + m->name + "' (" + m->where + ") is not fracturable (it has no fracture:)" : "the body has no material";
        r.Fail(bodies[i]["fracture_zone"], "body '" + b.name + "'.fracture_zone: " + why + "; a fracture zone limits where a fracturable body splits: give the material fracture: {...}, or remove fracture_zone");
      }
    }
    if (sc.periodic.Any() && b.model == "deformable") r.Fail(bodies[i]["model"] ? bodies[i]["model"] : bodies[i], "body '" + b.name + "': periodic boundaries (periodic: at " + sc.periodic.where + ") hold rigid bodies and spheres only; this body is deformable");
    { // 1/2 rho |v|^2 (and 1/2 rho |w|^2 a m^2) must be numbers: else the energies are Inf from the start
      const Material *m   = b.material.empty() ? nullptr : sc.FindMaterial(b.material);
      const double    rho = m ? m->density : 1.0;
      const auto      n2s = [](double x) { char t[32]; std::snprintf(t, sizeof(t), "%g", x); return std::string(t); };
      const auto      too_large = [&](const Vec3 &v, const char *key, const char *what) {
        const double v2 = v.x * v.x + v.y * v.y + v.z * v.z;
        if (!std::isfinite(0.5 * rho * v2)) r.Fail(bodies[i][key], "body '" + b.name + "'." + key + ": too large: " + what + " is not a finite number (density " + n2s(rho) + " kg/m^3)");
      };
      if (bodies[i]["velocity"]) too_large(b.velocity, "velocity", "its kinetic energy per unit volume, 1/2 density |v|^2,");
      if (bodies[i]["angular_velocity"]) too_large(b.angular_velocity, "angular_velocity", "1/2 density |w|^2 (its rotational energy per unit volume at 1 m from the axis)");
    }
    if (b.model == "deformable") {
      const Material *m = sc.FindMaterial(b.material);
      if (!(m->young > 0)) r.Fail(bodies[i]["material"], "body '" + b.name + "': a deformable body needs a material with young (and poisson); '" + m->name + "' (" + m->where + ") has no young");
    }
    sc.bodies.push_back(std::move(b));
  }
  if (root["generate"]) {
    const YAML::Node g = root["generate"];
    if (!g.IsSequence()) r.Fail(g, "generate: expected a list of {pack: {...}}" + Reader::Got(g));
    for (size_t i = 0; i < g.size(); ++i) {
      Pack p = ReadPack(r, i, g[i]);
      if (!sc.FindBody(p.like)) r.Fail(g[i]["pack"]["like"], "generate[" + std::to_string(i) + "].pack.like: no body named '" + p.like + "'");
      if (!sc.FindBody(p.like)->fracture_zones.empty())
        r.Fail(g[i]["pack"]["like"], "generate[" + std::to_string(i) + "].pack.like: body '" + p.like + "' has a fracture_zone (" + sc.FindBody(p.like)->fracture_zones[0].where + "), a box in world coordinates that cannot follow the copies a pack places and turns at random; pack a body without fracture_zone");
      sc.packs.push_back(p);
    }
  }
  if (root["output"]) {
    const YAML::Node o = root["output"];
    r.Keys(o, "output", {"dir", "every", "balance"});
    if (o["dir"]) sc.output_dir = r.String(o["dir"], "output.dir");
    if (o["every"]) sc.output_every = r.Positive(o["every"], "output.every");
    if (o["balance"]) sc.output_balance = r.Positive(o["balance"], "output.balance");
  }
  if (root["checkpoint"]) {
    const YAML::Node c = root["checkpoint"];
    r.Keys(c, "checkpoint", {"every", "keep"});
    sc.checkpoint_every = r.Positive(r.Required(c, "every", "checkpoint"), "checkpoint.every");
    if (c["keep"]) {
      sc.checkpoint_keep = r.Int(c["keep"], "checkpoint.keep");
      if (sc.checkpoint_keep < 1) r.Fail(c["keep"], "checkpoint.keep: must be at least 1, got " + c["keep"].Scalar());
    }
  }
  if (root["petsc"]) {
    sc.petsc       = r.String(root["petsc"], "petsc");
    sc.petsc_where = r.At(root["petsc"]);
  }
  if (sc.contact.present && sc.bodies.size() + sc.packs.size() < 2) r.Fail(sc.contact.where, "contact: the scene has a single body; nothing can touch (remove contact:)");
  return sc;
}

double VelocityField::Profile(double xi) const {
  switch (kind) {
  case Cantilever: { // first mode of a clamped-free beam, beta L = 1.8751..., normalised to 1 at the free end
    const double b = 1.8751040687119611, sg = 0.7340955137589676;
    auto         m = [&](double x) { return std::cosh(b * x) - std::cos(b * x) - sg * (std::sinh(b * x) - std::sin(b * x)); };
    return m(xi) / m(1.0);
  }
  case Sine: return std::sin(M_PI * xi);
  case Gaussian: return std::exp(-((xi - centre) / width) * ((xi - centre) / width));
  default: return 0;
  }
}

const char *SceneKeysHelp() {
  return "Scene file keys (YAML; doc/scenes.md has every key with an example):\n"
         "  title: text\n"
         "  gravity: [gx, gy, gz]                          m/s^2 (default 0)\n"
         "  time: {end: s (required), dt: s | auto, safety: 0.5, scheme: cd|pv|chin|omf30|omf32|fr|pefrl|t112|t16|d112|pc3|pc4|pc5}\n"
         "        dt auto = safety * K_crit(scheme) / omega_max (elements and contact)\n"
         "  materials: {NAME: {density: kg/m^3, young: Pa, poisson: (-1, 0.5), model: finite_strain|neo_hookean|small_strain, damping: Pa s,\n"
         "                     fracture: {tensile_strength: Pa, cohesion: Pa, friction_angle: degrees, G_I: J/m^2, G_II: J/m^2, joint_penalty: Pa, insert_at: (0, 1]}}}\n"
         "             (fracture: makes the deformable bodies of the material fracturable: a joint on every interior face;\n"
         "              with insert_at, the bodies start whole (or split in their fracture_zone) and a tetrahedron gets joints\n"
         "              during the run when its stress reaches insert_at times the strength)\n"
         "             granular contact of spheres: restitution: (0, 1], friction: mu, rolling_friction: mu_r, contact_law: hertz|hooke, kn: N/m, kt: N/m, gamma_n: 1/s, gamma_t: 1/s\n"
         "  contact: {penalty: Pa (required), friction: mu, normal_damping: Pa s/m, tangential_viscosity: Pa s/m, buffer: m | auto}\n"
         "  periodic: {axes: [x, y], lo: [x,y,z], hi: [x,y,z]}  periodic boundaries along the axes listed, cell [lo, hi) (rigid bodies and spheres)\n"
         "  bodies: list of\n"
         "    {name, model: rigid|deformable|sphere (shape {sphere: r})|auto (fdem chooses; fdem check shows why), material, shape, resolution: element size,\n"
         "     position: [x,y,z], rotation: {axis: [x,y,z], degrees}, velocity: [..], angular_velocity: [..],\n"
         "     fixed: true (rigid), fix: {below: [axis, value]} | {above: [axis, value]} | {group: NAME} (deformable),\n"
         "     move: {velocity: [..]} (rigid: a platen) | {velocity: [..], below|above|group: ...} (deformable: nodes held at v),\n"
         "     velocity_field: {shape: cantilever|sine|gaussian, along: [axis, from, to], direction: [..], amplitude: m/s,\n"
         "                      centre, width (gaussian; fractions of from..to)} (deformable, added to velocity),\n"
         "     fracture_zone: {min: [x,y,z], max: [x,y,z]} | [{min, max}, ...] (fracturable material: split only the tetrahedra\n"
         "                    whose centroids lie in a box, world coordinates; elsewhere no joints)}\n"
         "    shape: {box: [lx, ly, lz]} | {sphere: r} | {ellipsoid: [a, b, c]} | {cylinder: {radius, height}}\n"
         "         | {convex_hull: [[x,y,z], ...]} | {pebble: {size, seed}} | {mesh: FILE.msh} | {mesh: {file, group}}\n"
         "         | {spheres: [[x,y,z,r], ...]} (a clump: a rigid body whose contact shape is spheres, granular laws)\n"
         "  generate: list of {pack: {count, like: BODY, region: {lo: [..], hi: [..]}, scale: [min, max], seed}}\n"
         "  output: {dir: out, every: s, balance: s}        HDF5 frames every `every` (rigid.h5, mesh.h5, scene.xmf), balance.csv rows every `balance`\n"
         "  checkpoint: {every: s, keep: 2}                 DIR/checkpoint.h5 (+ .1, .2, ...); continue with -restart DIR/checkpoint.h5\n"
         "  petsc: \"-options\"                              inserted before the command line (the command line wins)\n";
}

} // namespace fdem::driver
