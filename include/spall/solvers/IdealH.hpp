#pragma once
// Owen (2010), "ASPH modeling of material damage and failure", Sec. II: the ideal smoothing
// scale from the sums of the last neighbor loop, per particle (the solver runs the loop).
#include "spall/core/SymmetricEigen.hpp"
#include "spall/core/Types.hpp"

#include <algorithm>
#include <cmath>

namespace spall::solvers {

// x^(1/Dim) without the general pow (a fifth of the smoothing update's time in 2D).
template <int Dim> double root(double x) {
  if constexpr (Dim == 1)
    return x;
  else if constexpr (Dim == 2)
    return std::sqrt(x);
  else
    return std::cbrt(x);
}

// Owen (2010) Eqs. 2-3: s = n_h^target/n_h (at most 4), a = 0.4 (1 + s^2) for s < 1 and
// 0.4 (1 + s^-3) otherwise; h scales by (1 - a + a s), |H| by its -nu power (Eq. 4).
inline double sizeFactor(double nh, double target) {
  const double sRatio = std::min(nh > 0.0 ? target / nh : 4.0, 4.0);
  const double a =
      sRatio < 1.0 ? 0.4 * (1.0 + sRatio * sRatio) : 0.4 * (1.0 + 1.0 / (sRatio * sRatio * sRatio));
  return 1.0 - a + a * sRatio;
}

// The bounds on h (or on every axis of H): [hMin, hMax], the longest at most hMaxRatio n_h
// (m/rho)^(1/nu), the size (ASPH: the mean axis, |H|^(-1/nu)) at least hMinRatio n_h
// (m/rho)^(1/nu), and (ASPH) longest/shortest at most maxAspectRatio.
struct SmoothingLimits {
  double nodesPerH, hMin, hMax, hMinRatio, hMaxRatio, maxAspectRatio;
};

// SPH: h' = factor h within the limits.
template <int Dim>
double idealH(double h, double factor, double m, double rho, const SmoothingLimits& lim) {
  double hNew = factor * h;
  const double hVolume = lim.nodesPerH * root<Dim>(m / rho);
  hNew = std::clamp(hNew, lim.hMinRatio * hVolume, lim.hMaxRatio * hVolume);
  return std::clamp(hNew, lim.hMin, lim.hMax);
}

// The shape's step of idealHTensor: along the geodesic from the shape of H (symmetric positive
// definite) towards the cell's, C^(-1/2) of its second moment C, both at unit determinant, half
// the correction's logarithm and at most kShapeStep per axis. M = S^-1 H_cell S^-1 (S = H^(1/2))
// holds the correction's ratios; the step is S f(M) S with f the square root clamped to
// [1/kShapeStep, kShapeStep]. False where C or H is degenerate (the shape is kept).
constexpr double kShapeStep = 1.2;
template <int Dim> bool relaxedShape(const Tensor<Dim>& H, const Tensor<Dim>& C, Tensor<Dim>& out) {
  if constexpr (Dim == 2) {
    // Closed forms for unit-determinant symmetric positive definite 2x2 A, B (eigenvalues a,
    // 1/a): A^-1 = adj A, A^(1/2) = (A + I) / sqrt(tr A + 2), and the geodesic's midpoint, the
    // geometric mean, is (A + B) / sqrt(det(A + B)). The result's scale is free (the caller
    // sets the size): out = A + B where the step is within the cap.
    const auto adj = [](const Tensor<2>& A) {
      Tensor<2> B;
      B << A(1, 1), -A(0, 1), -A(1, 0), A(0, 0);
      return B;
    };
    const double detH = H.determinant(), detC = C.determinant(), trC = C.trace();
    if (!(detH > 0.0 && H(0, 0) > 0.0 && trC > 0.0 && detC > 1e-12 * trC * trC)) return false;
    // C^(-1/2) at unit determinant: adj(C + d I), d = sqrt(det C), over sqrt(d (2 d + tr C)).
    const double d = std::sqrt(detC);
    const Tensor<2> target = adj(C + d * Tensor<2>::Identity()) / std::sqrt(d * (2.0 * d + trC));
    const Tensor<2> A = H / std::sqrt(detH);
    // tr M = tr(S^-1 target S^-1) = tr(target A^-1) = mu + 1/mu.
    const double trM = (target * adj(A)).trace();
    constexpr double cap2 = kShapeStep * kShapeStep;
    if (trM <= cap2 + 1.0 / cap2) {
      out = A + target;
      return true;
    }
    // Beyond the cap: f(mu1) = kShapeStep, f(mu0) = 1/kShapeStep, by the projector on mu1's axis.
    const Tensor<2> S = (A + Tensor<2>::Identity()) / std::sqrt(A.trace() + 2.0), Sinv = adj(S);
    Tensor<2> M = Sinv * target * Sinv;
    M = 0.5 * (M + M.transpose());
    const double gap = std::sqrt(std::max(trM * trM - 4.0, 0.0)), mu0 = 0.5 * (trM - gap);
    const Tensor<2> F = Tensor<2>::Identity() / kShapeStep +
                        ((kShapeStep - 1.0 / kShapeStep) / gap) * (M - mu0 * Tensor<2>::Identity());
    out = S * F * S;
    return true;
  } else {
    const SymmetricEigen<Dim> cell = symmetricEigen<Dim>(C);
    const SymmetricEigen<Dim> own = symmetricEigen<Dim>(H);
    if (!(cell.values[0] > 1e-12 * cell.values[Dim - 1] && cell.values[0] > 0.0 &&
          own.values[0] > 0.0))
      return false;
    Vec<Dim> target = cell.values.cwiseSqrt().cwiseInverse();
    target /= root<Dim>(target.prod());
    const Vec<Dim> sq = (own.values / root<Dim>(own.values.prod())).cwiseSqrt();
    const Tensor<Dim> S = own.vectors * sq.asDiagonal() * own.vectors.transpose();
    const Tensor<Dim> Sinv = own.vectors * sq.cwiseInverse().asDiagonal() * own.vectors.transpose();
    Tensor<Dim> M = Sinv * (cell.vectors * target.asDiagonal() * cell.vectors.transpose()) * Sinv;
    const SymmetricEigen<Dim> corr = symmetricEigen<Dim>(0.5 * (M + M.transpose()));
    const Vec<Dim> f =
        corr.values.cwiseMax(0.0).cwiseSqrt().cwiseMax(1.0 / kShapeStep).cwiseMin(kShapeStep);
    out = S * (corr.vectors * f.asDiagonal() * corr.vectors.transpose()) * S;
    out = 0.5 * (out + out.transpose());
    return true;
  }
}

// The ideal H: its size from Owen (2010) (Eqs. 1-4: n_h from Psi_0 = (sum W^H)^(1/nu) by the
// tabulated Psi_0(n_h), s = n_h^target/n_h, a = 0.4 (1 + s^2) or 0.4 (1 + s^-3), and |H| scales
// by (1 - a + a s)^-nu), its shape from the particle's Voronoi cell (solvers/VoronoiCell.hpp):
// axes along the eigenvectors of the cell's second moment C, lengths in proportion to the square
// roots of its eigenvalues, H ~ C^(-1/2) (as Spheral's 2024 ASPH takes it; a rectangular cell a
// by b gives axes in the ratio a/b, a cube a round ellipsoid).
// Why not Owen's Eqs. 5-6 (the kernel-weighted second moment of the neighbor directions in the
// frame eta = H x, and H stretched until they look isotropic there): for a uniform medium that
// moment is isotropic in the eta frame of any H, so it has no restoring force towards the
// medium's shape, and only the lattice's discreteness decides. On a square lattice that held;
// on a cubic one at n_h 1.5 it pushed back the wrong way: round ellipsoids grew ~11% per step
// along a body diagonal, to an axis ratio of 2.41 everywhere within a few hundred steps. The cell
// depends on positions alone, with no feedback through H, and continuously on them.
// The shape is relaxed towards the cell's as the size is (half the correction's logarithm per
// step, at most 20% per axis), not taken at once: a particle torn from its neighbors at km/s sees
// its cell change from one step to the next, and an ellipse that followed it flipped, lost
// neighbors and blew up (tools/stress, 2D ASPH, coarse hydro cells: 5 of 9 finished with the
// shape taken at once, 9 of 9 relaxed; fine, al_al and cu_al at 6 and 10 km/s: 0 of 4 and 4 of
// 4). A lattice's cell is a fixed point either way.
// Where the cell stays open (no neighbor on either side along some direction: cellSecond ==
// nullptr) the shape is kept and only the size changes.
// Limits: h_min <= every axis <= h_max, the longest axis <= h_max_ratio n_h (m/rho)^(1/nu) (as
// for SPH), and longest/shortest <= max_aspect_ratio. Updates H in place, and h to its longest
// axis 1/lambda_min(H) (the reach of the neighbor search). factor: sizeFactor(n_h of the last
// loop); cellSecond: the cell's second moment about its centroid.
template <int Dim>
void idealHTensor(Tensor<Dim>& H, double& h, double factor, const Tensor<Dim>* cellSecond, double m,
                  double rho, const SmoothingLimits& lim) {
  const double size = root<Dim>(std::abs(H.determinant())) / factor;
  Tensor<Dim> shape;
  const Tensor<Dim> Hs = 0.5 * (H + H.transpose());
  const bool relaxed = cellSecond && relaxedShape<Dim>(Hs, *cellSecond, shape);
  const SymmetricEigen<Dim> axes = symmetricEigen<Dim>(relaxed ? shape : Hs);
  Vec<Dim> lambda = axes.values.cwiseMax(0.0);
  const Tensor<Dim>& Q = axes.vectors;
  // The size within its floor: 1/size is the mean axis.
  const double hVolume = lim.nodesPerH * root<Dim>(m / rho);
  lambda *= std::min(size, 1.0 / (lim.hMinRatio * hVolume)) / root<Dim>(lambda.prod());
  // Limits on the axes 1/lambda.
  const double hLongest = std::min(lim.hMax, lim.hMaxRatio * hVolume);
  for (int k = 0; k < Dim; ++k) lambda[k] = std::clamp(lambda[k], 1.0 / hLongest, 1.0 / lim.hMin);
  const double lambdaMin = std::max(lambda.minCoeff(), lambda.maxCoeff() / lim.maxAspectRatio);
  for (int k = 0; k < Dim; ++k) lambda[k] = std::max(lambda[k], lambdaMin);
  H = Q * lambda.asDiagonal() * Q.transpose();
  h = 1.0 / lambda.minCoeff();
}

} // namespace spall::solvers
