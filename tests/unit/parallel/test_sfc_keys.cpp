// Space-filling-curve keys: bijective on a grid, and the Hilbert curve steps between face
// neighbours only (its defining locality property); the ownership lookup of key intervals.
#include "spall/parallel/Partition.hpp"
#include "spall/parallel/SfcKeys.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <set>
#include <vector>

using namespace spall;
using namespace spall::parallel;

namespace {

template <int Dim> std::vector<std::array<std::uint64_t, Dim>> grid(int bits) {
  std::vector<std::array<std::uint64_t, Dim>> out;
  const std::uint64_t n = std::uint64_t{1} << bits;
  std::array<std::uint64_t, Dim> c{};
  const std::uint64_t total = Dim == 2 ? n * n : n * n * n;
  for (std::uint64_t k = 0; k < total; ++k) {
    std::uint64_t r = k;
    for (int d = 0; d < Dim; ++d) c[static_cast<std::size_t>(d)] = r % n, r /= n;
    out.push_back(c);
  }
  return out;
}

// Every key 0 .. 2^(Dim bits) - 1 exactly once; consecutive Hilbert keys one cell apart.
template <int Dim> void checkCurve(int bits, bool hilbert) {
  const auto cells = grid<Dim>(bits);
  std::vector<int> at(cells.size(), -1);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::uint64_t k =
        hilbert ? hilbertKey<Dim>(cells[i], bits) : mortonKey<Dim>(cells[i], bits);
    ASSERT_LT(k, cells.size());
    ASSERT_EQ(at[k], -1) << "key " << k << " given twice";
    at[k] = static_cast<int>(i);
  }
  if (!hilbert) return;
  for (std::size_t k = 1; k < at.size(); ++k) {
    const auto& a = cells[static_cast<std::size_t>(at[k - 1])];
    const auto& b = cells[static_cast<std::size_t>(at[k])];
    std::uint64_t manhattan = 0;
    for (int d = 0; d < Dim; ++d)
      manhattan += a[static_cast<std::size_t>(d)] > b[static_cast<std::size_t>(d)]
                       ? a[static_cast<std::size_t>(d)] - b[static_cast<std::size_t>(d)]
                       : b[static_cast<std::size_t>(d)] - a[static_cast<std::size_t>(d)];
    ASSERT_EQ(manhattan, 1u) << "Hilbert keys " << k - 1 << " and " << k << " are not adjacent";
  }
}

} // namespace

TEST(SfcKeys, Hilbert2DBijectiveAndAdjacent) {
  checkCurve<2>(5, true);
}
TEST(SfcKeys, Hilbert3DBijectiveAndAdjacent) {
  checkCurve<3>(4, true);
}
TEST(SfcKeys, Morton2DAnd3DBijective) {
  checkCurve<2>(5, false);
  checkCurve<3>(4, false);
}

TEST(SfcKeys, MortonInterleavesAxisZeroLowest) {
  // (x, y) = (1, 0) -> 1, (0, 1) -> 2, (1, 1) -> 3 at one bit.
  EXPECT_EQ((mortonKey<2>({1, 0}, 1)), 1u);
  EXPECT_EQ((mortonKey<2>({0, 1}, 1)), 2u);
  EXPECT_EQ((mortonKey<2>({1, 1}, 1)), 3u);
}

TEST(SfcKeys, KeyMapClampsOutsideAndIsMonotoneIn1D) {
  const KeyMap<1> k(Vec<1>(0.0), Vec<1>(1.0), Curve::Hilbert);
  EXPECT_EQ(k(Vec<1>(-5.0)), 0u);
  EXPECT_LT(k(Vec<1>(0.25)), k(Vec<1>(0.5)));
  EXPECT_LT(k(Vec<1>(5.0)), kKeyEnd);
  EXPECT_EQ(k(Vec<1>(5.0)), k(Vec<1>(1e300)));
  EXPECT_EQ(k(Vec<1>(std::numeric_limits<double>::quiet_NaN())), 0u); // owned, then reported
  const KeyMap<3> k3(Vec<3>(0, 0, 0), Vec<3>(1, 1, 1), Curve::Hilbert);
  EXPECT_LT(k3(Vec<3>(1, 1, 1)), kKeyEnd);
}

TEST(SfcKeys, OwnershipSkipsEmptyIntervals) {
  // Ranks 1 and 2 own nothing (equal splitters): keys go to rank 0 or 3.
  const auto o = KeyOwnership::contiguous({0, 100, 100, 100});
  EXPECT_EQ(o.owner(0), 0);
  EXPECT_EQ(o.owner(99), 0);
  EXPECT_EQ(o.owner(100), 3);
  EXPECT_EQ(o.owner(kKeyEnd - 1), 3);
}

namespace {
// Skilling's AxesToTranspose as printed (branches, bit-by-bit interleave): the branch-free
// hilbertKey must give the same keys, so that decompositions (and checkpointed cuts) stay the
// same.
template <int Dim> std::uint64_t referenceHilbert(std::array<std::uint64_t, Dim> X, int bits) {
  const std::uint64_t M = std::uint64_t{1} << (bits - 1);
  for (std::uint64_t Q = M; Q > 1; Q >>= 1) {
    const std::uint64_t P = Q - 1;
    for (std::size_t i = 0; i < Dim; ++i) {
      if (X[i] & Q) {
        X[0] ^= P;
      } else {
        const std::uint64_t t = (X[0] ^ X[i]) & P;
        X[0] ^= t;
        X[i] ^= t;
      }
    }
  }
  for (std::size_t i = 1; i < Dim; ++i) X[i] ^= X[i - 1];
  std::uint64_t t = 0;
  for (std::uint64_t Q = M; Q > 1; Q >>= 1)
    if (X[Dim - 1] & Q) t ^= Q - 1;
  for (std::size_t i = 0; i < Dim; ++i) X[i] ^= t;
  std::uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (std::size_t i = 0; i < Dim; ++i) key = (key << 1) | ((X[i] >> b) & 1u);
  return key;
}

template <int Dim> void compareWithReference() {
  std::uint64_t state = 88172645463325252ull; // xorshift64: any coordinates, every bit pattern
  const auto next = [&] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  for (const int bits : {3, 10, keyBits<Dim>()})
    for (int k = 0; k < 20000; ++k) {
      std::array<std::uint64_t, Dim> c{};
      for (auto& v : c) v = next() & ((std::uint64_t{1} << bits) - 1);
      ASSERT_EQ(hilbertKey<Dim>(c, bits), referenceHilbert<Dim>(c, bits)) << "bits " << bits;
    }
}
} // namespace

TEST(SfcKeys, HilbertMatchesSkillingReference2D) {
  compareWithReference<2>();
}
TEST(SfcKeys, HilbertMatchesSkillingReference3D) {
  compareWithReference<3>();
}
