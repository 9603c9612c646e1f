// Graded spacing (app/GradedSites.cpp): the layers, the mass each shape holds, no overlaps or gaps
// at the transitions, h and the local spacing, and the deck's checks of a grading table.
#include "../../../src/app/GradedSites.hpp"
#include "spall/app/BodyGenerator.hpp"

#include "unit/app/GeneratedBodies.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <numbers>
#include <random>

using namespace spall;

namespace {

constexpr double kPiGraded = std::numbers::pi;

std::filesystem::path gradedDeck(const std::string& name, int dim, const std::string& body,
                                 const std::string& extra = "") {
  const auto path = std::filesystem::temp_directory_path() / ("spall_graded_" + name + ".toml");
  std::ofstream(path)
      << "[run]\ndimension = " << dim << "\nend_time = 1.0\n"
      << extra
      << "[[material]]\nname = \"m\"\ndensity = 2.0\neos = { type = \"ideal_gas\", gamma = 1.4 }\n"
      << "[[body]]\nname = \"b\"\nmaterial = \"m\"\n"
      << body << "[output]\ndirectory = \"unused\"\n";
  return path;
}

// With each particle's own spacing, h / n_h (n_h = 1.5, the default).
template <int Dim> struct GradedBody : fixtures::GeneratedBodies<Dim> {
  using fixtures::GeneratedBodies<Dim>::GeneratedBodies;
  std::size_t n() const { return this->store.localCount(); }
  Vec<Dim> x(std::size_t i) const { return this->store[this->f.x][i]; }
  double local(std::size_t i) const { return this->store[this->f.h][i] / 1.5; }
};

// The nearest other particle's distance over each particle's own spacing, at least (overlaps)
// and at most (holes) over the body; and the largest distance from a point of the body, sampled
// away from its surface, to the nearest particle, over that particle's spacing (gaps).
template <int Dim> struct PackingStats {
  double closest = 1e300, farthestNearest = 0.0, gap = 0.0;
};
template <int Dim, class Inside>
PackingStats<Dim> packingOf(const GradedBody<Dim>& g, Inside&& inside) {
  PackingStats<Dim> p;
  const std::size_t n = g.n();
  for (std::size_t i = 0; i < n; ++i) {
    double best = 1e300;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) best = std::min(best, (g.x(i) - g.x(j)).norm());
    p.closest = std::min(p.closest, best / g.local(i));
    if (inside(g.x(i), 2.0 * g.local(i)))
      p.farthestNearest = std::max(p.farthestNearest, best / g.local(i));
  }
  std::mt19937_64 rng(5);
  Vec<Dim> lo = g.x(0), hi = g.x(0);
  for (std::size_t i = 0; i < n; ++i) lo = lo.cwiseMin(g.x(i)), hi = hi.cwiseMax(g.x(i));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int s = 0; s < 4000; ++s) {
    Vec<Dim> y;
    for (int d = 0; d < Dim; ++d) y[d] = lo[d] + u(rng) * (hi[d] - lo[d]);
    std::size_t k = 0;
    double best = 1e300;
    for (std::size_t j = 0; j < n; ++j)
      if (const double r = (y - g.x(j)).norm(); r < best) best = r, k = j;
    if (inside(y, 2.0 * g.local(k))) p.gap = std::max(p.gap, best / g.local(k));
  }
  return p;
}

} // namespace

