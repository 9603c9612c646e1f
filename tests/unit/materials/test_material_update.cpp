// The per-particle material pass: each particle gets its own material's strength stage and EOS,
// the signal speed of a solid is the longitudinal one, and the evaluation advances no history.
#include "spall/materials/MaterialUpdate.hpp"

#include <gtest/gtest.h>

using namespace spall;
using namespace spall::materials;

namespace {

struct Particles {
  std::vector<double> rho, e, p, cs, eps, T;
  std::vector<std::int32_t> mat;
  std::vector<Tensor<3>> L, S;
  explicit Particles(std::size_t n)
      : rho(n), e(n), p(n), cs(n), eps(n), T(n), mat(n), L(n), S(n, Tensor<3>::Zero()) {}
  MaterialFields fields() { return {rho, e, mat, p, cs, L, S, eps, T}; }
};

} // namespace

TEST(MaterialUpdate, EachParticleGetsItsMaterialAndSolidsTheLongitudinalSpeed) {
  // Material 0: water-like linear EOS (fluid); 1: the same EOS with an elastic shear modulus;
  // 2: an ideal gas (gamma 1.4).
  const double rho0 = 1000.0, K = 2.2e9, G = 1.0e9;
  MaterialUpdate update({{LinearEos{rho0, K}, std::nullopt},
                         {LinearEos{rho0, K}, Strength{Elastic{G}}},
                         {IdealGas{1.4}, std::nullopt}});
  Particles P(3);
  P.rho = {1010.0, 1010.0, 1.2};
  P.e = {0.0, 0.0, 2.5e5};
  P.mat = {0, 1, 2};
  update.evaluate(P.fields());
  // p = K (rho/rho0 - 1), cs = sqrt(K/rho0) for the fluid; sqrt(cs^2 + 4G/(3 rho)) for the solid
  // (the longitudinal wave); p = (gamma - 1) rho e, cs = sqrt(gamma p / rho) for the gas. Exact
  // formulas, so a few ulps of tolerance.
  EXPECT_NEAR(P.p[0], K * 0.01, 1e-6);
  EXPECT_DOUBLE_EQ(P.cs[0], std::sqrt(K / rho0));
  EXPECT_NEAR(P.p[1], K * 0.01, 1e-6);
  EXPECT_DOUBLE_EQ(P.cs[1], std::sqrt(K / rho0 + 4.0 * G / (3.0 * 1010.0)));
  const double pGas = (1.4 - 1.0) * 1.2 * 2.5e5;
  EXPECT_DOUBLE_EQ(P.p[2], pGas);
  EXPECT_DOUBLE_EQ(P.cs[2], std::sqrt(1.4 * pGas / 1.2));
}

TEST(MaterialUpdate, UpdateRunsStrengthThenEosAndEvaluateAdvancesNoHistory) {
  const double rho0 = 8930.0, G = 46e9;
  const JohnsonCook jc{G, 90e6, 292e6, 0.31, 0.025, 1.09, 1.0, 293.0, 1356.0, 383.0, 0.9};
  const MieGruneisen eos{rho0, 3940.0, 1.49, 2.02};
  MaterialUpdate update({{eos, Strength{jc}}});
  Particles P(2);
  P.rho = {9000.0, 8900.0};
  P.e = {1.0e3, 0.0};
  P.mat = {0, 0};
  P.T = {293.0, 400.0};
  // A shear rate large enough to yield within dt, and a stretch.
  P.L[0](0, 1) = 2.0e5;
  P.L[1](0, 0) = 1.0e5, P.L[1](1, 1) = -0.5e5, P.L[1](2, 2) = -0.5e5;
  const double dt = 1.0e-8;
  Particles before = P;
  update.update(P.fields(), dt);
  for (std::size_t i = 0; i < 2; ++i) {
    // The same pure functions called directly, in the same order: identical to the bit.
    const StrengthState next =
        jc.update({before.S[i], before.eps[i], before.T[i]}, before.L[i], dt, before.rho[i]);
    EXPECT_EQ(P.S[i], next.S) << i;
    EXPECT_EQ(P.eps[i], next.plasticStrain) << i;
    EXPECT_EQ(P.T[i], next.temperature) << i;
    const EosState st = eos.evaluate(before.rho[i], before.e[i]);
    EXPECT_EQ(P.p[i], st.p) << i;
    EXPECT_EQ(P.cs[i], std::sqrt(st.cs * st.cs + 4.0 * G / (3.0 * before.rho[i]))) << i;
  }
  EXPECT_GT(P.S[0].norm(), 0.0); // the stage did act
  // The EOS-only refresh after a density change: p and cs follow, S, eps and T stay.
  const Particles advanced = P;
  P.rho[0] = 9100.0;
  update.evaluate(P.fields());
  EXPECT_EQ(P.S[0], advanced.S[0]);
  EXPECT_EQ(P.eps[0], advanced.eps[0]);
  EXPECT_EQ(P.T[0], advanced.T[0]);
  EXPECT_EQ(P.p[0], eos.evaluate(9100.0, P.e[0]).p);
  EXPECT_EQ(P.p[1], advanced.p[1]);
}

TEST(MaterialUpdate, TensionLimitFloorsThePressureAndLeavesTheSoundSpeed) {
  // Copper's Mie-Gruneisen EOS at 0.7 rho0 gives about -40 GPa; with a tension limit of -1.5 GPa
  // the pressure is the limit in update and evaluate alike, for a fluid and for a solid, the
  // sound speed stays the EOS's, and a compressed particle keeps its EOS pressure (exact: the
  // floor is a max).
  const double rho0 = 8930.0, pMin = -1.5e9;
  const MieGruneisen eos{rho0, 3940.0, 1.49, 2.02};
  const JohnsonCook jc{46e9, 90e6, 292e6, 0.31, 0.025, 1.09, 1.0, 293.0, 1356.0, 383.0, 0.9};
  Material fluid{eos, std::nullopt}, solid{eos, Strength{jc}};
  fluid.pMin = solid.pMin = pMin;
  MaterialUpdate limited({fluid, solid}), free({{eos, std::nullopt}, {eos, Strength{jc}}});
  for (bool advance : {false, true}) {
    Particles a(4), b(4);
    for (Particles* P : {&a, &b}) {
      P->rho = {0.7 * rho0, 0.7 * rho0, 1.1 * rho0, 1.1 * rho0};
      P->mat = {0, 1, 0, 1};
      P->T = {293.0, 293.0, 293.0, 293.0};
    }
    if (advance) {
      limited.update(a.fields(), 1e-9), free.update(b.fields(), 1e-9);
    } else {
      limited.evaluate(a.fields()), free.evaluate(b.fields());
    }
    for (std::size_t i = 0; i < 2; ++i) {
      ASSERT_LT(b.p[i], 10.0 * pMin); // the EOS's own tension, far past the limit
      EXPECT_EQ(a.p[i], pMin);
      EXPECT_EQ(a.cs[i], b.cs[i]);
    }
    for (std::size_t i = 2; i < 4; ++i) EXPECT_EQ(a.p[i], b.p[i]);
  }
}
