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
  // rectangle (second moment diag(a^2, b^2)/12): the axes move towards the cell's ratio, 4, the
  // long one along x, and the mean axis stops at half the volume scale.
  Tensor<2> H = Tensor<2>::Identity() / kVolumeH;
  double h = kVolumeH;
  Tensor<2> cell = Tensor<2>::Zero();
  cell(0, 0) = 4.0e-6 / 12.0, cell(1, 1) = 0.25e-6 / 12.0;
  idealHTensor<2>(H, h, 0.1, &cell, kM, kRho, kLimits);
  // One step: the shape is relaxed, half the correction's logarithm (each axis by sqrt(2)) capped
  // at 20% per axis, so the ratio is 1.2^2 (exact up to rounding).
  EXPECT_NEAR(1.0 / std::sqrt(H.determinant()), 0.5 * kVolumeH, 1e-12 * kVolumeH);
  EXPECT_NEAR(H(1, 1) / H(0, 0), 1.44, 1e-12);
  EXPECT_NEAR(H(0, 1), 0.0, 1e-12 * H(0, 0));
  // Repeated, the log error halves once within the cap: after 60 steps 2^-50 of it remains.
  for (int step = 1; step < 60; ++step) idealHTensor<2>(H, h, 0.1, &cell, kM, kRho, kLimits);
  EXPECT_NEAR(1.0 / std::sqrt(H.determinant()), 0.5 * kVolumeH, 1e-12 * kVolumeH);
  EXPECT_NEAR(H(1, 1) / H(0, 0), 4.0, 1e-12);
  EXPECT_NEAR(H(0, 1), 0.0, 1e-12 * H(0, 0));
  EXPECT_NEAR(h, 1.0 / H(0, 0), 1e-18);
}

TEST(IdealH, AsphShapeStepIsRelaxedAndCapped) {
  // The shape step, the geodesic from the present shape towards the cell's, taken from an
  // ellipse at 30 degrees (axis ratio 2) towards a square cell: the correction's ratios are
  // sqrt(2) and 1/sqrt(2) along the ellipse's axes, half their logarithm 2^(+-1/4) = 1.189 is
  // below the 20% cap, so the axis ratio goes 2 -> 2^(1/2) with the directions kept, and the
  // next step to 2^(1/4); a 4-to-1 ellipse takes the capped step to 4/1.44.
  const double c = std::cos(0.5236), s = std::sin(0.5236);
  Tensor<2> R;
  R << c, -s, s, c;
  const Tensor<2> square = Tensor<2>::Identity() * (1.0e-6 / 12.0);
  for (const double ratio : {2.0, 4.0}) {
    // Axes 2 mm and 2/ratio mm: within the floor (0.75 mm) and the cap (3 mm) before and after.
    Tensor<2> H = R * Vec<2>(1.0 / 2.0e-3, ratio / 2.0e-3).asDiagonal() * R.transpose();
    double h = 0.0;
    idealHTensor<2>(H, h, 1.0, &square, kM, kRho, kLimits);
    const SymmetricEigen<2> e = symmetricEigen<2>(H);
    const double expected = ratio == 2.0 ? std::sqrt(2.0) : 4.0 / 1.44;
    EXPECT_NEAR(e.values[1] / e.values[0], expected, 1e-12) << ratio;
    // The long axis (the smaller eigenvalue's vector) still at 30 degrees.
    EXPECT_NEAR(std::abs(e.vectors.col(0).dot(R.col(0))), 1.0, 1e-12) << ratio;
    // The size (the determinant) unchanged at factor 1.
    EXPECT_NEAR(std::sqrt(H.determinant()) * 2.0e-3, std::sqrt(ratio), 1e-12) << ratio;
  }
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

TEST(IdealH, AsphShapeStepIn3DHalvesTheLogOfEachAxisRatio) {
  // 3D (eigen-decompositions; 2D has closed forms): an ellipsoid with axes 1.5, 1, 1 mm turned
  // about (1, 1, 1) towards a cubic cell: the unit-determinant shape's eigenvalues (2/3, 1, 1)
  // over (2/3)^(1/3), corrected by their inverse square roots (1.145, 0.935, 0.935: within the
  // 20% cap), become their square roots: the axis ratio 1.5 -> sqrt(1.5), the long axis where it
  // was, the size kept.
  const Eigen::AngleAxisd turn(0.7, Vec<3>(1.0, 1.0, 1.0).normalized());
  const Tensor<3> R = turn.toRotationMatrix();
  Tensor<3> H = R * Vec<3>(1.0 / 1.5e-3, 1.0 / 1.0e-3, 1.0 / 1.0e-3).asDiagonal() * R.transpose();
  const double det = H.determinant();
  const Tensor<3> cube = Tensor<3>::Identity() * (1.0e-6 / 12.0);
  double h = 0.0;
  const SmoothingLimits limits{kNh, 0.0, kInf, 0.0, kInf, 10.0}; // no bound on the size
  idealHTensor<3>(H, h, 1.0, &cube, kM, kRho, limits);
  // 1e-8: Eigen's direct 3x3 solver (trigonometric) resolves a double eigenvalue to ~2e-9.
  const SymmetricEigen<3> e = symmetricEigen<3>(H);
  EXPECT_NEAR(e.values[2] / e.values[0], std::sqrt(1.5), 1e-8);
  EXPECT_NEAR(e.values[2] / e.values[1], 1.0, 1e-8);
  EXPECT_NEAR(std::abs(e.vectors.col(0).dot(R.col(0))), 1.0, 1e-8);
  EXPECT_NEAR(H.determinant() / det, 1.0, 1e-12);
  EXPECT_NEAR(h, 1.0 / e.values[0], 1e-15);
}
