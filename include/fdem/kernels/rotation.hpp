// Free (torque-free) rotation of a rigid body: the "drift" of the splitting
// schemes for rigid discrete elements.
//
// Representation (doc/book.md B): the orientation R is a Mat3 whose columns are the
// body's principal axes in inertial components, so a_inertial = R a_body and
// a_body = R^T a_inertial. I = (I1, I2, I3) are the principal moments (body
// frame, same order as the columns of R). H is the space-frame angular
// momentum; a drift holds H fixed and moves R by torque-free motion.
//
// Pure numerics, C++ standard library only. See doc/rotation.md.
#pragma once
#include <fdem/kernels/vec3.hpp>

namespace fdem::kernels {

// Rodrigues' formula (book eq 5.68): rotate the vector e by the rotation
// vector psi (axis psi/|psi|, angle |psi|). Exact for every angle; uses a
// series for the coefficients when |psi| is small (no division by |psi|).
Vec3 RotateRodrigues(const Vec3 &e, const Vec3 &psi);

// The rotation matrix exp([psi]x) of the rotation vector psi (same formula).
Mat3 RotationMatrix(const Vec3 &psi);

// rot(R, psi) of the book: every column (base vector) of R rotated by psi,
// i.e. RotationMatrix(psi) * R.
Mat3 RotateTriad(const Mat3 &R, const Vec3 &psi);

// Space-frame angular velocity omega = R I^-1 R^T H (book eqs 5.77-5.78); the
// body-frame one is transpose(R) * SpaceOmega(R, I, H).
Vec3 SpaceOmega(const Mat3 &R, const Vec3 &I, const Vec3 &H);
// The old name of SpaceOmega (it returns the space-frame omega too); kept until
// its last callers (src/contact, src/scene, src/model/rigid_output.cpp) switch.
inline Vec3 BodyOmega(const Mat3 &R, const Vec3 &I, const Vec3 &H) { return SpaceOmega(R, I, H); }

// Space-frame angular momentum H = R I R^T omega (book eqs 5.70-5.72).
Vec3 AngularMomentum(const Mat3 &R, const Vec3 &I, const Vec3 &omega);

// Rotational kinetic energy 0.5 H . omega with omega = SpaceOmega(R, I, H).
double RotationalKineticEnergy(const Mat3 &R, const Vec3 &I, const Vec3 &H);

// max_{ij} |(R^T R - Id)_{ij}|.
double OrthonormalityError(const Mat3 &R);

enum class FreeRotation {
  Munjiza,  // book 5.2.10 steps 1-7, RK4-averaged single rotation; order 2
  NoSquish, // Miller et al. 2002 symplectic splitting 3(s/2) 2(s/2) 1(s) 2(s/2) 3(s/2); order 2, reversible
  Exact     // exact torque-free motion (Jacobi elliptic functions; machine precision)
};
const char *FreeRotationName(FreeRotation kind);

// Advance R by torque-free motion over time s (s may be negative) with the
// space-frame angular momentum H held fixed. Throws InputError if a principal
// moment is not positive and finite or s/H are not finite.
Mat3 FreeRotate(FreeRotation kind, const Mat3 &R, const Vec3 &I, const Vec3 &H, double s);

// Analytic reference: body-frame angular velocity at time t of a torque-free
// body with principal moments I started at omega0_body (Euler's equations
// solved with Jacobi elliptic functions; symmetric tops and spheres in closed
// form; steady rotations and the separatrix handled). t may be negative.
void TorqueFreeOmegaBody(const Vec3 &I, const Vec3 &omega0_body, double t, Vec3 &omega_body);

// Jacobi elliptic functions sn, cn, dn of argument u and parameter m in
// [0, 1] (descending Landen / AGM; m = 1 gives tanh, sech, sech).
void JacobiSnCnDn(double u, double m, double &sn, double &cn, double &dn);
// Complete elliptic integral of the first kind K(m), m in [0, 1).
double EllipticK(double m);
// Incomplete elliptic integral of the first kind F(phi | m) for any real phi
// (Carlson's R_F with the quasi-periodicity F(phi + pi) = F(phi) + 2K).
double EllipticF(double phi, double m);

} // namespace fdem::kernels
