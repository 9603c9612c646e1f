// Kernel normalisation, derivative and SPH gradient consistency in 1/2/3D.
#include "spall/kernels/Kernels.hpp"
#include "spall/kernels/PsiTable.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <numbers>

using namespace spall::kernels;

namespace {

// Volume integral of W(r, h = 1) over the support by composite Simpson in r: 1D 2 int W dr,
// 2D 2 pi int r W dr, 3D 4 pi int r^2 W dr.
template <class K, int Dim> double volumeIntegral() {
  const int n = 20000;
  const double hstep = K::support / n;
  double sum = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double r = k * hstep;
    const double shell = Dim == 1   ? 2.0
                         : Dim == 2 ? 2.0 * std::numbers::pi * r
                                    : 4.0 * std::numbers::pi * r * r;
    const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    sum += w * shell * Kernel<K, Dim>::W(r, 1.0);
  }
  return sum * hstep / 3.0;
}

template <class K> void checkDerivative() {
  // Central differences of f against df: the error is O(eps^2) ~ 1e-10 for these polynomials
  // (away from the spline's knots at q = 1, 2 where f'' jumps).
  for (double q = 0.013; q < K::support; q += 0.0517) {
    const double eps = 1e-5;
    const double fd = (K::f(q + eps) - K::f(q - eps)) / (2 * eps);
    EXPECT_NEAR(K::df(q), fd, 1e-8) << "q = " << q;
  }
  EXPECT_EQ(K::f(K::support), 0.0);
  EXPECT_EQ(K::df(K::support), 0.0);
}

// First-order consistency of the SPH gradient on a cubic lattice of unit spacing with
// h = n_h: sum_j V_j (x_j - x_i) (x) grad_i W(x_i - x_j) = I. The lattice sum is a quadrature
// of the exact integral identity; with n_h = 1.5 sites per h its error is about 1% (measured:
// 1.0% in 3D for the cubic spline), so 2% separates quadrature error from a wrong gradient
// (a wrong normalisation or sign is off by O(1)).
template <class K, int Dim> void checkGradientConsistency(double nh) {
  using M = Eigen::Matrix<double, Dim, Dim>;
  using V = Eigen::Matrix<double, Dim, 1>;
  M sum = M::Zero();
  const int n = static_cast<int>(K::support * nh) + 1;
  const int ny = Dim >= 2 ? n : 0, nz = Dim >= 3 ? n : 0;
  for (int k = -nz; k <= nz; ++k)
    for (int j = -ny; j <= ny; ++j)
      for (int i = -n; i <= n; ++i) {
        V x;
        x[0] = i;
        if constexpr (Dim >= 2) x[1] = j;
        if constexpr (Dim >= 3) x[2] = k;
        const double r = x.norm();
        if (r == 0.0 || r >= K::support * nh) continue;
        const V gradW =
            Kernel<K, Dim>::dWdr(r, nh) * (-x) / r; // grad_i W(x_i - x_j), x = x_j - x_i
        sum += x * gradW.transpose();
      }
  const M err = sum - M::Identity();
  EXPECT_LT(err.cwiseAbs().maxCoeff(), 2e-2) << "Dim " << Dim << " n_h " << nh;
}

} // namespace

TEST(Kernels, NormalisedInEveryDimension) {
  // Simpson with 2e4 intervals integrates these piecewise polynomials to ~1e-12; 1e-8 leaves
  // room for the spline's kink at q = 1.
  EXPECT_NEAR((volumeIntegral<CubicSpline<1>, 1>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<CubicSpline<2>, 2>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<CubicSpline<3>, 3>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC2<1>, 1>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC2<2>, 2>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC2<3>, 3>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC4<1>, 1>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC4<2>, 2>()), 1.0, 1e-8);
  EXPECT_NEAR((volumeIntegral<WendlandC4<3>, 3>()), 1.0, 1e-8);
}

TEST(Kernels, DerivativesMatchFiniteDifferences) {
  checkDerivative<CubicSpline<3>>();
  checkDerivative<WendlandC2<1>>();
  checkDerivative<WendlandC2<3>>();
  checkDerivative<WendlandC4<1>>();
  checkDerivative<WendlandC4<3>>();
}

TEST(Kernels, LamEquation14In1D) {
  // Lam et al. (2001) Eq. 14: W = 2/(3h) (1 - 3/2 q^2 + 3/4 q^3) for q <= 1.
  const double h = 0.7, r = 0.35, q = r / h;
  EXPECT_NEAR((Kernel<CubicSpline<1>, 1>::W(r, h)),
              2.0 / (3.0 * h) * (1 - 1.5 * q * q + 0.75 * q * q * q), 1e-15);
}

TEST(Kernels, GradientFirstOrderConsistencyOnALattice) {
  checkGradientConsistency<CubicSpline<1>, 1>(1.5);
  checkGradientConsistency<CubicSpline<2>, 2>(1.5);
  checkGradientConsistency<CubicSpline<3>, 3>(1.5);
  checkGradientConsistency<WendlandC2<2>, 2>(1.5);
  checkGradientConsistency<WendlandC4<3>, 3>(1.5);
}

TEST(PsiTable, InvertsItselfAndIsNearlyLinear) {
  // Owen (2010), Fig. 3: Psi_0 is close to linear in n_h over the range people run (1 to 4):
  // the straight line through the end points stays within 3% of the range of Psi_0. The
  // inverse must reproduce n_h to the table's interpolation accuracy (300 entries over
  // [0.55, 8]: ~1e-3).
  const auto check = [](const PsiTable& t, int dim) {
    const double p1 = t.psi0(1.0), p4 = t.psi0(4.0);
    for (double nh = 1.0; nh <= 4.0; nh += 0.1) {
      EXPECT_NEAR(t.nodesPerH(t.psi0(nh)), nh, 2e-3 * nh) << dim << "D n_h " << nh;
      const double line = p1 + (p4 - p1) * (nh - 1.0) / 3.0;
      EXPECT_LT(std::abs(t.psi0(nh) - line), 0.03 * (p4 - p1)) << dim << "D n_h " << nh;
    }
    // Strictly increasing: a larger measured Psi_0 always means more nodes per h.
    for (double nh = 0.6; nh < 7.9; nh += 0.05) EXPECT_LT(t.psi0(nh), t.psi0(nh + 0.05) + 1e-15);
  };
  check(PsiTable::build<Kernel<CubicSpline<1>, 1>, 1>(), 1);
  check(PsiTable::build<Kernel<CubicSpline<2>, 2>, 2>(), 2);
  check(PsiTable::build<Kernel<CubicSpline<3>, 3>, 3>(), 3);
  check(PsiTable::build<Kernel<WendlandC4<3>, 3>, 3>(), 3);
}

TEST(PsiTable, MeasuredLatticeGivesItsNodesPerH) {
  // A 2D lattice of spacing dx seen with h = 1.7 dx must read back n_h = 1.7 from its W^H sum.
  const auto t = PsiTable::build<Kernel<CubicSpline<2>, 2>, 2>();
  const double dx = 0.01, h = 1.7 * dx;
  double sum = 0.0;
  for (int j = -5; j <= 5; ++j)
    for (int i = -5; i <= 5; ++i) {
      const double eta = std::hypot(i * dx, j * dx) / h;
      if (eta < 2.0) sum += Kernel<CubicSpline<2>, 2>::WH(eta);
    }
  EXPECT_NEAR(t.nodesPerH(std::sqrt(sum)), 1.7, 5e-3);
}
