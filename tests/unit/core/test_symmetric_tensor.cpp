// The upper-triangle storage of a symmetric tensor (the force loop's per-row scratch) against the
// full tensor it stands for: its entries, its product with a vector and its quadratic form, in
// 1D, 2D and 3D.
#include "spall/core/SymmetricTensor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace spall;

namespace {
template <int Dim> void checkAgainstFull(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Tensor<Dim> M;
  Vec<Dim> g;
  for (int r = 0; r < Dim; ++r) {
    g[r] = u(rng);
    for (int c = 0; c < Dim; ++c) M(r, c) = u(rng);
  }
  const Tensor<Dim> sym = 0.5 * (M + M.transpose());
  const SymTensor<Dim> s = SymTensor<Dim>::symmetricPart(M);
  // The entries are the symmetric part's, bit for bit (the same one addition and halving).
  for (int r = 0; r < Dim; ++r)
    for (int c = 0; c < Dim; ++c)
      EXPECT_EQ(s(r, c), sym(r, c)) << Dim << "D (" << r << "," << c << ")";
  EXPECT_EQ(s.full(), sym);
  // Products differ from Eigen's only in the order of a few additions: a few ulps of the
  // terms' magnitude (entries and g below 3, so terms below 9 and sums below 27*Dim).
  const Vec<Dim> Mg = s * g, ref = sym * g;
  for (int r = 0; r < Dim; ++r) EXPECT_NEAR(Mg[r], ref[r], 1e-13) << Dim << "D row " << r;
  EXPECT_NEAR(s.quadraticForm(g), g.dot(sym * g), 1e-12) << Dim << "D";
  const SymTensor<Dim> half = s / 2.0;
  for (int r = 0; r < Dim; ++r)
    for (int c = 0; c < Dim; ++c) EXPECT_EQ(half(r, c), sym(r, c) / 2.0);
}
} // namespace

TEST(SymTensor, StandsForTheSymmetricPartOfATensor) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    checkAgainstFull<1>(rng);
    checkAgainstFull<2>(rng);
    checkAgainstFull<3>(rng);
  }
}

TEST(SymTensor, StoresTheUpperTriangleRowByRow) {
  static_assert(SymTensor<1>::kSize == 1 && SymTensor<2>::kSize == 3 && SymTensor<3>::kSize == 6);
  static_assert(sizeof(SymTensor<3>) == 6 * sizeof(double));
  EXPECT_EQ(SymTensor<3>::index(0, 0), 0);
  EXPECT_EQ(SymTensor<3>::index(0, 2), 2);
  EXPECT_EQ(SymTensor<3>::index(1, 1), 3);
  EXPECT_EQ(SymTensor<3>::index(1, 2), 4);
  EXPECT_EQ(SymTensor<3>::index(2, 2), 5);
  EXPECT_EQ(SymTensor<2>::index(1, 1), 2);
  const SymTensor<3> z = SymTensor<3>::zero();
  EXPECT_EQ(z.full(), Tensor<3>::Zero());
}

// The force loop's rows in single precision: half the bytes; each entry is the symmetric part's
// rounded once to float, and products are taken in double from those entries, so that i and j of
// a pair read the same values (what keeps the pair force antisymmetric). The rows are written in
// one loop and read in another, as the force loop's: GCC 12 at -O3 -march=native may use the
// unrounded double where a value is rounded and read back within one expression (seen here),
// which a row read from memory cannot be.
TEST(SymTensor, SinglePrecisionRowsRoundEachEntryOnceAndMultiplyInDouble) {
  using RowTensor = SymTensor<3, float>;
  static_assert(sizeof(RowTensor) == 6 * sizeof(float));
  constexpr int kRows = 50;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Tensor<3>> sym(kRows);
  std::vector<Vec<3>> g(kRows);
  std::vector<RowTensor> rows(kRows);
  for (int k = 0; k < kRows; ++k) {
    Tensor<3> M;
    for (int r = 0; r < 3; ++r) {
      g[k][r] = u(rng);
      for (int c = 0; c < 3; ++c) M(r, c) = u(rng);
    }
    sym[k] = 0.5 * (M + M.transpose());
    rows[k] = RowTensor::symmetricPart(M);
  }
  for (int k = 0; k < kRows; ++k) {
    const RowTensor& s = rows[k];
    Tensor<3> rounded;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        rounded(r, c) = static_cast<double>(static_cast<float>(sym[k](r, c)));
        EXPECT_EQ(s(r, c), rounded(r, c));
        // Rounding to nearest: within half an ulp of float, 2^-24 relative.
        EXPECT_LE(std::abs(s(r, c) - sym[k](r, c)), std::ldexp(std::abs(sym[k](r, c)), -24));
      }
    EXPECT_EQ(s.full(), rounded);
    // The products of the rounded entries in double: as the double tensor's, to a few ulps.
    const Vec<3> Mg = s * g[k], ref = rounded * g[k];
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(Mg[r], ref[r], 1e-13);
    EXPECT_NEAR(s.quadraticForm(g[k]), g[k].dot(rounded * g[k]), 1e-12);
    EXPECT_TRUE(s.nonzero());
  }
  EXPECT_FALSE(RowTensor::zero().nonzero());
}
