// The model advisor (advisor.hpp, doc/advisor.md).
#include "advisor.hpp"
#include "shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace fdem::driver {
namespace {
// Measured costs on this project's benchmarks (doc/advisor.md): CPU seconds per step of
// one sphere in a settling bed, of one skin tetrahedron of a rigid pebble in a settled pile
// (contact included), and of one tetrahedron of a deformable mesh (the cd step).
constexpr double kSphereStep   = 1.1e-6;
constexpr double kContactPerSurfaceTet = 5.4e-6; // a pebble's step in a settled pile over its 26 skin tetrahedra
constexpr double kDeformPerTet = 3.8e-8;
// A fracturable body's step over the unsplit body's, less one, per share of its tetrahedra
// split (bench_fracturable -n 16, doc/fracture.md "Fracture zones": 12 times split
// everywhere; 1.8, 2.2 and 3.3 times with a sixteenth, an eighth and a quarter split).
constexpr double kSplitExtra = 11;



// Half the body's extent along the unit vector u (its placed shape).
double HalfExtent(const Body &b, const Vec3 &u) {
  if (b.shape.kind == ShapeKind::Box) {
    const Vec3 l = transpose(b.rotation) * u;
    return 0.5 * (std::fabs(l.x) * b.shape.size.x + std::fabs(l.y) * b.shape.size.y + std::fabs(l.z) * b.shape.size.z);
  }
  return -1;
}

// The radius of the sphere about the body's centre that holds its shape.
double SizeOf(const Shape &s) {
  switch (s.kind) {
  case ShapeKind::Sphere: return s.radius;
  case ShapeKind::Box: return 0.5 * norm(s.size);
  case ShapeKind::Ellipsoid: return std::max({s.size.x, s.size.y, s.size.z});
  case ShapeKind::Cylinder: return std::sqrt(s.radius * s.radius + 0.25 * s.height * s.height);
  case ShapeKind::Pebble: return s.radius;
  default: return -1; // from the mesh
  }
}

// A shape whose contacts a sphere reproduces: a sphere, or an ellipsoid within 10% of one.
bool SphereLike(const Shape &s) {
  if (s.kind == ShapeKind::Sphere) return true;
  if (s.kind != ShapeKind::Ellipsoid) return false;
  const double lo = std::min({s.size.x, s.size.y, s.size.z}), hi = std::max({s.size.x, s.size.y, s.size.z});
  return hi <= 1.1 * lo;
}

std::string Fmt(const char *f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}
} // namespace

