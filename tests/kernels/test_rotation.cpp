// Tests of the free-rotation kernels (include/fdem/kernels/rotation.hpp).
#include <fdem/kernels/error.hpp>
#include <fdem/kernels/rotation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

using namespace fdem::kernels;

namespace {

constexpr double kPi = 3.14159265358979323846;
const FreeRotation kAll[] = {FreeRotation::Munjiza, FreeRotation::NoSquish, FreeRotation::Exact};

Vec3 Had(const Vec3 &a, const Vec3 &b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
double MaxAbs(const Vec3 &a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }
double MaxAbs(const Mat3 &A) {
  double e = 0;
  for (auto &r : A.m)
    for (double v : r) e = std::max(e, std::fabs(v));
  return e;
}
Vec3 OmegaBodyOf(const Mat3 &R, const Vec3 &I, const Vec3 &H) { return transpose(R) * SpaceOmega(R, I, H); }
// A fixed, non-trivial initial orientation.
Mat3 SomeRotation() { return RotationMatrix({0.3, -1.1, 0.7}); }
double Order(double e_coarse, double e_fine, double ratio) { return std::log(e_coarse / e_fine) / std::log(ratio); }

// Run n drifts of length h from (R0, H) and return the maximum over the step
// points of |omega_body - exact(t)| (max norm).
double MaxBodyOmegaError(FreeRotation kind, const Vec3 &I, const Vec3 &w0, double h, double T,
                         const std::function<Vec3(double)> &exact) {
  Mat3 R = SomeRotation();
  const Vec3 H = R * Had(I, w0);
  const int n = static_cast<int>(std::lround(T / h));
  double err = 0;
  for (int i = 1; i <= n; ++i) {
    R = FreeRotate(kind, R, I, H, h);
    err = std::max(err, MaxAbs(OmegaBodyOf(R, I, H) - exact(i * h)));
  }
  return err;
}

// Classical RK4 on Euler's equations (independent check of the analytic reference).
Vec3 EulerRhs(const Vec3 &I, const Vec3 &w) {
  return {(I.y - I.z) / I.x * w.y * w.z, (I.z - I.x) / I.y * w.z * w.x, (I.x - I.y) / I.z * w.x * w.y};
}
Vec3 Rk4Euler(const Vec3 &I, Vec3 w, double T, int n) {
  const double h = T / n;
  for (int i = 0; i < n; ++i) {
    const Vec3 k1 = EulerRhs(I, w), k2 = EulerRhs(I, w + 0.5 * h * k1), k3 = EulerRhs(I, w + 0.5 * h * k2),
               k4 = EulerRhs(I, w + h * k3);
    w += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return w;
}

} // namespace

// ---------------------------------------------------------------- building blocks
TEST(Rotation, RodriguesKnownRotationsAndSmallAngle) {
  // Quarter turn about z maps x to y; half turn about (1,1,0)/sqrt2 maps x to y.
  EXPECT_LT(MaxAbs(RotateRodrigues({1, 0, 0}, {0, 0, kPi / 2}) - Vec3{0, 1, 0}), 1e-15);
  const double c = kPi / std::sqrt(2.0);
  EXPECT_LT(MaxAbs(RotateRodrigues({1, 0, 0}, {c, c, 0}) - Vec3{0, 1, 0}), 1e-15);
  // A vector along the axis is unchanged; the zero rotation is the identity.
  EXPECT_LT(MaxAbs(RotateRodrigues({0.2, 0.4, -0.1}, {0.2, 0.4, -0.1}) - Vec3{0.2, 0.4, -0.1}), 1e-16);
  EXPECT_LT(MaxAbs(RotateRodrigues({0.2, 0.4, -0.1}, {0, 0, 0}) - Vec3{0.2, 0.4, -0.1}), 1e-17);
  // Small angles agree with the first-order rotation e + psi x e to O(psi^2).
  const Vec3 e{0.3, -0.5, 0.8}, axis{0.6, 0.0, -0.8};
  for (double a : {1e-3, 1e-5, 1e-7, 1e-9}) {
    const Vec3 psi = a * axis;
    const Vec3 lin = e + cross(psi, e);
    EXPECT_LT(MaxAbs(RotateRodrigues(e, psi) - lin), 2.0 * a * a) << a;
    EXPECT_NEAR(norm(RotateRodrigues(e, psi)), norm(e), 1e-15);
  }
  // Continuity across the series switch (|psi| = 1e-4).
  const Vec3 below = RotateRodrigues(e, 0.99999999e-4 * axis), above = RotateRodrigues(e, 1.00000001e-4 * axis);
  EXPECT_LT(MaxAbs(below - above), 1e-11);
  // RotateTriad rotates every column; RotationMatrix is orthonormal with det 1.
  const Mat3 R = SomeRotation();
  EXPECT_LT(OrthonormalityError(R), 1e-15);
  EXPECT_NEAR(det(R), 1.0, 1e-15);
  const Mat3 R2 = RotateTriad(R, {0.1, 0.2, 0.3});
  EXPECT_LT(MaxAbs(R2 - RotationMatrix({0.1, 0.2, 0.3}) * R), 1e-15);
  EXPECT_LT(MaxAbs(R2.col(1) - RotateRodrigues(R.col(1), {0.1, 0.2, 0.3})), 1e-16);
}

TEST(Rotation, SpaceOmegaAndMomentum) {
  const Mat3 R = SomeRotation();
  const Vec3 I{1, 2, 3}, wb{0.4, -0.2, 0.9};
  const Vec3 w = R * wb;
  const Vec3 H = AngularMomentum(R, I, w);
  EXPECT_LT(MaxAbs(H - R * Vec3{0.4, -0.4, 2.7}), 1e-15);
  EXPECT_LT(MaxAbs(SpaceOmega(R, I, H) - w), 1e-15);
  EXPECT_NEAR(RotationalKineticEnergy(R, I, H), 0.5 * (0.16 + 2 * 0.04 + 3 * 0.81), 1e-15);
}

TEST(Rotation, JacobiEllipticFunctions) {
  // Limits.
  double sn, cn, dn;
  JacobiSnCnDn(0.7, 0.0, sn, cn, dn);
  EXPECT_NEAR(sn, std::sin(0.7), 1e-16);
  EXPECT_NEAR(dn, 1.0, 0);
  JacobiSnCnDn(0.7, 1.0, sn, cn, dn);
  EXPECT_NEAR(sn, std::tanh(0.7), 3e-16);
  EXPECT_NEAR(cn, 1.0 / std::cosh(0.7), 3e-16);
  EXPECT_NEAR(EllipticK(0.0), kPi / 2, 1e-15);
  // K(1/2) = Gamma(1/4)^2 / (4 sqrt(pi)).
  EXPECT_NEAR(EllipticK(0.5), std::pow(std::tgamma(0.25), 2) / (4 * std::sqrt(kPi)), 1e-14);
  for (double m : {1e-12, 0.1, 0.5, 0.9, 0.999999, 1 - 1e-12}) {
    const double K = EllipticK(m);
    JacobiSnCnDn(K, m, sn, cn, dn);
    EXPECT_NEAR(sn, 1.0, 1e-13) << m;
    EXPECT_NEAR(dn, std::sqrt(1 - m), 1e-7 * std::sqrt(1 - m) + 1e-15) << m;
    for (double u : {-7.3, -0.4, 0.0, 0.25, 1.9, 11.0}) {
      JacobiSnCnDn(u, m, sn, cn, dn);
      EXPECT_NEAR(sn * sn + cn * cn, 1.0, 1e-15);
      EXPECT_NEAR(dn * dn + m * sn * sn, 1.0, 1e-15);
      // d sn/du = cn dn by a 4th-order central difference.
      const double e = 1e-3;
      double s1, s2, s3, s4, c_, d_;
      JacobiSnCnDn(u - 2 * e, m, s1, c_, d_);
      JacobiSnCnDn(u - e, m, s2, c_, d_);
      JacobiSnCnDn(u + e, m, s3, c_, d_);
      JacobiSnCnDn(u + 2 * e, m, s4, c_, d_);
      EXPECT_NEAR((s1 - 8 * s2 + 8 * s3 - s4) / (12 * e), cn * dn, 1e-9) << m << " " << u;
      // F inverts the amplitude: sn(F(phi)) = sin(phi) for any phi.
      const double phi = 0.37 * u;
      JacobiSnCnDn(EllipticF(phi, m), m, sn, cn, dn);
      if (m < 0.99) {
        EXPECT_NEAR(sn, std::sin(phi), 1e-13) << m << " " << phi;
        EXPECT_NEAR(cn, std::cos(phi), 1e-13) << m << " " << phi;
      }
    }
  }
  EXPECT_THROW(JacobiSnCnDn(1.0, 1.5, sn, cn, dn), InputError);
}

// The analytic reference against a fine RK4 integration of Euler's equations,
// for both branches, all orderings of the moments (even and odd relabelings)
// and mixed signs; plus symmetric tops and a sphere.
TEST(Rotation, TorqueFreeReferenceMatchesEulerEquations) {
  const std::vector<Vec3> inertias = {{1, 2, 3}, {3, 1, 2}, {2, 3, 1}, {1, 3, 2}, {3, 2, 1}, {2, 1, 3},
                                      {1, 1, 2}, {2, 1, 2}, {0.5, 3, 3}, {2, 2, 2},  {1, 1.5, 4}};
  const std::vector<Vec3> starts = {{1, 0.5, 0.3}, {0.1, -0.2, 2.0}, {-1.5, 0.3, -0.2}, {0.01, 1.0, 0.02},
                                    {0.3, 0.3, -0.3}, {0, 0, 1.2}, {0, 0.7, 0}};
  double worst = 0;
  for (const Vec3 &I : inertias)
    for (const Vec3 &w0 : starts)
      for (double T : {0.7, -2.3, 6.0}) {
        Vec3 w;
        TorqueFreeOmegaBody(I, w0, T, w);
        const Vec3 ref = Rk4Euler(I, w0, T, 20000);
        const double e = MaxAbs(w - ref) / std::max(1.0, MaxAbs(w0));
        worst = std::max(worst, e);
        EXPECT_LT(e, 1e-9) << "I=" << I.x << "," << I.y << "," << I.z << " w0=" << w0.x << "," << w0.y << ","
                           << w0.z << " T=" << T;
      }
  std::printf("[reference] worst |analytic - RK4(h<=3e-4)| = %.2e\n", worst);
}

// ---------------------------------------------------------------- (a) the book's axisymmetric example
TEST(Rotation, BookAxisymmetricExample) {
  const Vec3 I{1, 1, 2}, w0{0, 1, 100};
  auto exact = [](double t) { return Vec3{-std::sin(100 * t), std::cos(100 * t), 100.0}; };
  const double hs[] = {0.005, 0.001, 0.0005, 0.00025, 0.000125};
  for (FreeRotation k : kAll) {
    double e[5];
    for (int i = 0; i < 5; ++i) e[i] = MaxBodyOmegaError(k, I, w0, hs[i], 0.25, exact);
    std::printf("[book example] %-8s max|w_body - exact| on [0,0.25]: h=5e-3 %.3e  1e-3 %.3e  5e-4 %.3e  2.5e-4 %.3e  "
                "1.25e-4 %.3e ; orders %.3f %.3f %.3f\n",
                FreeRotationName(k), e[0], e[1], e[2], e[3], e[4], Order(e[1], e[2], 2), Order(e[2], e[3], 2),
                Order(e[3], e[4], 2));
    if (k == FreeRotation::Exact) {
      // Machine precision: |omega| = 100, so 1e-11 is a relative error of 1e-13.
      for (double v : e) EXPECT_LT(v, 1e-11);
    } else {
      for (int i = 2; i < 4; ++i) {
        EXPECT_NEAR(Order(e[i], e[i + 1], 2), 2.0, 0.1) << FreeRotationName(k);
      }
      EXPECT_NEAR(Order(e[1], e[2], 2), 2.0, 0.15) << FreeRotationName(k);
    }
    if (k == FreeRotation::Munjiza) {
      // doc/book.md B: ~1.0e-2 at h = 5e-4 (0.0103 -> 0.00258 -> 0.00065 on halving).
      EXPECT_NEAR(e[2], 1.03e-2, 0.1e-2);
      EXPECT_NEAR(e[3], 2.58e-3, 0.1e-3);
      EXPECT_NEAR(e[4], 6.5e-4, 0.1e-4 * 3);
      // Fig 5.9: h = 5e-3 lags visibly (order-one error).
      EXPECT_GT(e[0], 0.3);
    }
  }
}

// ---------------------------------------------------------------- (b) asymmetric top
TEST(Rotation, AsymmetricTopOrders) {
  const Vec3 I{1, 2, 3};
  for (const Vec3 w0 : {Vec3{1.0, 0.5, 0.3}, Vec3{0.2, -0.4, 1.5}}) { // near axis 1 / near axis 3
    auto exact = [&](double t) {
      Vec3 w;
      TorqueFreeOmegaBody(I, w0, t, w);
      return w;
    };
    const double hs[] = {0.04, 0.02, 0.01, 0.005};
    for (FreeRotation k : kAll) {
      double e[4];
      for (int i = 0; i < 4; ++i) e[i] = MaxBodyOmegaError(k, I, w0, hs[i], 8.0, exact);
      std::printf("[asymmetric I=(1,2,3) w0=(%g,%g,%g)] %-8s err h=.04 %.3e .02 %.3e .01 %.3e .005 %.3e ; orders %.3f "
                  "%.3f %.3f\n",
                  w0.x, w0.y, w0.z, FreeRotationName(k), e[0], e[1], e[2], e[3], Order(e[0], e[1], 2),
                  Order(e[1], e[2], 2), Order(e[2], e[3], 2));
      if (k == FreeRotation::Exact) {
        for (double v : e) EXPECT_LT(v, 1e-12);
      } else {
        EXPECT_NEAR(Order(e[1], e[2], 2), 2.0, 0.1);
        EXPECT_NEAR(Order(e[2], e[3], 2), 2.0, 0.1);
      }
    }
  }
}

// Tennis-racket (Dzhanibekov) flip: start near the intermediate axis; omega_2
// changes sign every half period 2K(m)/lambda. K, m and lambda are computed
// here from Landau-Lifshitz's formulas and a Simpson quadrature, independently
// of the library's elliptic code.
TEST(Rotation, IntermediateAxisFlip) {
  const Vec3 I{1, 2, 3}, w0{1e-3, 1.0, 2e-3};
  const double L2 = I.x * I.x * w0.x * w0.x + I.y * I.y * w0.y * w0.y + I.z * I.z * w0.z * w0.z;
  const double E2 = I.x * w0.x * w0.x + I.y * w0.y * w0.y + I.z * w0.z * w0.z;
  ASSERT_GT(L2, E2 * I.y); // this start circles axis 3
  const double lam = std::sqrt((I.z - I.y) * (L2 - E2 * I.x) / (I.x * I.y * I.z));
  const double m = (I.y - I.x) * (E2 * I.z - L2) / ((I.z - I.y) * (L2 - E2 * I.x));
  // K(m) = int_0^{pi/2} dth / sqrt(1 - m sin^2 th) by composite Simpson with
  // 4e5 intervals (the integrand peaks at 1/sqrt(1-m) ~ 300 over a width
  // ~sqrt(1-m) ~ 3e-3, resolved by ~1000 intervals).
  const int N = 400000;
  double K = 0;
  for (int i = 0; i <= N; ++i) {
    const double th = 0.5 * kPi * i / N;
    const double f = 1.0 / std::sqrt(1.0 - m * std::sin(th) * std::sin(th));
    K += (i == 0 || i == N ? 1 : (i % 2 ? 4 : 2)) * f;
  }
  K *= 0.5 * kPi / N / 3.0;
  const double Thalf = 2 * K / lam;
  std::printf("[flip] m = 1 - %.3e, half period 2K/lambda = %.6f\n", 1 - m, Thalf);

  struct Run { FreeRotation k; double h, tol; };
  for (const Run run : {Run{FreeRotation::Exact, 0.01, 1e-8}, Run{FreeRotation::NoSquish, 0.001, 2e-7},
                        Run{FreeRotation::Munjiza, 0.001, 2e-6}}) {
    Mat3 R = SomeRotation();
    const Vec3 H = R * Had(I, w0);
    std::vector<double> flips;
    double prev = w0.y;
    const int n = static_cast<int>(std::lround(3.2 * Thalf / run.h));
    for (int i = 1; i <= n; ++i) {
      R = FreeRotate(run.k, R, I, H, run.h);
      const double cur = OmegaBodyOf(R, I, H).y;
      if ((cur > 0) != (prev > 0)) flips.push_back((i - 1) * run.h + run.h * prev / (prev - cur));
      prev = cur;
    }
    ASSERT_EQ(flips.size(), 3u) << FreeRotationName(run.k);
    // The first zero of sn(lambda t + tau0) is at (2K - tau0)/lambda; compare spacings.
    for (int i = 0; i + 1 < 3; ++i) {
      const double spacing = flips[i + 1] - flips[i];
      std::printf("[flip] %-8s h=%g flip spacing %.6f (rel. err %.2e)\n", FreeRotationName(run.k), run.h, spacing,
                  std::fabs(spacing - Thalf) / Thalf);
      EXPECT_NEAR(spacing, Thalf, run.tol * Thalf) << FreeRotationName(run.k);
    }
    // And the flip times themselves against the library's reference solution.
    for (double tf : flips) {
      Vec3 w;
      TorqueFreeOmegaBody(I, w0, tf, w);
      EXPECT_LT(std::fabs(w.y), std::max(1e-6, run.tol * 1e3)) << FreeRotationName(run.k) << " t=" << tf;
    }
  }
}

// ---------------------------------------------------------------- (c) conservation over 1e5 steps
// h = 0.05 (about 130 steps per period of the motion), 1e5 steps. Energy:
// Exact conserves it to rounding; NoSquish (symplectic) has a bounded O(h^2)
// oscillation, so the maximum over 1e5 steps equals the maximum over the first
// 1e4; Munjiza's update is neither symplectic nor symmetric and drifts
// secularly (linearly in time, ~h^3 per unit time), so the maximum grows ~10x.
TEST(Rotation, LongRunEnergyAndOrthonormality) {
  const Vec3 I{1, 2, 3}, w0{1.0, 0.5, 0.3};
  const double h = 0.05;
  const int n = 100000;
  for (FreeRotation k : kAll) {
    Mat3 R = SomeRotation();
    const Vec3 H = R * Had(I, w0);
    const double E0 = RotationalKineticEnergy(R, I, H);
    double drift = 0, drift1e4 = 0, orth = 0;
    for (int i = 1; i <= n; ++i) {
      R = FreeRotate(k, R, I, H, h);
      drift = std::max(drift, std::fabs(RotationalKineticEnergy(R, I, H) - E0) / E0);
      if (i == 10000) drift1e4 = drift;
      if (i % 97 == 0) orth = std::max(orth, OrthonormalityError(R));
    }
    orth = std::max(orth, OrthonormalityError(R));
    const double Lerr = std::fabs(norm(transpose(R) * H) - norm(H)) / norm(H);
    std::printf("[long run h=0.05] %-8s max rel. energy error: 1e4 steps %.3e, 1e5 steps %.3e; "
                "max |R^T R - I| %.2e; | |R^T H| - |H| |/|H| %.1e\n",
                FreeRotationName(k), drift1e4, drift, orth, Lerr);
    EXPECT_LT(orth, 1e-13) << FreeRotationName(k);
    EXPECT_LT(Lerr, 1e-13) << FreeRotationName(k);
    if (k == FreeRotation::Exact) EXPECT_LT(drift, 1e-12);
    if (k == FreeRotation::NoSquish) {
      EXPECT_LT(drift, 3e-4);
      EXPECT_LT(drift, 1.05 * drift1e4); // bounded, no secular drift
    }
    if (k == FreeRotation::Munjiza) {
      EXPECT_LT(drift, 5e-3);
      EXPECT_GT(drift, 5.0 * drift1e4); // secular drift
    }
  }
}

// ---------------------------------------------------------------- (d) time reversibility
TEST(Rotation, TimeReversibility) {
  const Vec3 I{1, 2, 3}, w0{0.2, -0.4, 1.5};
  const double h = 0.05;
  for (FreeRotation k : kAll) {
    const Mat3 R0 = SomeRotation();
    const Vec3 H = R0 * Had(I, w0);
    Mat3 R = R0;
    for (int i = 0; i < 1000; ++i) R = FreeRotate(k, R, I, H, h);
    const double away = MaxAbs(R - R0);
    for (int i = 0; i < 1000; ++i) R = FreeRotate(k, R, I, H, -h);
    const double back = MaxAbs(R - R0);
    // One step forward and back.
    const Mat3 R1 = FreeRotate(k, FreeRotate(k, R0, I, H, h), I, H, -h);
    std::printf("[reversibility h=0.05] %-8s |R(after 1000 fwd) - R0| %.2e, after 1000 back %.2e; one step %.2e\n",
                FreeRotationName(k), away, back, MaxAbs(R1 - R0));
    EXPECT_GT(away, 0.1);
    if (k == FreeRotation::Munjiza) {
      EXPECT_GT(MaxAbs(R1 - R0), 1e-8); // not reversible: O(h^3) defect per step
    } else {
      EXPECT_LT(back, 1e-11) << FreeRotationName(k);
      EXPECT_LT(MaxAbs(R1 - R0), 1e-14) << FreeRotationName(k);
    }
  }
  // Exact is a flow: drifts compose, Phi(s1) Phi(s2) = Phi(s1 + s2).
  const Mat3 R0 = SomeRotation();
  const Vec3 H = R0 * Had(I, w0);
  const Mat3 Ra = FreeRotate(FreeRotation::Exact, FreeRotate(FreeRotation::Exact, R0, I, H, 0.3), I, H, 2.9);
  const Mat3 Rb = FreeRotate(FreeRotation::Exact, R0, I, H, 3.2);
  EXPECT_LT(MaxAbs(Ra - Rb), 1e-13);
}

// ---------------------------------------------------------------- torque impulse (Strang kick-drift-kick)
TEST(Rotation, ConstantTorqueSpinUp) {
  for (FreeRotation k : kAll) {
    // (1) Asymmetric body spinning about its principal axis 3, torque along that axis.
    {
      const Vec3 I{1, 2, 3};
      const Mat3 R0 = SomeRotation();
      const Vec3 axis = R0.col(2);
      const double w0 = 5.0, Mz = 3.0, h = 0.01;
      Vec3 H = (I.z * w0) * axis;
      const Vec3 M = Mz * axis;
      Mat3 R = R0;
      double err = 0, errR = 0;
      for (int i = 1; i <= 100; ++i) {
        H += (0.5 * h) * M;
        R = FreeRotate(k, R, I, H, h);
        H += (0.5 * h) * M;
        const double t = i * h;
        err = std::max(err, MaxAbs(OmegaBodyOf(R, I, H) - Vec3{0, 0, w0 + Mz * t / I.z}));
        const Mat3 Rex = RotationMatrix((w0 * t + 0.5 * Mz * t * t / I.z) * axis) * R0;
        errR = std::max(errR, MaxAbs(R - Rex));
      }
      std::printf("[spin-up axis 3] %-8s max |w - (w0 + M t/I3)| %.2e, max |R - R_exact| %.2e\n",
                  FreeRotationName(k), err, errR);
      EXPECT_LT(err, 1e-12);
      EXPECT_LT(errR, 1e-12);
    }
    // (2) A sphere with off-axis spin and a general torque: omega(t) = omega0 + M t / I.
    {
      const Vec3 I{2, 2, 2};
      const Vec3 w0{1, -2, 0.5}, M{0.3, 0.1, -0.7};
      Mat3 R = SomeRotation();
      Vec3 H = 2.0 * w0;
      const double h = 0.02;
      double err = 0;
      for (int i = 1; i <= 100; ++i) {
        H += (0.5 * h) * M;
        R = FreeRotate(k, R, I, H, h);
        H += (0.5 * h) * M;
        err = std::max(err, MaxAbs(SpaceOmega(R, I, H) - (w0 + (i * h / 2.0) * M)));
      }
      EXPECT_LT(err, 1e-13) << FreeRotationName(k);
    }
  }
}

TEST(Rotation, SphereAndSymmetricTopExact) {
  // Sphere: rotation about the fixed omega = H/I.
  const Vec3 I{2, 2, 2}, H{0.4, -1.0, 0.6};
  const Mat3 R0 = SomeRotation();
  for (FreeRotation k : kAll) {
    const Mat3 R = FreeRotate(k, R0, I, H, 0.8);
    const double e = MaxAbs(R - RotationMatrix((0.8 / 2.0) * H) * R0);
    if (k == FreeRotation::NoSquish) {
      // The body-axis splitting is not exact for a sphere (the flows of
      // L1^2, L2^2, L3^2 do not commute): O(s^3) per step.
      std::printf("[sphere, one step s=0.8] nosquish error %.2e\n", e);
      EXPECT_GT(e, 1e-6);
      // Third order per step: 8x shorter step, ~512x smaller error.
      EXPECT_LT(MaxAbs(FreeRotate(k, R0, I, H, 0.1) - RotationMatrix(0.05 * H) * R0), e / 300);
    } else {
      EXPECT_LT(e, 1e-14) << FreeRotationName(k);
    }
  }
  // Symmetric top with long steps: Exact equals the reference at any step length.
  const Vec3 Is{1.5, 0.7, 1.5}, w0{0.3, 2.0, -0.8};
  const Vec3 Hs = R0 * Had(Is, w0);
  Mat3 R = R0;
  for (int i = 1; i <= 10; ++i) {
    R = FreeRotate(FreeRotation::Exact, R, Is, Hs, 0.9);
    Vec3 w;
    TorqueFreeOmegaBody(Is, w0, 0.9 * i, w);
    EXPECT_LT(MaxAbs(OmegaBodyOf(R, Is, Hs) - w), 1e-13);
  }
  // Asymmetric top with long steps (several periods per step).
  const Vec3 Ia{1, 2, 3}, wa{1.0, 0.5, 0.3};
  const Vec3 Ha = R0 * Had(Ia, wa);
  Mat3 Rs = R0, Rl = FreeRotate(FreeRotation::Exact, R0, Ia, Ha, 40.0);
  for (int i = 0; i < 4000; ++i) Rs = FreeRotate(FreeRotation::Exact, Rs, Ia, Ha, 0.01);
  EXPECT_LT(MaxAbs(Rs - Rl), 1e-11);
}

TEST(Rotation, BadInput) {
  const Mat3 R = Mat3::identity();
  EXPECT_THROW(FreeRotate(FreeRotation::Exact, R, {1, -2, 3}, {1, 0, 0}, 0.1), InputError);
  EXPECT_THROW(FreeRotate(FreeRotation::NoSquish, R, {1, 0, 3}, {1, 0, 0}, 0.1), InputError);
  EXPECT_THROW(FreeRotate(FreeRotation::Munjiza, R, {1, 2, 3}, {1, 0, 0}, NAN), InputError);
  try {
    FreeRotate(FreeRotation::Munjiza, R, {1, 2, -3}, {1, 0, 0}, 0.1);
  } catch (const InputError &e) {
    EXPECT_NE(std::string(e.what()).find("I3"), std::string::npos);
  }
}

// Exact drift for every ordering of the moments, both branches, near-symmetric
// and near-spherical bodies, starts near each axis: body-frame omega follows
// the reference, and the drift is a flow (one long step = many short ones).
TEST(Rotation, ExactRobustAcrossCases) {
  const std::vector<Vec3> inertias = {{1, 2, 3},        {3, 1, 2},         {2, 3, 1},  {1, 3, 2},
                                      {3, 2, 1},        {1, 1 + 1e-9, 2},  {2, 1, 1 + 1e-7},
                                      {1, 1 + 1e-6, 1 + 2e-6}, {0.2, 5, 5.1}};
  const std::vector<Vec3> starts = {{1, 0.5, 0.3}, {0.1, -0.2, 2.0}, {-1.5, 0.3, -0.2}, {1e-4, 1.0, -1e-4},
                                    {2.0, 1e-9, 0}, {0, 0, -3}};
  const Mat3 R0 = SomeRotation();
  double worst = 0, worstFlow = 0, worstOrth = 0;
  for (const Vec3 &I : inertias)
    for (const Vec3 &w0 : starts) {
      const Vec3 H = R0 * Had(I, w0);
      Mat3 R = R0;
      for (int i = 1; i <= 50; ++i) {
        R = FreeRotate(FreeRotation::Exact, R, I, H, 0.07);
        Vec3 w;
        TorqueFreeOmegaBody(I, w0, 0.07 * i, w);
        worst = std::max(worst, MaxAbs(OmegaBodyOf(R, I, H) - w) / MaxAbs(w0));
      }
      const Mat3 Rl = FreeRotate(FreeRotation::Exact, R0, I, H, 3.5);
      worstFlow = std::max(worstFlow, MaxAbs(R - Rl));
      worstOrth = std::max(worstOrth, OrthonormalityError(R));
      EXPECT_LT(MaxAbs(R - Rl), 1e-11) << I.x << "," << I.y << "," << I.z << " w0 " << w0.x << "," << w0.y << "," << w0.z;
    }
  std::printf("[exact, 54 cases] worst rel. omega error %.2e, worst |50 steps - 1 step| %.2e, orth %.1e\n", worst,
              worstFlow, worstOrth);
  EXPECT_LT(worst, 1e-11);
  EXPECT_LT(worstOrth, 1e-14);
}

// Steps short against the wobble (|Lam h| <= 0.01) take the exact rotation's short-step path (sn,
// cn, dn at the nodes by the addition theorem and series); 500 of them must land where one long
// step (the Landen recursion at every node) and the analytic angular velocity do.
TEST(Rotation, ExactShortStepsMatchOneLongStep) {
  const std::vector<Vec3> inertias = {{1, 2, 3}, {3, 1, 2}, {0.2, 5, 5.1}, {1, 1.3, 1.4}, {2, 1, 1 + 1e-7}};
  const std::vector<Vec3> starts   = {{1, 0.5, 0.3}, {0.1, -0.2, 2.0}, {-1.5, 0.3, -0.2}, {1e-4, 1.0, -1e-4}};
  const Mat3 R0 = SomeRotation();
  double worst = 0, worstFlow = 0;
  for (const Vec3 &I : inertias)
    for (const Vec3 &w0 : starts) {
      const Vec3 H = R0 * Had(I, w0);
      const double h = 0.002, T = 1.0;
      Mat3 R = R0;
      for (int i = 1; i <= 500; ++i) {
        R = FreeRotate(FreeRotation::Exact, R, I, H, h);
        if (i % 50) continue;
        Vec3 w;
        TorqueFreeOmegaBody(I, w0, h * i, w);
        worst = std::max(worst, MaxAbs(OmegaBodyOf(R, I, H) - w) / MaxAbs(w0));
      }
      const Mat3 Rl = FreeRotate(FreeRotation::Exact, R0, I, H, T);
      worstFlow = std::max(worstFlow, MaxAbs(R - Rl));
      EXPECT_LT(MaxAbs(R - Rl), 1e-11) << I.x << "," << I.y << "," << I.z << " w0 " << w0.x << "," << w0.y << "," << w0.z;
    }
  std::printf("[exact, short steps] worst rel. omega error %.2e, worst |500 steps - 1 step| %.2e\n", worst, worstFlow);
  EXPECT_LT(worst, 1e-11);
}
