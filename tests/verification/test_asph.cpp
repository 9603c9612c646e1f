// Owen (2010), Sec. II-D and Fig. 5: the ideal-H algorithm on a square lattice and on the same
// lattice rotated by 45 degrees, stretched by 2 and compressed by 2 (decks/
// asph_distorted_lattice_2d.toml). Particles at rest; H relaxes over the run. Only particles
// well inside the lattice count (8 mm from the centre; the free edges are 20 mm away and the
// longest support 6 mm).
#include "RunDeck.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <map>
#include <numbers>

using namespace spall;
using namespace spall::verification;

namespace {

struct Shapes {
  std::size_t count = 0;
  double worstAngle = 0.0;                 // degrees between the long axis and 45 degrees
  double minRatio = 1e300, maxRatio = 0.0; // longest over shortest axis
  double minH = 1e300, maxH = 0.0;         // sqrt(h_long h_short), the equivalent round h
};

Shapes run(const std::vector<std::string>& overrides, const std::string& tag) {
  int rc = -1;
  const auto dir = runSpall(deckPath("asph_distorted_lattice_2d.toml"), overrides, tag, &rc);
  EXPECT_EQ(rc, 0);
  const auto s = io::readSnapshot(lastSnapshot(dir));
  const auto& x = s.fields.at("position");
  const auto& H = s.fields.at("smoothing");
  Shapes out;
  for (std::size_t i = 0; i < s.count; ++i) {
    if (std::hypot(x[2 * i], x[2 * i + 1]) > 8.0e-3) continue;
    Eigen::Matrix2d Hi;
    Hi << H[4 * i], H[4 * i + 1], H[4 * i + 2], H[4 * i + 3];
    EXPECT_NEAR(Hi(0, 1), Hi(1, 0), 1e-9 * Hi.norm());
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
    eig.computeDirect(Hi);
    const double lo = eig.eigenvalues()[0], hi = eig.eigenvalues()[1];
    const Eigen::Vector2d longAxis = eig.eigenvectors().col(0); // smallest 1/h: longest axis
    double angle = std::atan2(longAxis[1], longAxis[0]) * 180.0 / std::numbers::pi;
    angle = std::fmod(angle + 180.0, 180.0);
    ++out.count;
    out.worstAngle = std::max(out.worstAngle, std::abs(angle - 45.0));
    out.minRatio = std::min(out.minRatio, hi / lo);
    out.maxRatio = std::max(out.maxRatio, hi / lo);
    const double h = 1.0 / std::sqrt(lo * hi);
    out.minH = std::min(out.minH, h), out.maxH = std::max(out.maxH, h);
  }
  std::filesystem::remove_all(dir);
  std::printf("[ measured ] %s: %zu particles, axis ratio %.4f..%.4f, long axis within %.3f deg "
              "of 45, round-equivalent h %.4g..%.4g m\n",
              tag.c_str(), out.count, out.minRatio, out.maxRatio, out.worstAngle, out.minH,
              out.maxH);
  EXPECT_GT(out.count, 150u);
  return out;
}

const std::string kSquare = "body.lattice.lattice_transform=[[1.0, 0.0], [0.0, 1.0]]";
constexpr double kTargetH = 1.5e-3; // n_h = 1.5 spacings of 1 mm

} // namespace

// Uniform lattice: H isotropic, effective n_h = h/spacing within 2% of the target (measured:
// ratio 1.0000, n_h 1.500).
TEST(AsphLattice, UniformLatticeIsRoundWithTheTargetNodesPerH) {
  const Shapes s = run({kSquare}, "asph_square");
  EXPECT_LT(s.maxRatio, 1.01);
  EXPECT_NEAR(s.minH / kTargetH, 1.0, 0.02);
  EXPECT_NEAR(s.maxH / kTargetH, 1.0, 0.02);
}

