// Monaghan's artificial stress tensor R of a particle (solvers/SphPairTerms.hpp; Gray, Monaghan &
// Swift 2001): in the principal frame of sigma = S - p I, R' = -epsilon sigma'/rho^2 for each
// tensile principal stress, 0 for a compressive one. 2D takes it in closed form; checked here
// against the 3D path's eigen-solver on plane stress states (the 3D path of a state whose third
// principal stress, -p + S_zz, is compressive has the same in-plane R).
#include "spall/solvers/SphPairTerms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace spall;
using solvers::pair::artificialStress;

namespace {

constexpr double kEps = 0.3, kRho = 8930.0;

// A deviator with the given in-plane part and S_zz = -(S_xx + S_yy), and p.
Tensor<3> deviator(double sxx, double sxy, double syy) {
  Tensor<3> S = Tensor<3>::Zero();
  S(0, 0) = sxx, S(1, 1) = syy, S(2, 2) = -(sxx + syy);
  S(0, 1) = S(1, 0) = sxy;
  return S;
}

} // namespace

TEST(ArtificialStress, ClosedForm2DMatchesTheEigenSolver) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int mixed = 0, tensile = 0, compressive = 0;
  for (int k = 0; k < 3000; ++k) {
    const double sxx = 1e9 * U(rng), sxy = 1e9 * U(rng), syy = 1e9 * U(rng), p = 1e9 * U(rng);
    const Tensor<3> S = deviator(sxx, sxy, syy);
    // The 3D path with the out-of-plane principal stress made compressive: only the zz entry
    // is lowered, so the in-plane principal stresses and axes are the 2D state's.
    Tensor<3> S3 = S;
    S3(2, 2) = p - 1e10; // sigma_zz = S_zz - p = -1e10: not tensile
    const Tensor<2> R2 = artificialStress<2>(S, p, kRho, kEps);
    const Tensor<3> R3 = artificialStress<3>(S3, p, kRho, kEps);
    // Round-off: the 3D path's direct solver (cubic roots) loses digits with the spread of the
    // eigenvalues (here up to 10x the in-plane ones): measured below 1e-12 of R's scale eps
    // |sigma| / rho^2; with -1e12 out of plane it reached 1e-10. 1e-11 leaves a decade.
    const double scale = kEps * 2e9 / (kRho * kRho);
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) EXPECT_NEAR(R2(r, c), R3(r, c), 1e-11 * scale) << "state " << k;
    Tensor<2> sigma;
    sigma << sxx - p, sxy, sxy, syy - p;
    Eigen::SelfAdjointEigenSolver<Tensor<2>> eig;
    eig.computeDirect(sigma);
    const auto l = eig.eigenvalues();
    if (l[1] <= 0.0) {
      ++compressive;
      EXPECT_EQ(R2, Tensor<2>::Zero());
    } else if (l[0] > 0.0) {
      ++tensile;
      // Both tensile: R = -eps sigma/rho^2 exactly.
      EXPECT_EQ(R2, (-kEps / (kRho * kRho)) * sigma);
    } else {
      ++mixed;
      // One tensile axis: R has that axis' eigenvalue and annihilates the other.
      const Eigen::Vector2d v1 = eig.eigenvectors().col(1), v0 = eig.eigenvectors().col(0);
      const double Rl = -kEps * l[1] / (kRho * kRho);
      EXPECT_NEAR(v1.dot(R2 * v1), Rl, 1e-12 * std::abs(Rl));
      EXPECT_NEAR(v0.dot(R2 * v0), 0.0, 1e-12 * std::abs(Rl));
      EXPECT_EQ(R2(0, 1), R2(1, 0));
    }
  }
  // All three cases were met.
  EXPECT_GT(mixed, 300);
  EXPECT_GT(tensile, 300);
  EXPECT_GT(compressive, 300);
}

TEST(ArtificialStress, IsotropicStates) {
  const Tensor<3> S = Tensor<3>::Zero();
  EXPECT_EQ(artificialStress<2>(S, 1e9, kRho, kEps), Tensor<2>::Zero()); // compression
  EXPECT_EQ(artificialStress<2>(S, 0.0, kRho, kEps), Tensor<2>::Zero()); // unloaded
  const Tensor<2> R = artificialStress<2>(S, -1e9, kRho, kEps);          // tension: r = 0
  EXPECT_DOUBLE_EQ(R(0, 0), -kEps * 1e9 / (kRho * kRho));
  EXPECT_DOUBLE_EQ(R(1, 1), R(0, 0));
  EXPECT_EQ(R(0, 1), 0.0);
}
