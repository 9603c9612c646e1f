// The particle store: registration, ghosts, permutation and field swaps move every field.
#include "spall/core/ParticleStore.hpp"

#include <gtest/gtest.h>

using namespace spall;

TEST(ParticleStore, GhostsCopyEveryFieldAndPermutationMovesAll) {
  ParticleStore s;
  auto id = s.add<ParticleId>("id");
  auto x = s.add<Vec<2>>("position");
  auto t = s.add<Tensor<2>>("tensor");
  s.resizeLocal(4);
  for (std::size_t i = 0; i < 4; ++i) {
    s[id][i] = 10 + i;
    s[x][i] = Vec<2>(i, -double(i));
    s[t][i] = Tensor<2>::Constant(double(i));
  }
  // A field registered late (a later model) gets storage for every particle.
  auto late = s.add<double>("late");
  EXPECT_EQ(s[late].size(), 4u);
  const std::size_t g = s.appendGhostCopy(2);
  EXPECT_EQ(s.ghostCount(), 1u);
  EXPECT_EQ(s[id][g], 12u);
  EXPECT_EQ(s[t][g](1, 1), 2.0);
  const std::vector<std::uint32_t> order{3, 1, 0, 2};
  s.permuteLocal(order);
  EXPECT_EQ(s.ghostCount(), 0u);
  EXPECT_EQ(s[id][0], 13u);
  EXPECT_EQ(s[x][0], Vec<2>(3, -3));
  EXPECT_EQ(s[t][3](0, 0), 2.0);
  // Same name, other type: a programming error caught at registration.
  EXPECT_THROW(s.add<double>("position"), std::logic_error);
  auto a = s.add<double>("a"), b = s.add<double>("b");
  s[a][0] = 1.0;
  s[b][0] = 2.0;
  s.swapValues(a, b);
  EXPECT_EQ(s[a][0], 2.0);
  EXPECT_EQ(s[b][0], 1.0);
}
