// Owen (2010), Sec. II-D and Fig. 5: the ideal-H algorithm on a square lattice and on the same
// lattice rotated by 45 degrees, stretched by 2 and compressed by 2 (decks/
// asph_distorted_lattice_2d.toml). Particles at rest; H relaxes over the run. Only particles
// well inside the lattice count (8 mm from the centre; the free edges are 20 mm away and the
// longest support 6 mm).
#include "RunDeck.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
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
