// Noh (1987) 2D implosion: post-shock density 16 (decks/noh_2d.toml).
#include "RunDeck.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace spall;
using namespace spall::verification;

TEST(Noh2D, PostShockDensityIsSixteen) {
  // Half the deck's resolution (spacing 0.02, ~7.8k particles) keeps the test under a minute.
  int rc = -1;
  const auto dir =
      runSpall(deckPath("noh_2d.toml"), {"run.resolution=0.5", "output.every=0.6"}, "noh", &rc);
  ASSERT_EQ(rc, 0);
  const auto s = io::readSnapshot(lastSnapshot(dir));
  const double t = s.time, shock = t / 3.0; // gamma = 5/3: the shock moves out at 1/3
  const auto& x = s.fields.at("position");
  const auto& rho = s.fields.at("density");
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.count; ++i) {
    const double r = std::hypot(x[2 * i], x[2 * i + 1]);
    // Between the wall-heating dip at the centre (r < 0.25 R_s) and the smeared shock (r > 0.75
    // R_s).
    if (r > 0.25 * shock && r < 0.75 * shock) sum += rho[i], ++n;
  }
  const double mean = sum / static_cast<double>(n);
  std::printf("Noh 2D at t = %.2f: mean post-shock density %.3f over %zu particles (exact 16)\n", t,
              mean, n);
  ASSERT_GT(n, 100u);
  EXPECT_NEAR(mean / 16.0, 1.0, 0.10); // the 10%
}