// Distorted lattice (Fig. 5c): the long axis along the stretched lattice direction (45 degrees)
// within 5 degrees, axis ratio 4 (spacings 2 mm and 0.5 mm) within 10%, and the same area as on
// the square lattice (volume-preserving). Measured: 45.000 degrees, ratio 4.000, h 1.500 mm.
TEST(AsphLattice, DistortedLatticeAxesFollowTheDistortion) {
  const Shapes s = run({}, "asph_distorted");
  EXPECT_LT(s.worstAngle, 5.0);
  EXPECT_NEAR(s.minRatio / 4.0, 1.0, 0.10);
  EXPECT_NEAR(s.maxRatio / 4.0, 1.0, 0.10);
  EXPECT_NEAR(s.minH / kTargetH, 1.0, 0.05);
  EXPECT_NEAR(s.maxH / kTargetH, 1.0, 0.05);
}

// SPH on the same lattices (Fig. 5b): round whatever the distortion, and its size nearly the
// square lattice's: the volume per particle is unchanged. Not exactly: n_h is read off the kernel
// sum, and a round kernel over an elongated neighborhood sums differently (measured h 1.588 mm
// against 1.500 mm, +5.9%); 10% bounds that.
TEST(AsphLattice, SphStaysRoundOnTheDistortedLattice) {
  const Shapes square = run({"solver.method=sph", kSquare}, "sph_square");
  const Shapes distorted = run({"solver.method=sph"}, "sph_distorted");
  EXPECT_LT(distorted.maxRatio, 1.0 + 1e-9);
  EXPECT_NEAR(square.maxH / kTargetH, 1.0, 0.02);
  EXPECT_NEAR(distorted.maxH / square.maxH, 1.0, 0.10);
}

// The cubic lattice at rest in 3D (decks/asph_cubic_lattice_3d.toml): every ellipsoid round, the
// block's faces, edges and corners included, after ~280 steps, and the interior's size the target.
// With Owen's eta-frame shape correction the interior's median axis ratio was 1.95 by 1 ms (255
// steps) and 2.41 later (a runaway, ~11% a step); the Voronoi cell is a cube on every particle
// (measured: 1.0000 over all 8000, interior size 1.5000 mm). 1.01 is the 2D test's bound; 2% on
// the size as there.
TEST(AsphLattice, CubicLatticeStaysRoundIn3D) {
  int rc = -1;
  const auto dir = runSpall(deckPath("asph_cubic_lattice_3d.toml"), {}, "asph_cubic", &rc);
  ASSERT_EQ(rc, 0);
  const auto s = io::readSnapshot(lastSnapshot(dir));
  std::filesystem::remove_all(dir);
  EXPECT_NEAR(s.time, 1.5e-3, 1e-9);
  const auto& x = s.fields.at("position");
  const auto& H = s.fields.at("smoothing");
  double worstRatio = 0.0, minH = 1e300, maxH = 0.0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < s.count; ++i) {
    const Eigen::Matrix3d Hi = Eigen::Map<const Eigen::Matrix3d>(&H[9 * i]);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(0.5 * (Hi + Hi.transpose()));
    const Eigen::Vector3d mu = eig.eigenvalues();
    worstRatio = std::max(worstRatio, mu[2] / mu[0]);
    // Interior: farther than the longest support (3 mm) from the faces at 10 mm.
    if (std::max({std::abs(x[3 * i]), std::abs(x[3 * i + 1]), std::abs(x[3 * i + 2])}) > 6.5e-3)
      continue;
    ++interior;
    const double h = 1.0 / std::cbrt(mu.prod());
    minH = std::min(minH, h), maxH = std::max(maxH, h);
  }
  std::printf(
      "[ measured ] cubic lattice 3D: %zu particles, largest axis ratio %.4f; %zu interior, "
      "round-equivalent h %.4g..%.4g m\n",
      s.count, worstRatio, interior, minH, maxH);
  EXPECT_EQ(s.count, 8000u);
  EXPECT_LT(worstRatio, 1.01);
  EXPECT_GT(interior, 1000u);
  EXPECT_NEAR(minH / kTargetH, 1.0, 0.02);
  EXPECT_NEAR(maxH / kTargetH, 1.0, 0.02);
}

