// Munjiza's potential contact force between two 4-node tetrahedra
// (book section 2.6, doc/book.md C), and a simple contact damping and
// friction model on top of it. Pure numerics; see doc/contact.md.
#pragma once
#include <array>

#include "fdem/kernels/vec3.hpp"

namespace fdem::kernels {

using Tet4 = std::array<Vec3, 4>;

// Potential of a tetrahedron (eq 2.36 with V_ijkl the sub-tetrahedron):
//   phi(p) = penalty * min_i lambda_i(p)   inside, 0 on the surface,
// penalty/4 at the centroid; lambda_i are the barycentric coordinates.
// The penalty is a modulus (Pa): a face pushed a depth d into a tetrahedron
// whose height over the penetrated face is H feels a pressure ~ penalty * d / H.
//
// The pair force is taken "in both directions": b's potential pushes a's
// faces that lie inside b, and a's potential pushes b's faces inside a:
//   f_a = -int_{a cap b} grad phi_b dV + int_{a cap b} grad phi_a dV,  f_b = -f_a.
struct TetPairContact {
  std::array<Vec3, 4> fa{}, fb{}; // nodal forces on a and on b
  double energy = 0;  // int_{a cap b} (phi_a + phi_b) dV; f = -grad(energy) for rigid motions
  double area = 0;    // half the total area of the clipped face polygons (~ contact area)
  double weight = 0;  // int phi dS over those polygons (= sum over both directions)
  Vec3 point{};       // phi-weighted centroid of the polygons; lies in a cap b
  bool overlap = false;
};

// Full result. Either orientation of a and b is accepted. Throws InputError
// for a degenerate (zero-volume) or non-finite tetrahedron and for a
// negative or non-finite penalty. Returns out.overlap: true when the
// tetrahedra overlap in a set of positive volume (then energy > 0).
bool PotentialContactForce(const Tet4 &a, const Tet4 &b, double penalty_a, double penalty_b, TetPairContact &out);

// A tetrahedron's barycentric coordinates as affine functions, lambda_k(p) =
// g[k].(p - o) + (k == 0), its centroid and volume: what the pair kernel needs
// of each tetrahedron. A caller evaluating many pairs builds one per
// tetrahedron (MakeTetFrame) instead of two per pair; the results are the same
// to the bit. MakeTetFrame throws InputError for a degenerate or non-finite
// tetrahedron (`name` goes into the message).
struct TetFrame {
  Vec3 o;
  Vec3 g[4];
  Vec3 centroid;
  double vol = 0; // |V|
};
void MakeTetFrame(const Tet4 &t, const char *name, TetFrame &f);
// As above, with the frames of a and b given (made by MakeTetFrame from a and b).
bool PotentialContactForce(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb, double penalty_a,
                           double penalty_b, TetPairContact &out);

// As above, with only some faces pushed: bit k of faces_a (faces_b) set when the face of a
// (b) opposite its vertex k is pushed by the other's potential (15: all, as above). Meant for
// the skin of a rigid body, whose faces shared by two of its tetrahedra feel equal and opposite
// forces at the same points in the two tetrahedra's pairs with any other tetrahedron (both
// pairs overlap wherever the shared face does): only the faces on the skin's surface need to
// be pushed, and the body's total force and torque are the same to round-off (doc/contact.md,
// "Surface faces only"). The pair's fa, fb, area, weight and point are then those of the
// pushed faces alone. `energy` is the pair's share of the total: the shared faces' terms,
// which cancel between the two pairs, are left out (their area inside the other tetrahedron,
// which the other's energy needs, is still found); the sum over all pairs of the bodies is
// the same to round-off, a single pair's value is not its overlap energy. overlap: the
// pushed faces feel a potential, or some face meets the other tetrahedron.
bool PotentialContactForce(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb, double penalty_a,
                           double penalty_b, int faces_a, int faces_b, TetPairContact &out);

// Separating axes, for a caller that evaluates the same pair at many nearby positions (the
// contact engine between two searches). SeparatingAxis returns a code for an axis along which
// the two tetrahedra are strictly apart, or 0 when it finds none (they overlap or touch): 1-4
// every vertex of b below face plane k = code - 1 of a (its barycentric coordinate lambda_k
// negative at all four, computed as PotentialContactForce computes it), 5-8 the same with a and
// b swapped, 9-44 the cross product of edge i = (code - 9) / 6 of a and edge j = (code - 9) % 6
// of b, along which the two sets of vertices are apart by more than 1e-9 to 1.42e-9 of the axis
// times the two edges' lengths (far above round-off, so that the pair kernel finds no overlap
// either).
// SeparatedAlong(code, ...) tests that one axis at the current positions: true only when the
// pair is apart along it, and then PotentialContactForce returns false with zero forces; false
// says nothing. fa, fb: the frames of a and b (MakeTetFrame).
int SeparatingAxis(const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb);
bool SeparatedAlong(int code, const Tet4 &a, const TetFrame &fa, const Tet4 &b, const TetFrame &fb);

// Nodal forces only (overwritten, not accumulated).
bool PotentialContactForce(const Tet4 &a, const Tet4 &b, double penalty_a, double penalty_b, std::array<Vec3, 4> &fa,
                           std::array<Vec3, 4> &fb);

// Dissipative contact parameters (doc/contact.md).
struct ContactDissipation {
  double normal_damping = 0;       // c_n, Pa s/m: damping pressure per unit normal approach speed
  double friction = 0;             // Coulomb coefficient mu
  double tangential_viscosity = 0; // c_t, Pa s/m: regularises stick (viscous below the Coulomb limit)
};

// Damping and friction forces of a pair whose potential contact force is
// `contact` (from PotentialContactForce at the same positions); va, vb are
// nodal velocities. With n the direction of the potential force on a,
// A = contact.area, x_c = contact.point, v = v_a(x_c) - v_b(x_c) (linear
// interpolation in each tetrahedron), v_n = v.n, v_t = v - v_n n:
//   F_n = max(-c_n A v_n, -|F_pot|)            (never turns the contact adhesive)
//   F_t = -min(mu (|F_pot| + F_n), c_t A |v_t|) v_t/|v_t|
// and F = F_n n + F_t acts on a at x_c, -F on b at x_c, spread by each
// tetrahedron's linear shape functions. Overwrites fa, fb (zero when there is
// no contact or no defined normal). Throws InputError on negative parameters.
void ContactDampingFriction(const Tet4 &a, const Tet4 &b, const std::array<Vec3, 4> &va,
                            const std::array<Vec3, 4> &vb, const TetPairContact &contact,
                            const ContactDissipation &param, std::array<Vec3, 4> &fa, std::array<Vec3, 4> &fb);
// As above, with the frames of a and b given.
void ContactDampingFriction(const TetFrame &ta, const TetFrame &tb, const std::array<Vec3, 4> &va,
                            const std::array<Vec3, 4> &vb, const TetPairContact &contact,
                            const ContactDissipation &param, std::array<Vec3, 4> &fa, std::array<Vec3, 4> &fb);

} // namespace fdem::kernels
