// The work of prescribed motions (moved mesh nodes, moved rigid bodies): each
// force evaluation gives the power of the reactions that hold the prescribed
// velocities, P = sum R . v with R = -(the force on the node or body, gravity
// included); the meter integrates P over the evaluation times with the
// trapezoidal rule. For the central-difference scheme (one force per step, at
// the step's end) that is exactly the impulse of the scheme's two half kicks
// times v. Evaluations at an unchanged time add nothing. Per rank (a sum).
#pragma once
#include <petscsys.h>

namespace fdem::model {
struct WorkMeter {
  PetscReal work = 0, power = 0, t = 0;
  bool      have = false;
  void      Sample(PetscReal tnow, PetscReal p) {
    if (have) work += 0.5 * (p + power) * (tnow - t);
    power = p, t = tnow, have = true;
  }
  // Restart: the work so far (on one rank), the next sample starts a new segment.
  void Reset(PetscReal w) { work = w, power = 0, t = 0, have = false; }
};
} // namespace fdem::model
