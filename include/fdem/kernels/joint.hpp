// The cohesive law of a fracture joint between two tetrahedra (doc/fracture.md):
// Munjiza's combined single and smeared crack model. A joint carries a normal
// traction sigma from its opening dn and a shear traction tau from its slip s;
// up to the peak the law hardens, beyond it the joint softens along
// Munjiza's curve z(D) with a damage D that never decreases, and at D = 1 the
// joint is broken and carries nothing. The shear traction is a secant
// stiffness (1 - w) p / h times the slip, with a shear damage w that never
// decreases either, so that a joint never gives back more work than it took
// although its shear strength follows the normal traction (Mohr-Coulomb).
// Pure functions on doubles; no PETSc, no MPI.
#pragma once
#include <string>

namespace fdem::kernels {

// The constants of Munjiza's softening curve (a, b, c) and its integral over
// [0, 1] (evaluated by JointSofteningIntegral; 0.3863 to 4 digits).
inline constexpr double kJointA = 0.63, kJointB = 1.8, kJointC = 6.0;

// z(D) = [1 - (a+b-1)/(a+b) exp(D (a+cb) / ((a+b)(1-a-b)))] [a (1-D) + b (1-D)^c],
// z(0) = 1, z(1) = 0, decreasing. D outside [0, 1] is clamped.
double JointSoftening(double D);
// The integral of z over [0, 1] (composite Simpson, 2^12 intervals).
double JointSofteningIntegral();

// A fracturable material (SI units; the scene file's `fracture:` block).
struct JointMaterial {
  std::string name;            // for messages
  double tensile_strength = 0; // f_t, Pa, > 0
  double cohesion = 0;         // c, Pa, > 0
  double friction_angle = 0;   // phi, degrees, in [0, 90)
  double GI = 0, GII = 0;      // fracture energies, J/m^2, > 0
  double penalty = 0;          // joint penalty p, Pa, > 0
};

// The law of one joint of a material in elements of size h (m): the peak and
// critical openings and slips follow from the material (doc/fracture.md):
//   dn_peak = 2 h f_t / p,  s_peak(sigma) = 2 h f_s / p,  f_s = max(c - sigma tan phi, 0),
//   dn_crit = dn_peak + (G_I - 2/3 f_t dn_peak) / (f_t Z),  Z = the integral of z,
// and the same for the slip with G_II, f_s; so that the whole area under the
// curve (hardening + softening) is the fracture energy.
struct JointLaw {
  double ft = 0, c = 0, tan_phi = 0, GI = 0, GII = 0, penalty = 0, h = 0;
  double dn_peak = 0, dn_crit = 0; // opening at the peak and at rupture, m
  double s_span = 0;               // s_crit - s_peak, the softening span of the slip (pure shear), m
  double inv_dn_peak = 0;          // 1 / dn_peak, 1/m
  double slip_per_strength = 0;    // 2 h / p: the slip at the shear peak is f_s times this, m/Pa
  double shear_stiffness = 0;      // K = p / h, Pa/m: the slope of the shear law at zero slip, whatever f_s
  // 1: a joint element's compression is the larger of the penalty's energy at its three points
  // and its exact integral over the pressed part of the face (JointElementForces); 0: the points'
  // alone. Not set by MakeJointLaw (0); the deformable model sets it from
  // -fdem_joint_face_compression, 1 by default (doc/fracture.md, "One joint element").
  double face_compression = 0;
};

// Checks the material and the element size and returns the law. Throws
// InputError naming the material and what is wrong: a non-positive strength,
// energy, penalty or size, a friction angle outside [0, 90), or a penalty too
// small for the element (the hardening branch alone would hold more energy
// than G_I: 2/3 f_t dn_peak >= G_I, i.e. the peak opening is too large).
JointLaw MakeJointLaw(const JointMaterial &m, double h);

// The history of one joint point: the largest damage reached and the shear damage (neither
// ever decreases).
struct JointState {
  double D = 0; // set it with SetDamage, which keeps `softening` with it
  // w in [0, 1]: the shear traction is (1 - w) K s. Each evaluation raises it to the law's
  // secant, 1 - tau_law / (K s), where that is larger (doc/fracture.md, "Shear"). A float,
  // so that a point's history stays small (24 bytes): the law rounds the secant to it, and the
  // tractions, the stored and the dissipated energy all use the rounded value.
  float shear_damage = 0;
  // z(D) rounded to a float, kept with D so that a softening point does not evaluate the curve
  // (an exp) at every evaluation: 1 while D = 0, 0 once broken. The tractions, the stored and
  // the dissipated energy all use the rounded value.
  float softening = 1;
  // The point's energies per area at its last evaluation: the tension term's undamaged energy
  // f_t dn_peak H(dn / dn_peak) and the shear's K s^2 / 2. A growth of D or w between two
  // evaluations dissipates the energy it releases at the mean of the two evaluations' values
  // (the trapezoidal rule), which is what the tractions' work over the step, as the explicit
  // schemes take it, leaves over: the balance's error is then second order in the step
  // (doc/fracture.md, "Energy"). Floats, as w and z are; -1: none yet (a fresh state, or one
  // set from its damage alone, takes the release at its own separation). JointBlockForces's
  // common path (undamaged points) keeps the shear's only: an undamaged point releases no
  // tension energy, and the step where it becomes damaged takes that release at its end.
  float last_tension = -1, last_shear = -1;
  // D = 1: the point carries nothing of the law (while its joint holds, a joint element keeps
  // the compression penalty at its broken points).
  bool broken() const { return D >= 1; }
  // D and its softening factor together (a restart, a test); damage in [0, 1].
  void SetDamage(double damage);
};

// A joint element is broken when all three of its points are: its faces are contact surfaces.
inline bool JointBroken(const JointState state[3]) { return state[0].broken() && state[1].broken() && state[2].broken(); }

struct JointTraction {
  double sigma = 0; // normal traction, Pa (tension > 0; compression < 0 is the penalty 2 f_t dn / dn_peak)
  double tau = 0;   // shear traction, Pa, in the direction of the slip (s >= 0 given)
  double D = 0;     // damage after this evaluation
  double dissipated = 0; // energy per area (J/m^2) dissipated by this evaluation's growth of D and w
};

// Tractions at opening dn (m, > 0 opening) and slip magnitude s >= 0 (m).
// Damage from both modes: D = min(1, sqrt(D_I^2 + D_II^2)) with
// D_I = (dn - dn_peak)+ / (dn_crit - dn_peak) and the same for the slip; the
// state keeps the largest D. sigma = z(D) f_t h(dn / dn_peak) in tension,
// tau_law = z(D) f_s h(s / s_peak), with h(x) = 2x - x^2 for x < 1 and 1 beyond.
// The shear traction is the secant form of that law: tau = (1 - w) K s, with the state's
// shear damage w raised to 1 - tau_law / (K s) where that is larger. Along a monotonic
// path at a fixed normal traction tau is tau_law exactly; where f_s falls or the slip
// unloads the joint keeps the softer secant, so that no cycle of opening and slip gives
// back more work than it took. `dissipated` is the energy of the growth of D and w: the
// release of psi at fixed separation, taken at the mean of the last evaluation's separation
// and this one's (the state keeps the last energies; at this one's where it has none).
// The state is updated (pass a copy to evaluate without committing).
JointTraction JointTractionAt(const JointLaw &law, double dn, double s, JointState &state);

// The energy per area (J/m^2) a joint point stores at opening dn and slip s in the history
// `state` (damage D, shear damage w): the free energy psi whose derivatives are the
// tractions at fixed D and w (doc/fracture.md),
//   psi = z(D) f_t dn_peak H(dn / dn_peak) + (1 - w) K s^2 / 2   (dn >= 0),
//   H(x) = x^2 - x^3/3 below the peak, 2/3 + (x - 1) beyond it,
// with the compression penalty's f_t dn^2 / dn_peak in place of the first term when
// dn < 0. Unloading at fixed D and w gives it back. It is 0 once broken. Growing D from D0
// to D1 and w from w0 to w1 at fixed separation dissipates psi(D0, w0) - psi(D1, w1) >= 0,
// and JointTractionAt's `dissipated` is that release at the mean separation of the step, so
// that the work done on a joint, summed by the trapezoidal rule over the evaluations, is the
// stored energy plus the sum of the dissipated to second order in the steps of the path.
double JointStoredEnergy(const JointLaw &law, double dn, double s, const JointState &state);

// The slip at the shear peak and at rupture for a normal traction sigma (Pa):
// s_peak = 2 h f_s / p; the softening span s_crit - s_peak is that of pure shear.
void JointSlipLimits(const JointLaw &law, double sigma, double *s_peak, double *s_crit);

// The opening dn0 and slip s0 >= 0 at which an intact joint carries the normal traction sigma
// (Pa, tension > 0) and the shear traction tau >= 0 on its hardening branch: where a joint
// inserted into a stressed body starts, so that it takes over the traction its face carried
// (doc/fracture.md, "Joints inserted during a run"). A traction at or beyond a peak (sigma >=
// f_t, tau >= f_s(sigma)) is taken at that peak; tau is 0 where f_s is 0.
void JointSeparationFor(const JointLaw &law, double sigma, double tau, double *dn0, double *s0);

} // namespace fdem::kernels

