// The granular law of kernels/granular.hpp for many touching sphere-sphere contacts at
// once (doc/spheres.md, "The race at the level of the driver"): the contacts' data in arrays, one array per quantity,
// so that the compiler runs several contacts per vector instruction (two with SSE2, four
// with AVX2 on a processor that has it, chosen when the program starts). The same
// arithmetic as GranularForce, in another order: the results agree to round-off
// (test_granular_batch). Pure functions on doubles; no PETSc, no MPI.
#pragma once
#include "fdem/kernels/granular.hpp"

#include <vector>

namespace fdem::kernels {

// The arrays of n contacts between spheres a and b; entry i of each belongs to contact i.
class GranularBatch {
public:
  enum Field {
    // inputs
    DX, DY, DZ,       // centre of a minus centre of b (m); must not be zero
    RA, RB,           // radii (m)
    VX, VY, VZ,       // velocity of a minus velocity of b (m/s)
    WAX, WAY, WAZ,    // angular velocity of a (rad/s)
    WBX, WBY, WBZ,    // angular velocity of b (rad/s)
    MSTAR,            // effective mass (kg)
    CN,               // Hooke: the normal damping coefficient m* gamma_n (N s/m); unused by Hertz
    SX, SY, SZ,       // the tangential spring (m): in, then advanced (out)
    // outputs
    FX, FY, FZ,       // force on a (N); b gets minus it
    TAX, TAY, TAZ,    // torque on a (N m)
    TBX, TBY, TBZ,    // torque on b (N m)
    ENERGY,           // elastic energy of the contact, normal and tangential (J)
    OVERLAP,          // r_a + r_b - |d| (m)
    kFields
  };
  // Room for n contacts (the arrays' contents are then undefined).
  void Resize(int n);
  int  Size() const { return n_; }
  double       *operator[](Field f) { return data_.data() + (size_t)f * cap_; }
  const double *operator[](Field f) const { return data_.data() + (size_t)f * cap_; }

private:
  int                 n_ = 0, cap_ = 0;
  std::vector<double> data_;
};

// The forces of contacts [begin, end) of the batch, all of one pair law p, for a step dt:
// what GranularForce gives for each, with the torques on both spheres and the elastic energy.
void GranularBatchForces(const GranularPair &p, double dt, GranularBatch &b, int begin, int end);

} // namespace fdem::kernels
