// Voronoi cells of a particle among its neighbors (solvers/VoronoiCell.hpp): lattices whose cells
// are known exactly, a free surface closed by the mirror rule, and an irregular neighborhood
// against a Monte Carlo integration of the nearest-particle region.
#include "spall/solvers/VoronoiCell.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace spall;
using namespace spall::solvers;

namespace {

// The lattice points A k, k in {-3..3}^Dim without 0, that satisfy `keep`.
template <int Dim, class Keep> std::vector<Vec<Dim>> lattice(const Tensor<Dim>& A, Keep keep) {
  std::vector<Vec<Dim>> out;
  Eigen::Matrix<int, Dim, 1> k;
  const int n = 7;
  int total = 1;
  for (int d = 0; d < Dim; ++d) total *= n;
  for (int c = 0; c < total; ++c) {
    int rest = c;
    for (int d = 0; d < Dim; ++d) k[d] = rest % n - 3, rest /= n;
    if (k.isZero()) continue;
    const Vec<Dim> p = A * k.template cast<double>();
    if (keep(k)) out.push_back(p);
  }
  return out;
}

template <int Dim>
CellMoments<Dim> cellOf(const std::vector<Vec<Dim>>& d, double halfWidth, bool* closed = nullptr) {
  VoronoiCell<Dim> cell;
  const bool ok = voronoiCell<Dim>(cell, d, halfWidth);
  if (closed) *closed = ok;
  return cell.moments();
}

Tensor<3> rotation() {
  return (Eigen::AngleAxisd(0.7, Vec<3>(1.0, 2.0, 3.0).normalized()) *
          Eigen::AngleAxisd(0.3, Vec<3>(0.0, 0.0, 1.0)))
      .toRotationMatrix();
}

} // namespace

// A rectangular lattice with spacings a, b, c: the cell is the box a x b x c, second moment
// diag(a^2, b^2, c^2)/12; the lattice rotated, the cell rotated with it. Tolerance: round-off of
// a few dozen clips (1e-12 relative; the ties at the box's edges and corners cut slivers of at
// most that size).
TEST(VoronoiCell, RectangularLatticeGivesItsBox) {
  const Vec<3> spacing(2.0e-3, 1.0e-3, 0.5e-3);
  for (const Tensor<3>& R : {Tensor<3>(Tensor<3>::Identity()), rotation()}) {
    const Tensor<3> A = R * spacing.asDiagonal();
    bool closed = false;
    const auto c = cellOf<3>(lattice<3>(A, [](const auto&) { return true; }), 6.0e-3, &closed);
    EXPECT_TRUE(closed);
    EXPECT_NEAR(c.volume, 1.0e-9, 1e-12 * 1.0e-9);
    EXPECT_LT(c.centroid.norm(), 1e-12 * 1.0e-3);
    const Tensor<3> expected = R * (spacing.cwiseAbs2() / 12.0).asDiagonal() * R.transpose();
    EXPECT_LT((c.second - expected).norm(), 1e-12 * expected.norm());
  }
}

// The cubic lattice: a cube, isotropic second moment d^2/12 (what keeps ASPH round there).
TEST(VoronoiCell, CubicLatticeIsIsotropic) {
  const double d = 1.0e-3;
  const auto c = cellOf<3>(
      lattice<3>(Tensor<3>(d * Tensor<3>::Identity()), [](const auto&) { return true; }), 3.0e-3);
  EXPECT_NEAR(c.volume, d * d * d, 1e-12 * d * d * d);
  EXPECT_LT((c.second - (d * d / 12.0) * Tensor<3>::Identity()).norm(), 1e-12 * d * d);
}

// The hexagonal lattice (spacing d): a regular hexagon of inradius d/2, area (sqrt 3/2) d^2,
// isotropic second moment 5 s^2/24 with side s = d/sqrt 3.
TEST(VoronoiCell, HexagonalLatticeIsARegularHexagon) {
  const double d = 1.0e-3;
  Tensor<2> A;
  A << d, 0.5 * d, 0.0, 0.5 * std::sqrt(3.0) * d;
  const auto c = cellOf<2>(lattice<2>(A, [](const auto&) { return true; }), 3.0e-3);
  EXPECT_NEAR(c.volume, 0.5 * std::sqrt(3.0) * d * d, 1e-12 * d * d);
  const double s2 = d * d / 3.0;
  EXPECT_LT((c.second - (5.0 * s2 / 24.0) * Tensor<2>::Identity()).norm(), 1e-12 * d * d);
}