namespace {

// Row neighbors of the particles away from the rod's ends and sides: particles of the same
// initial lattice row (the stretch is homogeneous, rows stay rows) inside the particle's own
// support, eta = |H_i x_ij| < 2.
std::vector<int> rowNeighbors(const std::string& method) {
  int rc = -1;
  const auto dir = runSpall(deckPath("stretching_rod_2d.toml"), {"solver.method=" + method},
                            "rod_" + method, &rc);
  EXPECT_EQ(rc, 0);
  const auto s0 = io::readSnapshot(snapshotAt(dir, 0.0));
  const auto s = io::readSnapshot(lastSnapshot(dir));
  std::filesystem::remove_all(dir);
  EXPECT_NEAR(s.time, 2.0e-5, 1e-9);
  std::map<double, std::pair<double, double>> initial; // id -> initial (x, y)
  for (std::size_t i = 0; i < s0.count; ++i)
    initial[s0.fields.at("id")[i]] = {s0.fields.at("position")[2 * i],
                                      s0.fields.at("position")[2 * i + 1]};
  const auto& x = s.fields.at("position");
  const auto& H = s.fields.at("smoothing");
  const auto& id = s.fields.at("id");
  std::vector<int> counts;
  for (std::size_t i = 0; i < s.count; ++i) {
    const auto [xi0, yi0] = initial.at(id[i]);
    if (std::abs(xi0) > 0.012 || std::abs(yi0) > 0.003) continue;
    int n = 0;
    for (std::size_t j = 0; j < s.count; ++j) {
      if (j == i || std::abs(initial.at(id[j]).second - yi0) > 1e-6) continue;
      const double dx = x[2 * j] - x[2 * i], dy = x[2 * j + 1] - x[2 * i + 1];
      const double ex = H[4 * i] * dx + H[4 * i + 1] * dy,
                   ey = H[4 * i + 2] * dx + H[4 * i + 3] * dy;
      n += std::hypot(ex, ey) < 2.0;
    }
    counts.push_back(n);
  }
  std::sort(counts.begin(), counts.end());
  return counts;
}

} // namespace

// Owen's stretching rod (decks/stretching_rod_2d.toml): stretched to twice its length, SPH's round
// support (sized by the unchanged volume per particle) reaches only the next particle along the
// row on each side: 2 row neighbors, down from 4 at the start (+-1 and +-2 spacings inside the
// 3-spacing support). ASPH stretches the ellipse with the rod and keeps the second one.
// X = 3: a particle with at least 3 row neighbors still reaches two spacings along the stretch on
// at least one side, which SPH has lost everywhere (its 2 are the nearest on each side). Measured
// at 20 us over 576 particles: SPH 2 for every one, ASPH at least 4 for every one, so the margin
// is one neighbor on each side of X.
TEST(AsphRod, StretchingRodKeepsRowNeighborsWhereSphLosesThem) {
  const auto sph = rowNeighbors("sph"), asph = rowNeighbors("asph");
  ASSERT_FALSE(sph.empty());
  ASSERT_EQ(sph.size(), asph.size());
  const int sphMax = sph.back(), asphMedian = asph[asph.size() / 2];
  std::printf("[ measured ] row neighbors at 20 us over %zu particles: SPH %d..%d, ASPH %d..%d "
              "(median %d, %zu with fewer than 3)\n",
              sph.size(), sph.front(), sph.back(), asph.front(), asph.back(), asphMedian,
              static_cast<std::size_t>(
                  std::count_if(asph.begin(), asph.end(), [](int n) { return n < 3; })));
  constexpr int X = 3;
  EXPECT_LT(sphMax, X);
  EXPECT_GE(asph.front(), X);
  EXPECT_GE(asphMedian, 4);
}