namespace fdem::kernels {

// One joint element: the triangle A (nodes xa[0..2], ordered so that its
// right-hand normal points out of A's tetrahedron, towards B) and the
// triangle B (nodes xb[0..2], node i of B coincident with node i of A in the
// unbroken reference). The separation xb - xa is taken at the 3 edge
// midpoints (a rule exact for quadratics) on the mid-surface (xa + xb) / 2,
// split into opening along its unit normal and slip; each point has its own
// history (state[3]) and weighs a third of the mid-surface area. Adds the
// nodal forces into fa[3][3] and fb[3][3] (fa = -fb summed: no net force) and
// returns the largest damage. A broken point (state.broken()) adds nothing.
// When dissipated is given, the energy (J) dissipated by this evaluation's growth of
// the points' damage is added to it, and, when the joint breaks through at this
// evaluation, the compression it kept (JointRemovedCompression), which goes with it.
double JointElementForces(const JointLaw &law, const double xa[3][3], const double xb[3][3], JointState state[3], double fa[3][3], double fb[3][3], double *dissipated = nullptr);
// The energy (J) the joint element stores at these positions (JointStoredEnergy
// at its three points, each weighing a third of the mid-surface area); no state change.
double JointElementEnergy(const JointLaw &law, const double xa[3][3], const double xb[3][3], const JointState state[3]);
// The compression energy (J) a joint element whose three points have all broken would still
// store at these positions if it were kept (the penalty of its broken points, by the law's
// compression rule; JointElementEnergy takes such a joint as removed and gives 0): the
// energy its removal takes out of the body (doc/fracture.md, "The handover to contact").
double JointRemovedCompression(const JointLaw &law, const double xa[3][3], const double xb[3][3]);

// Joint elements a block at a time (the deformable model's loop): up to kJointBlock joints
// with their coordinates component-major, so that the geometry, the law of the common
// point (undamaged, below both peaks) and the forces run two joints per SSE2 instruction;
// the other points go through JointTractionAt one by one. Each joint's forces and history
// are those of JointElementForces on it, which is a block of one.
inline constexpr int kJointBlock = 16;
struct JointBlock {
  int                n = 0;                 // joints in the block, <= kJointBlock
  alignas(16) double xa[9][kJointBlock];    // in: triangle A, node i component k at [3 i + k][joint]
  alignas(16) double xb[9][kJointBlock];    // in: triangle B, the same
  const JointLaw    *law[kJointBlock];      // in: each joint's law
  JointState        *state[kJointBlock];    // in/out: each joint's 3 points
  double            *dissipated[kJointBlock]; // in/out: nullptr, or where the joint's dissipated energy (J) is added
  alignas(16) double fa[9][kJointBlock];    // out: the forces on A's nodes, as xa; B's are their negatives
  double             Dmax[kJointBlock];     // out: each joint's largest damage (as JointElementForces returns)
};
void JointBlockForces(JointBlock &block);

} // namespace fdem::kernels
