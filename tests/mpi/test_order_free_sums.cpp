// Order-free sums (diagnostics/OrderFreeSums.hpp) on synthetic terms spread over the ranks: the
// same bits as one process summing all terms in a shuffled order, within 2^-61 of the largest
// term per term of an exact (long double, sorted by magnitude) reference, a single nonzero term
// exactly, a quantity with a non-finite term as plain doubles, and ranks without terms.
#include "spall/diagnostics/OrderFreeSums.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <span>
#include <vector>

using namespace spall;

namespace {

constexpr std::size_t kTerms = 5000, kQuantities = 4;

// Term g of quantity q: magnitudes over 12 decades and both signs (q 0), positive only (q 1),
// cancelling pairs around a large offset (q 2), one nonzero term (q 3).
double term(std::size_t g, std::size_t q) {
  std::mt19937_64 rng(1000003 * g + q);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  switch (q) {
  case 0:
    return u(rng) * std::pow(10.0, 6.0 * u(rng));
  case 1:
    return std::abs(u(rng)) + 1e-3;
  case 2:
    return (g % 2 ? -1.0 : 1.0) * 1e8 + u(rng);
  default:
    return g == 1234 ? 0.1 : 0.0;
  }
}

// This rank's share of the global terms: an uneven, interleaved slice (rank r takes g with
// g % (ranks + 1) == r, the last rank the rest), so the storage order differs from 0..n-1.
std::vector<std::size_t> share(int rank, int ranks) {
  std::vector<std::size_t> mine;
  for (std::size_t g = 0; g < kTerms; ++g) {
    const int owner =
        std::min(static_cast<int>(g % static_cast<std::size_t>(ranks + 1)), ranks - 1);
    if (owner == rank) mine.push_back(g);
  }
  std::reverse(mine.begin(), mine.end());
  return mine;
}

} // namespace

TEST(OrderFreeSums, SameBitsOnAnyRankCountAndOrder) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const auto mine = share(rank, ranks);
  const auto spread = diagnostics::orderFreeSums(
      mine.size(), kQuantities,
      [&](std::size_t i, std::span<double> t) {
        for (std::size_t q = 0; q < kQuantities; ++q) t[q] = term(mine[i], q);
      },
      MPI_COMM_WORLD);
  // One process, all terms, shuffled.
  std::vector<std::size_t> all(kTerms);
  std::iota(all.begin(), all.end(), 0);
  std::shuffle(all.begin(), all.end(), std::mt19937_64(7));
  const auto alone = diagnostics::orderFreeSums(
      all.size(), kQuantities,
      [&](std::size_t i, std::span<double> t) {
        for (std::size_t q = 0; q < kQuantities; ++q) t[q] = term(all[i], q);
      },
      MPI_COMM_SELF);
  for (std::size_t q = 0; q < kQuantities; ++q) {
    EXPECT_EQ(spread[q], alone[q]) << "quantity " << q << " on " << ranks << " ranks";
    // Against long double sums of the terms sorted by magnitude: each term loses at most one unit
    // of 2^-62 of the largest term's power of two (< 2^-61 of the largest), n terms at most n
    // such units.
    std::vector<double> t(kTerms);
    double largest = 0.0;
    for (std::size_t g = 0; g < kTerms; ++g) {
      t[g] = term(g, q);
      largest = std::max(largest, std::abs(t[g]));
    }
    std::sort(t.begin(), t.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    long double exact = 0.0L;
    for (double v : t) exact += v;
    const double bound = static_cast<double>(kTerms) * std::ldexp(largest, -61) +
                         std::abs(static_cast<double>(exact)) * 1e-16; // the result's rounding
    EXPECT_LE(std::abs(spread[q] - static_cast<double>(exact)), bound) << "quantity " << q;
  }
  EXPECT_EQ(spread[3], term(1234, 3)); // one nonzero term: that term exactly
}

TEST(OrderFreeSums, NonFiniteTermsAndEmptyRanks) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  // Only the last rank holds terms; one of quantity 1's is infinite.
  const std::size_t n = rank == ranks - 1 ? 10 : 0;
  const auto sums = diagnostics::orderFreeSums<2>(
      n,
      [&](std::size_t i, std::span<double> t) {
        t[0] = 0.5 * static_cast<double>(i + 1);
        t[1] = i == 3 ? std::numeric_limits<double>::infinity() : 1.0;
      },
      MPI_COMM_WORLD);
  EXPECT_EQ(sums[0], 27.5); // 0.5 (1 + ... + 10), exact
  EXPECT_TRUE(std::isinf(sums[1]));
  // No terms anywhere: zeros.
  const auto none = diagnostics::orderFreeSums<2>(
      0, [](std::size_t, std::span<double> t) { t[0] = t[1] = 1.0; }, MPI_COMM_WORLD);
  EXPECT_EQ(none[0], 0.0);
  EXPECT_EQ(none[1], 0.0);
}
