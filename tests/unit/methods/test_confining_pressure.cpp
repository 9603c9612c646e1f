// The confining pressure's table and its mapping onto particles (methods/modules/
// ConfiningPressure.hpp); the load itself is verified in tests/verification/
// test_confining_pressure.py.
#include "spall/methods/modules/ConfiningPressure.hpp"
#include "spall/methods/modules/Hydro.hpp"

#include <gtest/gtest.h>

namespace spall::methods {
namespace {

TEST(ConfiningPressure, TableIsLinearBetweenRowsAndConstantOutside) {
  const std::vector<std::pair<double, double>> table{{1.0, 10.0}, {3.0, 30.0}, {4.0, 0.0}};
  EXPECT_EQ(tabulated(table, -5.0), 10.0); // the first value before the first row
  EXPECT_EQ(tabulated(table, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(tabulated(table, 2.0), 20.0);
  EXPECT_DOUBLE_EQ(tabulated(table, 3.5), 15.0);
  EXPECT_EQ(tabulated(table, 3.0), 30.0); // a row's own value at its time
  EXPECT_EQ(tabulated(table, 4.0), 0.0);
  EXPECT_EQ(tabulated(table, 1e9), 0.0); // the last after the last
  EXPECT_EQ(tabulated({{0.0, 7.0}}, 5.0), 7.0);
}

TEST(ConfiningPressure, EachParticleGetsItsBodysLoadAtTheTime) {
  ParticleStore s;
  ParticleFields<2> f;
  Hydro<2>::addFields(s, f);
  ConfiningPressure<2> module({{2, {{0.0, 0.0}, {10.0, 100.0}}}, {0, {{0.0, 5.0}}}});
  module.registerFields(s, f);
  s.resizeLocal(4);
  const auto body = s[f.body];
  body[0] = 0, body[1] = 1, body[2] = 2, body[3] = 3;
  module.beforeRates(s, f, 2.5);
  const auto P = s[f.confiningPressure];
  EXPECT_EQ(P[0], 5.0);
  EXPECT_EQ(P[1], 0.0); // not loaded
  EXPECT_DOUBLE_EQ(P[2], 25.0);
  EXPECT_EQ(P[3], 0.0); // beyond the last loaded body
  // The load on the owned particles, -P A, added to what F holds (a grown column's rows are
  // not initialised: every particle's area set).
  for (std::size_t i = 0; i < 4; ++i) s[f.surfaceArea][i] = Vec<2>::Zero();
  s[f.surfaceArea][2] = Vec<2>(0.0, 2.0);
  std::vector<Vec<2>> F(4, Vec<2>(1.0, 1.0));
  module.addExternalForces(s, f, 2.5, F);
  EXPECT_EQ(F[0], Vec<2>(1.0, 1.0));
  EXPECT_EQ(F[1], Vec<2>(1.0, 1.0)); // not loaded
  EXPECT_DOUBLE_EQ(F[2][1], 1.0 - 25.0 * 2.0);
  EXPECT_EQ(F[2][0], 1.0);
}

} // namespace
} // namespace spall::methods