TEST(GradedSites, LayersGrowByTheRatioUpToTheMaximumAndFitAnEnd) {
  const auto layers = app::sites::gradedLayers(1.0, 3.0, 1.1, 2.0, 20.0);
  ASSERT_GT(layers.size(), 10u);
  double b = 0.0;
  for (std::size_t j = 0; j < layers.size(); ++j) {
    EXPECT_DOUBLE_EQ(layers[j].start, b); // contiguous: no gap, no overlap
    b += layers[j].thickness;
    // Three layers of the spacing within 3; then 1.1, 1.21, ... up to 2.
    const double expected = j < 3 ? 1.0 : std::min(2.0, std::pow(1.1, static_cast<double>(j - 2)));
    EXPECT_NEAR(layers[j].thickness, expected, 1e-12) << "layer " << j;
  }
  EXPECT_GE(b, 20.0);
  auto fitted = layers;
  app::sites::fitLayers(fitted, 3.0, 1.0, 20.0);
  EXPECT_NEAR(fitted.back().start + fitted.back().thickness, 20.0, 1e-12);
  for (std::size_t j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(fitted[j].thickness, 1.0); // fine kept
  // The graded layers stretched by one factor, within the last layer's share of the span.
  const double f = fitted[5].thickness / layers[5].thickness;
  EXPECT_NEAR(f, 1.0, 2.0 / 17.0);
  for (std::size_t j = 3; j < fitted.size(); ++j)
    EXPECT_NEAR(fitted[j].thickness, f * layers[j].thickness, 1e-12);
}

// A box graded from a plane on one of its faces holds whole layers and whole columns: its mass
// is rho V to round-off in 1D, 2D and 3D, as a uniform box's.
TEST(GradedSites, BoxFromAPlaneHoldsItsMassExactly) {
  const Deck d1 =
      loadDeck(gradedDeck("box1", 1, R"(shape = { type = "box", min = [0.0], max = [1.0] }
spacing = 0.01
grading = { within = 0.2, ratio = 1.1, max_spacing = 0.05, point = [0.0] }
)")
                   .string());
  GradedBody<1> g1(d1);
  EXPECT_NEAR(g1.bodies[0].mass, 2.0, 1e-12);
  // 20 layers of the spacing, ~17 growing ones, then ~14 of 0.05: far fewer than 100.
  EXPECT_LT(g1.n(), 60u);
  EXPECT_NEAR(g1.local(0), 0.01, 1e-15);
  const Deck d2 =
      loadDeck(gradedDeck("box2", 2, R"(shape = { type = "box", min = [0.0, 0.0], max = [1.0, 0.5] }
spacing = 0.01
grading = { within = 0.1, ratio = 1.1, max_spacing = 0.04, plane = { point = [0.0, 0.0], normal = [1.0, 0.0] } }
)")
                   .string());
  GradedBody<2> g2(d2);
  EXPECT_NEAR(g2.bodies[0].mass, 2.0 * 0.5, 1e-12);
  const Deck d3 =
      loadDeck(gradedDeck("box3", 3,
                          R"(shape = { type = "box", min = [0.0, 0.0, 0.0], max = [0.3, 0.2, 0.2] }
spacing = 0.01
grading = { within = 0.05, ratio = 1.2, max_spacing = 0.04, plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, -1.0] } }
)")
                   .string());
  GradedBody<3> g3(d3);
  EXPECT_NEAR(g3.bodies[0].mass, 2.0 * 0.3 * 0.2 * 0.2, 1e-12);
}

// rz: a cylinder graded from its axis (a line in the half-plane) holds rho pi R^2 L to
// round-off (whole strips of whole rings); graded from a point on the axis (half rings) a ball
// holds 4/3 pi R^3 within the clipped outer layer's share.
TEST(GradedSites, AxisymmetricBodiesHoldTheirMass) {
  const Deck line = loadDeck(
      gradedDeck("rzline", 2, R"(shape = { type = "box", min = [0.0, 0.0], max = [0.1, 0.05] }
spacing = 0.001
grading = { within = 0.01, ratio = 1.05, max_spacing = 0.004, line = { point = [0.0, 0.0], direction = [0.0, 1.0] } }
)",
                 "geometry = \"rz\"\n")
          .string());
  GradedBody<2> gl(line);
  EXPECT_NEAR(gl.bodies[0].mass / (2.0 * kPiGraded * 0.01 * 0.05), 1.0, 1e-12);
  const Deck point = loadDeck(
      gradedDeck("rzpoint", 2, R"(shape = { type = "sphere", center = [0.0, 0.0], radius = 0.05 }
spacing = 0.001
grading = { within = 0.01, ratio = 1.05, max_spacing = 0.003, point = [0.0, 0.0] }
)",
                 "geometry = \"rz\"\n")
          .string());
  GradedBody<2> gp(point);
  // The layers fit the radius exactly; the half rings' mass sum 2 pi r dA over each half
  // annulus, exact for its volume to O((s/r)^2) of the ring's: ~1e-4 over the ball.
  EXPECT_NEAR(gp.bodies[0].mass / (2.0 * 4.0 / 3.0 * kPiGraded * std::pow(0.05, 3)), 1.0, 1e-3);
  for (std::size_t i = 0; i < gp.n(); ++i) ASSERT_GT(gp.x(i)[0], 0.0);
}