// A free surface: the lattice only on one side (k_z <= 0) leaves the Voronoi cell open upwards;
// the mirrored neighbors close it at the inward half-spacing, which gives back the cube. Also at an
// edge (k_y <= 0 and k_z <= 0) and a corner of the lattice (k <= 0 on every axis). Without
// neighbors there is nothing to mirror and the cell stays open.
TEST(VoronoiCell, FreeSurfaceIsClosedByMirroring) {
  const double d = 1.0e-3;
  const Tensor<3> A = d * rotation();
  for (int open = 1; open <= 3; ++open) {
    bool closed = false;
    const auto c = cellOf<3>(lattice<3>(A,
                                        [open](const auto& k) {
                                          for (int a = 3 - open; a < 3; ++a)
                                            if (k[a] > 0) return false;
                                          return true;
                                        }),
                             3.0e-3, &closed);
    EXPECT_TRUE(closed) << open << " open sides";
    EXPECT_NEAR(c.volume, d * d * d, 1e-9 * d * d * d) << open << " open sides";
    EXPECT_LT((c.second - (d * d / 12.0) * Tensor<3>::Identity()).norm(), 1e-9 * d * d)
        << open << " open sides";
  }
  bool closed = true;
  cellOf<3>({}, 3.0e-3, &closed);
  EXPECT_FALSE(closed);
}

// Irregular neighbors (a jittered cubic lattice): volume, centroid (the particle: the cell is
// symmetric about it) and second moment against a Monte Carlo integral of the points x that are,
// and whose mirror image -x is, nearer the particle than any neighbor. With N = 400000
// samples in a box of 8 times the cell's volume, the volume's relative standard error is
// sqrt(7/N) ~ 0.4%, and the moments' about as large: 2% is five standard errors.
TEST(VoronoiCell, IrregularCellMatchesMonteCarlo) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2), unit(-1.0, 1.0);
  std::vector<Vec<3>> d;
  for (const auto& p :
       lattice<3>(Tensor<3>(Tensor<3>::Identity()), [](const auto&) { return true; }))
    d.push_back(p + Vec<3>(jitter(rng), jitter(rng), jitter(rng)));
  bool closed = false;
  const auto c = cellOf<3>(d, 3.0, &closed);
  ASSERT_TRUE(closed);
  const int N = 400000;
  double vol = 0.0;
  Vec<3> m1 = Vec<3>::Zero();
  Tensor<3> m2 = Tensor<3>::Zero();
  for (int s = 0; s < N; ++s) {
    const Vec<3> x(unit(rng), unit(rng), unit(rng)); // the box [-1, 1]^3, volume 8
    bool nearest = true;
    for (const auto& p : d)
      nearest = nearest && (x - p).squaredNorm() >= x.squaredNorm() &&
                (x + p).squaredNorm() >= x.squaredNorm();
    if (!nearest) continue;
    vol += 1.0, m1 += x, m2 += x * x.transpose();
  }
  const Vec<3> centroid = m1 / vol;
  const Tensor<3> second = m2 / vol - centroid * centroid.transpose();
  EXPECT_NEAR(c.volume, 8.0 * vol / N, 0.02 * c.volume);
  EXPECT_LT((c.centroid - centroid).norm(), 0.02 * std::cbrt(c.volume));
  EXPECT_LT(c.centroid.norm(), 1e-12 * std::cbrt(c.volume));
  EXPECT_LT((c.second - second).norm(), 0.02 * c.second.norm());
}

// A cubic lattice displaced by tiny amounts (1e-15 to 1e-6 of the spacing): bisectors and their
// mirrors nearly coincide and pass near corners, along edges and along faces, where clips that
// decided a corner once per face, or joined the new face's corners by angle, made cells 20-60%
// too large or too small (the corner-graph clip keeps the surface closed). The volume
// moves by at most the six faces' displacements, 3 x jitter of the spacing each way: 10 jitter
// bounds it (plus round-off).
TEST(VoronoiCell, NearlyCubicLatticeIsNearlyACube) {
  std::mt19937_64 rng(3);
  const double d = 0.508e-3;
  for (double jitter : {1e-15, 1e-13, 1e-11, 1e-9, 1e-7, 1e-6}) {
    std::uniform_real_distribution<double> u(-jitter * d, jitter * d);
    double worst = 0.0;
    for (int trial = 0; trial < 300; ++trial) {
      auto offsets = lattice<3>(Tensor<3>(d * Tensor<3>::Identity()),
                                [](const auto& k) { return k.cwiseAbs().maxCoeff() <= 2; });
      for (auto& p : offsets) p += Vec<3>(u(rng), u(rng), u(rng));
      const auto c = cellOf<3>(offsets, 2.0 * 0.762e-3);
      worst = std::max(worst, std::abs(c.volume / (d * d * d) - 1.0));
    }
    EXPECT_LT(worst, 10.0 * jitter + 1e-12) << "jitter " << jitter;
  }
}
