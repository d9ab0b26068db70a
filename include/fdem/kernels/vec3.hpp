// Small fixed-size vector and matrix types shared by the kernels.
// Plain value types on doubles; no PETSc, no MPI.
#pragma once
#include <array>
#include <cmath>

namespace fdem::kernels {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  constexpr Vec3() = default;
  constexpr Vec3(double a, double b, double c) : x(a), y(b), z(c) {}
  constexpr double &operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 &operator+=(const Vec3 &o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3 &operator-=(const Vec3 &o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3 &operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
};
constexpr Vec3 operator+(Vec3 a, const Vec3 &b) { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3 &b) { return a -= b; }
constexpr Vec3 operator-(const Vec3 &a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(double s, Vec3 a) { return a *= s; }
constexpr Vec3 operator*(Vec3 a, double s) { return a *= s; }
constexpr Vec3 operator/(Vec3 a, double s) { return a *= (1.0 / s); }
constexpr double dot(const Vec3 &a, const Vec3 &b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3 &a, const Vec3 &b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3 &a) { return std::sqrt(dot(a, a)); }

// Row-major 3x3 matrix: m[r][c].
struct Mat3 {
  std::array<std::array<double, 3>, 3> m{};
  static constexpr Mat3 identity() {
    Mat3 I;
    I.m[0][0] = I.m[1][1] = I.m[2][2] = 1.0;
    return I;
  }
  static constexpr Mat3 diag(double a, double b, double c) {
    Mat3 D;
    D.m[0][0] = a; D.m[1][1] = b; D.m[2][2] = c;
    return D;
  }
  // Matrix whose columns are a, b, c.
  static constexpr Mat3 columns(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    Mat3 M;
    for (int r = 0; r < 3; ++r) { M.m[r][0] = a[r]; M.m[r][1] = b[r]; M.m[r][2] = c[r]; }
    return M;
  }
  constexpr double &operator()(int r, int c) { return m[r][c]; }
  constexpr double operator()(int r, int c) const { return m[r][c]; }
  constexpr Vec3 col(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
  constexpr Vec3 row(int r) const { return {m[r][0], m[r][1], m[r][2]}; }
};
constexpr Mat3 transpose(const Mat3 &A) {
  Mat3 T;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) T.m[r][c] = A.m[c][r];
  return T;
}
constexpr Mat3 operator*(const Mat3 &A, const Mat3 &B) {
  Mat3 C;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) C.m[r][c] = A.m[r][0] * B.m[0][c] + A.m[r][1] * B.m[1][c] + A.m[r][2] * B.m[2][c];
  return C;
}
constexpr Vec3 operator*(const Mat3 &A, const Vec3 &v) {
  return {A.m[0][0] * v.x + A.m[0][1] * v.y + A.m[0][2] * v.z, A.m[1][0] * v.x + A.m[1][1] * v.y + A.m[1][2] * v.z,
          A.m[2][0] * v.x + A.m[2][1] * v.y + A.m[2][2] * v.z};
}
constexpr Mat3 operator+(Mat3 A, const Mat3 &B) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) A.m[r][c] += B.m[r][c];
  return A;
}
constexpr Mat3 operator-(Mat3 A, const Mat3 &B) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) A.m[r][c] -= B.m[r][c];
  return A;
}
constexpr Mat3 operator*(double s, Mat3 A) {
  for (auto &row : A.m)
    for (auto &v : row) v *= s;
  return A;
}
constexpr double det(const Mat3 &A) {
  return A.m[0][0] * (A.m[1][1] * A.m[2][2] - A.m[1][2] * A.m[2][1]) - A.m[0][1] * (A.m[1][0] * A.m[2][2] - A.m[1][2] * A.m[2][0]) +
         A.m[0][2] * (A.m[1][0] * A.m[2][1] - A.m[1][1] * A.m[2][0]);
}
// Inverse; the caller checks det(A) != 0 first.
constexpr Mat3 inverse(const Mat3 &A) {
  const double d = det(A);
  Mat3 B;
  B.m[0][0] = (A.m[1][1] * A.m[2][2] - A.m[1][2] * A.m[2][1]) / d;
  B.m[0][1] = (A.m[0][2] * A.m[2][1] - A.m[0][1] * A.m[2][2]) / d;
  B.m[0][2] = (A.m[0][1] * A.m[1][2] - A.m[0][2] * A.m[1][1]) / d;
  B.m[1][0] = (A.m[1][2] * A.m[2][0] - A.m[1][0] * A.m[2][2]) / d;
  B.m[1][1] = (A.m[0][0] * A.m[2][2] - A.m[0][2] * A.m[2][0]) / d;
  B.m[1][2] = (A.m[0][2] * A.m[1][0] - A.m[0][0] * A.m[1][2]) / d;
  B.m[2][0] = (A.m[1][0] * A.m[2][1] - A.m[1][1] * A.m[2][0]) / d;
  B.m[2][1] = (A.m[0][1] * A.m[2][0] - A.m[0][0] * A.m[2][1]) / d;
  B.m[2][2] = (A.m[0][0] * A.m[1][1] - A.m[0][1] * A.m[1][0]) / d;
  return B;
}
constexpr double trace(const Mat3 &A) { return A.m[0][0] + A.m[1][1] + A.m[2][2]; }

} // namespace fdem::kernels
