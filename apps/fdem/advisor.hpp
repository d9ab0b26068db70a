// The model advisor (doc/advisor.md): for each body the cheapest of the three models
// (sphere, rigid polyhedron, deformable mesh) that serves it, with the reason and the
// estimated cost per step of each choice; `model: auto` applies it. Pure C++ on the scene.
#pragma once
#include "scene.hpp"

#include <string>
#include <vector>

namespace fdem::driver {

struct Advice {
  std::string model;          // sphere | rigid | deformable
  std::string why;
  double      strain   = -1;  // the expected strain (< 0: unknown, no young)
  double      cost[3]  = {-1, -1, -1}; // CPU seconds per step as sphere, rigid, deformable (< 0: not possible)
  double      dt_deformable = -1;       // the stable step of the body as a deformable mesh (s)
};

// The advice for body b of scene sc (its placed shape, its material, the scene's gravity
// and speeds): deformable where the expected strain exceeds strain_limit, or the body has
// node sets, a velocity field or a fracturable material; else a sphere where the shape is
// a sphere (or an ellipsoid within 10% of one), else a rigid polyhedron.
// costs: also the costs per step and the deformable stable step (they mesh the shape; the
// choice itself needs the mesh only for a shape read from a file).
Advice AdviseBody(const Scene &sc, const Body &b, double strain_limit, bool costs = true);

// Resolves every `model: auto` body to its advised model (an ellipsoid becomes the sphere
// of its volume); appends one line per resolved body to `report`.
void ApplyAuto(Scene &sc, double strain_limit, std::vector<std::string> &report);

// The advice for every body, as lines for `fdem check` (at most `max_lines` bodies, then a summary).
std::vector<std::string> AdviceReport(const Scene &sc, double strain_limit, size_t max_lines);

} // namespace fdem::driver