// Rings about a point (2D), cylinders about a line and shells about a point (3D): the mass of a
// concentric shape, and the packing. No two particles closer than 0.8 of the smaller local
// spacing (a cubic lattice: 1.0; the innermost ring of three: 0.87); no particle's nearest
// neighbor farther than 1.25 of its spacing; no point of the body farther than 0.9 of the local
// spacing from a particle (a cubic lattice's deepest hole: 0.87 in 3D, 0.71 in 2D).
TEST(GradedSites, RoundReferencesPackWithoutOverlapsOrGaps) {
  const Deck disk = loadDeck(
      gradedDeck("disk", 2, R"(shape = { type = "sphere", center = [0.1, 0.0], radius = 0.05 }
spacing = 0.002
grading = { within = 0.01, ratio = 1.1, max_spacing = 0.006, point = [0.1, 0.0] }
)")
          .string());
  GradedBody<2> gd(disk);
  EXPECT_NEAR(gd.bodies[0].mass / (2.0 * kPiGraded * 0.05 * 0.05), 1.0, 1e-12); // whole annuli
  const auto pd = packingOf(gd, [](const Vec<2>& y, double margin) {
    return (y - Vec<2>(0.1, 0.0)).norm() < 0.05 - margin;
  });
  EXPECT_GT(pd.closest, 0.8);
  EXPECT_LT(pd.farthestNearest, 1.25);
  EXPECT_LT(pd.gap, 0.9);

  const Deck rod = loadDeck(
      gradedDeck(
          "rod", 3,
          R"(shape = { type = "cylinder", base = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.03, length = 0.02 }
spacing = 0.002
grading = { within = 0.006, ratio = 1.2, max_spacing = 0.005, line = { point = [0.0, 0.0, -1.0], direction = [0.0, 0.0, 2.0] } }
)")
          .string());
  GradedBody<3> gr(rod);
  EXPECT_NEAR(gr.bodies[0].mass / (2.0 * kPiGraded * 0.03 * 0.03 * 0.02), 1.0, 1e-12);
  const auto pr = packingOf(gr, [](const Vec<3>& y, double margin) {
    return std::hypot(y[0], y[1]) < 0.03 - margin && y[2] > margin && y[2] < 0.02 - margin;
  });
  EXPECT_GT(pr.closest, 0.8);
  EXPECT_LT(pr.farthestNearest, 1.25);
  EXPECT_LT(pr.gap, 0.9);

  const Deck ball = loadDeck(
      gradedDeck("ball", 3, R"(shape = { type = "sphere", center = [0.0, 0.0, 0.0], radius = 0.03 }
spacing = 0.002
grading = { within = 0.008, ratio = 1.15, max_spacing = 0.005, point = [0.0, 0.0, 0.0] }
)")
          .string());
  GradedBody<3> gb(ball);
  EXPECT_NEAR(gb.bodies[0].mass / (2.0 * 4.0 / 3.0 * kPiGraded * std::pow(0.03, 3)), 1.0, 1e-12);
  const auto pb =
      packingOf(gb, [](const Vec<3>& y, double margin) { return y.norm() < 0.03 - margin; });
  // A Fibonacci shell packs less evenly near its poles: its closest pair, 0.74 of the spacing.
  EXPECT_GT(pb.closest, 0.7);
  EXPECT_LT(pb.farthestNearest, 1.25);
  EXPECT_LT(pb.gap, 0.9);
  // The spacing is the body's within `within` and grows to max_spacing (fitted: within 10%).
  double finest = 1e300, coarsest = 0.0;
  for (std::size_t i = 0; i < gb.n(); ++i) {
    // (a shell of n sites stands for its volume over n: the innermost, of 3, for 0.87 s^3)
    if (gb.x(i).norm() < 0.008 - 0.002) {
      EXPECT_NEAR(gb.local(i), 0.002, 0.05 * 0.002);
    }
    finest = std::min(finest, gb.local(i)), coarsest = std::max(coarsest, gb.local(i));
  }
  EXPECT_NEAR(coarsest / 0.005, 1.0, 0.1);
}

