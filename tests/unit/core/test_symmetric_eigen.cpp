// The closed-form 2x2 symmetric eigen-decomposition (the ASPH smoothing update takes three per
// particle per step) against Eigen's iterative solver, including the cases a closed form gets
// wrong easily: diagonal with a < c, equal entries, nearly equal eigenvalues, negative and huge
// or tiny entries.
#include "spall/core/SymmetricEigen.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace spall;

namespace {
// Residual |M v - l v| and orthonormality, relative to |M| (backward stability), and the
// values ascending and equal to Eigen's to a few ulps of |M|.
void checkDecomposition(const Tensor<2>& M, const char* what) {
  const SymmetricEigen<2> e = symmetricEigen<2>(M);
  const double norm = std::max(M.cwiseAbs().maxCoeff(), 1e-300);
  EXPECT_LE(e.values[0], e.values[1]) << what;
  for (int k = 0; k < 2; ++k) {
    const Vec<2> v = e.vectors.col(k);
    EXPECT_LT((M * v - e.values[k] * v).cwiseAbs().maxCoeff(), 1e-14 * norm)
        << what << " column " << k;
  }
  EXPECT_LT((e.vectors.transpose() * e.vectors - Tensor<2>::Identity()).norm(), 1e-14) << what;
  // A 2x2 Eigen solver in direct mode is a reference that does not share our formula.
  Eigen::SelfAdjointEigenSolver<Tensor<2>> ref;
  ref.computeDirect(M, Eigen::EigenvaluesOnly);
  EXPECT_LT((e.values - ref.eigenvalues()).cwiseAbs().maxCoeff(), 1e-14 * norm) << what;
}
} // namespace

TEST(SymmetricEigen, SpecialCases) {
  Tensor<2> M;
  M << 1.0, 0.0, 0.0, 3.0;
  checkDecomposition(M, "diagonal a < c");
  EXPECT_NEAR(std::abs(symmetricEigen<2>(M).vectors(1, 1)), 1.0, 1e-15); // l1 = 3 along y
  M << 3.0, 0.0, 0.0, 1.0;
  checkDecomposition(M, "diagonal a > c");
  EXPECT_NEAR(std::abs(symmetricEigen<2>(M).vectors(0, 1)), 1.0, 1e-15); // l1 = 3 along x
  M << 2.0, 0.0, 0.0, 2.0;
  checkDecomposition(M, "isotropic");
  M << 1.0, 0.0, 0.0, 1.0 + 0x1p-52;
  checkDecomposition(M, "eigenvalues one ulp apart");
  EXPECT_NEAR(std::abs(symmetricEigen<2>(M).vectors(1, 1)), 1.0, 1e-12); // the larger along y
  M << -2.0, 1.0, 1.0, -5.0;
  checkDecomposition(M, "negative definite");
  M << 1e200, 3e199, 3e199, 2e200;
  checkDecomposition(M, "huge entries");
  M << 1.0, 1e-160, 1e-160, 1.0;
  checkDecomposition(M, "tiny off-diagonal");
  M.setZero();
  const SymmetricEigen<2> zero = symmetricEigen<2>(M);
  EXPECT_EQ(zero.values, Vec<2>::Zero());
  EXPECT_EQ(zero.vectors, Tensor<2>::Identity());
}

TEST(SymmetricEigen, RandomAndNearlyDegenerateMatrices) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    Tensor<2> M;
    const double b = u(rng);
    M << u(rng), b, b, u(rng);
    checkDecomposition(M, "random");
    // Eigenvalues a few ulps apart in a random orientation.
    const double angle = 3.141592653589793 * u(rng);
    const Tensor<2> Q = Eigen::Rotation2Dd(angle).toRotationMatrix();
    const Vec<2> l(1.0, 1.0 + 1e-14 * std::abs(u(rng)));
    checkDecomposition(Tensor<2>(Q * l.asDiagonal() * Q.transpose()), "nearly degenerate");
  }
}
