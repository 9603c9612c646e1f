// Particle generation: lattice counts, masses against the shapes' exact volumes, ids, jitter.
#include "spall/app/BodyGenerator.hpp"
#include "spall/core/Random.hpp"

#include "unit/app/GeneratedBodies.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <numbers>
#include <set>

using namespace spall;

namespace {

Deck deckFrom(const std::string& name, int dim, const std::string& bodies) {
  const auto path = std::filesystem::temp_directory_path() / ("spall_gen_" + name + ".toml");
  std::ofstream(path)
      << "[run]\ndimension = " << dim << "\nend_time = 1.0\nseed = 3\n"
      << "[[material]]\nname = \"m\"\ndensity = 2.0\neos = { type = \"ideal_gas\", gamma = 1.4 }\n"
      << bodies << "[output]\ndirectory = \"unused\"\n";
  return loadDeck(path.string());
}

template <int Dim> using Generated = fixtures::GeneratedBodies<Dim>;

} // namespace

TEST(BodyGenerator, BoxFillsExactlyWithStableIds) {
  const Deck deck = deckFrom("box", 3, R"([[body]]
name = "a"
material = "m"
shape = { type = "box", min = [0.0, 0.0, 0.0], max = [1.0, 0.5, 0.25] }
spacing = 0.05
)");
  Generated<3> g(deck);
  // 20 x 10 x 5 cells; the mass is exactly rho * volume.
  ASSERT_EQ(g.store.localCount(), 1000u);
  EXPECT_NEAR(g.bodies[0].mass, 2.0 * 0.125, 1e-12);
  std::set<ParticleId> ids(g.store[g.f.id].begin(), g.store[g.f.id].end());
  EXPECT_EQ(ids.size(), 1000u);
  EXPECT_EQ(*ids.rbegin(), 999u);
  // h = n_h * spacing (default n_h = 1.5).
  EXPECT_NEAR(g.store[g.f.h][0], 1.5 * 0.05, 1e-12);
}

TEST(BodyGenerator, ShapesHoldTheirVolume) {
  // Lattice-clipped shapes: mass = rho * (sites inside) * (volume per site) approaches the exact
  // volume; with ~30 spacings across, the boundary discretisation error is a few 1e-3.
  const Deck disk = deckFrom("disk", 2, R"([[body]]
name = "disk"
material = "m"
shape = { type = "sphere", center = [0.0, 0.0], radius = 1.0 }
spacing = 0.03
lattice = "hexagonal"
)");
  Generated<2> d(disk);
  EXPECT_NEAR(d.bodies[0].mass / (2.0 * std::numbers::pi), 1.0, 5e-3);
  const Deck ring = deckFrom("ring", 2, R"([[body]]
name = "ring"
material = "m"
shape = { type = "ring", center = [0.0, 0.0], inner_radius = 0.5, outer_radius = 1.0 }
spacing = 0.02
)");
  Generated<2> r(ring);
  EXPECT_NEAR(r.bodies[0].mass / (2.0 * std::numbers::pi * 0.75), 1.0, 5e-3);
  const Deck cyl = deckFrom("cylinder", 3, R"([[body]]
name = "rod"
material = "m"
shape = { type = "cylinder", base = [0.0, 0.0, 0.0], axis = [1.0, 1.0, 0.0], radius = 0.2, length = 1.0 }
spacing = 0.02
lattice = "hexagonal"
)");
  Generated<3> c(cyl);
  EXPECT_NEAR(c.bodies[0].mass / (2.0 * std::numbers::pi * 0.04), 1.0, 1e-2);
  const Deck ball = deckFrom("ball", 3, R"([[body]]
name = "ball"
material = "m"
shape = { type = "sphere", center = [0.0, 0.0, 0.0], radius = 0.5 }
spacing = 0.025
lattice_transform = [[2.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]]
)");
  Generated<3> b(ball);
  EXPECT_NEAR(b.bodies[0].mass / (2.0 * 4.0 / 3.0 * std::numbers::pi * 0.125), 1.0, 1e-2);
}

TEST(BodyGenerator, CylinderLayersSitHalfASpacingInsideItsEnds) {
  // A cylinder along z, an odd (75) and an even (76) number of spacings long: in both, layers
  // at (k + 1/2) dx from the base, the first half a spacing above it and the last half a spacing
  // below the top (a Taylor bar starts in contact with its wall whatever the resolution).
  for (const int layers : {75, 76}) {
    const double dx = 0.01, length = layers * dx;
    const Deck deck = deckFrom("cyl_layers", 3,
                               R"([[body]]
name = "rod"
material = "m"
shape = { type = "cylinder", base = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.035, length = )" +
                                   std::to_string(length) + R"( }
spacing = 0.01
)");
    Generated<3> g(deck);
    std::set<long> zs;
    for (const auto& x : g.store[g.f.x]) {
      const double k = x[2] / dx - 0.5;
      ASSERT_NEAR(k, std::round(k), 1e-9) << "a layer off the half-integer sites, " << layers;
      zs.insert(std::lround(k));
    }
    EXPECT_EQ(static_cast<int>(zs.size()), layers);
    EXPECT_EQ(*zs.begin(), 0);
    EXPECT_EQ(*zs.rbegin(), layers - 1);
  }
}

