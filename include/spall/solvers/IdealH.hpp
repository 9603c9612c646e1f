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

// f(M) for a symmetric M with eigen-decomposition e and f(e.values) = fmu. In 2D without
// eigenvectors: f(M) = f(mu_0) I + (f(mu_1) - f(mu_0)) P with P = (M - mu_0 I)/(mu_1 - mu_0),
// the projector onto the larger eigenvalue's axis (for nearly equal eigenvalues f(M) ~
// f(mu_0) I).
template <int Dim>
Tensor<Dim> spectralMap(const Tensor<Dim>& M, const SymmetricEigen<Dim>& e, const Vec<Dim>& fmu) {
  if constexpr (Dim == 2) {
    const Vec<2>& mu = e.values;
    Tensor<2> out = fmu[0] * Tensor<2>::Identity();
    const double gap = mu[1] - mu[0];
    if (gap > 1e-12 * std::abs(mu[1]))
      out += ((fmu[1] - fmu[0]) / gap) * (M - mu[0] * Tensor<2>::Identity());
    return out;
  } else {
    return e.vectors * fmu.asDiagonal() * e.vectors.transpose();
  }
}

// Owen (2010), Sec. II: the ideal H from the sums of the last neighbor loop.
// Size (Eqs. 1-4): n_h from Psi_0 = (sum W^H)^(1/nu) by the tabulated Psi_0(n_h), s = n_h^target/
// n_h, a = 0.4 (1 + s^2) or 0.4 (1 + s^-3), and |H| scales by (1 - a + a s)^-nu.
// Shape (Eqs. 5-6): the goal is that "in the local eta space the neighbors of node i should
// appear isotropic" (Sec. II-B). Psi_2 is Eq. 5's kernel-weighted second moment of the
// neighbor directions, taken in the eta = H_i x frame: sum_j (W^H(eta_j)/eta_j^(nu-1))^2
// eta^_j eta^_j^T. Neighbors that sit closer in eta along an axis weigh more there, and the
// shape correction T = Psi_2^(1/2)/|Psi_2|^(1/2nu) (Eq. 6's normalised square root) stretches
// eta along it: eta' = T eta, so H' = (H T^2 H)^(1/2) (the kernel sees only |eta|). When the
// neighbors look isotropic in eta, T = I: any lattice mapped by a linear A (Fig. 5) is then a
// fixed point at H ~ (A A^T)^(-1/2), whatever the weights, because a square, hexagonal or cubic
// lattice has no preferred direction for a second moment. (Eq. 5 as printed takes the moment of
// the physical directions and Eq. 6 its inverse root; without the eta frame a distorted lattice
// is not a fixed point: the physical-frame version settled at axis ratio 2.8 instead of 4.)
// Limits: h_min <= every axis <= h_max, the longest axis <= h_max_ratio n_h (m/rho)^(1/nu) (as
// for SPH), and longest/shortest <= max_aspect_ratio.
// Updates H in place, and h to its longest axis 1/lambda_min(H) (the reach of the neighbor
// search). psi2Eta: Eq. 5's moment in the eta frame of H; psi2x: the physical-frame moment of
// the axes; factor: sizeFactor(n_h of the last loop).
template <int Dim>
void idealHTensor(Tensor<Dim>& H, double& h, double factor, const Tensor<Dim>& psi2Eta,
                  const Tensor<Dim>& psi2x, double m, double rho, const SmoothingLimits& lim) {
  const double size = root<Dim>(std::abs(H.determinant())) / factor;
  // The shape correction, where Psi_2 sees neighbors in every direction (a particle with
  // neighbors on one line only keeps its shape). H' = (H T^2 H)^(1/2) shares the
  // eigenvectors of H T^2 H, its eigenvalues are their square roots.
  Tensor<Dim> G = H * H;
  // (2D needs only the eigenvalues of Psi_2, see spectralMap; 3D its eigenvectors too.)
  const SymmetricEigen<Dim> psi2 =
      Dim == 2 ? SymmetricEigen<Dim>{symmetricEigenvalues<Dim>(psi2Eta), Tensor<Dim>::Zero()}
               : symmetricEigen<Dim>(psi2Eta);
  const Vec<Dim>& mu = psi2.values;
  if (mu[0] > 1e-6 * mu[Dim - 1] && mu[0] > 0.0) {
    // Relaxed like the size (Eqs. 2-3): half the correction per step, at most 20% per axis,
    // so that a transient neighborhood (a particle passing between rows) cannot flip or
    // collapse the ellipse in one step.
    Vec<Dim> t = mu.cwiseSqrt().cwiseSqrt();
    t /= root<Dim>(t.prod());
    t = t.cwiseMax(1.0 / 1.2).cwiseMin(1.2);
    const Tensor<Dim> T2 = spectralMap<Dim>(psi2Eta, psi2, t.cwiseAbs2());
    G = H * T2 * H;
    G = 0.5 * (G + G.transpose());
  }
  Vec<Dim> lambda = symmetricEigenvalues<Dim>(G).cwiseMax(0.0).cwiseSqrt();
  // The axes from a physical-frame moment, sum_j W^H(eta_j)^2 x^_j x^_j / r_j^2 (Eq. 5 with
  // the physical distance in place of eta, so that closer neighbors always weigh more): it
  // keeps the symmetry of the node distribution, which the eta-frame correction alone can
  // break (on the distorted lattice 179 of 204 particles settled 7 degrees off, at one of
  // two mirror-image states whose eta-frame moment is isotropic too). Its eigenvectors in
  // ascending order carry H's eigenvalues in ascending order.
  // (Where that moment is degenerate, a particle with neighbors on one line, the axes of the
  // corrected H stay.)
  const SymmetricEigen<Dim> axes = symmetricEigen<Dim>(psi2x);
  const bool axesKnown = axes.values[0] > 1e-6 * axes.values[Dim - 1] && axes.values[0] > 0.0;
  const Tensor<Dim> Q = axesKnown ? axes.vectors : symmetricEigen<Dim>(G).vectors;
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
