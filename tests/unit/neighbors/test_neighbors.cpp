// The cell-list neighbor search against brute force, with unequal h and ghosts.
#include "spall/neighbors/NeighborList.hpp"

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
