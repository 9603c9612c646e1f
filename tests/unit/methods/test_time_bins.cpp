// The bookkeeping of hierarchical time steps (methods/TimeBins.hpp) on synthetic rows: bins from
// stable steps, the alignment of a step's start, the end of a woken particle's step and the
// neighbor limiter. The stepping itself: tests/verification/test_time_bins.py.
#include "spall/methods/TimeBins.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace spall::methods::bins {
namespace {

// A list of rows in the wide encoding (each index in two 16-bit units).
neighbors::NeighborList rowsOf(const std::vector<std::vector<std::uint32_t>>& rows) {
  neighbors::NeighborList nl;
  nl.offsets.push_back(0);
  for (const auto& row : rows) {
    for (std::uint32_t j : row) {
      nl.units.push_back(static_cast<std::uint16_t>(j & 0xffffu));
      nl.units.push_back(static_cast<std::uint16_t>(j >> 16));
    }
    nl.offsets.push_back(nl.units.size());
    nl.base.push_back(neighbors::NeighborList::kWide);
    nl.entries += row.size();
  }
  return nl;
}

TEST(TimeBins, BinIsTheLargestPowerOfTwoOfTheFinestStepWithin) {
  const double delta = 1.0e-8;
  EXPECT_EQ(binOf(delta, delta, 6), 0);
  EXPECT_EQ(binOf(1.999 * delta, delta, 6), 0);
  EXPECT_EQ(binOf(2.0 * delta, delta, 6), 1); // exactly 2 delta: a step of 2 delta is stable
  EXPECT_EQ(binOf(7.9 * delta, delta, 6), 2);
  EXPECT_EQ(binOf(32.0 * delta, delta, 6), 5);
  EXPECT_EQ(binOf(1.0e3 * delta, delta, 6), 5); // the slowest bin holds what is slower
  EXPECT_EQ(binOf(0.5 * delta, delta, 6), 0);   // (the finest step is the smallest)
  EXPECT_EQ(binOf(INFINITY, delta, 4), 3);      // no signal, no force: the slowest bin
  EXPECT_EQ(binOf(5.0 * delta, delta, 1), 0);   // one bin: every particle in it
}

TEST(TimeBins, AStepStartsOnlyWhereItsBinDividesTheSubstep) {
  EXPECT_EQ(alignedBin(0, 5), 5); // the run's step starts: any bin
  EXPECT_EQ(alignedBin(1, 5), 0);
  EXPECT_EQ(alignedBin(2, 5), 1);
  EXPECT_EQ(alignedBin(12, 5), 2);
  EXPECT_EQ(alignedBin(16, 5), 4);
  EXPECT_EQ(alignedBin(16, 3), 3); // never above the run's step
  // Every step from an aligned start ends within the run's step of 2^K substeps.
  for (std::int32_t s = 0; s < 32; ++s) {
    const int k = alignedBin(s, 5);
    EXPECT_EQ(s % (1 << k), 0);
    EXPECT_LE(s + (1 << k), 32);
  }
}

TEST(TimeBins, AWokenStepEndsAtTheNextMultipleOfItsNewBin) {
  EXPECT_EQ(wakeEnd(5, 2), 8);
  EXPECT_EQ(wakeEnd(8, 2), 12); // strictly after the substep it is woken at
  EXPECT_EQ(wakeEnd(0, 0), 1);
  EXPECT_EQ(wakeEnd(13, 3), 16);
  // Never after the step it was in: a multiple of 2^k of a larger bin's step is one of 2^k's.
  for (std::int32_t start = 0; start < 32; start += 16)
    for (std::int32_t s = start; s < start + 16; ++s)
      for (int k = 0; k < 4; ++k) EXPECT_LE(wakeEnd(s, k), start + 16);
}

TEST(TimeBins, LimiterKeepsNeighborsWithinTwoBins) {
  // A chain 0-1-2-3-4-5 (row i lists i-1 and i+1) with one fast particle at its start: the
  // limit spreads one neighbor a sweep, 2 bins a neighbor (steps within a factor of 4).
  const std::size_t n = 6;
  std::vector<std::vector<std::uint32_t>> rows(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) rows[i].push_back(static_cast<std::uint32_t>(i - 1));
    if (i + 1 < n) rows[i].push_back(static_cast<std::uint32_t>(i + 1));
  }
  const auto nl = rowsOf(rows);
  std::vector<std::int32_t> bin{0, 11, 11, 11, 11, 11}, next(n);
  int sweeps = 0;
  while (limitSweep(nl, n, bin, next)) {
    bin = next;
    ++sweeps;
  }
  EXPECT_EQ(bin, (std::vector<std::int32_t>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(sweeps, 5);
  // A sweep reads the bins as they were: the rows' order does not matter.
  std::vector<std::int32_t> once{0, 11, 11, 11, 11, 11};
  limitSweep(nl, n, once, next);
  EXPECT_EQ(next, (std::vector<std::int32_t>{0, 2, 11, 11, 11, 11}));
}

TEST(TimeBins, GhostsLimitTheirOwnedNeighbors) {
  // Two owned rows, the second with a ghost (row 2) in bin 0; ghosts are read, not written.
  const auto nl = rowsOf({{1}, {0, 2}});
  std::vector<std::int32_t> bin{5, 5, 0}, next(2);
  EXPECT_TRUE(limitSweep(nl, 2, bin, next));
  EXPECT_EQ(next[0], 5);
  EXPECT_EQ(next[1], 2);
  std::vector<std::uint32_t> buf;
  EXPECT_EQ(neighborsBin(nl, 1, bin, buf, 9), 0);
  EXPECT_EQ(neighborsBin(rowsOf({{}}), 0, bin, buf, 9), 9); // no neighbor: `none`
}

} // namespace
} // namespace spall::methods::bins
