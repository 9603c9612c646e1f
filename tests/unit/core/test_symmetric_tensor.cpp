// The upper-triangle storage of a symmetric tensor (the force loop's per-row scratch) against the
// full tensor it stands for: its entries, its product with a vector and its quadratic form, in
// 1D, 2D and 3D.
#include "spall/core/SymmetricTensor.hpp"

#include <gtest/gtest.h>

#include <random>

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