Advice AdviseBody(const Scene &sc, const Body &b, double strain_limit, bool costs) {
  Advice          a;
  const Material *m    = b.material.empty() ? nullptr : sc.FindMaterial(b.material);
  const bool      ball = SphereLike(b.shape);
  // the mesh (rigid skin and deformable mesh alike) for the costs
  kernels::TetMesh mesh;
  bool             meshed = false;
  if (costs || b.shape.kind == ShapeKind::Mesh) try {
      mesh   = ShapeMesh(b);
      meshed = true;
    } catch (const std::exception &) {
    }
  double size = SizeOf(b.shape);
  if (size < 0 && meshed) size = BoundingRadius(mesh);
  const double ntet = meshed ? (double)mesh.tets.size() : -1, nsurf = meshed ? (double)kernels::SurfaceTets(mesh).tets.size() : -1;
  a.cost[0]         = ball ? kSphereStep : -1;
  a.cost[1]         = meshed ? kContactPerSurfaceTet * nsurf : -1;
  // the expected strain: impact speed (own, the fastest other body's, a fall over the scene's height) over the wave speed, or self-weight
  if (m && m->young > 0 && m->density > 0) {
    const double g = norm(sc.gravity);
    double       zlo = 1e300, zhi = -1e300, vmax = 0;
    const Vec3   up = g > 0 ? (-1.0 / g) * sc.gravity : Vec3(0, 0, 1);
    for (const Body &o : sc.bodies) {
      const double so = std::max(SizeOf(o.shape), 0.0), h = dot(o.position, up), ho = HalfExtent(o, up) >= 0 ? HalfExtent(o, up) : so;
      zlo             = std::min(zlo, h - ho);
      zhi             = std::max(zhi, h + ho);
      if (&o != &b) vmax = std::max(vmax, norm(o.velocity) + norm(o.angular_velocity) * so);
    }
    const double H = std::max(zhi - zlo, 0.0), c = std::sqrt(m->young / m->density);
    const double v = norm(b.velocity) + norm(b.angular_velocity) * std::max(size, 0.0) + vmax + std::sqrt(2 * g * H);
    const double e_imp = v / c, e_static = m->density * g * H / m->young;
    a.strain           = std::max(e_imp, e_static);
    a.why              = e_imp >= e_static ? Fmt("expected strain %.2g (impact %.3g m/s over the wave speed %.4g m/s)", a.strain, v, c) : Fmt("expected strain %.2g (self-weight over %.3g m of height)", a.strain, H);
    if (meshed) {
      a.cost[2]         = kContactPerSurfaceTet * nsurf + kDeformPerTet * ntet;
      double hmin       = 1e300;
      for (const auto &T : mesh.tets) { // the smallest altitude
        const Vec3 &p0 = mesh.nodes[T[0]], &p1 = mesh.nodes[T[1]], &p2 = mesh.nodes[T[2]], &p3 = mesh.nodes[T[3]];
        const double V6 = std::fabs(dot(p1 - p0, cross(p2 - p0, p3 - p0)));
        for (int k = 0; k < 4; ++k) {
          const Vec3 &q = mesh.nodes[T[(k + 1) % 4]], &r = mesh.nodes[T[(k + 2) % 4]], &s = mesh.nodes[T[(k + 3) % 4]];
          const double A2 = norm(cross(r - q, s - q));
          if (A2 > 0) hmin = std::min(hmin, V6 / A2);
        }
      }
      const double nu = m->poisson, cp = std::sqrt(m->young * (1 - nu) / (m->density * (1 + nu) * (1 - 2 * nu)));
      if (hmin < 1e300) a.dt_deformable = 2.0 / (2 * cp / hmin); // K_crit 2 (cd) over omega = 2 c_p / h_min
    }
  } else a.why = "its material has no young: it cannot deform here";
  // a fracturable material: its tetrahedra split (all without zones, else those whose placed
  // centroids lie in one) cost more as a deformable body (doc/fracture.md, "Fracture zones")
  std::string frac;
  if (m && m->fracture.present && b.shape.kind != ShapeKind::Spheres) {
    double split = 1;
    if (!b.fracture_zones.empty() && meshed && ntet > 0) {
      double in = 0;
      for (const auto &T : mesh.tets) {
        const Vec3 c = b.position + b.rotation * (0.25 * (mesh.nodes[T[0]] + mesh.nodes[T[1]] + mesh.nodes[T[2]] + mesh.nodes[T[3]]));
        bool       any = false;
        for (const FractureZone &z : b.fracture_zones) any = any || (c.x >= z.lo.x && c.x <= z.hi.x && c.y >= z.lo.y && c.y <= z.hi.y && c.z >= z.lo.z && c.z <= z.hi.z);
        in += any;
      }
      split = in / ntet;
    }
    if (a.cost[2] >= 0) a.cost[2] += kDeformPerTet * ntet * kSplitExtra * split;
    if (b.fracture_zones.empty()) frac = "fracturable, split everywhere: about " + Fmt("%.0f", 1 + kSplitExtra) + " times the unsplit body's step; a fracture_zone where cracks may run costs less";
    else if (meshed) frac = Fmt("fracturable in its fracture_zone: %.0f%% of its tetrahedra split, about %.2g times the unsplit body's step", 100 * split, 1 + kSplitExtra * split);
    else frac = "fracturable in its fracture_zone";
  }
  // the rules, in order
  const Material *mm = m;
  if (b.shape.kind == ShapeKind::Spheres) { // its cost: that of its spheres; it has no mesh to deform
    a.model   = "rigid";
    a.why     = "a clump of spheres is a rigid body";
    a.cost[0] = a.cost[2] = -1;
    a.cost[1] = kSphereStep * (double)b.shape.radii.size();
  } else if (b.fix.kind != NodeSet::None || (b.moved && b.model == "deformable") || b.velocity_field.kind != VelocityField::None) {
    a.model = "deformable";
    a.why   = "it has node sets or a velocity field (only a mesh has nodes); " + a.why;
  } else if (mm && mm->fracture.present) {
    a.model = "deformable";
    a.why   = "its material fractures; " + a.why;
  } else if (b.fixed || (b.moved && b.model != "deformable")) {
    a.model = ball ? "sphere" : "rigid";
    a.why   = "it is held (fixed or moved): its strain does not change the others' motion";
  } else if (a.strain > strain_limit) {
    a.model = "deformable";
    a.why   = a.why + Fmt(" above the limit %.2g", strain_limit);
  } else if (ball) {
    a.model = "sphere";
    a.why   = "nearly spherical (its orientation does not change its contacts); " + a.why + (a.strain >= 0 ? Fmt(" below the limit %.2g", strain_limit) : "");
  } else {
    a.model = "rigid";
    a.why   = "its shape matters to its contacts; " + a.why + (a.strain >= 0 ? Fmt(" below the limit %.2g", strain_limit) : "");
  }
  if (a.model == "deformable" && !frac.empty()) a.why += "; " + frac;
  return a;
}

