// The artificial viscosity from linearly reconstructed velocities (solvers/SphPairTerms.hpp,
// Frontiere, Raskin & Owen 2017): no approach, so no viscosity, in a linear velocity field; the
// full approach where the two gradients disagree (a shock); symmetric in the pair; on a lattice in
// isochoric flow (pure shear) the viscous heating vanishes inside while the plain viscosity heats
// it there (its forces cancel inside by symmetry; its heating does not); a lattice in uniform
// compression keeps most of the plain viscosity (the isochoric gate).
#include "SolverLattice.hpp"
#include "spall/solvers/SphPairTerms.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace spall;

namespace {
constexpr double kQc = 1.0 / 1.5; // the mean spacing in units of h at n_h = 1.5
} // namespace

TEST(ViscosityReconstruction, LinearFieldLeavesNoApproach) {
  // v = G x: v_ij . x_ij = x . G x = a = b, and the limiter is 1.
  const double vr = -3.0;
  EXPECT_EQ(solvers::pair::reconstructedApproach(vr, vr, vr, 1.0, kQc), 0.0);
}

TEST(ViscosityReconstruction, DisagreeingGradientsKeepTheApproach) {
  // Opposite signs (one side compresses, the other expands): the limiter is 0.
  EXPECT_EQ(solvers::pair::reconstructedApproach(-2.0, -4.0, 1.0, 1.0, kQc), -2.0);
  // Gradients in the ratio r = 10: phi = 40/121, a third of the linear part is removed.
  const double a = -10.0, b = -1.0, vr = -20.0;
  const double phi = 4.0 * a * b / ((a + b) * (a + b));
  EXPECT_DOUBLE_EQ(solvers::pair::reconstructedApproach(vr, a, b, 1.0, kQc),
                   vr - 0.5 * phi * (a + b));
  // Symmetric in the pair (r -> 1/r), and never an approach from a separating reconstruction.
  EXPECT_EQ(solvers::pair::reconstructedApproach(vr, a, b, 1.0, kQc),
            solvers::pair::reconstructedApproach(vr, b, a, 1.0, kQc));
  EXPECT_EQ(solvers::pair::reconstructedApproach(-0.5, -4.0, -4.0, 1.0, kQc), 0.0);
}

TEST(ViscosityReconstruction, CloseParticlesGetTheViscosityBack) {
  // Closer than the mean spacing the reconstruction fades (Rosswog 2015): at the spacing nothing
  // changes, 0.2 h closer phi falls to 1/e, 0.6 h closer the approach is almost all back.
  const double vr = -3.0;
  EXPECT_EQ(solvers::pair::reconstructedApproach(vr, vr, vr, kQc, kQc), 0.0);
  EXPECT_NEAR(solvers::pair::reconstructedApproach(vr, vr, vr, kQc - 0.2, kQc),
              vr * (1.0 - std::exp(-1.0)), 1e-12);
  EXPECT_LT(solvers::pair::reconstructedApproach(vr, vr, vr, kQc - 0.6, kQc), 0.99 * vr);
}

namespace {

// A lattice in the linear flow v = G x (about its centre), with the velocity gradient of a first
// evaluation in place, as the previous step leaves it; returns the largest |de/dt| over the
// particles whose neighbors' neighbors are all inside (two supports, 6 spacings, from every edge:
// the plain L is off by tens of percent within a support of a free surface).
double innerHeating(bool reconstruct, double alpha, const Tensor<2>& G) {
  SolverConfig cfg;
  cfg.artificial_viscosity.alpha = alpha;
  cfg.artificial_viscosity.beta = 2.0 * alpha;
  cfg.artificial_viscosity.reconstruct = reconstruct;
  const int n = 20;
  fixtures::SolverLattice l(n, cfg, true, G);
  for (std::size_t i = 0; i < l.store.localCount(); ++i) // unstressed, as a run starts
    l.store[l.f.S][i].setZero(), l.store[l.f.L][i].setZero();
  l.evaluate(); // L of every particle
  l.evaluate(); // the rates with that L
  const double dp = fixtures::SolverLattice::dp, edge = n * dp, margin = 6.0 * dp;
  double worst = 0.0;
  for (std::size_t i = 0; i < l.store.localCount(); ++i) {
    const Vec<2> x = l.store[l.f.x][i];
    if (x.minCoeff() > margin && x.maxCoeff() < edge - margin)
      worst = std::max(worst, std::abs(l.store[l.f.dedt][i]));
  }
  return worst;
}

} // namespace

namespace {
const Tensor<2> kShear{{50.0, 0.0}, {0.0, -50.0}}; // isochoric: tr G = 0
const Tensor<2> kCompression = -50.0 * Tensor<2>::Identity();
} // namespace

TEST(ViscosityReconstruction, IsochoricFlowFeelsNoViscosityInside) {
  // Unstressed and at the reference density, nothing but the viscosity heats the lattice: without
  // it de/dt is round-off. The plain viscosity heats every approaching pair; reconstructed, the
  // linear field leaves no approach where both gradients are exact (inside: L is within 0.7% of
  // G there, and a + b then exceeds the approach, so the clipped approach is exactly 0).
  const double none = innerHeating(false, 0.0, kShear);
  const double plain = innerHeating(false, 1.0, kShear);
  const double rebuilt = innerHeating(true, 1.0, kShear);
  EXPECT_GT(plain, 1e3 * none);
  EXPECT_EQ(rebuilt, none);
}

TEST(ViscosityReconstruction, UniformCompressionKeepsMostOfTheViscosity) {
  // chi = sqrt 2 in 2D: the gate exp(-2) leaves 86% of each pair's approach, and the heating
  // (linear and quadratic in it) between 0.7 and 1 of the plain one.
  const double plain = innerHeating(false, 1.0, kCompression);
  const double rebuilt = innerHeating(true, 1.0, kCompression);
  EXPECT_GT(rebuilt, 0.7 * plain);
  EXPECT_LT(rebuilt, plain);
}

TEST(ViscosityReconstruction, IsochoricGate) {
  using solvers::pair::isochoricGate;
  EXPECT_EQ(isochoricGate<3>(Tensor<3>::Zero()), 1.0);
  EXPECT_EQ(isochoricGate<2>(kShear), 1.0);
  EXPECT_NEAR(isochoricGate<3>(Tensor<3>{{-2.0, 0, 0}, {0, 0, 0}, {0, 0, 0}}), std::exp(-1.0),
              1e-15); // uniaxial strain
  EXPECT_NEAR(isochoricGate<3>(-Tensor<3>::Identity()), std::exp(-3.0), 1e-15);
}
