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
  // An ellipse with axes 3 mm and 0.75 mm (ratio 4, mean axis the volume scale) whose neighbors
  // ask it to shrink ten times, isotropic in its own frame (no shape change): its mean axis stops
  // at half the volume scale and its axis ratio is kept.
  Tensor<2> H = Tensor<2>::Zero();
  H(0, 0) = 1.0 / 3.0e-3, H(1, 1) = 1.0 / 0.75e-3;
  double h = 3.0e-3;
  const Tensor<2> isotropic = Tensor<2>::Identity();
  Tensor<2> psi2x = Tensor<2>::Zero(); // its axes along x and y
  psi2x(0, 0) = 1.0, psi2x(1, 1) = 2.0;
  idealHTensor<2>(H, h, 0.1, isotropic, psi2x, kM, kRho, kLimits);
  const double meanAxis = 1.0 / std::sqrt(H.determinant());
  EXPECT_NEAR(meanAxis, 0.5 * kVolumeH, 1e-12 * kVolumeH);
  EXPECT_NEAR(H(1, 1) / H(0, 0), 4.0, 1e-12);
  EXPECT_NEAR(h, 1.0 / H(0, 0), 1e-18);
}