void ApplyAuto(Scene &sc, double strain_limit, std::vector<std::string> &report) {
  for (Body &b : sc.bodies) {
    if (b.model != "auto") continue;
    const Advice a = AdviseBody(sc, b, strain_limit, false);
    if (a.model == "sphere" && b.shape.kind == ShapeKind::Ellipsoid) { // the sphere of the same volume
      b.shape.radius = std::cbrt(b.shape.size.x * b.shape.size.y * b.shape.size.z);
      b.shape.kind   = ShapeKind::Sphere;
    }
    const Material *m = b.material.empty() ? nullptr : sc.FindMaterial(b.material);
    if (a.model == "deformable" && !(m && m->young > 0)) throw SceneError(b.where + ": body '" + b.name + "': model: auto: it needs a mesh (" + a.why + "), and a deformable body needs a material with young");
    if (a.model == "deformable" && sc.periodic.Any()) throw SceneError(b.where + ": body '" + b.name + "': model: auto: it needs a mesh (" + a.why + "), and periodic boundaries (periodic: at " + sc.periodic.where + ") hold rigid bodies and spheres only; give it model: rigid or sphere");
    b.model = a.model;
    report.push_back("model: auto: body '" + b.name + "' is " + a.model + " (" + a.why + ")");
  }
  // Walls for grains: when every body that moves is a sphere or a clump (no deformable body, no
  // rigid polyhedron that moves), a fixed rigid box meets spheres only, whose contact sees its
  // surface alone (doc/spheres.md, "Walls for grains"): one cell per side (12 surface triangles) instead of
  // cubes of its smallest side, unless the scene gives its resolution.
  bool grains_only = true;
  for (const Body &b : sc.bodies) grains_only = grains_only && (b.model == "sphere" || (b.model == "rigid" && (b.Granular() || b.fixed)));
  int walls = 0;
  for (Body &b : sc.bodies)
    if (grains_only && b.model == "rigid" && b.fixed && b.shape.kind == ShapeKind::Box && b.resolution < 0) {
      b.resolution = std::max({b.shape.size.x, b.shape.size.y, b.shape.size.z});
      ++walls;
    }
  if (walls) report.push_back("walls: " + std::to_string(walls) + " fixed box" + (walls > 1 ? "es" : "") + " meshed as one cell each (only spheres and clumps meet them; resolution: sets it)");
}

std::vector<std::string> AdviceReport(const Scene &sc, double strain_limit, size_t max_lines) {
  std::vector<std::string>   out;
  std::map<std::string, int> count;
  size_t                     shown = 0;
  out.push_back(Fmt("model advice (doc/advisor.md; strain limit %.2g, -fdem_advise_strain; costs: CPU s per step on one core, from this project's benchmarks):", strain_limit));
  for (const Body &b : sc.bodies) {
    const bool   show = shown++ < max_lines;
    const Advice a    = AdviseBody(sc, b, strain_limit, show); // the costs of the bodies shown only
    ++count[a.model];
    if (!show) continue;
    std::string cost;
    const char *names[3] = {"sphere", "rigid", "deformable"};
    for (int k = 0; k < 3; ++k) {
      if (a.cost[k] < 0) continue;
      char buf[128];
      if (k == 2 && a.dt_deformable > 0) std::snprintf(buf, sizeof buf, "%s%s %.2g (its own stable step %.2g s)", cost.empty() ? "" : ", ", names[k], a.cost[k], a.dt_deformable);
      else std::snprintf(buf, sizeof buf, "%s%s %.2g", cost.empty() ? "" : ", ", names[k], a.cost[k]);
      cost += buf;
    }
    out.push_back("  body '" + b.name + "' (" + b.model + "): " + a.model + (a.model == b.model ? "" : " [differs]") + " -- " + a.why + "; per step: " + cost);
  }
  if (shown > max_lines) out.push_back("  ... " + std::to_string(shown - max_lines) + " more bodies");
  std::string sum = "  advised: ";
  for (const auto &kv : count) sum += std::to_string(kv.second) + " " + kv.first + " ";
  out.push_back(sum);
  return out;
}

} // namespace fdem::driver
