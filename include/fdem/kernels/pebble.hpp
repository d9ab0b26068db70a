// Random convex pebbles: the points whose convex hull (MakeConvexPolyhedronTets,
// massprops.hpp) is an irregular stone. Pure numerics, C++ standard library only.
#pragma once
#include <fdem/kernels/vec3.hpp>

#include <random>
#include <vector>

namespace fdem::kernels {

// One random stream for a sequence of pebbles (and whatever else the caller
// draws between them, through U()): the engine and both distributions are kept
// together because std::normal_distribution carries a spare value from one
// draw to the next, so the same seed gives the same pebbles only if the same
// distribution objects are used throughout.
struct PebbleRandom {
  std::mt19937_64                        rng;
  std::uniform_real_distribution<double> uniform{0.0, 1.0};
  std::normal_distribution<double>       normal{0.0, 1.0};
  explicit PebbleRandom(unsigned long seed) : rng(seed) {}
  double U() { return uniform(rng); } // uniform in [0, 1)
};

struct Pebble {
  double            a = 0, b = 0, c = 0; // semi-axes of the ellipsoid the points lie on (or just inside)
  std::vector<Vec3> points;              // 12 points, body frame centred on the ellipsoid's centre
};

// A pebble of long semi-axis a: b = a (0.6 + 0.3 U), c = a (0.35 + 0.25 U), then
// 12 points r (a dx, b dy, c dz) with d a uniformly random direction and
// r = 1 - 0.15 U (pushed in by up to 15%). Draws from `random` in that order.
Pebble RandomPebble(double a, PebbleRandom &random);

} // namespace fdem::kernels
