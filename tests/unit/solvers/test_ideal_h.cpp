// The limits of the ideal smoothing scale (solvers/IdealH.hpp) relative to a particle's own
// volume: h between h_min_ratio and h_max_ratio times n_h (m/rho)^(1/nu), for SPH's h and for
// ASPH's mean axis.
#include "spall/solvers/IdealH.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace spall;
using namespace spall::solvers;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// 2D: a particle of 1 mm^2 at n_h 1.5: its own-volume scale is 1.5 mm.
constexpr double kM = 1.0e-3, kRho = 1000.0, kNh = 1.5, kVolumeH = 1.5e-3;
const SmoothingLimits kLimits{kNh, 0.0, kInf, 0.5, 2.0, 10.0};

} // namespace

TEST(IdealH, SphStaysWithinItsVolumeRatios) {
  // Neighbors piled up (the size factor asks for a tenth) or thinned out (ten times): h stops
  // at 0.5 and 2 times the volume scale; within them it follows the factor. Exact up to the
  // rounding of the products.
  EXPECT_NEAR(idealH<2>(kVolumeH, 0.1, kM, kRho, kLimits), 0.5 * kVolumeH, 1e-18);
  EXPECT_NEAR(idealH<2>(kVolumeH, 10.0, kM, kRho, kLimits), 2.0 * kVolumeH, 1e-18);
  EXPECT_NEAR(idealH<2>(kVolumeH, 0.9, kM, kRho, kLimits), 0.9 * kVolumeH, 1e-18);
  // Without the floor (ratio 0) the piled-up neighbors take h down with them.
  SmoothingLimits none = kLimits;
  none.hMinRatio = 0.0;
  EXPECT_NEAR(idealH<2>(kVolumeH, 0.1, kM, kRho, none), 0.1 * kVolumeH, 1e-18);
}

TEST(IdealH, AsphMeanAxisStaysAboveItsVolumeFloor) {
  // A round H whose neighbors ask it to shrink ten times and whose Voronoi cell is a 2 by 0.5
  // rectangle (second moment diag(a^2, b^2)/12): the axes take the cell's ratio, 4, the long one
  // along x, and the mean axis stops at half the volume scale.
  Tensor<2> H = Tensor<2>::Identity() / kVolumeH;
  double h = kVolumeH;
  Tensor<2> cell = Tensor<2>::Zero();
  cell(0, 0) = 4.0e-6 / 12.0, cell(1, 1) = 0.25e-6 / 12.0;
  idealHTensor<2>(H, h, 0.1, &cell, kM, kRho, kLimits);
  const double meanAxis = 1.0 / std::sqrt(H.determinant());
  EXPECT_NEAR(meanAxis, 0.5 * kVolumeH, 1e-12 * kVolumeH);
  EXPECT_NEAR(H(1, 1) / H(0, 0), 4.0, 1e-12);
  EXPECT_NEAR(H(0, 1), 0.0, 1e-12 * H(0, 0));
  EXPECT_NEAR(h, 1.0 / H(0, 0), 1e-18);
}

TEST(IdealH, AsphOpenCellKeepsItsShape) {
  // No closed cell (a free surface): an ellipse at 30 degrees with axes 3 and 0.75 mm keeps its
  // axes' directions and ratio while its size follows the factor (0.8: every axis 0.8 times as
  // long, the mean 1.2 mm above its floor of 0.75 mm, the longest 2.4 mm below its cap of 3 mm).
  const double c = std::cos(0.5236), s = std::sin(0.5236);
  Tensor<2> R;
  R << c, -s, s, c;
  const Vec<2> axes(1.0 / 3.0e-3, 1.0 / 0.75e-3);
  Tensor<2> H = R * axes.asDiagonal() * R.transpose();
  const Tensor<2> before = H;
  double h = 3.0e-3;
  idealHTensor<2>(H, h, 0.8, nullptr, kM, kRho, kLimits);
  EXPECT_LT((H - before / 0.8).norm(), 1e-12 * before.norm());
  EXPECT_NEAR(h, 2.4e-3, 1e-15);
}
