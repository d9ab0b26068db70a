// The coefficient tables of the splitting schemes (pure data, shared by the
// TS types and by the exact stability analysis), and the exact linear step
// map of every scheme on the book's test oscillator x'' = -omega^2 x.
#pragma once
#include <string>
#include <vector>

namespace fdem::kernels {

struct SplittingTable {
  const char         *name;
  const char         *description;
  int                 order;
  std::string         ops;  // 'K' kick, 'D' drift, in order
  std::vector<double> coef; // fraction of h of each op
  std::vector<double> grad; // force-gradient coefficient xi of each kick (v += c h a + xi h^3 G, G = 2 (da/dx) a)
  double              kcrit;      // exact (omega h)_crit from the spectral radius of the step map
  double              kcrit_book; // Table 5.2 (0: not in the book)
};

// cd, pv, omf30, chin, fr, pefrl, omf32 (Munjiza 5.12-5.13, 5.101, 5.111-5.115; PEFRL: doc/book.md A).
const std::vector<SplittingTable> &BuiltinSplittingTables();

// The step map of scheme `name` on x'' = -x with step K (= omega h), as an
// n x n row-major matrix acting on the scheme's whole state (x, v and any
// history). Returns false for an unknown name.
//  splitting schemes: (x, v); t16: (x, v); t112: (x, v, a_{t-h}); d112: (x, x_{t-h}, v);
//  pcN: the Nordsieck vector (x, h v, h^2 a/2, ...).
bool SchemeStepMatrix(const std::string &name, double K, std::vector<double> &A, int &n);

// The exact stability limit (omega h)_crit of scheme `name`: the value
// SchemeCriticalK finds, to 12 digits, stored (0 for PC-4, which grows at
// every step size; -1 for an unknown name).
double SchemeKcrit(const std::string &name);

// Spectral radius of an n x n matrix by repeated squaring (relative accuracy ~1e-13).
double SpectralRadius(const std::vector<double> &A, int n);
double SchemeSpectralRadius(const std::string &name, double K);

// Largest K such that rho(K') <= 1 + tol for all 0 < K' <= K (scan then bisection).
double SchemeCriticalK(const std::string &name, double tol = 1e-12, double Kmax = 7.0);

} // namespace fdem::kernels
