// The cell-list neighbor search against brute force, with unequal h and ghosts.
#include "spall/neighbors/NeighborList.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <random>
#include <set>

using namespace spall;

namespace {
template <int Dim> void compareWithBruteForce(std::size_t n, std::size_t owned) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0), hd(0.02, 0.08);
  std::vector<Vec<Dim>> x(n);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x[i][d] = u(rng);
    h[i] = hd(rng);
  }
  x[n - 1] *= 50.0; // a far-flung particle must not blow up the grid
  neighbors::CellGrid<Dim> grid;
  neighbors::NeighborList nl;
  neighbors::buildNeighborList<Dim>(x, h, owned, 2.0, grid, nl);
  for (std::size_t i = 0; i < owned; ++i) {
    std::set<std::uint32_t> expect;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double reach = 2.0 * std::max(h[i], h[j]);
      if ((x[i] - x[j]).squaredNorm() < reach * reach) expect.insert(static_cast<std::uint32_t>(j));
    }
    const auto got = nl.of(i);
    ASSERT_EQ(std::set<std::uint32_t>(got.begin(), got.end()), expect) << "particle " << i;
    ASSERT_EQ(got.size(), expect.size()) << "a neighbor listed twice for particle " << i;
  }
}
} // namespace

TEST(NeighborList, MatchesBruteForce1D) {
  compareWithBruteForce<1>(400, 350);
}
TEST(NeighborList, MatchesBruteForce2D) {
  compareWithBruteForce<2>(1500, 1200);
}
TEST(NeighborList, MatchesBruteForce3D) {
  compareWithBruteForce<3>(3000, 2500);
}

namespace {
// Ellipsoidal supports (ASPH): random orientations, axes 0.01-0.1 (aspect ratios up to 10). The
// list must hold exactly the pairs where either support |H x| < 2 covers the other particle;
// the sphere of the longest axis would list up to 10^(Dim-1) times as many.
template <int Dim> void compareEllipsoidsWithBruteForce(std::size_t n, std::size_t owned) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0), axis(0.01, 0.1);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec<Dim>> x(n);
  std::vector<Tensor<Dim>> H(n);
  std::vector<double> h(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < Dim; ++d) x[i][d] = u(rng);
    Tensor<Dim> Q;
    if constexpr (Dim == 2)
      Q = Eigen::Rotation2Dd(6.283185307179586 * u(rng)).toRotationMatrix();
    else
      Q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    Vec<Dim> lengths;
    for (int d = 0; d < Dim; ++d) lengths[d] = axis(rng);
    H[i] = Q * lengths.cwiseInverse().asDiagonal() * Q.transpose();
    h[i] = lengths.maxCoeff();
  }
  neighbors::CellGrid<Dim> grid;
  neighbors::NeighborList nl;
  neighbors::buildNeighborList<Dim>(x, h, std::span<const Tensor<Dim>>(H), owned, 2.0, grid, nl);
  std::size_t pairs = 0, sphere = 0;
  for (std::size_t i = 0; i < owned; ++i) {
    std::set<std::uint32_t> expect;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const Vec<Dim> xij = x[i] - x[j];
      if ((H[i] * xij).norm() < 2.0 || (H[j] * xij).norm() < 2.0)
        expect.insert(static_cast<std::uint32_t>(j));
      const double reach = 2.0 * std::max(h[i], h[j]);
      sphere += xij.squaredNorm() < reach * reach;
    }
    const auto got = nl.of(i);
    ASSERT_EQ(std::set<std::uint32_t>(got.begin(), got.end()), expect) << "particle " << i;
    ASSERT_EQ(got.size(), expect.size()) << "a neighbor listed twice for particle " << i;
    pairs += got.size();
  }
  EXPECT_LT(pairs, sphere); // the ellipses, not their enclosing spheres
}
} // namespace

TEST(NeighborList, EllipsoidalSupportsMatchBruteForce2D) {
  compareEllipsoidsWithBruteForce<2>(1500, 1200);
}
TEST(NeighborList, EllipsoidalSupportsMatchBruteForce3D) {
  compareEllipsoidsWithBruteForce<3>(3000, 2500);
}
