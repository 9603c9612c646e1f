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
  Vec<Dim> lambda;
  Tensor<Dim> Q;
  const SymmetricEigen<Dim> cell =
      cellSecond ? symmetricEigen<Dim>(*cellSecond) : SymmetricEigen<Dim>{};
  const SymmetricEigen<Dim> own = symmetricEigen<Dim>(0.5 * (H + H.transpose()));
  lambda = own.values.cwiseMax(0.0);
  Q = own.vectors;
  if (cellSecond && cell.values[0] > 1e-12 * cell.values[Dim - 1] && cell.values[0] > 0.0 &&
      lambda[0] > 0.0) {
    // The target shape (unit determinant): ascending moments, the narrowest direction first,
    // the largest 1/axis.
    Vec<Dim> target = cell.values.cwiseSqrt().cwiseInverse();
    target /= root<Dim>(target.prod());
    const Tensor<Dim> Ht = cell.vectors * target.asDiagonal() * cell.vectors.transpose();
    // A step along the geodesic from the present shape towards it, relaxed as the size is
    // (Eqs. 2-3): half the correction's logarithm, at most 20% per axis. M = S^-1 Ht S^-1
    // (S = H^(1/2), unit determinant) holds the correction's ratios; H' = S f(M) S.
    const Vec<Dim> sq = (lambda / root<Dim>(lambda.prod())).cwiseSqrt();
    const Tensor<Dim> S = Q * sq.asDiagonal() * Q.transpose();
    const Tensor<Dim> Sinv = Q * sq.cwiseInverse().asDiagonal() * Q.transpose();
    Tensor<Dim> M = Sinv * Ht * Sinv;
    const SymmetricEigen<Dim> corr = symmetricEigen<Dim>(0.5 * (M + M.transpose()));
    const Vec<Dim> f = corr.values.cwiseMax(0.0).cwiseSqrt().cwiseMax(1.0 / 1.2).cwiseMin(1.2);
    M = S * (corr.vectors * f.asDiagonal() * corr.vectors.transpose()) * S;
    const SymmetricEigen<Dim> next = symmetricEigen<Dim>(0.5 * (M + M.transpose()));
    lambda = next.values.cwiseMax(0.0);
    Q = next.vectors;
  }
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
