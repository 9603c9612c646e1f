// Pairs across a crack (a column of failed particles, damage 1, in a 2D elastic lattice): they
// carry compression only, conserve momentum and energy pair by pair, take no part in the
// velocity gradient or the density rate (an open crack is not the material's expansion), and the
// rows at the crack keep the plain kernel gradient (B = I).
#include "SolverLattice.hpp"

#include <gtest/gtest.h>
#include <numbers>

using namespace spall;

namespace {

constexpr int kN = 14;
constexpr int kCrackColumn = 6;

struct Cracked : fixtures::SolverLattice {
  Cracked(VelocityGradient method, const Tensor<2>& G, unsigned jitter = 0, bool rz = false)
      : SolverLattice(kN, config(method, rz), true, G, true) {
    if (jitter != 0) disorder(jitter);
    for (std::size_t i = 0; i < store.localCount(); ++i) {
      store[f.damage][i] = failed(i) ? 1.0 : 0.0;
      // rz: x is the radius and each particle a ring of mass 2 pi r rho dA.
      if (rz) store[f.m][i] *= 2.0 * std::numbers::pi * store[f.x][i][0];
    }
  }
  static SolverConfig config(VelocityGradient method, bool rz) {
    SolverConfig cfg;
    cfg.velocity_gradient = method;
    if (rz) cfg.geometry = Geometry::RZ;
    return cfg;
  }
  static bool failed(std::size_t i) { return static_cast<int>(i) / kN == kCrackColumn; }
  // Whether a failed particle is in i's neighbor list (the list the rates were computed from).
  bool nextToCrack(std::size_t i) const {
    for (std::uint32_t j : nl.row(i))
      if (failed(j)) return true;
    return false;
  }
};

Tensor<2> stretch() {
  Tensor<2> G;
  G << 40.0, 10.0, -5.0, -20.0;
  return G;
}

} // namespace

TEST(CrackedPairs, ConserveMomentumAndEnergy) {
  // Disordered positions, velocities, densities and stresses: some cracked pairs approach (and
  // carry pressure and viscosity), some separate. Tolerance: round-off relative to the largest
  // single contribution, times the particle count (as for the intact lattice).
  for (VelocityGradient method : {VelocityGradient::Sph, VelocityGradient::Corrected}) {
    Cracked l(method, stretch(), 11);
    l.evaluate();
    const auto t = l.totals();
    EXPECT_GT(t.scaleP, 0.0);
    EXPECT_LT(t.momentum.norm(), 1e-12 * t.scaleP * kN * kN);
    EXPECT_LT(std::abs(t.power), 1e-12 * t.scaleE * kN * kN);
  }
}

TEST(CrackedPairs, ConserveMomentumAndEnergyInRz) {
  // The same in rz, where the hoop force adds to each row: total energy conserved, and momentum
  // along z (the axis); the radial momentum is not conserved in rz.
  for (VelocityGradient method : {VelocityGradient::Sph, VelocityGradient::Corrected}) {
    Cracked l(method, stretch(), 11, true);
    l.evaluate();
    const auto t = l.totals();
    EXPECT_GT(t.scaleP, 0.0);
    EXPECT_LT(std::abs(t.momentum[1]), 1e-12 * t.scaleP * kN * kN);
    EXPECT_LT(std::abs(t.power), 1e-12 * t.scaleE * kN * kN);
  }
}

TEST(CrackedPairs, RzRingAmongFailedRingsFeelsNoHoopPull) {
  // rz, at rest: one intact ring next to the axis in tension (rho 5% below the reference), every
  // ring around it failed (stress-free). All its pairs are cracked and carry -max(p, 0) I = 0 of
  // its stress, so the hoop force, the complement of those pairs' weights, carries none either:
  // no force, no work (exactly 0). With its tension in the hoop force it was pulled toward the
  // axis by -2 sigma_tt k_r / rho with nothing to balance it or relax it (its density rate is
  // frozen by the cracks), and its p dV work ran its energy and tension away in a penetration.
  Cracked l(VelocityGradient::Sph, Tensor<2>::Zero(), 0, true);
  const std::size_t k = 1 * kN + kN / 2; // the second column from the axis
  for (std::size_t i = 0; i < l.store.localCount(); ++i)
    l.store[l.f.damage][i] = i == k ? 0.0 : 1.0;
  l.store[l.f.rho][k] *= 0.95;
  l.evaluate();
  ASSERT_LT(l.store[l.f.p][k], 0.0);
  EXPECT_EQ(l.store[l.f.a][k].norm(), 0.0);
  EXPECT_EQ(l.store[l.f.dedt][k], 0.0);
}

