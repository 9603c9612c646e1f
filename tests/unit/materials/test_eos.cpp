// Equations of state against values worked by hand from their defining equations.
#include "spall/materials/Eos.hpp"

#include <gtest/gtest.h>

using namespace spall::materials;

TEST(Eos, IdealGasSodLeftState) {
  // rho = 1, p = 1, gamma = 1.4: e = p / ((gamma-1) rho) = 2.5, cs = sqrt(1.4).
  const IdealGas g{1.4};
  EXPECT_DOUBLE_EQ(*g.energyForPressure(1.0, 1.0), 2.5);
  const auto s = g.evaluate(1.0, 2.5);
  EXPECT_DOUBLE_EQ(s.p, 1.0);
  EXPECT_DOUBLE_EQ(s.cs, std::sqrt(1.4));
}

TEST(Eos, LinearIsBarotropic) {
  const LinearEos l{1000.0, 2.2e9};
  const auto s = l.evaluate(1010.0, 123.0);
  EXPECT_NEAR(s.p, 2.2e9 * 0.01, 1e-3);
  EXPECT_DOUBLE_EQ(s.cs, std::sqrt(2.2e9 / 1000.0));
  EXPECT_FALSE(l.energyForPressure(1000.0, 1e5).has_value());
}

TEST(Eos, MieGruneisenCopperMatchesLamEquations) {
  // Lam et al. (2001) Table 2, copper: rho0 = 8930, C0 = 3940, S = 1.49, Gamma = 2.02.
  const MieGruneisen cu{8930.0, 3940.0, 1.49, 2.02};
  const double rho0 = 8930.0, C0 = 3940.0, S = 1.49, G = 2.02;
  // Cold compression eta = 1%: Eq. 4 with e = 0 and Gamma rho = Gamma0 rho0 (materials/Eos.hpp)
  // is (1 - G eta/(2(1 + eta))) p_H; the cubic p_H of Eqs. 5-6 is the third-order expansion of
  // Eq. 12, so they agree to O(eta^4) ~ 1e-6 relative.
  const double eta = 0.01;
  const double pH12 = rho0 * C0 * C0 * eta * (1 + eta) / std::pow(1 - (S - 1) * eta, 2);
  const auto s = cu.evaluate(rho0 * (1 + eta), 0.0);
  EXPECT_NEAR(s.p / ((1 - 0.5 * G * eta / (1 + eta)) * pH12), 1.0, 2e-6);
  // By hand: a0 = 8930 * 3940^2 = 1.386257480e11 Pa; p_H = a0 (0.01 + 1.98e-4 + 1.7003e-6); the
  // cold factor 1 - 2.02 * 0.01 / 2.02 = 0.99. (Lam's Gamma = Gamma0 gives 0.9899: 1e-4 apart.)
  const double a0 = 1.386257480e11;
  EXPECT_NEAR(s.p, 0.99 * a0 * (0.01 + 1.98e-4 + 1.7003e-6), 1e3);
  // At the reference state the sound speed is the bulk sound speed C0.
  EXPECT_NEAR(cu.evaluate(rho0, 0.0).cs, C0, 1e-9);
  // The thermal term: at rho0, p = Gamma rho0 e.
  EXPECT_NEAR(cu.evaluate(rho0, 1000.0).p, G * rho0 * 1000.0, 1e-6);
  // energyForPressure inverts evaluate.
  EXPECT_NEAR(cu.evaluate(9000.0, *cu.energyForPressure(9000.0, 2e9)).p, 2e9, 1e-3);
}

// The cold curve rises monotonically however far a particle is compressed: with Gamma = Gamma0
// (Lam et al.'s form) it turns over at rho = (1 + 2/Gamma0) rho0 = 1.99 rho0 for copper and is
// negative beyond, which pulls an over-compressed particle in without bound.
TEST(Eos, MieGruneisenColdPressureRisesPastTwiceTheDensity) {
  const MieGruneisen cu{8930.0, 3940.0, 1.49, 2.02};
  const MieGruneisen al{2785.0, 5328.0, 1.338, 2.0};
  for (const MieGruneisen& m : {cu, al}) {
    double last = 0.0;
    for (double ratio = 1.01; ratio < 4.0; ratio += 0.01) {
      const double p = m.evaluate(ratio * m.rho0, 0.0).p;
      EXPECT_GT(p, last) << "rho/rho0 = " << ratio;
      last = p;
    }
  }
}

TEST(Eos, DpDrhoMatchesFiniteDifference) {
  const MieGruneisen cu{8930.0, 3940.0, 1.49, 2.02};
  const IdealGas g{5.0 / 3.0};
  for (double rho : {8800.0, 8930.0, 9500.0, 20000.0}) {
    const double d = 1e-3 * rho;
    const double fd = (cu.evaluate(rho + d, 5e4).p - cu.evaluate(rho - d, 5e4).p) / (2 * d);
    // Central difference; p is a cubic in rho on each side, error O(d^2 p''') ~ 1e-6 relative.
    // (8930 itself is the kink between the tension and compression branches: skip its FD.)
    if (rho != 8930.0) {
      EXPECT_NEAR(cu.dpdrho(rho, 5e4) / fd, 1.0, 1e-5);
    }
  }
  EXPECT_DOUBLE_EQ(g.dpdrho(2.0, 3.0), (5.0 / 3.0 - 1.0) * 3.0);
}