TEST(BodyGenerator, JitterDependsOnSeedAndIdOnly) {
  const std::string body = R"([[body]]
name = "a"
material = "m"
shape = { type = "box", min = [0.0, 0.0], max = [1.0, 1.0] }
spacing = 0.1
jitter = 0.2
)";
  Generated<2> a(deckFrom("jitter_a", 2, body)), b(deckFrom("jitter_b", 2, body));
  double maxShift = 0.0;
  for (std::size_t i = 0; i < a.store.localCount(); ++i) {
    ASSERT_EQ(a.store[a.f.x][i], b.store[b.f.x][i]); // reproducible
    const auto& x = a.store[a.f.x][i];
    const double cx = (std::floor(x[0] / 0.1) + 0.5) * 0.1,
                 cy = (std::floor(x[1] / 0.1) + 0.5) * 0.1;
    maxShift = std::max({maxShift, std::abs(x[0] - cx), std::abs(x[1] - cy)});
  }
  EXPECT_GT(maxShift, 0.01);      // it moved
  EXPECT_LE(maxShift, 0.2 * 0.1); // by at most jitter * spacing per axis
  EXPECT_NE(hashedUniform(3, 5, 0), hashedUniform(4, 5, 0));
}

// The first clamped-free mode: F(0) = F'(0) = 0 at the clamp, F''(L) = F'''(L) = 0 at the free end
// (no moment, no shear), and the tip moves at tip_speed. Derivatives by central differences of
// step L/1000 (truncation ~1e-6 relative; the tolerances are 1e-4 of the scale of each derivative).
TEST(BodyGenerator, CantileverModeIsClampedFreeBeamMode) {
  CantileverVelocityConfig c{{0.1, 0.0}, 0.2, 0.57};
  const auto v = [&](double x) { return app::cantileverModeVelocity(c, x); };
  const double L = c.length, x0 = c.root[0], d = L / 1000.0, k = 1.8751040687119611 / L;
  EXPECT_NEAR(v(x0 + L), 0.57, 1e-12);
  EXPECT_EQ(v(x0), 0.0);
  EXPECT_EQ(v(x0 - 0.05), 0.0); // the clamp does not move
  // F'(0) from the one-sided difference: F ~ k^2 x^2 near the clamp, so F(d)/d -> 0.
  EXPECT_LT(v(x0 + d) / d, 1e-2 * 0.57 * k);
  const double xe = x0 + L - 2 * d; // the derivatives at the free end, from inside
  const double f2 = (v(xe + d) - 2 * v(xe) + v(xe - d)) / (d * d);
  const double f3 =
      (v(xe + 2 * d) - 2 * v(xe + d) + 2 * v(xe - d) - v(xe - 2 * d)) / (2 * d * d * d);
  EXPECT_LT(std::abs(f2), 2e-2 * 0.57 * k * k); // O(d) away from the end: k^3 d ~ 2e-3 k^2
  EXPECT_LT(std::abs(f3), 2e-2 * 0.57 * k * k * k);
}

// A body that joins later (insert_time) is left out of the t = 0 particles but counted, and
// insertBody then makes exactly the particles generateBodies would have made at t = 0 (ids in
// deck order, the jitter of those ids), whatever stood in the grown rows before.
TEST(BodyGenerator, InsertedBodyIsTheBodyOfTimeZero) {
  const std::string bodies = R"([[body]]
name = "late"
material = "m"
shape = { type = "box", min = [0.0, 2.0], max = [1.0, 2.5] }
spacing = 0.1
velocity = [0.0, -3.0]
jitter = 0.1
@INSERT@
[[body]]
name = "early"
material = "m"
shape = { type = "box", min = [0.0, 0.0], max = [1.0, 1.0] }
spacing = 0.1
)";
  const auto with = [&](const std::string& insert) {
    std::string b = bodies;
    b.replace(b.find("@INSERT@"), 8, insert);
    return b;
  };
  Generated<2> all(deckFrom("insert_all", 2, with("")));
  const Deck waitingDeck = deckFrom("insert_wait", 2, with("insert_time = 1.0e-3"));
  Generated<2> g(waitingDeck);
  ASSERT_EQ(all.store.localCount(), 150u);
  ASSERT_EQ(g.store.localCount(), 100u); // only "early" at t = 0
  EXPECT_EQ(g.bodies[0].particles, 50u); // "late" counted all the same
  EXPECT_NEAR(g.bodies[0].mass, all.bodies[0].mass, 1e-15);
  EXPECT_EQ(g.store[g.f.id][0], 50u); // "early" keeps the ids after "late"'s
  // Rows left by earlier particles must not leak into the new ones.
  g.store.appendGhosts(80);
  for (std::size_t i = 100; i < 180; ++i) g.store[g.f.e][i] = 123.0;
  const app::BodySummary made = app::insertBody<2>(
      waitingDeck, {{materials::IdealGas{1.4}, std::nullopt}}, 0, 0, g.store, g.f);
  // The summary a new run makes of the body (count, mass and spacing: a restart's waiting body).
  ASSERT_EQ(made.particles, 50u);
  EXPECT_EQ(made.mass, all.bodies[0].mass);
  EXPECT_EQ(made.spacing, all.bodies[0].spacing);
  EXPECT_EQ(made.name, all.bodies[0].name);
  ASSERT_EQ(g.store.localCount(), 150u);
  for (std::size_t k = 0; k < 50; ++k) {
    const std::size_t i = 100 + k; // appended after the owned rows; generated first in `all`
    EXPECT_EQ(g.store[g.f.id][i], all.store[all.f.id][k]);
    EXPECT_EQ(g.store[g.f.x][i], all.store[all.f.x][k]);
    EXPECT_EQ(g.store[g.f.v][i], all.store[all.f.v][k]);
    EXPECT_EQ(g.store[g.f.m][i], all.store[all.f.m][k]);
    EXPECT_EQ(g.store[g.f.h][i], all.store[all.f.h][k]);
    EXPECT_EQ(g.store[g.f.e][i], 0.0);
    EXPECT_EQ(g.store[g.f.body][i], 0);
  }
}