TEST(CrackedPairs, CrackIsAFreeSurface) {
  // At rest in uniform hydrostatic tension (rho 1% below the reference). A failed particle's
  // pairs transmit max(p, 0) = 0 and no deviatoric stress: nothing pulls on it (exactly zero).
  // And nothing crosses the crack: the piece left of it moves as if the rest of the lattice were
  // gone (moved a metre away), to round-off. The intact particles two spacings to its right are
  // still inside their kernels; without the three-point rule they pull the piece's edge back
  // (by ~25% of its acceleration here). With the plain gradient, so that the rows at the crack
  // compute what rows at a free edge compute.
  const auto tension = [](Cracked& l) {
    for (std::size_t i = 0; i < l.store.localCount(); ++i) l.store[l.f.rho][i] *= 0.99;
  };
  Cracked l(VelocityGradient::Sph, Tensor<2>::Zero()),
      alone(VelocityGradient::Sph, Tensor<2>::Zero());
  tension(l), tension(alone);
  for (std::size_t i = 0; i < alone.store.localCount(); ++i)
    if (static_cast<int>(i) / kN >= kCrackColumn) alone.store[alone.f.x][i][0] += 1.0;
  l.evaluate(), alone.evaluate();
  ASSERT_LT(l.store[l.f.p][0], 0.0);
  double scale = 0.0;
  for (std::size_t i = 0; i < l.store.localCount(); ++i)
    scale = std::max(scale, alone.store[alone.f.a][i].norm());
  ASSERT_GT(scale, 0.0);
  for (std::size_t i = 0; i < l.store.localCount(); ++i) {
    const int column = static_cast<int>(i) / kN;
    if (Cracked::failed(i)) {
      EXPECT_EQ(l.store[l.f.a][i].norm(), 0.0) << "failed particle " << i;
    } else if (column < kCrackColumn) {
      EXPECT_LT((l.store[l.f.a][i] - alone.store[alone.f.a][i]).norm(), 1e-12 * scale)
          << "particle " << i << " left of the crack";
    }
  }
}

TEST(CrackedPairs, CrackIsNotExpansion) {
  // v = G x across the lattice. A failed particle's pairs are all cracked: no velocity gradient,
  // no density rate (exactly 0). Rows next to the crack keep B = I; rows whose supports do not
  // reach it keep the exact corrected gradient (round-off, as on the intact lattice), free
  // surfaces included.
  const Tensor<2> G = stretch();
  Cracked l(VelocityGradient::Corrected, G);
  l.evaluate();
  int atCrack = 0, exact = 0;
  for (std::size_t i = 0; i < l.store.localCount(); ++i) {
    const double rho = l.store[l.f.rho][i];
    const Tensor<2> L = l.store[l.f.L][i].topLeftCorner<2, 2>();
    const bool identity = l.store[l.f.B][i] == Tensor<3>::Identity();
    if (Cracked::failed(i)) {
      EXPECT_EQ(l.store[l.f.drhodt][i], 0.0) << "failed particle " << i;
      EXPECT_EQ(L.norm(), 0.0) << "failed particle " << i;
      EXPECT_TRUE(identity) << "failed particle " << i;
    } else if (l.nextToCrack(i)) {
      EXPECT_TRUE(identity) << "particle " << i << " beside the crack";
      ++atCrack;
    } else {
      EXPECT_NEAR(l.store[l.f.drhodt][i], -rho * G.trace(), 1e-9 * rho * 40.0) << "particle " << i;
      EXPECT_LT((L - G).cwiseAbs().maxCoeff(), 1e-9 * 40.0) << "particle " << i;
      ++exact;
    }
  }
  // The kernel reaches (up to) three spacings: two or three columns on each side border it.
  EXPECT_GE(atCrack, 4 * kN);
  EXPECT_LE(atCrack, 6 * kN);
  EXPECT_GT(exact, 0);
}
