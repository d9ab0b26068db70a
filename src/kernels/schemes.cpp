// Splitting tables and the exact linear stability analysis of the schemes.
#include <fdem/kernels/schemes.hpp>

#include <cmath>
#include <stdexcept>

namespace fdem::kernels {

const std::vector<SplittingTable> &BuiltinSplittingTables() {
  static const std::vector<SplittingTable> tables = [] {
    std::vector<SplittingTable> t;
    // Central difference (5.12-5.13) reported with the velocity at the step: kick-drift-kick.
    t.push_back({"cd", "central difference (Munjiza 5.12-5.13), synchronised velocities", 2, "KDK", {0.5, 1, 0.5}, {}, 2.0, 2.0});
    t.push_back({"pv", "position Verlet / leap-frog (5.101)", 2, "DKD", {0.5, 1, 0.5}, {}, 2.0, 2.0});
    {
      const double r = std::cbrt(36 + 2 * std::sqrt(326.0));
      const double l = 0.5 - r / 12 + 1 / (6 * r); // (5.112): 0.19318332750378...
      t.push_back({"omf30", "Omelyan-Mryglod-Folk OMF30 (5.112), 2nd order, 2 forces", 2, "KDKDK", {l, 0.5, 1 - 2 * l, 0.5, l}, {}, 2.553145233832, 2.5});
    }
    // Chin (5.111) with the bracketed reading: middle kick (2/3) h [a + h^2/48 grad|a|^2] = (2/3) h a + h^3/72 G.
    t.push_back({"chin", "Chin's force-gradient scheme (5.111), 4th order", 4, "KDKDK", {1.0 / 6, 0.5, 2.0 / 3, 0.5, 1.0 / 6}, {0, 0, 1.0 / 72, 0, 0}, 2 * std::sqrt(3.0), 3.05});
    {
      const double l = (std::cbrt(2.0) + 1 / std::cbrt(2.0) - 1) / 6; // (5.115)
      t.push_back({"fr", "Forest & Ruth (5.114-5.115), 4th order", 4, "KDKDKDK", {l + 0.5, 2 * l + 1, -l, -4 * l - 1, -l, 2 * l + 1, l + 0.5}, {}, 1.573401947435, 1.572});
    }
    {
      const double xi = 0.1786178958448091, l = -0.2123418310626054, chi = -0.06626458266981849;
      t.push_back({"pefrl", "Omelyan-Mryglod-Folk PEFRL, 4th order, 4 forces", 4, "DKDKDKDKD", {xi, (1 - 2 * l) / 2, chi, l, 1 - 2 * (chi + xi), l, chi, (1 - 2 * l) / 2, xi}, {}, 2.989449545907, 0});
    }
    {
      const double rho = 0.6419108866816235e-01, theta = 0.1919807940455741e+00, vth = 0.1518179640276466e+00, lam = 0.2158369476787619e+00, xi = 0.9628905212024874e-03;
      const double dm = (1 - 2 * (theta + rho)) / 2, km = 1 - 2 * (lam + vth);
      t.push_back({"omf32", "Omelyan-Mryglod-Folk OMF32 (5.113), 4th order force-gradient", 4, "DKDKDKDKDKD", {rho, vth, theta, lam, dm, km, dm, lam, theta, vth, rho}, {0, 0, 0, xi, 0, 0, 0, xi, 0, 0, 0}, 3.122329357352, 3.111});
    }
    return t;
  }();
  return tables;
}

namespace {
using Mat = std::vector<double>;
Mat Mul(const Mat &A, const Mat &B, int n) {
  Mat C(n * n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      const double a = A[i * n + k];
      if (a == 0) continue;
      for (int j = 0; j < n; ++j) C[i * n + j] += a * B[k * n + j];
    }
  return C;
}
double Norm1(const Mat &A, int n) {
  double m = 0;
  for (int j = 0; j < n; ++j) {
    double s = 0;
    for (int i = 0; i < n; ++i) s += std::fabs(A[i * n + j]);
    m = std::fmax(m, s);
  }
  return m;
}
} // namespace

bool SchemeStepMatrix(const std::string &name, double K, std::vector<double> &A, int &n) {
  const double h = K;
  for (const auto &t : BuiltinSplittingTables()) {
    if (name != t.name) continue;
    n = 2;
    Mat M = {1, 0, 0, 1};
    for (size_t i = 0; i < t.ops.size(); ++i) {
      const double c = t.coef[i];
      Mat          S;
      if (t.ops[i] == 'D') S = {1, c * h, 0, 1};                // x += c h v
      else {
        const double xi = i < t.grad.size() ? t.grad[i] : 0.0; // a = -x, G = 2 (da/dx) a = 2 x
        S = {1, 0, -c * h + 2 * xi * h * h * h, 1};             // v += c h a + xi h^3 G
      }
      M = Mul(S, M, 2);
    }
    A = M;
    return true;
  }
  const double h2 = h * h;
  if (name == "t16") { // (5.104-5.105) with b = -1
    n = 2;
    const double d = 1 + h2 / 6;
    A = {1 - h2 / 2, h - h * h2 / 6, -h / d, (1 - h2 / 3) / d};
    return true;
  }
  if (name == "t112") { // state (x, v, a_old); (5.102-5.103)
    n = 3;
    const double d = 1 + h2 / 12;
    // x+ = x + [v h + (7 (-x) - a_old) h^2/12] / d
    const double xx = 1 - 7 * h2 / 12 / d, xv = h / d, xa = -h2 / 12 / d;
    // v+ = v + h/12 (-8 x - 5 x+ - a_old)
    A = {xx, xv, xa, h / 12 * (-8 - 5 * xx), 1 - 5 * h / 12 * xv, h / 12 * (-5 * xa - 1), -1, 0, 0};
    return true;
  }
  if (name == "d112") { // state (x, x_old, v); (5.106-5.107) with h^2 in the denominator; a_old = -x_old
    n = 3;
    const double d = 1 + h2 / 12;
    // x+ = x_old + [x - x_old + v h - x h^2/2] / d
    const double xx = (1 - h2 / 2) / d, xo = 1 - 1 / d, xv = h / d;
    // v+ = v + h/12 (-8 x - 5 x+ + x_old)
    A = {xx, xo, xv, 1, 0, 0, h / 12 * (-8 - 5 * xx), h / 12 * (1 - 5 * xo), 1 - 5 * h / 12 * xv};
    return true;
  }
  if (name == "pc3" || name == "pc4" || name == "pc5") {
    const int    q = name[2] - '0';
    const double a3[] = {1.0 / 6, 5.0 / 6, 1, 1.0 / 3}, a4[] = {19.0 / 120, 3.0 / 4, 1, 1.0 / 2, 1.0 / 12}, a5[] = {3.0 / 16, 251.0 / 360, 1, 11.0 / 18, 1.0 / 6, 1.0 / 60};
    const double *al = q == 3 ? a3 : (q == 4 ? a4 : a5);
    n = q + 1;
    // predictor: Pascal matrix P[i][j] = C(j, i)
    Mat P(n * n, 0.0);
    for (int j = 0; j < n; ++j) {
      double c = 1;
      for (int i = 0; i <= j; ++i) {
        P[i * n + j] = c; // C(j, i)
        c = c * (j - i) / (i + 1);
      }
    }
    // delta = h^2/2 a(x_p) - z_p[2] = -h^2/2 z_p[0] - z_p[2];  z = z_p + alpha delta
    Mat C(n * n, 0.0);
    for (int i = 0; i < n; ++i) {
      C[i * n + i] = 1;
      C[i * n + 0] += al[i] * (-h2 / 2);
      C[i * n + 2] += al[i] * (-1);
    }
    A = Mul(C, P, n);
    return true;
  }
  return false;
}

double SchemeKcrit(const std::string &name) {
  for (const auto &t : BuiltinSplittingTables())
    if (name == t.name) return t.kcrit;
  // SchemeCriticalK's values (tests/kernels/test_schemes checks them), closed
  // forms where the limit is a double root (T-1/12, D-1/12: sqrt 6; PC-3: sqrt 2)
  if (name == "t16") return 2.282783446878;
  if (name == "t112" || name == "d112") return std::sqrt(6.0);
  if (name == "pc3") return std::sqrt(2.0);
  if (name == "pc4") return 0.0; // grows at every step size
  if (name == "pc5") return 0.312971661128;
  return -1;
}

double SpectralRadius(const std::vector<double> &A, int n) {
  // A^(2^k) = e^{L_k} B_k with ||B_k|| = 1; rho = lim exp(L_k / 2^k)
  Mat    B = A;
  double s = Norm1(B, n);
  if (s == 0) return 0;
  for (double &b : B) b /= s;
  double L = std::log(s), scale = 1;
  for (int k = 0; k < 60; ++k) {
    B     = Mul(B, B, n);
    s     = Norm1(B, n);
    if (s == 0) return 0;
    for (double &b : B) b /= s;
    L     = 2 * L + std::log(s);
    scale *= 2;
  }
  return std::exp(L / scale);
}

double SchemeSpectralRadius(const std::string &name, double K) {
  std::vector<double> A;
  int                 n;
  if (!SchemeStepMatrix(name, K, A, n)) throw std::invalid_argument("unknown scheme " + name);
  return SpectralRadius(A, n);
}

double SchemeCriticalK(const std::string &name, double tol, double Kmax) {
  const double dK = 1e-3;
  double       lo = 0;
  for (double K = dK; K <= Kmax; K += dK) {
    if (SchemeSpectralRadius(name, K) > 1 + tol) {
      double hi = K;
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi);
        (SchemeSpectralRadius(name, mid) > 1 + tol ? hi : lo) = mid;
      }
      return lo;
    }
    lo = K;
  }
  return Kmax;
}

} // namespace fdem::kernels
