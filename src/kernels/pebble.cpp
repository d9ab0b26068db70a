// Random convex pebbles (include/fdem/kernels/pebble.hpp).
#include <fdem/kernels/pebble.hpp>

namespace fdem::kernels {

Pebble RandomPebble(double a, PebbleRandom &R) {
  Pebble p;
  p.a = a;
  p.b = a * (0.6 + 0.3 * R.U());
  p.c = a * (0.35 + 0.25 * R.U());
  while (p.points.size() < 12) {
    Vec3 d(R.normal(R.rng), R.normal(R.rng), R.normal(R.rng));
    if (norm(d) < 1e-6) continue;
    d              = d / norm(d);
    const double r = 1 - 0.15 * R.U();
    p.points.push_back(Vec3(p.a * r * d.x, p.b * r * d.y, p.c * r * d.z));
  }
  return p;
}

} // namespace fdem::kernels