// A plane at an angle to a box: the layers are clipped like any lattice; the box's mass within
// the clipped surface layer's share, the packing as above.
TEST(GradedSites, InclinedPlaneInABox) {
  const Deck d = loadDeck(
      gradedDeck("inclined", 2, R"(shape = { type = "box", min = [0.0, 0.0], max = [0.1, 0.06] }
spacing = 0.002
grading = { within = 0.01, ratio = 1.1, max_spacing = 0.006, plane = { point = [0.05, 0.03], normal = [1.0, 1.0] } }
)")
          .string());
  GradedBody<2> g(d);
  // The surface's clipped sites: O(perimeter x coarse spacing / 2) / area, ~5%, and unbiased.
  EXPECT_NEAR(g.bodies[0].mass / (2.0 * 0.1 * 0.06), 1.0, 0.03);
  const auto p = packingOf(g, [](const Vec<2>& y, double m) {
    return y[0] > m && y[0] < 0.1 - m && y[1] > m && y[1] < 0.06 - m;
  });
  EXPECT_GT(p.closest, 0.8);
  EXPECT_LT(p.gap, 0.9);
}

TEST(GradedSites, DeckChecksTheGradingTable) {
  const auto fails = [](const std::string& name, int dim, const std::string& body,
                        const std::string& what, const std::string& extra = "") {
    const auto path = gradedDeck(name, dim, body, extra);
    try {
      loadDeck(path.string());
      ADD_FAILURE() << name << ": no error";
    } catch (const DeckError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string shape = "shape = { type = \"box\", min = [0.0, 0.0], max = [1.0, 1.0] }\n"
                            "spacing = 0.1\n";
  fails("two", 2,
        shape + "grading = { within = 0.2, max_spacing = 0.4, point = [0.0, 0.0], "
                "plane = { point = [0.0, 0.0], normal = [1.0, 0.0] } }\n",
        "exactly one reference");
  fails("none", 2, shape + "grading = { within = 0.2, max_spacing = 0.4 }\n", "exactly one");
  fails("coarse", 2, shape + "grading = { within = 0.2, max_spacing = 0.05, point = [0.0, 0.0] }\n",
        "below the body's spacing");
  fails("zero", 2,
        shape + "grading = { within = 0.2, max_spacing = 0.4, line = { point = [0.0, 0.0], "
                "direction = [0.0, 0.0] } }\n",
        "zero vector");
  fails("hex", 2,
        shape + "lattice = \"hexagonal\"\ngrading = { within = 0.2, max_spacing = 0.4, point = "
                "[0.0, 0.0] }\n",
        "cubic lattice");
  fails("ratio", 2,
        shape + "grading = { within = 0.2, ratio = 3.0, max_spacing = 0.4, point = [0.0, 0.0] }\n",
        "ratio");
  fails("mpm", 2, shape + "grading = { within = 0.2, max_spacing = 0.4, point = [0.0, 0.0] }\n",
        "graded body", "[solver]\nmethod = \"mpm\"\n");
  fails("line1d", 1,
        "shape = { type = \"box\", min = [0.0], max = [1.0] }\nspacing = 0.1\ngrading = { within "
        "= 0.2, max_spacing = 0.4, line = { point = [0.0], direction = [1.0] } }\n",
        "run.dimension 2 or 3");
}

// A reference far from the body would lay its layers all the way: refused before they are laid.
TEST(GradedSites, FarReferenceIsADeckError) {
  const Deck d =
      loadDeck(gradedDeck("far", 2, R"(shape = { type = "box", min = [0.0, 0.0], max = [1.0, 1.0] }
spacing = 0.01
grading = { within = 0.1, max_spacing = 0.02, point = [1.0e9, 0.0] }
)")
                   .string());
  try {
    GradedBody<2> g(d);
    ADD_FAILURE() << "no error";
  } catch (const DeckError& e) {
    EXPECT_NE(std::string(e.what()).find("far side of the body"), std::string::npos) << e.what();
  }
}
