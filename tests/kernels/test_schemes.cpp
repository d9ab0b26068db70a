// Exact stability limits of the schemes from the spectral radius of their
// linear step maps on x'' = -x, against the exact values of doc/book.md A (Table 5.2).
#include <fdem/kernels/schemes.hpp>
#include <gtest/gtest.h>
#include <cmath>
#include <string>

using namespace fdem::kernels;

TEST(SchemeStability, CriticalKMatchesExactValues) {
  struct {
    const char *name;
    double      kexact, tol;
  } cases[] = {{"cd", 2.0, 1e-6},          {"pv", 2.0, 1e-6},         {"t16", 2.2828, 1e-3}, {"t112", std::sqrt(6.0), 1e-5}, {"d112", std::sqrt(6.0), 1e-5},
               {"pc3", std::sqrt(2.0), 1e-5}, {"pc5", 0.313, 2e-3},   {"chin", 2 * std::sqrt(3.0), 1e-6}, {"omf30", 2.553, 1e-3}, {"omf32", 3.122, 1e-3},
               {"fr", 1.5734, 1e-3},       {"pefrl", 2.990, 1e-3}};
  for (auto &c : cases) {
    const double k = SchemeCriticalK(c.name);
    EXPECT_NEAR(k, c.kexact, c.tol) << c.name;
    // the limit is sharp: clearly unstable a little above it
    EXPECT_GT(SchemeSpectralRadius(c.name, k * 1.01 + 1e-3), 1 + 1e-9) << c.name;
  }
}

TEST(SchemeStability, StoredLimitsAreTheAnalysedOnes) {
  // the K_crit that -ts_view and the divergence messages print
  for (const char *name : {"cd", "pv", "t112", "t16", "d112", "pc3", "pc5", "chin", "omf30", "omf32", "fr", "pefrl"}) {
    // where the limit is a closed form at a double root (T-1/12, D-1/12: sqrt 6;
    // Chin: 2 sqrt 3) the squaring resolves K only to ~1e-6 and ~1e-8; elsewhere it is sharp
    const std::string n   = name;
    const double      tol = (n == "t112" || n == "d112") ? 2e-6 : (n == "chin" ? 5e-8 : 1e-9);
    EXPECT_NEAR(SchemeKcrit(name), SchemeCriticalK(name), tol) << name;
  }
  EXPECT_NEAR(SchemeKcrit("pefrl"), 2.98945, 1e-5); // not the rounded 2.990 (above the limit)
  EXPECT_EQ(SchemeKcrit("pc4"), 0.0);
  EXPECT_EQ(SchemeKcrit("nosuch"), -1.0);
}

TEST(SchemeStability, PC4IsUnstableAtEveryStep) {
  // doc/book.md A: rho - 1 ~ 6e-10 at K = 0.05 and ~5e-7 at K = 0.155
  for (double K : {0.01, 0.05, 0.1, 0.155, 0.3}) EXPECT_GT(SchemeSpectralRadius("pc4", K), 1.0 + 1e-14) << K;
  EXPECT_NEAR(SchemeSpectralRadius("pc4", 0.155) - 1, 5e-7, 3e-7);
}

TEST(SchemeStability, SymplecticSchemesAreNeutralBelowTheLimit) {
  for (const auto &t : BuiltinSplittingTables())
    for (double f : {0.1, 0.5, 0.9}) EXPECT_NEAR(SchemeSpectralRadius(t.name, f * t.kcrit), 1.0, 1e-12) << t.name;
}

TEST(SchemeStability, TablesAreConsistent) {
  for (const auto &t : BuiltinSplittingTables()) {
    double kick = 0, drift = 0;
    for (size_t i = 0; i < t.ops.size(); ++i) (t.ops[i] == 'K' ? kick : drift) += t.coef[i];
    EXPECT_NEAR(kick, 1.0, 1e-14) << t.name;
    EXPECT_NEAR(drift, 1.0, 1e-14) << t.name;
    EXPECT_NEAR(SchemeCriticalK(t.name), t.kcrit, 2e-3) << t.name;
  }
}

TEST(SchemeStability, SpectralRadiusOfKnownMatrices) {
  EXPECT_NEAR(SpectralRadius({2, 0, 0, 0.5}, 2), 2.0, 1e-12);
  EXPECT_NEAR(SpectralRadius({0, -1, 1, 0}, 2), 1.0, 1e-12); // rotation
  EXPECT_NEAR(SpectralRadius({1, 1, 0, 1}, 2), 1.0, 1e-6);   // Jordan block: slow but converging
}
