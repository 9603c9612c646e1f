// The particle store: registration, ghosts, permutation and field swaps move every field.
#include "spall/core/ParticleStore.hpp"

#include <gtest/gtest.h>
#include <limits>

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

// The rescue copy: the flagged columns' owned rows come back byte for byte, whatever the store
// did since (more rows, fewer rows, ghosts); unflagged columns are not copied.
TEST(ParticleStore, RowsCopyRestoresTheFlaggedColumnsExactly) {
  ParticleStore s;
  auto id = s.add<ParticleId>("id", kCheckpoint);
  auto x = s.add<Vec<3>>("position", kCheckpoint);
  auto scratch = s.add<double>("scratch", 0);
  s.resizeLocal(5);
  for (std::size_t i = 0; i < 5; ++i) {
    s[id][i] = 100 + i;
    s[x][i] = Vec<3>(0.1 * double(i), 1.0 / 3.0 + double(i), -1e-300);
    s[scratch][i] = 7.0;
  }
  ParticleStore::RowsCopy copy;
  s.copyRows(kCheckpoint, copy);
  EXPECT_EQ(copy.count, 5u);
  // (Packed: consecutive ids keep one byte each, the positions' constant third component none.)
  EXPECT_LT(copy.size(), 5u * (sizeof(ParticleId) + sizeof(Vec<3>)));
  // The store moves on: rows change, some leave, ghosts arrive.
  s[x][0] = Vec<3>::Constant(std::numeric_limits<double>::quiet_NaN());
  const std::vector<std::uint32_t> keep{4, 2};
  s.keepLocal(keep);
  s.appendGhostCopy(0);
  s.restoreRows(copy);
  ASSERT_EQ(s.localCount(), 5u);
  EXPECT_EQ(s.ghostCount(), 0u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(s[id][i], 100 + i);
    EXPECT_EQ(s[x][i], Vec<3>(0.1 * double(i), 1.0 / 3.0 + double(i), -1e-300));
  }
  // A copy of more rows than the store holds grows it; copying again reuses the buffers.
  s.resizeLocal(2);
  s.restoreRows(copy);
  EXPECT_EQ(s[id][4], 104u);
  s.copyRows(kCheckpoint, copy);
  EXPECT_EQ(copy.count, 5u);
}
