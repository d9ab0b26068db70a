// Extras for the work-precision benchmark on top of examples/common/fpu_chain.hpp
// (added functions only; the chain itself is unchanged):
//   InitialRough    - a rough, strongly nonlinear initial state, the same for any
//                     number of ranks (a hash of the global index, not a RNG stream)
//   RHSCombined     - dU/dt = [p/m | f(x)] as one RHS for TSRK (counts one force)
//   JacobianProductCounted - fpu::JacobianProduct that counts its calls
//   PositionMaxDiff - max |x_a - x_b| over the position split
#pragma once
#include "../../examples/common/fpu_chain.hpp"

#include <cstdint>

namespace fpu {

// Counters that live beside the chain (the Chain struct itself is not changed).
struct Counters {
  PetscInt njvp = 0;
};
inline Counters &Count() {
  static Counters c;
  return c;
}

// Uniform number in [-1, 1) from a 64-bit hash of (i, stream): independent of the partition.
inline double HashUniform(std::uint64_t i, std::uint64_t stream) {
  std::uint64_t z = i * 0x9E3779B97F4A7C15ull + stream * 0xD1B54A32D192ED03ull + 0x2545F4914F6CDD1Dull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z = z ^ (z >> 31);
  return 2.0 * (double)(z >> 11) * (1.0 / 9007199254740992.0) - 1.0;
}

// x_i uniform in [-amp, amp], v_i = p_i/m_i uniform in [-amp, amp]: every spring is
// stretched by O(amp), so with beta = 1 and amp = 0.25 the quartic term is
// 3 beta r^2 <= 0.75 of the linear one; the highest frequency is ~ 2 sqrt((1 + 3 beta r^2)/m_min).
inline PetscErrorCode InitialRough(Chain *c, PetscReal amp, Vec U) {
  PetscScalar *u;
  PetscFunctionBeginUser;
  PetscCall(VecGetArray(U, &u));
  for (PetscInt i = 0; i < c->n; ++i) {
    const PetscInt g = c->start + i;
    u[i]        = amp * HashUniform((std::uint64_t)g, 1);
    u[c->n + i] = Mass(g) * amp * HashUniform((std::uint64_t)g, 2);
  }
  PetscCall(VecRestoreArray(U, &u));
  PetscFunctionReturn(0);
}

// One RHS for the whole state (TSRK): [dq/dt | dp/dt] = [p/m | f(x)].
inline PetscErrorCode RHSCombined(TS ts, PetscReal t, Vec U, Vec F, void *ctx) {
  Chain *c = (Chain *)ctx;
  Vec    x, p, dx, dp;
  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(U, c->isq, &x));
  PetscCall(VecGetSubVector(U, c->isp, &p));
  PetscCall(VecGetSubVector(F, c->isq, &dx));
  PetscCall(VecGetSubVector(F, c->isp, &dp));
  PetscCall(RHSPosition(ts, t, p, dx, ctx));
  PetscCall(RHSMomentum(ts, t, x, dp, ctx)); // counts the force evaluation
  PetscCall(VecRestoreSubVector(F, c->isp, &dp));
  PetscCall(VecRestoreSubVector(F, c->isq, &dx));
  PetscCall(VecRestoreSubVector(U, c->isp, &p));
  PetscCall(VecRestoreSubVector(U, c->isq, &x));
  PetscFunctionReturn(0);
}

inline PetscErrorCode JacobianProductCounted(TS ts, PetscReal t, Vec x, Vec W, Vec JW, void *ctx) {
  PetscFunctionBeginUser;
  PetscCall(JacobianProduct(ts, t, x, W, JW, ctx));
  Count().njvp++;
  PetscFunctionReturn(0);
}

// max_i |x_a,i - x_b,i| over the positions; work: a position-sized vector.
inline PetscErrorCode PositionMaxDiff(Chain *c, Vec Ua, Vec Ub, Vec work, PetscReal *d) {
  Vec xa, xb;
  PetscFunctionBeginUser;
  PetscCall(VecGetSubVector(Ua, c->isq, &xa));
  PetscCall(VecGetSubVector(Ub, c->isq, &xb));
  PetscCall(VecWAXPY(work, -1.0, xb, xa));
  PetscCall(VecNorm(work, NORM_INFINITY, d));
  PetscCall(VecRestoreSubVector(Ub, c->isq, &xb));
  PetscCall(VecRestoreSubVector(Ua, c->isq, &xa));
  PetscFunctionReturn(0);
}

} // namespace fpu
